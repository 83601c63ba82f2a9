"""The exports of a compass calibrated from a flight (method ``compass_flight``): each firmware's own formula,
written here from its source and not from app/, applied with the numbers parsed back from the export's text
to raw readings, gives trical's ``h_body = M (Q m_L − b − k p)`` to 1e-4 µT — also when the stored orientation
is wrong and the export sets a new one; and what the firmware would refuse is refused with words.

ArduPilot, libraries/AP_Compass/AP_Compass_Backend.cpp: ``rotate_field`` turns the sensor's field by
``COMPASS_ORIENTn`` (an external compass; ``Vector3::rotate`` in libraries/AP_Math/vector3.cpp), then
``correct_field`` in milligauss: ``mag += offsets; mag *= scale_factor; mag = mat * mag; mag += mot * p``.
PX4, src/lib/sensor_calibration/Magnetometer.hpp ``Correct``: ``_rotation * (_scale * ((data + _power *
_power_compensation) - _offset))`` in gauss, ``_rotation = Dcmf(Eulerf(rot_lookup[ROT]))`` (src/lib/conversion),
power the throttle or ``current_a * 0.001`` (kA, VehicleMagnetometer::UpdatePowerCompensation).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from pymavlink import mavutil
from pyulog import ULog
from scipy.spatial.transform import Rotation

from app.io.errors import ExportError
from app.io.exports.compass import FLIGHT_COMPASS_EXPORTS, export_flight_compass
from app.io.exports.exporters import export_calibration

EYE = np.eye(3)

# ArduPilot's Vector3::rotate, case by case (libraries/AP_Math/vector3.cpp), for the entries used here
AP_ROTATE = {
    0: lambda x, y, z: (x, y, z),
    2: lambda x, y, z: (-y, x, z),  # ROTATION_YAW_90: tmp = x; x = -y; y = tmp
    4: lambda x, y, z: (-x, -y, z),  # ROTATION_YAW_180: x = -x; y = -y
    6: lambda x, y, z: (y, -x, z),  # ROTATION_YAW_270: tmp = x; x = y; y = -tmp
    8: lambda x, y, z: (x, -y, -z),  # ROTATION_ROLL_180
    10: lambda x, y, z: (y, x, -z),  # ROTATION_ROLL_180_YAW_90: tmp = x; x = y; y = tmp; z = -z
    12: lambda x, y, z: (-x, y, -z),  # ROTATION_PITCH_180
    16: lambda x, y, z: (x, -z, y),  # ROTATION_ROLL_90: tmp = z; z = y; y = -tmp
    24: lambda x, y, z: (z, y, -x),  # ROTATION_PITCH_90: tmp = z; z = -x; x = tmp
}
# PX4's rot_lookup (roll, pitch, yaw in degrees, src/lib/conversion/rotation.h), for the entries used here
PX4_LOOKUP = {0: (0, 0, 0), 2: (0, 0, 90), 6: (0, 0, 270), 8: (180, 0, 0), 12: (0, 180, 0)}

YAW_90 = np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])
ROLL_180 = np.diag([1.0, -1, -1])


def ap_rotate(number: int, v: np.ndarray) -> np.ndarray:
    return np.array([AP_ROTATE[number](*row) for row in v])


def px4_rotation(number: int) -> np.ndarray:
    roll, pitch, yaw = PX4_LOOKUP[number]
    return Rotation.from_euler("ZYX", [yaw, pitch, roll], degrees=True).as_matrix()


def soft_iron(rng, scale=0.06) -> np.ndarray:
    a = rng.normal(scale=scale, size=(3, 3))
    return np.eye(3) + (a + a.T) / 2


def flight_body(
    firmware="ardupilot",
    *,
    Q=EYE,
    M=EYE,
    b=(12.0, -20.0, 31.0),
    k=(0.4, -0.3, 0.6),
    motor="current",
    instance=0,
    orientation=0,
    params=None,
    frame_to_body=EYE,
    ok=True,
) -> dict:
    return {
        "id": "cal_flight",
        "method": "compass_flight",
        "created_at": "2026-12-04T07:00:00Z",
        "ok": ok,
        "reasons": [] if ok else ["the heading error grew on segments left out"],
        "unit": "uT",
        "model": {
            "type": "compass_flight",
            "M": np.asarray(M).tolist(),
            "b": list(b),
            "k": list(k),
            "Q": np.asarray(Q).tolist(),
        },
        "metrics": {
            "heading_error_before_deg": 7.1,
            "heading_error_before_p95_deg": 12.0,
            "heading_error_after_deg": 1.2,
            "heading_error_after_p95_deg": 2.4,
        },
        "flight": {
            "firmware": firmware,
            "instance": instance,
            "structure": "soft_iron",
            "motor": motor,
            "rotation_nearest": {"ardupilot": 0, "px4": 0, "name": "None"},
            "orientation_agrees": bool(np.allclose(Q, frame_to_body)),
            "frame_to_body": np.asarray(frame_to_body).tolist(),
            "stored": {
                "firmware": firmware,
                "instance": instance,
                "offsets_ut": [0, 0, 0],
                "matrix": np.eye(3).tolist(),
                "motor": [0, 0, 0],
                "motor_kind": None,
                "orientation": orientation,
                "params": params or {},
            },
        },
    }


def trical(body: dict, m_L: np.ndarray, p: np.ndarray) -> np.ndarray:
    Q, M = np.array(body["model"]["Q"]), np.array(body["model"]["M"])
    b, k = np.array(body["model"]["b"]), np.array(body["model"]["k"]) * (body["flight"]["motor"] is not None)
    return (M @ (m_L @ Q.T - b - np.outer(p, k)).T).T


def parse_ardupilot(text: str) -> dict[str, float]:
    return {name: float(v) for name, v in (line.split() for line in text.splitlines() if line and line[0] != "#")}


def parse_px4(text: str) -> dict[str, float]:
    out = {}
    for line in text.splitlines():
        if line.startswith("param set "):
            _, _, name, value = line.split()
            out[name] = float(value)
    return out


def ardupilot_correct(
    params: dict, instance: int, stored_orient: int, sensor_ut: np.ndarray, p: np.ndarray, motct: int
) -> np.ndarray:
    """AP_Compass_Backend::rotate_field then correct_field, with the export's parameters; µT in, µT out."""
    s = "" if instance == 0 else str(instance + 1)

    def v(g):
        return np.array([params[f"COMPASS_{g}{s}_{a}"] for a in "XYZ"])

    orient = int(params.get(f"COMPASS_ORIENT{s}", stored_orient))
    mag = ap_rotate(orient, sensor_ut) * 10.0  # milligauss
    mag = mag + v("OFS")
    mag = mag * params[f"COMPASS_SCALE{s}"]
    dia, odi = v("DIA"), v("ODI")
    mat = np.array([[dia[0], odi[0], odi[1]], [odi[0], dia[1], odi[2]], [odi[1], odi[2], dia[2]]])
    mag = mag @ mat.T
    assert params.get("COMPASS_MOTCT", motct) == motct
    mag = mag + np.outer(p, v("MOT"))
    return mag / 10.0


