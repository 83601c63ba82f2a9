"""A flight log's compass with its context: raw readings, the firmware's stored calibration, attitude,
current or throttle, position and date — what a compass fit from a flight needs.

The readers of the two formats (:mod:`.formats.dataflash`, :mod:`.formats.ulog`) give the tables; this
module picks the compass instance asked, reads its readings back to *raw* where the firmware logged them
corrected, and puts every series on one clock: seconds on the flight controller's clock (since its boot:
ArduPilot's ``TimeUS``/``TimeMS``, PX4's ``timestamp_sample``/``timestamp``), which every message of a log
shares.

What is raw, what is corrected (what a logged compass reading is, per firmware and generation; the
reading's ``raw_how`` says which; docs/rest.md has the same table):

- ArduPilot Copter 3.3–3.5 (``TimeMS`` or ``TimeUS``), ``MAG``/``MAG2``/``MAG3`` with OfsX…, MOfsX…:
  corrected, body frame (COMPASS_ORIENT, AHRS_ORIENTATION), mG, ``h = D (m + O + MOfs)``; read back
  ``m = D⁻¹ h − O − MOfs`` (O: COMPASS_OFS*, D: COMPASS_DIA*/ODI*).
- ArduPilot Copter 3.6 on (COMPASS_PMOT_EN or COMPASS_SCALE in the parameters), ``MAG`` (with ``I``
  later): corrected, body frame, ``h = D s (m + O) + MOfs``; read back ``m = (D s)⁻¹ (h − MOfs) − O``.
- ArduPilot, every release, ``IMU``/``ACC``/``GYR``: corrected (INS_ACCOFFS/ACCSCAL, gyro offsets),
  body frame; not read back here.
- PX4 1.6–1.8, ``sensor_combined.magnetometer_ga``: corrected, body frame, gauss, ``h = R S (m − o)``;
  read back ``m = S⁻¹ Rᵀ h + o`` (o: CAL_MAGn_xOFF, S: xSCALE/xODIAG, R: the rotation below).
- PX4 1.9–1.11, ``sensor_mag`` per instance: after the driver's CAL_MAGn offsets and scales, the
  driver's frame; read back ``m = S⁻¹ h + o``.
- PX4 1.12 on, ``sensor_mag`` (and ``sensor_accel``/``sensor_gyro``): raw, the driver's frame (the
  chip's axes turned onto the board's), gauss; the firmware's field is computed with PX4's formula.
- PX4 1.9 on, ``vehicle_magnetometer``: corrected, body frame, the selected compass; compared with the
  firmware's field computed from sensor_mag when it is the same compass (a note gives the rms); read
  back ``m = S⁻¹ Rᵀ h + o − c p`` when the log has no sensor_mag.

The firmwares' formulas, from their sources:

- ArduPilot, ``AP_Compass_Backend::correct_field`` (libraries/AP_Compass/AP_Compass_Backend.cpp): the
  driver has rotated the raw field into the body frame (COMPASS_ORIENTn, and AHRS_ORIENTATION for an
  internal compass) before; then in Copter 3.3–3.5 ``mag += offsets; mag += motor_offset; mag = mat *
  mag`` (the motor offset inside the matrix); from the release that added the per-motor compensation
  (COMPASS_PMOT_EN, Copter 3.6) ``mag += offsets; mag = mat * mag; mag += motor_offset``, and later
  ``mag *= scale_factor`` (COMPASS_SCALE) before the matrix.  ``mat`` is
  ``[[DIA_X, ODI_X, ODI_Y], [ODI_X, DIA_Y, ODI_Z], [ODI_Y, ODI_Z, DIA_Z]]``; ``motor_offset =
  COMPASS_MOT * thr_or_curr`` (COMPASS_MOTCT 1: throttle 0..1, 2: current in A).  The logger writes the
  corrected field with the offsets (OfsX…, int16, the parameter truncated) and the motor offset applied
  (MOfsX…) — the order is told by COMPASS_PMOT_EN or COMPASS_SCALE in the log's parameters
  (:data:`ARDUPILOT_MOTOR_AFTER_MATRIX`); with DIA/ODI the identity or no motor offset both orders are
  the same.
- PX4, ``calibration::Magnetometer::Correct`` (src/lib/sensor_calibration/Magnetometer.hpp):
  ``rotation * (scale * ((data + power_compensation) - offset))`` in gauss, ``scale`` the symmetric
  matrix of CAL_MAGn_XSCALE… on its diagonal and CAL_MAGn_XODIAG, YODIAG, ZODIAG off it,
  ``power_compensation = CAL_MAGn_XCOMP… * power`` with power from CAL_MAG_COMP_TYP (1 throttle,
  2 and 3 the current of battery 0 or 1 in kA), ``rotation`` CAL_MAGn_ROT for an external compass, the
  board's SENS_BOARD_ROT for an internal one (CAL_MAGn_ROT −1).  Before PX4 1.12 the driver applied the
  offsets and scales (``PX4Magnetometer``, earlier ``mag_calibration_s``) and the sensors module the
  rotation: the same formula without power compensation, and sensor_mag logged after the offsets and
  scales.  The note a reading carries says which (``raw_how``); where sensor_mag is raw and
  vehicle_magnetometer logged, a note gives how far PX4's formula applied to sensor_mag lies from it.

The stored calibration (:class:`FirmwareCompassCal`) keeps each parameter's meaning: ArduPilot's
COMPASS_OFS (mG, ×0.1 to µT) is *added* to the raw field, PX4's CAL_MAGn_xOFF (gauss, ×100) is
*subtracted*.
"""

