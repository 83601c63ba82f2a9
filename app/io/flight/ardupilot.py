"""ArduPilot's part of :mod:`.context`: a DataFlash log's compass read back to raw, its stored
calibration (COMPASS_*), attitude (ATT, AHR2), current (BAT, CURR), throttle (CTUN) and first GPS fix.
The formulas and the generations are in :mod:`.context`'s docstring."""

from __future__ import annotations

import numpy as np

from ..errors import LogFormatError
from . import dataflash
from .context import (
    GPS_3D_FIX,
    MILLIGAUSS_TO_UT,
    FirmwareCompassCal,
    FlightCompassLog,
    euler_to_c_nb,
    gps_to_utc,
    one_power_clock,
    symmetric,
)

ARDUPILOT_SUFFIX = ("", "2", "3")
ARDUPILOT_MOTOR_AFTER_MATRIX = ("COMPASS_PMOT_EN", "COMPASS_SCALE", "COMPASS_SCALE2", "COMPASS_SCALE3")
"""Parameters only a firmware that applies the motor offset after DIA/ODI has: correct_field moved the motor
compensation after the matrix with the per-motor compensation (COMPASS_PMOT_*, Copter 3.6), and COMPASS_SCALE
came later still."""
"""ArduPilot's compass parameters per instance: COMPASS_OFS_X, COMPASS_OFS2_X, COMPASS_OFS3_X …"""


def ardupilot_cal(values: dict, instance: int) -> FirmwareCompassCal:
    """The compass calibration ArduPilot stored for ``instance`` (COMPASS_OFS{,2,3}_X …, DIA, ODI, MOT,
    MOTCT, ORIENT, SCALE)."""
    k = ARDUPILOT_SUFFIX[instance] if instance < len(ARDUPILOT_SUFFIX) else str(instance + 1)
    names = {
        "ofs": [f"COMPASS_OFS{k}_{a}" for a in "XYZ"],
        "dia": [f"COMPASS_DIA{k}_{a}" for a in "XYZ"],
        "odi": [f"COMPASS_ODI{k}_{a}" for a in "XYZ"],
        "mot": [f"COMPASS_MOT{k}_{a}" for a in "XYZ"],
    }
    orient = "COMPASS_ORIENT" + k
    scale = "COMPASS_SCALE" + k
    extern = "COMPASS_EXTERNAL" if not k else "COMPASS_EXTERN" + k  # 0 internal, 1 external, 2 forced external
    used = {n: values[n] for group in names.values() for n in group if n in values}
    for n in ("COMPASS_MOTCT", orient, scale, extern):
        if n in values:
            used[n] = values[n]
    ofs = np.array([values.get(n, 0.0) for n in names["ofs"]])
    dia = np.array([values.get(n, 0.0) for n in names["dia"]])
    if not dia.any():  # correct_field: diagonals of zero are set to one
        dia = np.ones(3)
    matrix = symmetric(dia, [values.get(n, 0.0) for n in names["odi"]])
    s = values.get(scale, 0.0)
    if s > 0:  # have_scale_factor: COMPASS_SCALE multiplies before the matrix
        matrix = matrix * s
    motct = int(values.get("COMPASS_MOTCT", 0))
    return FirmwareCompassCal(
        firmware="ardupilot",
        instance=instance,
        offsets_ut=ofs * MILLIGAUSS_TO_UT,
        matrix=matrix,
        motor=np.array([values.get(n, 0.0) for n in names["mot"]]) * MILLIGAUSS_TO_UT,
        motor_kind={1: "throttle", 2: "current"}.get(motct),
        orientation=int(values[orient]) if orient in values else None,
        params=used,
        switch="COMPASS_USE" + k,
        external=None if extern not in values else values[extern] > 0,
    )


def _first(reader, buf, names):
    """``(message, columns)`` of the first of ``names`` the log has (instance 0 when it has several)."""
    for n in names:
        t = dataflash.table(reader, buf, n)
        if t is None:
            continue
        field = dataflash.instance_field(reader, n)
        if field is not None and field in t:
            first = np.min(t[field])
            t = {c: v[t[field] == first] for c, v in t.items()}
        return n, t
    return None, None


ATTITUDE_MESSAGES = ("ATT", "AHR2", "XKF1", "NKF1", "EKF1")
"""ArduPilot's attitude estimates with Roll, Pitch, Yaw (deg): the one the vehicle flew by (ATT), the DCM backup
(AHR2), and EKF3's, EKF2's and the older EKF's first core (XKF1, NKF1, EKF1). ATT's yaw comes from the estimator
that used the primary compass, which flatters that compass's "before"."""


