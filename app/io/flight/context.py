"""A flight log's compass with its context: raw readings, the firmware's stored calibration, attitude,
current or throttle, position and date — what a compass fit from a flight needs.

The readers of the two formats (:mod:`.dataflash`, :mod:`.ulog`) give the tables; this
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
  (:data:`.ardupilot.ARDUPILOT_MOTOR_AFTER_MATRIX`); with DIA/ODI the identity or no motor offset both orders are
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

Each firmware's part is its own module (:mod:`.ardupilot`, :mod:`.px4`); this one holds what they share, and
:func:`.compass.read_flight_compass` reads a log by its firmware's part.

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

from ..errors import LogFormatError
from . import dataflash, ulog

MILLIGAUSS_TO_UT = dataflash.MILLIGAUSS_TO_UT
GAUSS_TO_UT = ulog.GAUSS_TO_UT
GPS_EPOCH = dt.datetime(1980, 1, 6, tzinfo=dt.UTC)
LEAP_SECONDS = (
    (dt.datetime(2017, 1, 1, tzinfo=dt.UTC), 18),
    (dt.datetime(2015, 7, 1, tzinfo=dt.UTC), 17),
    (dt.datetime(2012, 7, 1, tzinfo=dt.UTC), 16),
    (dt.datetime(2009, 1, 1, tzinfo=dt.UTC), 15),
    (dt.datetime(2006, 1, 1, tzinfo=dt.UTC), 14),
)
"""GPS time minus UTC from each date on (IERS Bulletin C; GPS time has no leap seconds)."""
GPS_3D_FIX = 3
"""ArduPilot's GPS Status and PX4's fix_type both number a 3-D fix 3 (AP_GPS::GPS_OK_FIX_3D, msg/SensorGps.msg)."""


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
    switch : str or None
        The parameter that has the firmware use this compass (ArduPilot COMPASS_USEn, PX4 CAL_MAGn_PRIO or,
        before 1.12, CAL_MAGn_EN); None where the log stores no calibration slot for it.
    external : bool or None
        Whether the firmware takes it for an external compass (ArduPilot COMPASS_EXTERNAL, _EXTERN2, _EXTERN3
        non-zero; PX4 a CAL_MAGn_ROT of its own, −1 meaning internal); None where the log does not say.
    """

    firmware: str
    instance: int
    offsets_ut: np.ndarray
    matrix: np.ndarray
    motor: np.ndarray
    motor_kind: str | None
    orientation: int | None
    params: dict
    switch: str | None = None
    external: bool | None = None

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


def one_power_clock(current, throttle, notes: list):
    """One clock for the current and the throttle: the times of the one logged more often, the other
    interpolated linearly onto them (PX4 logs battery_status at about 1 Hz, the controls far faster).

    ``current`` and ``throttle`` are ``(time_s, values, source words)`` or None; returns ``(time_s, current_a,
    throttle, source words)``, all None (and a note) when the log has neither."""
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


CALIBRATION_PREFIXES = (
    "COMPASS_",
    "INS_ACC",
    "INS_GYR",
    "AHRS_ORIENTATION",
    "CAL_ACC",
    "CAL_GYRO",
    "CAL_MAG",
    "SENS_BOARD",
)
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
            except Exception as exc:  # pyulog raises many kinds on a damaged file
                raise LogFormatError(
                    f"{name} starts as a PX4 ULog but cannot be read ({type(exc).__name__}: {exc}): "
                    "the file is damaged; download the log again"
                ) from None
    elif head.startswith(dataflash.MAGIC):
        reader, buf, _ = dataflash.open_log(path, name)
        values = dataflash.params(reader, buf)
    else:
        raise LogFormatError(f"{name} is not a flight controller's log (PX4 .ulg or ArduPilot .bin)")
    return {k: v for k, v in sorted(values.items()) if k.startswith(CALIBRATION_PREFIXES)}