from __future__ import annotations

import contextlib
import datetime as dt
import io
from dataclasses import asdict, dataclass

import numpy as np

from .errors import LogFormatError
from .formats import dataflash, ulog

MILLIGAUSS_TO_UT = dataflash.MILLIGAUSS_TO_UT
GAUSS_TO_UT = ulog.GAUSS_TO_UT
KILOAMP_PER_AMP = 1e-3
"""PX4's CAL_MAGn_xCOMP are per kA of battery current (src/modules/sensors/vehicle_magnetometer: current_a * 0.001)."""
GPS_EPOCH = dt.datetime(1980, 1, 6, tzinfo=dt.timezone.utc)
LEAP_SECONDS = ((dt.datetime(2017, 1, 1, tzinfo=dt.timezone.utc), 18),
                (dt.datetime(2015, 7, 1, tzinfo=dt.timezone.utc), 17),
                (dt.datetime(2012, 7, 1, tzinfo=dt.timezone.utc), 16),
                (dt.datetime(2009, 1, 1, tzinfo=dt.timezone.utc), 15),
                (dt.datetime(2006, 1, 1, tzinfo=dt.timezone.utc), 14))
"""GPS time minus UTC from each date on (IERS Bulletin C; GPS time has no leap seconds)."""
GPS_3D_FIX = 3
"""ArduPilot's GPS Status and PX4's fix_type both number a 3-D fix 3 (AP_GPS::GPS_OK_FIX_3D, msg/SensorGps.msg)."""
ARDUPILOT_SUFFIX = ("", "2", "3")
ARDUPILOT_MOTOR_AFTER_MATRIX = ("COMPASS_PMOT_EN", "COMPASS_SCALE", "COMPASS_SCALE2", "COMPASS_SCALE3")
"""Parameters only a firmware that applies the motor offset after DIA/ODI has: correct_field moved the motor
compensation after the matrix with the per-motor compensation (COMPASS_PMOT_*, Copter 3.6), and COMPASS_SCALE
came later still."""
"""ArduPilot's compass parameters per instance: COMPASS_OFS_X, COMPASS_OFS2_X, COMPASS_OFS3_X …"""
PX4_ROTATIONS_RPY = ((0, 0, 0), (0, 0, 45), (0, 0, 90), (0, 0, 135), (0, 0, 180), (0, 0, 225), (0, 0, 270),
                     (0, 0, 315), (180, 0, 0), (180, 0, 45), (180, 0, 90), (180, 0, 135), (0, 180, 0),
                     (180, 0, 225), (180, 0, 270), (180, 0, 315), (90, 0, 0), (90, 0, 45), (90, 0, 90),
                     (90, 0, 135), (270, 0, 0), (270, 0, 45), (270, 0, 90), (270, 0, 135), (0, 90, 0), (0, 270, 0))
"""PX4's enum Rotation 0–25 as roll, pitch, yaw in degrees (src/lib/conversion/rotation.h, rot_lookup), the
entries every PX4 release shares; a later entry is refused by name."""


@dataclass(frozen=True)
class FirmwareCompassCal:
    """What the firmware stored for one compass and applies in flight (from the log's parameters).

    Attributes
    ----------
    firmware : {"ardupilot", "px4"}
    instance : int
    offsets_ut : numpy.ndarray of shape (3,)
        As the parameter means it: ArduPilot's COMPASS_OFS × 0.1 (added to the raw field), PX4's
        CAL_MAGn_xOFF × 100 (subtracted).
    matrix : numpy.ndarray of shape (3, 3)
        ArduPilot's DIA/ODI (times COMPASS_SCALE when set), PX4's xSCALE/xODIAG; the identity when absent.
    motor : numpy.ndarray of shape (3,)
        µT per A (current) or per unit throttle 0..1: ArduPilot COMPASS_MOT × 0.1, PX4 xCOMP × 100 (× 1e-3
        per A for the current, whose parameter is per kA).
    motor_kind : {"current", "throttle"} or None
        ArduPilot COMPASS_MOTCT, PX4 CAL_MAG_COMP_TYP; None when disabled.
    orientation : int or None
        COMPASS_ORIENTn / CAL_MAGn_ROT (the firmware's enum), None when absent.
    params : dict
        The parameters' names and values it came from.
    """

    firmware: str
    instance: int
    offsets_ut: np.ndarray
    matrix: np.ndarray
    motor: np.ndarray
    motor_kind: str | None
    orientation: int | None
    params: dict

    def to_dict(self) -> dict:
        d = asdict(self)
        for k in ("offsets_ut", "matrix", "motor"):
            d[k] = np.asarray(d[k]).tolist()
        return d