def _ardupilot_attitude(reader, buf, name, wanted: str | None = None):
    """``(time_s, C_nb, source)`` of ``wanted`` (one of :data:`ATTITUDE_MESSAGES`), by default the first logged."""
    if wanted is not None and wanted not in ATTITUDE_MESSAGES:
        raise LogFormatError(
            f"attitude {wanted!r} is not an ArduPilot attitude message: give attitude as one of "
            f"{', '.join(ATTITUDE_MESSAGES)}"
        )
    if wanted is not None and dataflash.table(reader, buf, wanted) is None:
        logged = [m for m in ATTITUDE_MESSAGES if dataflash.table(reader, buf, m) is not None]
        raise LogFormatError(
            f"{name} has no {wanted} messages: choose attitude among those it logs ({', '.join(logged) or 'none'})"
        )
    msg, t = _first(reader, buf, ATTITUDE_MESSAGES if wanted is None else (wanted,))
    if t is None:
        return None, None, None
    rpy = [dataflash.column(t, msg, (f,), name) for f in ("Roll", "Pitch", "Yaw")]
    return dataflash.time_us(t, msg, name) * 1e-6, euler_to_c_nb(*rpy), f"{msg} Roll, Pitch, Yaw (deg)"


def _scaled(values, per: float) -> np.ndarray:
    """A logged integer in hundredths (or thousandths) as a float; a float field as it is."""
    v = np.asarray(values)
    return v.astype(float) * per if v.dtype.kind in "iu" else v.astype(float)


def _ardupilot_power(reader, buf, name, release, notes):
    current = throttle = None
    msg, t = _first(reader, buf, ("BAT", "CURR"))
    if t is not None and ("Curr" in t):
        # CURR of Copter ≤ 3.4 logs int16 current_amps * 100 (centi-amps); BAT and later CURR log A as float.
        current = (dataflash.time_us(t, msg, name) * 1e-6, _scaled(t["Curr"], 0.01), f"{msg}.Curr")
    tmsg, tt = _first(reader, buf, ("CTUN",))
    field = None if tt is None else "ThO" if "ThO" in tt else "ThrOut" if "ThrOut" in tt else None
    if field is not None:
        if "Plane" in release:  # Plane's CTUN logs the throttle servo's scaled output, percent
            value, how = np.asarray(tt[field], dtype=float) * 0.01, f"CTUN.{field} (Plane, percent)"
        else:  # Copter: ThO 0..1 (float), ThrOut 0..1000 (int16) in older logs
            value, how = _scaled(tt[field], 1e-3), f"CTUN.{field}"
        throttle = (dataflash.time_us(tt, tmsg, name) * 1e-6, value, how)
    return one_power_clock(current, throttle, notes)


def _ardupilot_position(reader, buf, name, notes):
    msg, t = _first(reader, buf, ("GPS",))
    if t is None:
        notes.append("no GPS messages: the place and date of the flight must be given")
        return None, None, None, None
    status = dataflash.column(t, msg, ("Status",), name)
    good = np.flatnonzero(np.asarray(status) >= GPS_3D_FIX)
    if not len(good):
        notes.append("the GPS never had a 3-D fix: the place and date of the flight must be given")
        return None, None, None, None
    i = int(good[0])
    lat = float(dataflash.column(t, msg, ("Lat",), name)[i])
    lon = float(dataflash.column(t, msg, ("Lng", "Lon"), name)[i])
    alt = float(dataflash.column(t, msg, ("Alt",), name)[i])
    week = dataflash.column(t, msg, ("GWk", "Week"), name)[i]
    # GPS of the TimeMS generation: TimeMS is the GPS milliseconds of the week, T the board's clock (ms).
    ms = dataflash.column(t, msg, ("GMS",) if "GMS" in t else ("TimeMS",), name)[i]
    utc = gps_to_utc(int(week), float(ms)) if week > 0 else None
    return lat, lon, alt, utc


def ardupilot_release(reader, buf) -> str:
    """The firmware's banner from the log's MSG (``ArduPilot Copter V3.3-dev``), or ``ArduPilot``."""
    msgs = dataflash.table(reader, buf, "MSG")
    if msgs is not None and "Message" in msgs:
        for m in msgs["Message"]:
            text = m.split(b"\0")[0].decode("ascii", "replace")
            if text.startswith(("APM:", "Ardu")):
                return "ArduPilot " + text.replace("APM:", "").split(" (")[0].strip()
    return "ArduPilot"


def _ardupilot_generation(reader, release, mag_msg, t) -> str:
    clock = "TimeUS" if "TimeUS" in t else "TimeMS"
    layout = mag_msg if dataflash.instance_field(reader, mag_msg) is None else f"{mag_msg} with I"
    return f"{release} ({clock}, {layout})"


