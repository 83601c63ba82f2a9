"""Temperature: each axis's offset as a polynomial of the sensor's temperature."""

from __future__ import annotations

from collections.abc import Collection, Sequence
from typing import Any

import numpy as np

from app.calibration import CalibrationError
from app.io.log import TO_SI, LogData
from app.workflows.calibration import Calibration
from app.workflows.recordings import NOMINAL_RATE_HZ, RecordingSource
from app.workflows.requests import SensorsRequest

TEMPERATURE_SENSORS = ("acc", "gyr")


def temperature_log(log: LogData, *, sensors: Sequence[str] | None = None, **fields: Any) -> Calibration:
    """Temperature calibration (app.calibration.temperature) of a still recording that carries the sensor's
    temperature; accelerometers in g become m/s², gyroscopes in deg/s rad/s (the firmwares' units)."""
    from app.calibration.temperature import calibrate_temperature

    if log.temperature_c is None:
        raise CalibrationError(
            "the recording has no temperature: method temperature fits each axis's offset against the sensor's "
            "temperature — give a CSV with a temp_c column (°C, one per sample, beside the readings), or a flight "
            "controller's log (PX4 .ulg, ArduPilot .bin) that records its IMU's temperature"
        )
    wanted = list(sensors) if sensors else [s for s in TEMPERATURE_SENSORS if getattr(log, s) is not None]
    missing = [s for s in wanted if getattr(log, s) is None]
    if not wanted or missing:
        raise CalibrationError(
            f"the recording has no {', '.join(missing or TEMPERATURE_SENSORS)} samples (it has "
            f"{', '.join(log.channels)}): method temperature calibrates the accelerometer and the gyroscope"
        )
    notes = list(log.warnings) + list(log.notes)
    arrays: dict[str, np.ndarray] = {}
    for name in wanted:
        unit = log.units[name]
        if unit == "raw":
            raise CalibrationError(
                f"the {name} readings are counts whose scale is unknown: the firmwares' temperature parameters are "
                "in m/s² and rad/s — give chip (e.g. chip=mpu6050-2g,mpu6050-250dps), or the unit"
            )
        scale = TO_SI[name][unit]
        arrays[name] = np.asarray(getattr(log, name), dtype=float) * scale
    rate = log.sampling_rate_hz
    if rate is None:
        rate = NOMINAL_RATE_HZ
        notes.append(f"the rests were looked for as if sampled at {NOMINAL_RATE_HZ:g} Hz (the log has no rate)")
    result = calibrate_temperature(
        log.temperature_c, sampling_rate_hz=rate, time_s=log.time_s, acc=arrays.get("acc"), gyr=arrays.get("gyr")
    )
    ids = sensor_ids(log, wanted)
    return Calibration.of(result, {}, unit=result.unit, notes=notes, **({"sensor_ids": ids} if ids else {}), **fields)


def sensor_ids(log: LogData, sensors: Collection[str]) -> dict[str, int]:
    """The firmware's device id of each sensor a flight log's IMU was read from (``LogData.flight``: the
    instance and source read, and the log's list of instances), for the parameters that name the sensor a
    calibration belongs to (PX4's ``TC_A0_ID``, ``TC_G0_ID``); empty for other recordings, or a source without
    ids (PX4's ``sensor_combined``)."""
    if log.flight is None:
        return {}
    imu = log.flight.imu
    source = {"acc": imu.get("source"), "gyr": imu.get("gyr_source") or imu.get("source")}
    ids = {}
    for row in log.flight.instances:
        sensor = row["sensor"]
        if (
            sensor in sensors
            and row["instance"] == imu.get("instance")
            and row["source"] == source[sensor]
            and row.get("device_id")
        ):
            ids[sensor] = int(row["device_id"])
    return ids


def temperature(request: SensorsRequest, recording: RecordingSource) -> Calibration:
    """Method ``temperature``: a still recording that carries the sensor's temperature (:func:`temperature_log`)."""
    log = recording.read()
    return temperature_log(
        log,
        sensors=request.sensors,
        device_id=request.device_id,
        label=request.label or recording.meta.get("filename"),
        **recording.source_fields,
    )