@dataclass(frozen=True)
class FlightCompassLog:
    """One compass of a flight log with what a fit from the flight needs, every time on one clock.

    Attributes
    ----------
    firmware, generation : str
        ``"ardupilot"`` / ``"px4"``; the firmware's release and layout read (``"ArduPilot Copter V3.3-dev
        (TimeMS, MAG2)"``).
    instance : int
        The compass instance.
    time_s : numpy.ndarray of shape (N,)
        The compass's sample times, s on the controller's clock (since boot).
    mag_raw_ut : numpy.ndarray of shape (N, 3)
        Raw in frame L (ArduPilot: the body frame under the current COMPASS_ORIENT; PX4: sensor_mag's frame).
    mag_firmware_ut : numpy.ndarray of shape (N, 3)
        The field the firmware used (corrected, body frame): logged, or computed with its formula.
    raw_how : str
        How the raw readings were had.
    frame_to_body : numpy.ndarray of shape (3, 3)
        The rotation L → body the firmware applies (the identity for ArduPilot).
    stored : FirmwareCompassCal
    attitude_time_s, attitude_c_nb, attitude_source
        (K,) s, (K, 3, 3) body → NED, and the message; None when the log has no attitude.
    power_time_s, current_a, throttle, power_source
        (P,) s, the battery current in A and the throttle 0..1 on those times (either may be None).
    latitude_deg, longitude_deg, altitude_m : float or None
        The first 3-D fix.
    utc : datetime.datetime or None
        The UTC time of that fix.
    notes : tuple of str
    """

    firmware: str
    generation: str
    instance: int
    time_s: np.ndarray
    mag_raw_ut: np.ndarray
    mag_firmware_ut: np.ndarray
    raw_how: str
    frame_to_body: np.ndarray
    stored: FirmwareCompassCal
    attitude_time_s: np.ndarray | None
    attitude_c_nb: np.ndarray | None
    attitude_source: str | None
    power_time_s: np.ndarray | None
    current_a: np.ndarray | None
    throttle: np.ndarray | None
    power_source: str | None
    latitude_deg: float | None
    longitude_deg: float | None
    altitude_m: float | None
    utc: dt.datetime | None
    notes: tuple = ()


# -- shared maths ---------------------------------------------------------------------------------------

def euler_to_c_nb(roll_deg, pitch_deg, yaw_deg) -> np.ndarray:
    """(K, 3, 3) body → NED of roll, pitch, yaw in degrees, ZYX (``C = Rz(yaw) Ry(pitch) Rx(roll)``, as
    ArduPilot's ``Matrix3f::from_euler`` and PX4's ``matrix::Dcm(Euler)``)."""
    r, p, y = (np.radians(np.asarray(a, dtype=float)) for a in (roll_deg, pitch_deg, yaw_deg))
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    c = np.empty(r.shape + (3, 3))
    c[..., 0, 0] = cp * cy
    c[..., 0, 1] = sr * sp * cy - cr * sy
    c[..., 0, 2] = cr * sp * cy + sr * sy
    c[..., 1, 0] = cp * sy
    c[..., 1, 1] = sr * sp * sy + cr * cy
    c[..., 1, 2] = cr * sp * sy - sr * cy
    c[..., 2, 0] = -sp
    c[..., 2, 1] = sr * cp
    c[..., 2, 2] = cr * cp
    return c


def quaternion_to_c_nb(q) -> np.ndarray:
    """(K, 3, 3) body → NED of unit quaternions (K, 4) ``w, x, y, z`` (PX4's vehicle_attitude ``q``,
    Hamilton, rotating body into NED: msg/VehicleAttitude.msg)."""
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    c = np.empty((len(q), 3, 3))
    c[:, 0, 0] = 1 - 2 * (y * y + z * z)
    c[:, 0, 1] = 2 * (x * y - w * z)
    c[:, 0, 2] = 2 * (x * z + w * y)
    c[:, 1, 0] = 2 * (x * y + w * z)
    c[:, 1, 1] = 1 - 2 * (x * x + z * z)
    c[:, 1, 2] = 2 * (y * z - w * x)
    c[:, 2, 0] = 2 * (x * z - w * y)
    c[:, 2, 1] = 2 * (y * z + w * x)
    c[:, 2, 2] = 1 - 2 * (x * x + y * y)
    return c


