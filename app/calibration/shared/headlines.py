"""The sensors' names as the core's reasons and figures say them.

How a calibration's figures are told to a person (its headline, the note under its verdict) is not the
core's: app/headlines.py says it by result class.
"""

from __future__ import annotations

SENSOR_WORDS = {"acc": "accelerometer", "gyr": "gyroscope", "mag": "magnetometer"}
TEMPERATURE_SENSORS = ("acc", "gyr")
"""The sensors a temperature calibration models, in the order its figures are told."""
FIGURE_WORDS = {"mg": "mg", "deg/s": "°/s"}
"""A drift's unit as its figure names it."""
