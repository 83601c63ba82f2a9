"""PX4's part of :mod:`.context`: a ULog's compass (sensor_mag, or read back from sensor_combined or
vehicle_magnetometer), its stored calibration (CAL_MAGn_* matched by device id), attitude (vehicle_attitude),
current (battery_status), throttle (actuator_controls_0, vehicle_thrust_setpoint) and first GPS fix.
The formulas and the generations are in :mod:`.context`'s docstring."""

from __future__ import annotations

import datetime as dt

import numpy as np

from app.calibration.shared.rotations import PX4_EVERY_RELEASE, PX4_ROTATIONS, px4_matrix

from ..errors import LogFormatError
from . import ulog
from .context import (
    GAUSS_TO_UT,
    GPS_3D_FIX,
    FirmwareCompassCal,
    FlightCompassLog,
    euler_to_c_nb,
    one_power_clock,
    quaternion_to_c_nb,
    symmetric,
)

KILOAMP_PER_AMP = 1e-3
"""PX4's CAL_MAGn_xCOMP are per kA of battery current (src/modules/sensors/vehicle_magnetometer: current_a * 0.001)."""


def px4_rotation(number: int, name: str, what: str) -> np.ndarray:
    """PX4's rotation ``number`` as a matrix (rotation.cpp get_rot_matrix), one of the entries every PX4 release
    shares (:data:`app.calibration.shared.rotations.PX4_EVERY_RELEASE`); a later entry is refused by name."""
    if not 0 <= number <= PX4_EVERY_RELEASE:
        last = PX4_ROTATIONS[PX4_EVERY_RELEASE][0]
        raise LogFormatError(
            f"{name}: {what} is {number}, a rotation of PX4's list past ROTATION_{last} "
            f"({PX4_EVERY_RELEASE}) that trical does not hold; set it to one of 0–{PX4_EVERY_RELEASE} "
            "or leave the compass internal"
        )
    return px4_matrix(number)


PX4_TOPICS = ("sensor_mag", "sensor_combined", "vehicle_magnetometer") + ulog.CONTEXT_TOPICS
"""The topics the compass from a flight reads: the compass's and the flight's context."""


def px4_cal(values: dict, slot: int, instance: int) -> FirmwareCompassCal:
    """The calibration PX4 stored in CAL_MAG{slot}_* (for the compass ``instance``), with CAL_MAG_COMP_TYP."""
    p = f"CAL_MAG{slot}_"
    names = [
        p + n
        for n in (
            "ID",
            "ROT",
            "XOFF",
            "YOFF",
            "ZOFF",
            "XSCALE",
            "YSCALE",
            "ZSCALE",
            "XODIAG",
            "YODIAG",
            "ZODIAG",
            "XCOMP",
            "YCOMP",
            "ZCOMP",
            "PRIO",
            "EN",
        )
    ]
    names += ["CAL_MAG_COMP_TYP", "SENS_BOARD_ROT"]
    used = {n: values[n] for n in names if n in values}
    scale = [values.get(p + f"{a}SCALE", 1.0) or 1.0 for a in "XYZ"]
    kind = {1: "throttle", 2: "current", 3: "current"}.get(int(values.get("CAL_MAG_COMP_TYP", 0)))
    comp = np.array([values.get(p + f"{a}COMP", 0.0) for a in "XYZ"]) * GAUSS_TO_UT
    if kind == "current":
        comp = comp * KILOAMP_PER_AMP
    rot = values.get(p + "ROT")
    return FirmwareCompassCal(
        firmware="px4",
        instance=instance,
        offsets_ut=np.array([values.get(p + f"{a}OFF", 0.0) for a in "XYZ"]) * GAUSS_TO_UT,
        matrix=symmetric(scale, [values.get(p + f"{a}ODIAG", 0.0) for a in "XYZ"]),
        motor=comp,
        motor_kind=kind,
        orientation=None if rot is None else int(rot),
        params=used,
        # 1.12 on a priority, 0 disabling it; before, CAL_MAGn_EN; neither in the log: not said
        switch=next((p + k for k in ("PRIO", "EN") if slot >= 0 and p + k in values), None),
        external=None if rot is None else int(rot) >= 0,  # CAL_MAGn_ROT −1: internal, the board's rotation
    )