def px4_level(params: dict) -> np.ndarray:
    """GetSensorLevelAdjustment: Eulerf(radians(SENS_BOARD_X_OFF), radians(Y_OFF), radians(Z_OFF))."""
    roll, pitch, yaw = (params.get(f"SENS_BOARD_{a}_OFF", 0.0) for a in "XYZ")
    return Rotation.from_euler("ZYX", [yaw, pitch, roll], degrees=True).as_matrix()


def px4_correct(
    params: dict, slot: int, stored_rot: int, sensor_ut: np.ndarray, power: np.ndarray, level: np.ndarray = EYE
) -> np.ndarray:
    """Magnetometer::Correct with the export's parameters; µT in, µT out; power already in PX4's unit;
    ``_rotation = level adjustment * get_rot_matrix(ROT)`` (Magnetometer::set_rotation)."""

    def c(g):
        return np.array([params[f"CAL_MAG{slot}_{a}{g}"] for a in "XYZ"])

    R = level @ px4_rotation(int(params.get(f"CAL_MAG{slot}_ROT", stored_rot)))
    d, o = c("SCALE"), c("ODIAG")
    S = np.array([[d[0], o[0], o[1]], [o[0], d[1], o[2]], [o[1], o[2], d[2]]])
    data = sensor_ut / 100.0  # gauss
    corrected = ((data + np.outer(power, c("COMP")) - c("OFF")) @ S.T) @ R.T
    return corrected * 100.0


@pytest.fixture
def rng():
    return np.random.default_rng(32)