def symmetric(diagonal, off_diagonal) -> np.ndarray:
    """``[[d0, o0, o1], [o0, d1, o2], [o1, o2, d2]]``: ArduPilot's DIA/ODI and PX4's xSCALE/xODIAG layout."""
    d, o = np.asarray(diagonal, dtype=float), np.asarray(off_diagonal, dtype=float)
    return np.array([[d[0], o[0], o[1]], [o[0], d[1], o[2]], [o[1], o[2], d[2]]])


def gps_to_utc(week: int, ms: float) -> dt.datetime:
    """UTC of a GPS week and milliseconds of the week (GPS time less the leap seconds of that date)."""
    gps = GPS_EPOCH + dt.timedelta(weeks=int(week), milliseconds=float(ms))
    leap = next((s for since, s in LEAP_SECONDS if gps >= since), 13)
    return gps - dt.timedelta(seconds=leap)


def px4_rotation(number: int, name: str, what: str) -> np.ndarray:
    """PX4's rotation ``number`` as a matrix (``R = Rz(yaw) Ry(pitch) Rx(roll)``, rotation.cpp get_rot_matrix)."""
    if not 0 <= number < len(PX4_ROTATIONS_RPY):
        raise LogFormatError(f"{name}: {what} is {number}, a rotation of PX4's list past ROTATION_PITCH_270 (25) that "
                             "trical does not hold; set it to one of 0–25 or leave the compass internal")
    return euler_to_c_nb(*PX4_ROTATIONS_RPY[number])


# -- ArduPilot -------------------------------------------------------------------------------------------

def ardupilot_cal(values: dict, instance: int) -> FirmwareCompassCal:
    """The compass calibration ArduPilot stored for ``instance`` (COMPASS_OFS{,2,3}_X …, DIA, ODI, MOT,
    MOTCT, ORIENT, SCALE)."""
    k = ARDUPILOT_SUFFIX[instance] if instance < len(ARDUPILOT_SUFFIX) else str(instance + 1)
    names = {"ofs": [f"COMPASS_OFS{k}_{a}" for a in "XYZ"], "dia": [f"COMPASS_DIA{k}_{a}" for a in "XYZ"],
             "odi": [f"COMPASS_ODI{k}_{a}" for a in "XYZ"], "mot": [f"COMPASS_MOT{k}_{a}" for a in "XYZ"]}
    orient = "COMPASS_ORIENT" + k
    scale = "COMPASS_SCALE" + k
    used = {n: values[n] for group in names.values() for n in group if n in values}
    for n in ("COMPASS_MOTCT", orient, scale):
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
        firmware="ardupilot", instance=instance, offsets_ut=ofs * MILLIGAUSS_TO_UT, matrix=matrix,
        motor=np.array([values.get(n, 0.0) for n in names["mot"]]) * MILLIGAUSS_TO_UT,
        motor_kind={1: "throttle", 2: "current"}.get(motct), orientation=int(values[orient]) if orient in values
        else None, params=used)


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


def _ardupilot_attitude(reader, buf, name):
    msg, t = _first(reader, buf, ("ATT", "AHR2"))
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
    return _power(current, throttle, notes)


def _power(current, throttle, notes):
    """One clock for the current and the throttle: the times of the one logged more often, the other
    interpolated linearly onto them (PX4 logs battery_status at about 1 Hz, the controls far faster)."""
    if current is None and throttle is None:
        notes.append("no battery current and no throttle in the log: the motors' interference cannot be fitted")
        return None, None, None, None
    present = [x for x in (current, throttle) if x is not None]
    base = max(present, key=lambda x: len(x[0]))
    t = base[0]
    onto = [None if x is None else x[1] if x is base else np.interp(t, x[0], x[1]) for x in (current, throttle)]
    source = " and ".join(x[2] for x in present)
    if len(present) == 2:
        other = throttle if base is current else current
        source += f" ({other[2]} interpolated onto {base[2].split('.')[0]}'s times)"
    return t, onto[0], onto[1], source


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


def _ardupilot_release(reader, buf) -> str:
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


