"""A calibration a device already holds, read from the file its firmware or ground station wrote.

:func:`read_calibration` recognises the file by its content, never by its name alone: a DataFlash log or a ULog by
their magic bytes, trical's JSON export by its ``$schema``, a Betaflight or INAV CLI dump by its version line or
its ``set`` lines, and parameter files by the parameters they hold (ArduPilot's ``INS_``/``COMPASS_``, PX4's
``CAL_``). One module per family: :mod:`.ardupilot`, :mod:`.px4`, :mod:`.cli_dump` (Betaflight, INAV),
:mod:`.trical_json`; :mod:`.parameters` reads the text of every parameter file.
"""

from __future__ import annotations

import json
import re
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from app.calibration.shared.errors import CalibrationError
from app.calibration.shared.result import CalibrationResult

from ..errors import LogFormatError
from ..flight import dataflash, ulog
from ..flight.ardupilot import ardupilot_release
from ..plural import counted
from . import ardupilot, cli_dump, parameters, px4, trical_json

FIRMWARE_NAMES = {
    "ardupilot": "ArduPilot",
    "px4": "PX4",
    "betaflight": "Betaflight",
    "inav": "INAV",
    "trical": "trical's JSON export",
}
"""What ``firmware`` may force (the format is otherwise recognised from the content), and its name for a person."""
FIRMWARES = tuple(FIRMWARE_NAMES)

ACCEPTED = (
    "ArduPilot parameter files (Mission Planner .param, MAVProxy .parm) and DataFlash logs (.bin); PX4's "
    "QGroundControl .params, param set lines and ULogs (.ulg); Betaflight and INAV CLI diff all or dump; "
    "trical's JSON export"
)
CODE = "unrecognised_calibration"
ARDUPILOT_PREFIXES = ("INS_ACC", "INS_GYR", "COMPASS_OFS", "COMPASS_DIA")
PX4_PREFIXES = ("CAL_ACC", "CAL_GYRO", "CAL_MAG")


@dataclass(frozen=True)
class ImportedFile:
    """What a file gave: the result, the caller's fields it carries, and what it was recognised as."""

    result: CalibrationResult
    recognised: str
    fields: dict = field(default_factory=dict)


def _refuse(message: str) -> LogFormatError:
    return LogFormatError(message, status=422, code=CODE)


def _with_file(data: bytes, suffix: str, read):
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / f"import{suffix}"
        path.write_bytes(data)
        return read(path)


def _dataflash_params(path: Path) -> tuple[dict[str, float], str | None]:
    """The log's parameters, and the firmware's version its banner states (``ArduCopter V4.6.2`` → ``4.6.2``)."""
    reader, buf, _ = dataflash.open_log(path)
    found = re.search(r"\bV(\d+\.\d+(?:\.\d+)?)", ardupilot_release(reader, buf))
    return dataflash.params(reader, buf), None if found is None else found.group(1)


def _ulog_params(path: Path) -> tuple[dict[str, float], str | None]:
    log, _ = ulog.open_ulog(path, "the file", "export its parameters from QGroundControl instead (a .params file)")
    found = ulog.release(log)
    return {k: float(v) for k, v in log.initial_parameters.items()}, (
        None if found is None else ".".join(str(v) for v in found)
    )


def _from_params(family: str, params: dict[str, float], kind: str, version: str | None, instance: int):
    reader = ardupilot if family == "ardupilot" else px4
    try:
        return reader.from_parameters(params, file_kind=kind, version=version, instance=instance)
    except LookupError as exc:
        raise _refuse(
            f"the file is {kind} of {reader.FIRMWARE} with {counted(len(params), 'parameter')} but {exc}: export the "
            "parameters after the sensors were calibrated"
        ) from None


def _family_of(params: dict[str, float]) -> str | None:
    if any(n.startswith(ARDUPILOT_PREFIXES) for n in params):
        return "ardupilot"
    if any(n.startswith(PX4_PREFIXES) for n in params):
        return "px4"
    return None


