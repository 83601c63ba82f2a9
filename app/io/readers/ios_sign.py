"""The sign of the accelerations: iOS Core Motion reads −g on the up axis, trical wants +g.

Core Motion (``CMAccelerometerData.acceleration``, ``CMDeviceMotion.gravity`` and
``userAcceleration``) reports accelerations in g with the opposite sign of Android's sensors and the
W3C Accelerometer: at rest face up an iPhone reads z = −1 g, an Android phone +9.81 m/s²
(docs/conventions.md, "Frame and sign").  trical's readings are specific force, +g on the up axis.

The sign is decided from what the file says, never from the orientation of the data (a device
resting face down reads like an iPhone resting face up):

* the caller's ``sign`` (+1 keeps the file's accelerations, −1 negates them) wins;
* else a header with Core Motion's names — SensorLog's ``accelerometerAccelerationX(G)``,
  ``motionUserAccelerationX(G)``, ``motionGravityX(G)``, or ``userAcceleration``/``gravity``
  columns — in g says an iOS Core Motion log: negated, and a note on the recording says so;
* such names over readings in m/s² are kept as they are: Core Motion itself writes g, so an app
  converted them, and may have fixed the sign on the way (phyphox multiplies by −9.81);
* a reader may have decided already (Sensor Logger's ``Metadata.csv``): its ``LogData.sign``.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Iterable

from ..errors import LogFormatError
from ..log import LogData

SIGNS = (1, -1)
_CORE_MOTION = re.compile(r"accelerometeracceleration[xyz]|useracceleration[xyz]?|motiongravity[xyz]")
_GRAVITY = re.compile(r"^gravity[xyz]")
MAX_NAMED = 3


def _compact(name: str) -> str:
    return re.sub(r"[^a-z]", "", name.lower().split("(")[0])


def core_motion_columns(columns: Iterable[str] | None) -> list[str]:
    """The columns whose names are Core Motion's (SensorLog's, or ``userAcceleration``/``gravity``)."""
    compact = [(c, _compact(str(c))) for c in columns or ()]
    found = [c for c, k in compact if _CORE_MOTION.match(k)]
    if any(_CORE_MOTION.match(k) and k.startswith("useracceleration") for _, k in compact):
        found += [c for c, k in compact if _GRAVITY.match(k)]  # gravity beside userAcceleration: Core Motion's
    return found


def check_sign(sign: object) -> int | None:
    """``sign`` as +1 or −1 (None when not given).

    Raises
    ------
    LogFormatError
        Any other value.
    """
    if sign is None:
        return None
    if sign not in SIGNS:
        raise LogFormatError(f"sign must be 1 (keep the file's accelerations) or -1 (negate them); got {sign!r}")
    return int(sign)


def settle_sign(log: LogData, sign: int | None) -> LogData:
    """The log with its accelerations on trical's sign (+g up), ``log.sign`` saying what was applied.

    Parameters
    ----------
    log : LogData
        As the reader returned it (``log.sign``: what the reader applied already).
    sign : {1, -1} or None
        The caller's factor on the file's accelerations; None to decide from the header.
    """
    sign = check_sign(sign)
    notes = []
    cues = core_motion_columns(log.columns)
    if sign is None:
        if not cues or log.sign != 1:
            return log
        named = ", ".join(cues[:MAX_NAMED]) + (", …" if len(cues) > MAX_NAMED else "")
        if log.units.get("acc") != "g":
            return dataclasses.replace(
                log,
                notes=tuple(log.notes)
                + (
                    f"the header names Core Motion columns ({named}) but the readings are in {log.units.get('acc')}, "
                    "not Core Motion's g: an app converted them, so their sign is kept as it is; pass sign=-1 if "
                    "the up axis reads -g",
                ),
            )
        sign = -1
        notes.append(
            f"this looks like an iOS Core Motion log ({named}): its accelerations were negated "
            "(+g on the up axis); pass sign=1 to keep them"
        )
    elif sign == -1 and log.sign == 1:
        notes.append("accelerations negated as sign=-1 asks")
    elif sign == 1 and (cues or log.sign == -1):
        notes.append("sign=1 given: the file's accelerations are kept as they are (not negated)")
    if sign == log.sign:
        return dataclasses.replace(log, notes=tuple(log.notes) + tuple(notes))
    acc = None if log.acc is None else -log.acc
    return dataclasses.replace(log, acc=acc, sign=sign, notes=tuple(log.notes) + tuple(notes))