def _read_ardupilot(path, mag_instance, name) -> FlightCompassLog:
    reader, buf, said = dataflash.open_log(path, name)
    values = dataflash.params(reader, buf)
    mags = dataflash.instances(reader, buf, dataflash.MAG_NAMES)
    have = sorted({i for i, _, _ in mags})
    if not have:
        raise LogFormatError(f"{name} is an ArduPilot DataFlash log without compass messages (MAG): log the compass "
                             "(LOG_BITMASK with COMPASS)")
    instance = have[0] if mag_instance is None else int(mag_instance)
    if instance not in have:
        raise LogFormatError(f"{name} has no compass instance {instance}: its compass instances are "
                             f"{', '.join(map(str, have))}; give mag_instance as one of them")
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
            notes.append(f"{int(differ.any(axis=1).sum())} of {len(h)} {msg} rows carry offsets OfsX… other than "
                         "COMPASS_OFS in the parameters (learnt or set in flight): those rows are read back with the "
                         "logged offsets (whole mG)")
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
    raw_how = (f"read back to raw from {msg} (logged corrected, body frame) with OfsX…, MOfsX… and COMPASS_DIA/ODI"
               f"{'/SCALE' if newer else ''}: {formula}")
    att_t, att_c, att_source = _ardupilot_attitude(reader, buf, name)
    if att_t is None:
        notes.append("no ATT or AHR2 messages: the attitude is missing (log ATTITUDE_MED/FAST)")
    release = _ardupilot_release(reader, buf)
    p_t, cur, thr, p_source = _ardupilot_power(reader, buf, name, release, notes)
    lat, lon, alt, utc = _ardupilot_position(reader, buf, name, notes)
    if said.getvalue().strip():
        notes.append(f"{name}: pymavlink reported: {said.getvalue().strip()[:200]}")
    return FlightCompassLog(
        firmware="ardupilot", generation=_ardupilot_generation(reader, release, msg, t), instance=instance,
        time_s=time_s,
        mag_raw_ut=raw_mg * MILLIGAUSS_TO_UT, mag_firmware_ut=h * MILLIGAUSS_TO_UT, raw_how=raw_how,
        frame_to_body=np.eye(3), stored=stored, attitude_time_s=att_t, attitude_c_nb=att_c,
        attitude_source=att_source, power_time_s=p_t, current_a=cur, throttle=thr, power_source=p_source,
        latitude_deg=lat, longitude_deg=lon, altitude_m=alt, utc=utc, notes=tuple(notes))


# -- PX4 -------------------------------------------------------------------------------------------------

PX4_TOPICS = ("sensor_mag", "sensor_combined", "vehicle_magnetometer", "vehicle_attitude", "battery_status",
              "actuator_controls_0", "vehicle_thrust_setpoint", "vehicle_gps_position", "sensor_gps",
              "vehicle_global_position")


def px4_cal(values: dict, slot: int, instance: int) -> FirmwareCompassCal:
    """The calibration PX4 stored in CAL_MAG{slot}_* (for the compass ``instance``), with CAL_MAG_COMP_TYP."""
    p = f"CAL_MAG{slot}_"
    names = [p + n for n in ("ID", "ROT", "XOFF", "YOFF", "ZOFF", "XSCALE", "YSCALE", "ZSCALE", "XODIAG", "YODIAG",
                             "ZODIAG", "XCOMP", "YCOMP", "ZCOMP", "PRIO", "EN")]
    names += ["CAL_MAG_COMP_TYP", "SENS_BOARD_ROT"]
    used = {n: values[n] for n in names if n in values}
    scale = [values.get(p + f"{a}SCALE", 1.0) or 1.0 for a in "XYZ"]
    kind = {1: "throttle", 2: "current", 3: "current"}.get(int(values.get("CAL_MAG_COMP_TYP", 0)))
    comp = np.array([values.get(p + f"{a}COMP", 0.0) for a in "XYZ"]) * GAUSS_TO_UT
    if kind == "current":
        comp = comp * KILOAMP_PER_AMP
    rot = values.get(p + "ROT")
    return FirmwareCompassCal(
        firmware="px4", instance=instance,
        offsets_ut=np.array([values.get(p + f"{a}OFF", 0.0) for a in "XYZ"]) * GAUSS_TO_UT,
        matrix=symmetric(scale, [values.get(p + f"{a}ODIAG", 0.0) for a in "XYZ"]), motor=comp, motor_kind=kind,
        orientation=None if rot is None else int(rot), params=used)


def _px4_slot(values: dict, device_id: int | None, instance: int, notes: list) -> int | None:
    """The CAL_MAGn slot whose CAL_MAGn_ID is ``device_id`` (PX4 matches calibrations by device id)."""
    slots = sorted({int(k[7:].split("_")[0]) for k in values if k.startswith("CAL_MAG") and k.endswith("_ID")
                    and k[7:].split("_")[0].isdigit()})
    if device_id:
        for n in slots:
            if int(values.get(f"CAL_MAG{n}_ID", 0)) == device_id:
                return n
        notes.append(f"no CAL_MAGn_ID equals the compass's device id {device_id}: PX4 has no calibration stored for "
                     "it (offsets 0, scale 1)")
        return None
    if instance in slots:
        notes.append(f"the compass's device id is not logged: CAL_MAG{instance}_* taken by its instance number")
        return instance
    return None


def _ds(ulog_file, topic, multi_id=0):
    for d in ulog_file.data_list:
        if d.name == topic and d.multi_id == multi_id:
            return d.data
    return None


def _t(data) -> np.ndarray:
    return np.asarray(data.get("timestamp_sample", data["timestamp"]), dtype=np.int64) * 1e-6