def _px4_slot(values: dict, device_id: int | None, instance: int, notes: list) -> int | None:
    """The CAL_MAGn slot whose CAL_MAGn_ID is ``device_id`` (PX4 matches calibrations by device id)."""
    slots = sorted(
        {
            int(k[7:].split("_")[0])
            for k in values
            if k.startswith("CAL_MAG") and k.endswith("_ID") and k[7:].split("_")[0].isdigit()
        }
    )
    if device_id:
        for n in slots:
            if int(values.get(f"CAL_MAG{n}_ID", 0)) == device_id:
                return n
        notes.append(
            f"no CAL_MAGn_ID equals the compass's device id {device_id}: PX4 has no calibration stored for "
            "it (offsets 0, scale 1)"
        )
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
            notes.append(
                f"SENS_BOARD_X/Y/Z_OFF are {', '.join(f'{x:.2f}' for x in extra)} degrees: the board's "
                "rotation includes them"
            )
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
    return one_power_clock(current, throttle, notes)


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
        utc = dt.datetime.fromtimestamp(utc_us * 1e-6, dt.UTC) if utc_us > 0 else None
        return lat, lon, alt, utc
    g = _ds(u, "vehicle_global_position")
    if g is not None and "lat" in g and len(g["lat"]):
        notes.append("no GPS fix logged: the place from vehicle_global_position, the date must be given")
        return float(g["lat"][0]), float(g["lon"][0]), float(g["alt"][0]), None
    notes.append("no GPS position in the log: the place and date of the flight must be given")
    return None, None, None, None


def _px4_body_instances(u) -> list[int]:
    """The instances of a calibrated body-frame compass, for logs without sensor_mag: sensor_combined's (PX4 ≤
    1.8, instance 0), else each vehicle_magnetometer ``multi_id`` (as :mod:`app.io.flight.ulog` lists them)."""
    combined = _ds(u, "sensor_combined")
    if combined is not None and ulog.combined_mag(combined) is not None:
        return [0]
    return sorted(
        d.multi_id for d in u.data_list if d.name == "vehicle_magnetometer" and "magnetometer_ga[0]" in d.data
    )


def _px4_body_mag(u, instance: int = 0):
    """``(time_us, gauss, topic, device_id)`` of a calibrated body-frame compass, for logs without sensor_mag:
    sensor_combined's magnetometer_ga (PX4 ≤ 1.8), else vehicle_magnetometer's ``instance``; or None."""
    combined = _ds(u, "sensor_combined")
    found = None if combined is None else ulog.combined_mag(combined)
    if found is not None:
        return found[0], found[1], "sensor_combined.magnetometer_ga", None
    vm = _ds(u, "vehicle_magnetometer", instance)
    if vm is None or "magnetometer_ga[0]" not in vm:
        return None
    device = int(vm["device_id"][-1]) if "device_id" in vm and len(vm["device_id"]) else None
    t = np.asarray(vm.get("timestamp_sample", vm["timestamp"]), dtype=np.int64)
    return (
        t,
        np.column_stack([vm[f"magnetometer_ga[{k}]"] for k in range(3)]).astype(float),
        "vehicle_magnetometer",
        device,
    )


def px4_correct(raw_ut, cal: FirmwareCompassCal, rotation, power=None) -> np.ndarray:
    """PX4's ``Magnetometer::Correct``: ``R (S ((m + c p) − o))`` in µT (rows of ``raw_ut``)."""
    m = np.asarray(raw_ut, dtype=float)
    if power is not None and cal.motor_kind is not None:
        m = m + np.outer(power, cal.motor)
    return (m - cal.offsets_ut) @ cal.matrix.T @ np.asarray(rotation).T


def _open_ulog(path, name):
    """The ULog parsed (:func:`app.io.flight.ulog.open_ulog`, pyulog's printing kept off the output); a file pyulog
    cannot read is refused."""
    return ulog.open_ulog(path, name, "download the log again")[0]


def _px4_power_at(stored: FirmwareCompassCal, cur, thr, p_t, time_s, notes: list) -> np.ndarray | None:
    """The power the stored motor compensation asks for (current or throttle) on the compass's times, or None
    (no compensation, or the log lacks it: a note says so)."""
    if stored.motor_kind is None:
        return None
    src = cur if stored.motor_kind == "current" else thr
    if src is None:
        notes.append(
            f"CAL_MAG_COMP_TYP asks for the {stored.motor_kind}, which the log lacks: no power compensation applied"
        )
        return None
    return np.interp(time_s, p_t, src)


def _compare_vehicle_magnetometer(u, values, time_s, firmware, device, how: str, notes: list) -> None:
    """A note on the firmware's field computed from sensor_mag against the logged vehicle_magnetometer, when
    that is this compass (its rms difference), else that it was not logged."""
    vm = _ds(u, "vehicle_magnetometer")
    # vehicle_magnetometer is the selected compass: its device_id when logged, else CAL_MAG_PRIME names it.
    selected = (
        int(vm["device_id"][-1])
        if vm is not None and "device_id" in vm and len(vm["device_id"])
        else int(values.get("CAL_MAG_PRIME", 0)) or None
    )
    if vm is not None and "magnetometer_ga[0]" in vm and device is not None and selected == device:
        logged = np.column_stack([vm[f"magnetometer_ga[{k}]"] for k in range(3)]) * GAUSS_TO_UT
        vt = _t(vm)
        inside = (time_s >= vt[0]) & (time_s <= vt[-1])
        if inside.sum() >= 2:
            onto = np.column_stack([np.interp(time_s[inside], vt, logged[:, k]) for k in range(3)])
            rms = float(np.sqrt(np.mean(np.sum((onto - firmware[inside]) ** 2, axis=1))))
            notes.append(
                f"the firmware's field ({how}) differs from the logged vehicle_magnetometer by "
                f"{rms:.2f} µT rms (the latter filtered, interpolated onto sensor_mag's times)"
            )
    else:
        notes.append(f"the firmware's field: {how} (no vehicle_magnetometer of this compass logged)")


