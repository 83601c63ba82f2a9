"""The numerical core of trical: numpy and scipy only, nothing of HTTP, JSON or files.

One method = one function = one frozen result dataclass (docs/architecture.md). What the methods share is
:mod:`.shared` (the result's base among it, which imports no method); the methods are :mod:`.still` (the still
readings' models), :mod:`.noise`, :mod:`.cube`, :mod:`.magnetometer`, :mod:`.autocal` and :mod:`.temperature`, over
:mod:`.segments` (where a recording rests); :mod:`.registry` knows every method's result class. This face offers the
six-position fits, the errors, gravity and the orientations.
"""

from .shared.errors import CalibrationError, InsufficientDataError
from .shared.gravity import STANDARD_GRAVITY, normal_gravity
from .shared.orientations import CANONICAL_SIX, nearest_orientation, up_vector
from .still.affine import AffineCalibration, fit_orientations, fit_six_position

__all__ = [
    "CANONICAL_SIX",
    "STANDARD_GRAVITY",
    "AffineCalibration",
    "CalibrationError",
    "InsufficientDataError",
    "fit_orientations",
    "fit_six_position",
    "nearest_orientation",
    "normal_gravity",
    "up_vector",
]
