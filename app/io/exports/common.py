"""What every export shares: the file it returns, and each sensor's correction ``f = M (m − o)``
taken from the calibration's typed result (app.calibration.registry)."""

from __future__ import annotations

from dataclasses import dataclass

from app.calibration.shared.correction import AffineCorrection
from app.calibration.shared.errors import CalibrationError

from ..errors import ExportError

JSON_SCHEMA = "https://trical.dev/schema/calibration/v1"
FRAME = "device frame of the data: x right, y up along the screen, z out of the screen (W3C DeviceMotion)"


@dataclass(frozen=True)
class Export:
    """An export's file: text, or bytes for a binary format (``motioncal``); ``notes`` say what the
    format does not carry of the calibration."""

    content: str | bytes
    media_type: str
    filename: str
    notes: tuple = ()


def _result(body: dict):
    from app.calibration import registry  # from_dict imports every model

    try:
        return registry.from_dict(body)
    except CalibrationError as exc:
        raise ExportError(f"{exc}: this calibration cannot be exported") from None


def result_class(body: dict):
    """The result class a stored calibration names (app.calibration.registry): its class answers (``KIND``,
    ``PER_SENSOR``) say which exports fit it, even for a body cut short."""
    from app.calibration import registry  # class_of imports every model

    try:
        return registry.class_of(body)
    except CalibrationError as exc:
        raise ExportError(f"{exc}: this calibration cannot be exported") from None


def only_compass(body: dict) -> bool:
    """Whether the calibration corrects the magnetometer alone (the compass's own firmware parameters)."""
    return [c.sensor for c in sensor_corrections(body)] == ["mag"]


def sensor_corrections(body: dict) -> list[AffineCorrection]:
    """Every sensor correction a calibration holds: the accelerometer's, and for the cube method
    (Särkkä et al., IEEE Sensors Journal 17(11) 2017) the gyroscope's and magnetometer's too."""
    corrections = list(_result(body).corrections().values())
    if not corrections:
        raise ExportError("the calibration holds no sensor model to export: use the json export")
    return corrections


def accelerometer_correction(body: dict) -> AffineCorrection:
    """The accelerometer's correction ``a = M (m − o)``, for the formats that hold one sensor."""
    acc = [c for c in sensor_corrections(body) if c.sensor == "acc"]
    if not acc:
        raise ExportError("this calibration has no accelerometer model: use the json export")
    return acc[0]


def accelerometer_readings(body: dict):
    """The still readings the accelerometer's correction was fitted on (N × 3, the calibration's input unit),
    or None where the calibration holds none."""
    return _result(body).still_readings()


def unit_label(unit: str | None) -> str:
    """How a text export names a unit: readings whose scale is unknown (``raw``) are counts."""
    return "counts" if unit == "raw" else str(unit)


def describe(body: dict, source: str) -> list[str]:
    """Lines naming the calibration, for the comment header of a text export; ``source`` is its
    correction's (:attr:`AffineCorrection.source`)."""
    return [
        f"trical calibration {body['id']}",
        f"method: {body['method']}, created {body['created_at']}, device: {body.get('device_id') or '-'}",
        f"input unit: {unit_label(body.get('unit'))}, output unit: {unit_label(body.get('output_unit'))}, "
        f"gravity: {body.get('gravity')}",
        f"calibrated a = M (m - o): {source}",
    ]