def read_ardupilot(path, mag_instance, name, attitude: str | None = None) -> FlightCompassLog:
    reader, buf, said = dataflash.open_log(path, name)
    values = dataflash.params(reader, buf)
    mags = dataflash.instances(reader, buf, dataflash.MAG_NAMES)
    have = sorted({i for i, _, _ in mags})
    if not have:
        raise LogFormatError(
            f"{name} is an ArduPilot DataFlash log without compass messages (MAG): log the compass "
            "(LOG_BITMASK with COMPASS)"
        )
    instance = have[0] if mag_instance is None else int(mag_instance)
    if instance not in have:
        raise LogFormatError(
            f"{name} has no compass instance {instance}: its compass instances are "
            f"{', '.join(map(str, have))}; give mag_instance as one of them"
        )
    msg, t = next((m, x) for i, m, x in mags if i == instance)
    notes = []
    time_s = dataflash.time_us(t, msg, name) * 1e-6
    h = np.column_stack([dataflash.column(t, msg, (f"Mag{a}",), name) for a in "XYZ"]).astype(float)
    stored = ardupilot_cal(values, instance)
    ofs = np.broadcast_to(stored.offsets_ut / MILLIGAUSS_TO_UT, h.shape).copy()
    if all(f"Ofs{a}" in t for a in "XYZ"):
        logged = np.column_stack([t[f"Ofs{a}"] for a in "XYZ"]).astype(float)
        # OfsX… are the offsets applied, logged as int16 (truncated): the parameter where it rounds to them,
        # the logged value where they differ (offsets learnt or set in flight).
        differ = np.abs(logged - ofs) > 1.0
        if differ.any():
            ofs[differ] = logged[differ]
            notes.append(
                f"{int(differ.any(axis=1).sum())} of {len(h)} {msg} rows carry offsets OfsX… other than "
                "COMPASS_OFS in the parameters (learnt or set in flight): those rows are read back with the "
                "logged offsets (whole mG)"
            )
    else:
        notes.append(f"{msg} has no OfsX… fields: read back with COMPASS_OFS of the parameters")
    if all(f"MOfs{a}" in t for a in "XYZ"):
        mofs = np.column_stack([t[f"MOfs{a}"] for a in "XYZ"]).astype(float)
    else:
        mofs = np.zeros_like(h)
        notes.append(f"{msg} has no MOfsX… fields: no motor offset is taken out")
    d_inv = np.linalg.inv(stored.matrix)
    newer = any(n in values for n in ARDUPILOT_MOTOR_AFTER_MATRIX)
    if newer:  # h = D s (m + O) + MOfs (stored.matrix holds D s)
        raw_mg = (h - mofs) @ d_inv.T - ofs
        formula = "m = (D s)⁻¹ (h − MOfs) − O"
    else:  # Copter 3.3–3.5: h = D (m + O + MOfs)
        raw_mg = h @ d_inv.T - ofs - mofs
        formula = "m = D⁻¹ h − O − MOfs"
    raw_how = (
        f"read back to raw from {msg} (logged corrected, body frame) with OfsX…, MOfsX… and COMPASS_DIA/ODI"
        f"{'/SCALE' if newer else ''}: {formula}"
    )
    att_t, att_c, att_source = _ardupilot_attitude(reader, buf, name, attitude)
    if att_t is None:
        notes.append("no ATT, AHR2 or EKF messages: the attitude is missing (log ATTITUDE_MED/FAST)")
    release = ardupilot_release(reader, buf)
    p_t, cur, thr, p_source = _ardupilot_power(reader, buf, name, release, notes)
    lat, lon, alt, utc = _ardupilot_position(reader, buf, name, notes)
    if said.getvalue().strip():
        notes.append(f"{name}: pymavlink reported: {said.getvalue().strip()[:200]}")
    return FlightCompassLog(
        firmware="ardupilot",
        generation=_ardupilot_generation(reader, release, msg, t),
        instance=instance,
        time_s=time_s,
        mag_raw_ut=raw_mg * MILLIGAUSS_TO_UT,
        mag_firmware_ut=h * MILLIGAUSS_TO_UT,
        raw_how=raw_how,
        frame_to_body=np.eye(3),
        stored=stored,
        attitude_time_s=att_t,
        attitude_c_nb=att_c,
        attitude_source=att_source,
        power_time_s=p_t,
        current_a=cur,
        throttle=thr,
        power_source=p_source,
        latitude_deg=lat,
        longitude_deg=lon,
        altitude_m=alt,
        utc=utc,
        notes=tuple(notes),
    )