def readings(rng, n=200):
    return rng.normal(scale=35.0, size=(n, 3)), rng.uniform(0.0, 40.0, size=n)


# -- ArduPilot ----------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("motor, motct", [("current", 2), ("throttle", 1), (None, 0)])
def test_ardupilot_formula_reproduces_tricals_correction(rng, motor, motct):
    body = flight_body(M=soft_iron(rng), motor=motor, params={"COMPASS_EXTERNAL": 1})
    sensor, p = readings(rng)
    if motor == "throttle":
        p = rng.uniform(0.0, 1.0, size=len(p))
    text = export_flight_compass(body, "ardupilot").content
    params = parse_ardupilot(text)
    assert "COMPASS_ORIENT" not in params
    assert ("COMPASS_MOTCT" in params) == (motor is not None)
    h = ardupilot_correct(params, 0, 0, sensor, p, motct if motor else 0)
    assert np.abs(h - trical(body, sensor, p)).max() < 1e-4


def test_ardupilot_wrong_orientation_is_replaced_and_still_reproduces(rng):
    # stored COMPASS_ORIENT 8 (Roll180); the compass is in fact at Roll180Yaw90 (10): the flight shows Q = Yaw90
    body = flight_body(Q=YAW_90, M=soft_iron(rng), orientation=8, params={"COMPASS_EXTERNAL": 1})
    sensor, p = readings(rng)
    m_L = ap_rotate(8, sensor)  # what the log holds: the field turned by the stored orientation
    params = parse_ardupilot(export_flight_compass(body, "ardupilot").content)
    assert params["COMPASS_ORIENT"] == 10
    h = ardupilot_correct(params, 0, 8, sensor, p, 2)
    assert np.abs(h - trical(body, m_L, p)).max() < 1e-4


def test_ardupilot_second_compass_uses_its_own_names(rng):
    body = flight_body(
        Q=YAW_90 @ YAW_90,
        M=soft_iron(rng),
        instance=1,
        orientation=0,
        params={"COMPASS_EXTERN2": 1, "COMPASS_MOTCT": 1},
    )
    sensor, p = readings(rng)
    text = export_flight_compass(body, "ardupilot").content
    params = parse_ardupilot(text)
    assert {"COMPASS_OFS2_X", "COMPASS_DIA2_Z", "COMPASS_ODI2_Y", "COMPASS_MOT2_X", "COMPASS_SCALE2"} <= set(params)
    assert params["COMPASS_ORIENT2"] == 4  # Yaw180
    assert not any(name.startswith(("COMPASS_OFS_", "COMPASS_DIA_")) for name in params)
    assert "it was 1" in text  # the other compasses' COMPASS_MOT were fitted against throttle
    h = ardupilot_correct(params, 1, 0, sensor, p, 2)
    assert np.abs(h - trical(body, sensor, p)).max() < 1e-4


def test_ardupilot_per_motor_compensation_is_turned_off_for_the_first_compass(rng):
    body = flight_body(params={"COMPASS_PMOT_EN": 1, "COMPASS_EXTERNAL": 1})
    assert parse_ardupilot(export_flight_compass(body, "ardupilot").content)["COMPASS_PMOT_EN"] == 0


def test_ardupilot_internal_compass_with_right_orientation_exports(rng):
    body = flight_body(M=soft_iron(rng), orientation=0, params={"COMPASS_EXTERNAL": 0, "AHRS_ORIENTATION": 0})
    assert "COMPASS_ORIENT" not in parse_ardupilot(export_flight_compass(body, "ardupilot").content)