def _px4_attitude(u, notes: list):
    """``(time_s, C_nb, source)`` of vehicle_attitude's quaternion, or three None (a note says so)."""
    att = _ds(u, "vehicle_attitude")
    if att is not None and "q[0]" in att:
        return (
            _t(att),
            quaternion_to_c_nb(np.column_stack([att[f"q[{k}]"] for k in range(4)])),
            "vehicle_attitude q (w, x, y, z)",
        )
    notes.append("no vehicle_attitude in the log: the attitude is missing")
    return None, None, None


def read_px4(path, mag_instance, name, attitude: str | None = None) -> FlightCompassLog:
    if attitude not in (None, "vehicle_attitude"):
        raise LogFormatError(
            f"attitude {attitude!r}: a PX4 log's attitude is vehicle_attitude (give attitude as that, or leave it out)"
        )
    u = _open_ulog(path, name)
    values = dict(u.initial_parameters)
    notes: list[str] = []
    raw_mags = sorted(d.multi_id for d in u.data_list if d.name == "sensor_mag" and {"x", "y", "z"} <= set(d.data))
    have = raw_mags or _px4_body_instances(u)
    if not have:
        raise LogFormatError(
            f"{name} is a PX4 ULog without compass readings (no sensor_mag, no magnetometer_ga in "
            "sensor_combined, no vehicle_magnetometer): log the compass (SDLOG_PROFILE with 'Sensor "
            "comparison', or sensor_mag in etc/logging/logger_topics.txt)"
        )
    instance = have[0] if mag_instance is None else int(mag_instance)
    if instance not in have:
        raise LogFormatError(
            f"{name} has no compass instance {instance}: its compass instances are "
            f"{', '.join(map(str, have))}; give mag_instance as one of them"
        )
    number, release = u.msg_info_dict.get("ver_sw_release"), ulog.release(u)  # release: None exactly without number
    version = "PX4 v{}.{}.{}".format(*release, (int(number) >> 8) & 0xFF) if release else "PX4 (release not logged)"
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
        body = _px4_body_mag(u, instance)
        assert body is not None, "have holds an instance: sensor_mag's or the body's"
        t_us, ga, topic, device = body
        time_s = t_us * 1e-6
        device = device or int(values.get("CAL_MAG_PRIME", 0)) or None  # the selected compass
        slot = _px4_slot(values, device, 0, notes) if device else 0
        generation = f"{version} ({topic.split('.')[0]})"
    stored = px4_cal(values, slot, instance) if slot is not None else px4_cal({}, -1, instance)
    rotation = _px4_rotation(values, stored, slot, name, notes)
    power = _px4_power_at(stored, cur, thr, p_t, time_s, notes)
    if raw_mags and not sensor_mag_calibrated:
        raw = logged_mag
        raw_how = "logged raw (sensor_mag, the driver's frame)"
        firmware = px4_correct(raw, stored, rotation, power)
    elif raw_mags:
        raw = np.linalg.solve(stored.matrix, logged_mag.T).T + stored.offsets_ut
        raw_how = (
            f"read back to raw from sensor_mag (calibrated by the driver before PX4 1.12, its frame) with "
            f"CAL_MAG{slot}_xOFF/xSCALE: m = S⁻¹ h + o"
        )
        firmware = logged_mag @ rotation.T
    if raw_mags:
        how = (
            f"PX4's formula applied to sensor_mag with CAL_MAG{slot}_*"
            if not sensor_mag_calibrated
            else "sensor_mag turned into the body frame"
        )
        _compare_vehicle_magnetometer(u, values, time_s, firmware, device, how, notes)
    if not raw_mags:
        firmware = ga * GAUSS_TO_UT
        raw = np.linalg.solve(stored.matrix, (firmware @ rotation).T).T + stored.offsets_ut  # S⁻¹ Rᵀ h + o
        formula = "m = S⁻¹ Rᵀ h + o"
        if power is not None:
            raw = raw - np.outer(power, stored.motor)
            formula += " − c p"
        raw_how = (
            f"read back to raw from {topic} (logged calibrated, body frame) with CAL_MAG{slot}_* and the "
            f"rotation: {formula}"
        )
    att_t, att_c, att_source = _px4_attitude(u, notes)
    lat, lon, alt, utc = _px4_position(u, notes)
    if u.file_corruption:
        notes.append(f"{name}: pyulog found damaged data in the file and skipped it")
    return FlightCompassLog(
        firmware="px4",
        generation=generation,
        instance=instance,
        time_s=time_s,
        mag_raw_ut=raw,
        mag_firmware_ut=firmware,
        raw_how=raw_how,
        frame_to_body=rotation,
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
