"""The response model of a calibration a device already holds, read from its firmware's file (method imported)."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field

from app.api.schemas.common import CalibrationCommon, Mat3Out, Out, Vec3Out


class ImportedModel(Out):
    type: Literal["imported"]
    acc_M: Mat3Out | None = Field(None, description="The accelerometer's f = M (m − o): the firmware's scales.")
    acc_o: Vec3Out | None = Field(None, description="The accelerometer's offset, m/s².")
    gyr_M: Mat3Out | None = Field(None, description="The gyroscope's M: the identity (the firmwares hold a bias).")
    gyr_o: Vec3Out | None = Field(None, description="The gyroscope's bias, rad/s.")
    mag_M: Mat3Out | None = Field(None, description="The compass's soft iron (symmetric).")
    mag_o: Vec3Out | None = Field(None, description="The compass's hard iron, µT.")


class ImportedUncertainty(Out):
    note: str = Field(description="Imported, not fitted: no intervals.")


class ReadFromOut(Out):
    firmware: str = Field(description="ArduPilot, PX4, Betaflight or INAV.")
    version: str | None = Field(description="The firmware's version where the file states it.")
    file_kind: str = Field(description="What was read, e.g. `QGroundControl .params`, `DataFlash log PARM`.")
    frame: str = Field(description="The frame the firmware applies the corrections in, in words.")
    units: dict[str, str] = Field(description="By sensor, the unit of o and of the readings corrected (trical's).")
    firmware_units: dict[str, str] = Field(description="By sensor, the unit the firmware holds its offset in.")
    parameters: dict[str, dict[str, Any]] = Field(description="By sensor, the firmware's parameters read, as read.")


class ImportedOut(CalibrationCommon):
    method: Literal["imported"]
    model: ImportedModel
    uncertainty: ImportedUncertainty
    metrics: dict[str, Any] = Field(description="None: nothing was fitted.")
    read_from: ReadFromOut = Field(description="What the calibration was read from.")
