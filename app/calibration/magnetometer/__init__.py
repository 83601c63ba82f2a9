"""The compass: a magnetometer's hard and soft iron from a device turned through all directions, or from a flight.

:func:`fit_magnetometer` (in :mod:`.fit`) is the method for a turn; :mod:`.coverage` the directions a turn
covers, :mod:`.ellipsoid` the closed-form starts, :mod:`.refine` the geometric fit and its covariance.
:func:`fit_flight_compass` (in :mod:`.flight`, its algebra in :mod:`.flight_model`) calibrates a flight
controller's compass from a flight log against the field its attitude expects.
"""

from .fit import fit_magnetometer
from .flight import FlightCompassResult, fit_flight_compass
from .flight_calibration import FlightCompassCalibration
from .result import MagnetometerResult

__all__ = [
    "FlightCompassCalibration",
    "FlightCompassResult",
    "MagnetometerResult",
    "fit_flight_compass",
    "fit_magnetometer",
]
