"""trical: calibration of the motion sensors of phones and small IMU boards."""

__version__ = "0.1.0"
