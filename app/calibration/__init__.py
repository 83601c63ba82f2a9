"""The numerical core of trical: numpy and scipy only, nothing of HTTP, JSON or files.

One method = one function = one frozen result dataclass (docs/architecture.md).
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
