"""The cube method of Särkkä et al. (IEEE Sensors J. 2017): accelerometer, gyroscope and magnetometer from
one recording of still positions joined by known rotations (docs/methods.md, protocols cube24 and
ferraris)."""

from .accmag import FieldSensorCalibration, fit_field_sensor
from .calibrate import CubeCalibration, calibrate_cube
from .gyro import GyroCalibration, fit_gyroscope
from .protocols import Protocol, cube24, explicit_protocol, ferraris, get_protocol
from .segmentation import Segmentation, segment_recording
from .sequence import SequenceCheck, check_sequence

__all__ = [
    "CubeCalibration",
    "FieldSensorCalibration",
    "GyroCalibration",
    "Protocol",
    "Segmentation",
    "SequenceCheck",
    "calibrate_cube",
    "check_sequence",
    "cube24",
    "explicit_protocol",
    "ferraris",
    "fit_field_sensor",
    "fit_gyroscope",
    "get_protocol",
    "segment_recording",
]
