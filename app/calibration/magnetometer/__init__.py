"""The compass: a magnetometer's hard and soft iron from a device turned through all directions.

:func:`fit_magnetometer` (in :mod:`.fit`) is the method; :mod:`.coverage` the directions a turn
covers, :mod:`.ellipsoid` the closed-form starts, :mod:`.refine` the geometric fit and its covariance.
"""

from .fit import fit_magnetometer
from .result import MagnetometerResult

__all__ = ["MagnetometerResult", "fit_magnetometer"]