@pytest.mark.parametrize(
    "change, words",
    [
        ({"b": (200.0, 0.0, 0.0)}, "COMPASS_OFFS_MAX"),
        ({"M": np.diag([6.0, 1.0, 1.0])}, "COMPASS_DIA_X = 6"),
        ({"M": [[2.0, 1.2, 0.0], [1.2, 2.0, 0.0], [0.0, 0.0, 2.0]]}, "COMPASS_ODI_X = 1.2"),
        ({"k": (150.0, 0.0, 0.0)}, "COMPASS_MOT_X = -1500"),
        ({"ok": False}, "failed its checks"),
        ({"params": {"COMPASS_EXTERNAL": 0}, "Q": YAW_90}, "AHRS_ORIENTATION"),
        ({"Q": Rotation.from_euler("z", 20, degrees=True).as_matrix()}, "cannot hold it"),
        ({"Q": 2 * np.eye(3)}, "not a rotation"),
        ({"M": [[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]}, "not symmetric"),
    ],
)
def test_ardupilot_refuses_what_ardupilot_would_refuse(change, words):
    with pytest.raises(ExportError, match=words):
        export_flight_compass(flight_body(**change), "ardupilot")


# -- PX4 ----------------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("motor", ["current", "throttle"])
def test_px4_formula_reproduces_tricals_correction(rng, motor):
    # an external compass at Roll180 (CAL_MAG1_ROT 8), slot 1, rotation agreeing with the flight
    R = px4_rotation(8)
    body = flight_body(
        "px4",
        Q=R,
        frame_to_body=R,
        M=soft_iron(rng),
        motor=motor,
        orientation=8,
        params={"CAL_MAG1_ID": 396825, "CAL_MAG1_ROT": 8},
    )
    sensor, p = readings(rng)
    if motor == "throttle":
        p = rng.uniform(0.0, 1.0, size=len(p))
    params = parse_px4(export_flight_compass(body, "px4").content)
    assert "CAL_MAG1_ROT" not in params
    assert params["CAL_MAG_COMP_TYP"] == {"throttle": 1, "current": 2}[motor]
    power = p * 0.001 if motor == "current" else p  # PX4's power: current_a * 0.001 (kA), or the throttle
    h = px4_correct(params, 1, 8, sensor, power)
    assert np.abs(h - trical(body, sensor, p)).max() < 1e-4


def test_px4_wrong_rotation_is_replaced_and_still_reproduces(rng):
    # stored CAL_MAG0_ROT 0; the flight shows the compass at Yaw270 (6)
    Q = px4_rotation(6)
    body = flight_body(
        "px4",
        Q=Q,
        frame_to_body=np.eye(3),
        M=soft_iron(rng),
        orientation=0,
        params={"CAL_MAG0_ID": 12345, "CAL_MAG0_ROT": 0, "CAL_MAG_COMP_TYP": 3},
    )
    sensor, p = readings(rng)
    params = parse_px4(export_flight_compass(body, "px4").content)
    assert params["CAL_MAG0_ROT"] == 6
    assert params["CAL_MAG_COMP_TYP"] == 3  # the log's battery instance 1 kept
    h = px4_correct(params, 0, 0, sensor, p * 0.001)
    assert np.abs(h - trical(body, sensor, p)).max() < 1e-4


@pytest.mark.parametrize(
    "change, words",
    [
        ({"M": np.diag([4.0, 1.0, 1.0])}, "CAL_MAG2_XSCALE = 4"),
        ({"ok": False}, "failed its checks"),
        ({"params": {"CAL_MAG2_ROT": -1, "CAL_MAG2_ID": 7}, "Q": YAW_90}, "SENS_BOARD_ROT"),
        ({"params": {}}, "which CAL_MAGn slot"),
        ({"firmware": "ardupilot"}, "ArduPilot log"),
    ],
)
def test_px4_refuses_what_px4_would_refuse(change, words):
    kwargs = {"params": {"CAL_MAG2_ID": 7, "CAL_MAG2_ROT": 0}, **change}
    with pytest.raises(ExportError, match=words):
        export_flight_compass(flight_body(kwargs.pop("firmware", "px4"), **kwargs), "px4")


# -- the firmware's own calibration, stored in real logs ----------------------------------------------------------
# A body whose model is the calibration the firmware stored exports the stored parameters themselves.

REAL = Path(__file__).resolve().parents[1] / "data" / "flight_logs"  # see tests/data/README.md


def dataflash_params(path: Path) -> dict[str, float]:
    log = mavutil.mavlink_connection(str(path))
    out = {}
    while (msg := log.recv_match(type="PARM")) is not None:
        out[msg.Name] = float(msg.Value)
    return out


@pytest.mark.parametrize("instance", [0, 1, 2])
def test_ardupilot_export_of_the_stored_calibration_is_the_stored_parameters(instance):
    params = {k: v for k, v in dataflash_params(REAL / "test.BIN").items() if k.startswith(("COMPASS_", "AHRS_"))}
    s = "" if instance == 0 else str(instance + 1)

    def v(g):
        return np.array([params[f"COMPASS_{g}{s}_{a}"] for a in "XYZ"])

    dia, odi = v("DIA"), v("ODI")
    M = np.array([[dia[0], odi[0], odi[1]], [odi[0], dia[1], odi[2]], [odi[1], odi[2], dia[2]]])
    body = flight_body(
        M=M,
        b=-0.1 * v("OFS"),
        motor=None,
        instance=instance,
        orientation=int(params[f"COMPASS_ORIENT{s}"]),
        params=params,
    )
    out = parse_ardupilot(export_flight_compass(body, "ardupilot").content)
    for name in (f"COMPASS_{g}{s}_{a}" for g in ("OFS", "DIA", "ODI") for a in "XYZ"):
        assert out[name] == pytest.approx(params[name], rel=1e-6, abs=1e-7), name
    assert f"COMPASS_ORIENT{s}" not in out  # AHRS_ORIENTATION 8 for the internal ones, 0 for the external: kept
    with pytest.raises(ExportError, match="COMPASS_OFFS_MAX 850"):  # this log's own limit, not the default 1800
        export_flight_compass(dict(body, model={**body["model"], "b": [90.0, 0.0, 0.0]}), "ardupilot")


def test_px4_export_of_the_stored_calibration_is_the_stored_parameters(rng):
    params = {
        k: v
        for k, v in ULog(str(REAL / "sample_log_small.ulg")).initial_parameters.items()
        if k.startswith(("CAL_MAG", "SENS_BOARD"))
    }

    def c(g):
        return np.array([params[f"CAL_MAG1_{a}{g}"] for a in "XYZ"])  # slot 1: the external compass

    level = px4_level(params)  # SENS_BOARD_X_OFF 0.76, Y_OFF -2.94 degrees in this log
    R = level @ px4_rotation(int(params["CAL_MAG1_ROT"]))
    S, off = np.diag(c("SCALE")), 100.0 * c("OFF")
    body = flight_body("px4", Q=R, frame_to_body=R, M=R @ S @ R.T, b=R @ off, motor=None, params=params)
    body["flight"]["stored"]["offsets_ut"] = off.tolist()  # picks CAL_MAG1 among the log's four slots
    out = parse_px4(export_flight_compass(body, "px4").content)
    for name in (f"CAL_MAG1_{a}{g}" for g in ("OFF", "SCALE") for a in "XYZ"):
        assert out[name] == pytest.approx(params[name], rel=1e-6, abs=1e-7), name
    assert "CAL_MAG1_ROT" not in out and not any(name.startswith("CAL_MAG0_") for name in out)
    # the same board with the compass turned: the new CAL_MAG1_ROT under the level adjustment still reproduces
    wrong = flight_body("px4", Q=level @ px4_rotation(12), frame_to_body=R, M=soft_iron(rng), params=params)
    wrong["flight"]["stored"]["offsets_ut"] = off.tolist()
    out = parse_px4(export_flight_compass(wrong, "px4").content)
    assert out["CAL_MAG1_ROT"] == 12
    sensor, p = readings(rng)
    h = px4_correct(out, 1, 0, sensor, p * 0.001, level)
    assert np.abs(h - trical(wrong, sensor, p)).max() < 1e-4


# -- JSON and the formats ------------------------------------------------------------------------------------------


def test_json_holds_the_correction_and_the_firmwares_parameters(rng):
    body = flight_body(Q=YAW_90, orientation=8, params={"COMPASS_EXTERNAL": 1})
    doc = json.loads(export_calibration(body, "json").content)
    assert doc["correction"]["formula"] == "h_body = M (Q m - b - k p)"
    assert doc["correction"]["Q"] == YAW_90.tolist()
    assert doc["firmware_parameters"]["COMPASS_ORIENT"] == 10
    failed = json.loads(export_calibration(flight_body(ok=False), "json").content)
    assert failed["firmware_parameters"] is None and "failed its checks" in failed["firmware_parameters_refused"]
    empty = dict(flight_body(ok=False), model={"type": "compass_flight"})  # a body cut short: no numbers
    assert json.loads(export_calibration(empty, "json").content)["correction"]["Q"] is None


def test_other_formats_are_refused_naming_the_ones_that_fit():
    assert FLIGHT_COMPASS_EXPORTS == ("json", "ardupilot", "px4", "flight_svg")
    with pytest.raises(ExportError, match="json, ardupilot, px4"):
        export_calibration(flight_body(), "c")