def _px4_rotation(values, cal: FirmwareCompassCal, slot, name, notes) -> np.ndarray:
    rot = cal.orientation
    if rot is None or rot < 0:  # internal: the board's rotation
        board = int(values.get("SENS_BOARD_ROT", 0))
        extra = [values.get(f"SENS_BOARD_{a}_OFF", 0.0) for a in "XYZ"]
        if any(abs(x) > 1e-3 for x in extra):
            notes.append(f"SENS_BOARD_X/Y/Z_OFF are {', '.join(f'{x:.2f}' for x in extra)} degrees: the board's "
                         "rotation includes them")
        # get_board_rotation_matrix (src/lib/conversion/rotation.cpp): the offsets' rotation times SENS_BOARD_ROT's
        return euler_to_c_nb(*extra) @ px4_rotation(board, name, "SENS_BOARD_ROT")
    return px4_rotation(rot, name, f"CAL_MAG{slot}_ROT")


def _px4_power(u, notes):
    current = throttle = None
    bat = _ds(u, "battery_status")
    if bat is not None and "current_a" in bat:
        amps = np.asarray(bat["current_a"], dtype=float)
        if (amps >= 0).any():
            current = (_t(bat), amps, "battery_status.current_a")
        else:  # msg/BatteryStatus.msg: -1 when the current is not measured
            notes.append("battery_status.current_a is −1 throughout (no current sensor): the throttle stands in")
    act = _ds(u, "actuator_controls_0")
    thrust = _ds(u, "vehicle_thrust_setpoint")
    if act is not None and "control[3]" in act:
        throttle = (_t(act), np.asarray(act["control[3]"], dtype=float), "actuator_controls_0.control[3]")
    elif thrust is not None and "xyz[2]" in thrust:
        # FRD thrust setpoint: up is −z, 0..1 of full thrust.
        throttle = (_t(thrust), -np.asarray(thrust["xyz[2]"], dtype=float), "−vehicle_thrust_setpoint.xyz[2]")
    return _power(current, throttle, notes)


def _px4_position(u, notes):
    for topic in ("vehicle_gps_position", "sensor_gps"):
        g = _ds(u, topic)
        if g is None:
            continue
        fix = np.asarray(g.get("fix_type", np.zeros(len(g["timestamp"]))))
        good = np.flatnonzero(fix >= GPS_3D_FIX)
        if not len(good):
            continue
        i = int(good[0])
        if "latitude_deg" in g:  # PX4 ≥ 1.14: degrees and metres as doubles
            lat, lon, alt = (float(g[k][i]) for k in ("latitude_deg", "longitude_deg", "altitude_msl_m"))
        else:  # older: int32 1e-7 degrees, int32 mm
            lat, lon, alt = float(g["lat"][i]) * 1e-7, float(g["lon"][i]) * 1e-7, float(g["alt"][i]) * 1e-3
        utc_us = int(g.get("time_utc_usec", [0] * (i + 1))[i])
        utc = dt.datetime.fromtimestamp(utc_us * 1e-6, dt.timezone.utc) if utc_us > 0 else None
        return lat, lon, alt, utc
    g = _ds(u, "vehicle_global_position")
    if g is not None and "lat" in g and len(g["lat"]):
        notes.append("no GPS fix logged: the place from vehicle_global_position, the date must be given")
        return float(g["lat"][0]), float(g["lon"][0]), float(g["alt"][0]), None
    notes.append("no GPS position in the log: the place and date of the flight must be given")
    return None, None, None, None


def _px4_body_mag(u):
    """``(time_us, gauss, topic, device_id)`` of a calibrated body-frame compass, for logs without sensor_mag:
    sensor_combined's magnetometer_ga (PX4 ≤ 1.8), else vehicle_magnetometer (the selected compass); or None."""
    combined = _ds(u, "sensor_combined")
    found = None if combined is None else ulog.combined_mag(combined)
    if found is not None:
        return found[0], found[1], "sensor_combined.magnetometer_ga", None
    vm = _ds(u, "vehicle_magnetometer")
    if vm is None or "magnetometer_ga[0]" not in vm:
        return None
    device = int(vm["device_id"][-1]) if "device_id" in vm and len(vm["device_id"]) else None
    t = np.asarray(vm.get("timestamp_sample", vm["timestamp"]), dtype=np.int64)
    return t, np.column_stack([vm[f"magnetometer_ga[{k}]"] for k in range(3)]).astype(float), \
        "vehicle_magnetometer", device


def px4_correct(raw_ut, cal: FirmwareCompassCal, rotation, power=None) -> np.ndarray:
    """PX4's ``Magnetometer::Correct``: ``R (S ((m + c p) − o))`` in µT (rows of ``raw_ut``)."""
    m = np.asarray(raw_ut, dtype=float)
    if power is not None and cal.motor_kind is not None:
        m = m + np.outer(power, cal.motor)
    return (m - cal.offsets_ut) @ cal.matrix.T @ np.asarray(rotation).T