def read_calibration(data: bytes, *, firmware: str | None = None, instance: int = 0) -> ImportedFile:
    """The calibration a file holds, recognised from its content (``firmware`` forces the family).

    Parameters
    ----------
    data : bytes
        The file.
    firmware : {"ardupilot", "px4", "betaflight", "inav", "trical"}, optional
    instance : int
        Which IMU and compass (ArduPilot's 0–2, PX4's slot) of a file holding several.

    Raises
    ------
    LogFormatError
        A file of no accepted kind (code ``unrecognised_calibration``), naming what it looked like and what is
        accepted; one of an accepted kind that holds no calibration.
    """
    if not data:
        raise _refuse(f"the file is empty: give one of {ACCEPTED}")
    if firmware is not None and firmware not in FIRMWARES:
        raise _refuse(f"firmware {firmware!r} is not one trical reads: give one of {', '.join(FIRMWARES)}")
    if data.startswith(dataflash.MAGIC) and firmware in (None, "ardupilot"):
        params, version = _with_file(data, ".bin", _dataflash_params)
        result = _from_params("ardupilot", params, "DataFlash log PARM", version, instance)
        return ImportedFile(result, "an ArduPilot DataFlash log's parameters")
    if data.startswith(ulog.MAGIC) and firmware in (None, "px4"):
        params, version = _with_file(data, ".ulg", _ulog_params)
        return ImportedFile(
            _from_params("px4", params, "ULog parameters", version, instance), "a PX4 ULog's parameters"
        )
    try:
        if b"\x00" in data[:4096]:
            raise UnicodeDecodeError("utf-8", data[:1], 0, 1, "a NUL byte")
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise _refuse(
            f"the file is binary but neither a DataFlash log nor a ULog (it starts {data[:8]!r}): give one of "
            f"{ACCEPTED}"
        ) from None
    if text.lstrip().startswith("{") and firmware in (None, "trical"):
        return _trical(text)
    dump = cli_dump.firmware_of(text)
    values = cli_dump.sets(text)
    wants_dump = firmware in ("betaflight", "inav")
    if wants_dump or (firmware is None and (dump is not None or values)):
        return _dump(firmware, dump, values)
    params, kind, version = parameters.parse(text)
    family = firmware if firmware in ("ardupilot", "px4") else _family_of(params)
    if family is not None:
        return ImportedFile(_from_params(family, params, kind, version, instance), f"{kind} of {family}")
    seen = (
        f"{counted(len(params), 'parameter')} ({kind}) of no calibration"
        if params
        else "no parameter, set line or JSON"
    )
    raise _refuse(f"the file holds {seen}: give one of {ACCEPTED}, or name its family in `firmware`")


def _trical(text: str) -> ImportedFile:
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as exc:
        raise _refuse(f"the file starts as JSON but is not ({exc.msg} at line {exc.lineno}): give {ACCEPTED}") from None
    if not trical_json.is_export(doc):
        raise _refuse(
            f"the file is JSON but not trical's export (its $schema is not trical's): give a file of {ACCEPTED}"
        )
    try:
        result, fields = trical_json.from_export(doc)
    except CalibrationError as exc:
        raise _refuse(f"the file is trical's JSON export but {exc}") from None
    return ImportedFile(result, "trical's JSON export", fields)


def _dump(firmware: str | None, dump, values: dict[str, str]) -> ImportedFile:
    name, board, version = dump if dump is not None else (None, None, None)
    if firmware is not None:
        name = "INAV" if firmware == "inav" else "Betaflight"
    if name is None:
        name = "INAV" if any(k.startswith(("acczero_", "accgain_")) for k in values) else "Betaflight"
    kind = f"{name} CLI diff/dump" + (f" ({board})" if board else "")
    read = cli_dump.inav if name == "INAV" else cli_dump.betaflight
    dump = f"the file is {'an' if name == 'INAV' else 'a'} {name} CLI dump with {counted(len(values), 'set line')}"
    try:
        result = read(values, version, kind)
    except cli_dump.NotANumber as exc:
        raise _refuse(f"{dump} but {exc}: give it the number {name}'s CLI printed") from None
    except LookupError as exc:
        raise _refuse(f"{dump} but {exc}: calibrate the accelerometer and run diff all again") from None
    return ImportedFile(result, kind)
