"""The gyroscope's unit from its data: real MPU-6050 recordings first (their counts, and the same counts in
°/s and rad/s by the datasheet's 131 LSB per °/s), then seeded turns for each scale a real file cannot show."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.calibration.shared.plausible import GYR_PARTS, GYRO_BIAS_MAX_DPS
from app.io.readers import read_log
from app.io.readers.chips import GYR_LSB_PER_DPS
from app.io.readers.gyro_unit import compose, gyro_evidence, rotate_back
from app.io.readers.read_options import ReadOptions
from tests.conftest import DATA

CORPUS = DATA / "real" / "corpus"
STILL = CORPUS / "mpu6050_still_gyro_counts_named_gyro" / "gyro_static.csv"  # tomisuarez2, 30 s at 100 Hz
TURNS = CORPUS / "mpu6050_session1_turns_headerless" / "example_data_calibration_rows3001_8000.csv"
FS = 100.0
LSB = 131.0  # MPU-6050 PS rev. 3.4, section 6.1: FS_SEL 0


def _still() -> np.ndarray:
    return np.loadtxt(STILL, delimiter=",")


def _turns() -> tuple[np.ndarray, np.ndarray]:
    d = np.loadtxt(TURNS, delimiter=",")
    return d[:, :3], d[:, 3:]


def _write(tmp_path, name, header, columns, fmt="%.5f"):
    p = tmp_path / name
    t = np.arange(len(columns[0])) / FS
    body = np.column_stack([t, *columns])
    np.savetxt(p, body, delimiter=",", fmt=fmt, header=header or "", comments="")
    if not header:
        p.write_text(p.read_text().lstrip("\n"))
    return p


def test_the_chips_table_holds_the_offsets_the_limit_is_derived_from():
    assert {p.name: p.zero_rate_dps for p in GYR_PARTS}["MPU-6050"] == 20.0
    assert 1.5 * max(p.zero_rate_dps for p in GYR_PARTS) == GYRO_BIAS_MAX_DPS


def test_a_real_still_mpu6050_in_deg_s_is_read_in_deg_s_whatever_the_header(tmp_path):
    # The real still counts in °/s (÷131): an offset of 3.5 °/s is 200 °/s read as rad/s, beyond any MEMS part.
    dps = _still() / LSB
    log = read_log(_write(tmp_path, "still.csv", "t,gyr_x,gyr_y,gyr_z", [dps]))
    assert log.units["gyr"] == "deg/s" and log.warnings == ()
    assert any(n.startswith("gyroscope unit deg/s inferred from the data") for n in log.notes)
    said = read_log(_write(tmp_path, "said.csv", "t,gyr_x (rad/s),gyr_y (rad/s),gyr_z (rad/s)", [dps]))
    assert said.units["gyr"] == "deg/s"
    assert said.warnings[0].startswith("the header said rad/s for the gyroscope, but a still")
    given = read_log(_write(tmp_path, "given.csv", "t,gyr_x,gyr_y,gyr_z", [dps]), ReadOptions(units={"gyr": "rad/s"}))
    assert given.units["gyr"] == "deg/s" and given.warnings[0].startswith("gyr_unit said rad/s for the gyroscope")


def test_a_real_still_mpu6050_in_rad_s_is_read_in_rad_s():
    # The same counts in rad/s: its noise read as °/s (0.00016 °/s/√Hz) is below every part's datasheet.
    ev = gyro_evidence(_still() / LSB * math.pi / 180.0, whole=False, acc=None, fs=FS, time_s=None)
    assert ev.unit == "rad/s" and "noise" in ev.words


def test_real_still_counts_leave_their_scale_open():
    ev = gyro_evidence(_still(), whole=True, acc=None, fs=FS, time_s=None)
    assert ev.unit is None and ev.offset == pytest.approx(457, abs=5)


def test_the_real_turns_between_rests_tell_131_lsb_per_dps():
    # tomisuarez2's own fit of this session: 0.00013737, 0.00013292, 0.00013394 rad/s per count, i.e.
    # 127.4, 131.3, 130.3 LSB per °/s.
    acc, gyr = _turns()
    ev = gyro_evidence(gyr, whole=True, acc=acc, fs=FS, time_s=None)
    assert ev.unit == "raw@131" and ev.moves >= 5
    assert ev.turn_errors["raw@131"] < 10.0 and min(v for k, v in ev.turn_errors.items() if k != "raw@131") > 40.0
    for unit, scale in (("deg/s", 1 / LSB), ("rad/s", math.pi / 180.0 / LSB)):
        assert gyro_evidence(gyr * scale, whole=False, acc=acc, fs=FS, time_s=None).unit == unit


def test_composed_increments_turn_a_vector_as_one_rotation():
    steps = np.tile([0.0, 0.0, math.pi / 2 / 1000], (1000, 1))  # 90° about z in 1000 steps
    v = rotate_back(compose(steps), np.array([1.0, 0.0, 0.0]))
    np.testing.assert_allclose(v, [0.0, -1.0, 0.0], atol=1e-9)


def _simulated_turns(seed: int, lsb: float | None, unit: str):
    """Rests and turns about random axes: the accelerometer reads gravity in the body frame, the gyroscope
    the body rate (rad/s, °/s, or counts at ``lsb`` per °/s) with an MPU-6050's offset and noise."""
    rng = np.random.default_rng(seed)
    g = np.array([0.0, 0.0, 1.0])
    acc, rate = [], []
    q = np.array([1.0, 0.0, 0.0, 0.0])
    for _ in range(6):
        for _ in range(int(2 * FS)):  # a 2 s rest
            acc.append(rotate_back(q, g))
            rate.append(np.zeros(3))
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        w = axis * math.radians(rng.uniform(60, 120))  # rad/s for 1 s
        for _ in range(int(FS)):
            q = _step(q, w / FS)
            acc.append(rotate_back(q, g))
            rate.append(w)
    acc, rate = np.array(acc), np.array(rate)
    dps = np.degrees(rate) + [2.0, -1.5, 0.8] + rng.normal(0, 0.05, rate.shape)
    acc = acc + rng.normal(0, 0.003, acc.shape)
    if lsb is not None:
        return acc, np.round(dps * lsb)
    return acc, dps if unit == "deg/s" else np.radians(dps)