def _read_px4(path, mag_instance, name) -> FlightCompassLog:
    from pyulog import ULog  # here: only ULog uploads load it

    said = io.StringIO()
    try:
        with contextlib.redirect_stdout(said):
            u = ULog(str(path), message_name_filter_list=list(PX4_TOPICS), disable_str_exceptions=True)
    except Exception as exc:  # noqa: BLE001 - pyulog raises many kinds on a damaged file
        raise LogFormatError(f"{name} starts as a PX4 ULog but cannot be read ({type(exc).__name__}: {exc}): the "
                             "file is damaged or cut short in its definitions; download the log again") from None
    values = dict(u.initial_parameters)
    notes = []
    raw_mags = sorted(d.multi_id for d in u.data_list if d.name == "sensor_mag" and {"x", "y", "z"} <= set(d.data))
    body = None if raw_mags else _px4_body_mag(u)
    have = raw_mags or ([0] if body is not None else [])
    if not have:
        raise LogFormatError(f"{name} is a PX4 ULog without compass readings (no sensor_mag, no magnetometer_ga in "
                             "sensor_combined, no vehicle_magnetometer): log the compass (SDLOG_PROFILE with 'Sensor "
                             "comparison', or sensor_mag in etc/logging/logger_topics.txt)")
    instance = have[0] if mag_instance is None else int(mag_instance)
    if instance not in have:
        raise LogFormatError(f"{name} has no compass instance {instance}: its compass instances are "
                             f"{', '.join(map(str, have))}; give mag_instance as one of them")
    number = u.msg_info_dict.get("ver_sw_release")
    version = ("PX4 v{}.{}.{}".format(*ulog.release(u), (int(number) >> 8) & 0xFF) if number
               else "PX4 (release not logged)")
    # Before PX4 1.12 the driver (PX4Magnetometer) applied CAL_MAGn offsets and scales itself: sensor_mag is
    # calibrated there; from 1.12 the calibration is the sensors module's (lib/sensor_calibration) and sensor_mag raw.
    sensor_mag_calibrated = ulog.release_before(u, ulog.RAW_SENSORS_FROM)
    p_t, cur, thr, p_source = _px4_power(u, notes)
    if raw_mags:
        d = _ds(u, "sensor_mag", instance)
        time_s = _t(d)
        logged_mag = np.column_stack([d[a] for a in "xyz"]).astype(float) * GAUSS_TO_UT
        device = int(d["device_id"][-1]) if "device_id" in d and len(d["device_id"]) else None
        slot = _px4_slot(values, device, instance, notes)
        generation = f"{version} (sensor_mag{', calibrated' if sensor_mag_calibrated else ''})"
    else:
        t_us, ga, topic, device = body
        time_s = t_us * 1e-6
        device = device or int(values.get("CAL_MAG_PRIME", 0)) or None  # the selected compass
        slot = _px4_slot(values, device, 0, notes) if device else 0
        generation = f"{version} ({topic.split('.')[0]})"
    stored = px4_cal(values, slot, instance) if slot is not None else px4_cal({}, -1, instance)
    rotation = _px4_rotation(values, stored, slot, name, notes)
    power = None
    if stored.motor_kind is not None:
        src = cur if stored.motor_kind == "current" else thr
        if src is None:
            notes.append(f"CAL_MAG_COMP_TYP asks for the {stored.motor_kind}, which the log lacks: no power "
                         "compensation applied")
        else:
            power = np.interp(time_s, p_t, src)
    if raw_mags and not sensor_mag_calibrated:
        raw = logged_mag
        raw_how = "logged raw (sensor_mag, the driver's frame)"
        firmware = px4_correct(raw, stored, rotation, power)
    elif raw_mags:
        raw = np.linalg.solve(stored.matrix, logged_mag.T).T + stored.offsets_ut
        raw_how = (f"read back to raw from sensor_mag (calibrated by the driver before PX4 1.12, its frame) with "
                   f"CAL_MAG{slot}_xOFF/xSCALE: m = S⁻¹ h + o")
        firmware = logged_mag @ rotation.T
    if raw_mags:
        vm = _ds(u, "vehicle_magnetometer")
        # vehicle_magnetometer is the selected compass: its device_id when logged, else CAL_MAG_PRIME names it.
        selected = (int(vm["device_id"][-1]) if vm is not None and "device_id" in vm and len(vm["device_id"])
                    else int(values.get("CAL_MAG_PRIME", 0)) or None)
        how = ("PX4's formula applied to sensor_mag with CAL_MAG{}_*".format(slot) if not sensor_mag_calibrated
               else "sensor_mag turned into the body frame")
        if vm is not None and "magnetometer_ga[0]" in vm and device is not None and selected == device:
            logged = np.column_stack([vm[f"magnetometer_ga[{k}]"] for k in range(3)]) * GAUSS_TO_UT
            vt = _t(vm)
            inside = (time_s >= vt[0]) & (time_s <= vt[-1])
            if inside.sum() >= 2:
                onto = np.column_stack([np.interp(time_s[inside], vt, logged[:, k]) for k in range(3)])
                rms = float(np.sqrt(np.mean(np.sum((onto - firmware[inside]) ** 2, axis=1))))
                notes.append(f"the firmware's field ({how}) differs from the logged vehicle_magnetometer by "
                             f"{rms:.2f} µT rms (the latter filtered, interpolated onto sensor_mag's times)")
        else:
            notes.append(f"the firmware's field: {how} (no vehicle_magnetometer of this compass logged)")
    if not raw_mags:
        firmware = ga * GAUSS_TO_UT
        raw = np.linalg.solve(stored.matrix, (firmware @ rotation).T).T + stored.offsets_ut  # S⁻¹ Rᵀ h + o
        formula = "m = S⁻¹ Rᵀ h + o"
        if power is not None:
            raw = raw - np.outer(power, stored.motor)
            formula += " − c p"
        raw_how = (f"read back to raw from {topic} (logged calibrated, body frame) with CAL_MAG{slot}_* and the "
                   f"rotation: {formula}")
    att = _ds(u, "vehicle_attitude")
    if att is not None and "q[0]" in att:
        att_t = _t(att)
        att_c = quaternion_to_c_nb(np.column_stack([att[f"q[{k}]"] for k in range(4)]))
        att_source = "vehicle_attitude q (w, x, y, z)"
    else:
        att_t = att_c = att_source = None
        notes.append("no vehicle_attitude in the log: the attitude is missing")
    lat, lon, alt, utc = _px4_position(u, notes)
    if u.file_corruption:
        notes.append(f"{name}: pyulog found damaged data in the file and skipped it")
    return FlightCompassLog(
        firmware="px4", generation=generation, instance=instance, time_s=time_s, mag_raw_ut=raw,
        mag_firmware_ut=firmware, raw_how=raw_how, frame_to_body=rotation, stored=stored, attitude_time_s=att_t,
        attitude_c_nb=att_c, attitude_source=att_source, power_time_s=p_t, current_a=cur, throttle=thr,
        power_source=p_source, latitude_deg=lat, longitude_deg=lon, altitude_m=alt, utc=utc, notes=tuple(notes))


