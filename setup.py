"""The package's one compiled part, beside pyproject.toml (which holds everything else): the Allan sums'
fused loop, app/calibration/noise/allan_fused.pyx, turned into C by Cython and built where a C compiler is
present. It is optional: without a compiler the install goes on, and app.calibration.noise.allan sums in numpy
(the same figures, slower)."""

from setuptools import Extension, setup

setup(
    ext_modules=[
        Extension("app.calibration.noise.allan_fused", ["app/calibration/noise/allan_fused.pyx"], optional=True)
    ]
)