def _step(q, r):
    from app.io.readers.gyro_unit import _mul

    return _mul(q, compose(r[None]))


@pytest.mark.parametrize("lsb", GYR_LSB_PER_DPS)
def test_each_counts_scale_is_told_by_the_turns(lsb):
    acc, gyr = _simulated_turns(3, lsb, "raw")
    assert gyro_evidence(gyr, whole=True, acc=acc, fs=FS, time_s=None).unit == f"raw@{lsb:g}"


@pytest.mark.parametrize("unit", ["rad/s", "deg/s"])
def test_rad_s_and_deg_s_are_told_by_the_turns(unit):
    acc, gyr = _simulated_turns(4, None, unit)
    ev = gyro_evidence(gyr, whole=False, acc=acc, fs=FS, time_s=None)
    assert ev.unit == unit and "integral" in ev.words


def test_a_still_gyroscope_nothing_decides_is_asked_about(tmp_path):
    # An offset of 0.3 and a noise of 0.003 per √Hz: 17 °/s and 0.17 °/s/√Hz in rad/s, 0.3 °/s and 0.003
    # °/s/√Hz in °/s — both a MEMS part's. Nothing said: read as rad/s, and the question is on the log.
    rng = np.random.default_rng(8)
    gyr = np.array([0.2, -0.2, 0.1]) + rng.normal(0, 0.003 * math.sqrt(FS), (3000, 3))
    log = read_log(_write(tmp_path, "g.csv", "t,gyr_x,gyr_y,gyr_z", [gyr]))
    assert log.units["gyr"] == "rad/s"
    assert log.questions and log.questions[0]["sensor"] == "gyr"
    assert "give gyr_unit (rad/s or deg/s)" in log.questions[0]["detail"]
    said = read_log(_write(tmp_path, "h.csv", "t,gyr_x (deg/s),gyr_y (deg/s),gyr_z (deg/s)", [gyr]))
    assert said.units["gyr"] == "deg/s" and said.questions == ()