def read_flight_compass(path, *, mag_instance: int | None = None, name: str = "the file") -> FlightCompassLog:
    """One compass of a PX4 ULog or ArduPilot DataFlash log, raw, with the flight's context.

    Parameters
    ----------
    path : path-like
    mag_instance : int, optional
        The compass instance (default the first the log has).
    name : str
        How messages name the file.

    Raises
    ------
    LogFormatError
        Not a flight log, a damaged file, no compass, an instance the log lacks, or a message without a field
        trical needs (named).
    """
    with open(path, "rb") as f:
        head = f.read(16)
    if head.startswith(ulog.MAGIC):
        with dataflash.unknown_layout(name, "a PX4 ULog"):
            return _read_px4(path, mag_instance, name)
    if head.startswith(dataflash.MAGIC):
        with dataflash.unknown_layout(name):
            return _read_ardupilot(path, mag_instance, name)
    raise LogFormatError(f"{name} is not a flight controller's log: a compass from a flight reads a PX4 ULog (.ulg) "
                         "or an ArduPilot DataFlash log (.bin)")


CALIBRATION_PREFIXES = ("COMPASS_", "INS_ACC", "INS_GYR", "AHRS_ORIENTATION", "CAL_ACC", "CAL_GYRO", "CAL_MAG",
                        "SENS_BOARD")
"""The parameters holding what a firmware stored of its sensors' calibration (ArduPilot, PX4)."""


def stored_calibration_parameters(path, *, name: str = "the file") -> dict:
    """The sensors' calibration the firmware stored in a flight log's parameters (ArduPilot PARM, PX4's initial
    parameters): COMPASS_*, INS_ACC*/INS_GYR*, CAL_ACC*/CAL_GYRO*/CAL_MAG*, the board's orientation."""
    with open(path, "rb") as f:
        head = f.read(16)
    if head.startswith(ulog.MAGIC):
        from pyulog import ULog

        with contextlib.redirect_stdout(io.StringIO()):
            try:
                values = ULog(str(path), message_name_filter_list=[], disable_str_exceptions=True).initial_parameters
            except Exception as exc:  # noqa: BLE001 - pyulog raises many kinds on a damaged file
                raise LogFormatError(f"{name} starts as a PX4 ULog but cannot be read ({type(exc).__name__}: {exc}): "
                                     "the file is damaged; download the log again") from None
    elif head.startswith(dataflash.MAGIC):
        reader, buf, _ = dataflash.open_log(path, name)
        values = dataflash.params(reader, buf)
    else:
        raise LogFormatError(f"{name} is not a flight controller's log (PX4 .ulg or ArduPilot .bin)")
    return {k: v for k, v in sorted(values.items()) if k.startswith(CALIBRATION_PREFIXES)}
