"""Units decided from the data (app.io.readers.units) and the chips' datasheet scales
(app.io.readers.chips), read through read_log as an upload is."""

from __future__ import annotations

import numpy as np
import pytest

from app.io.errors import LogFormatError
from app.io.readers import read_log
from app.io.readers.chips import CHIPS, parse_chips
from app.io.readers.read_options import ReadOptions
from app.io.readers.units import field_magnitude, infer_mag_unit
from simulations.logs import simulate_static_log
from simulations.magnetometer import simulate_session

G = 9.80665
SIX = simulate_static_log(np.random.default_rng(22), sampling_rate_hz=100.0, rest_s=(2.0, 2.5), turn_s=(1.0, 1.5))
ACC = SIX.samples  # m/s²
T = np.arange(len(ACC)) / 100.0
MAG, _, B_TRUE = simulate_session(7, n=600)  # µT, a 48 µT field, hard iron up to 60 µT


def _write(tmp_path, header: str, columns: list, fmt: str = "%.6f", name: str = "log.csv"):
    path = tmp_path / name
    data = np.column_stack(columns)
    with open(path, "w") as f:
        f.write(header + "\n")
        for row in data:
            f.write(
                ",".join(f"{v:.3f}" if (i == 0 and header.startswith("t,")) else (fmt % v) for i, v in enumerate(row))
                + "\n"
            )
    return path


def _read(path, **kw):
    return read_log(
        path,
        ReadOptions(sampling_rate_hz=kw.pop("sampling_rate_hz", None), units=kw.pop("units", {}), **kw),
        name=path.name,
    )


# -- the datasheet scales ----------------------------------------------------------------------

DATASHEET = {
    # MPU-6050 Product Specification rev. 3.4, sections 6.1 and 6.2 (same on the ICM-20948, DS-000189).
    "mpu6050-2g": 1 / 16384,
    "mpu6050-4g": 1 / 8192,
    "mpu6050-8g": 1 / 4096,
    "mpu6050-16g": 1 / 2048,
    "mpu6050-250dps": 1 / 131,
    "mpu6050-500dps": 1 / 65.5,
    "mpu6050-1000dps": 1 / 32.8,
    "mpu6050-2000dps": 1 / 16.4,
    # AK8963, AK09916: µT per LSB.
    "ak8963-16bit": 0.15,
    "ak8963-14bit": 0.6,
    "ak09916": 0.15,
    # LSB per gauss → µT per LSB (1 G = 100 µT).
    "qmc5883l-2g": 100 / 12000,
    "qmc5883l-8g": 100 / 3000,
    **{f"hmc5883l-{g}": 100 / g for g in (1370, 1090, 820, 660, 440, 390, 330, 230)},
    "lis3mdl-4g": 100 / 6842,
    "lis3mdl-8g": 100 / 3421,
    "lis3mdl-12g": 100 / 2281,
    "lis3mdl-16g": 100 / 1711,
    "mmc5983ma-18bit": 100 / 16384,
    "mmc5983ma-16bit": 100 / 4096,
}


def test_every_chip_carries_its_datasheet_scale_and_no_other():
    assert set(CHIPS) == set(DATASHEET)
    for name, scale in DATASHEET.items():
        assert CHIPS[name].scale == pytest.approx(scale, rel=1e-12), name
        assert CHIPS[name].unit == {"acc": "g", "gyr": "deg/s", "mag": "uT"}[CHIPS[name].sensor]


def test_chip_names_are_checked_one_per_sensor():
    assert {s: c.name for s, c in parse_chips("MPU6050-4g, mpu6050-500dps,ak8963-16bit").items()} == {
        "acc": "mpu6050-4g",
        "gyr": "mpu6050-500dps",
        "mag": "ak8963-16bit",
    }
    with pytest.raises(LogFormatError, match="chip 'mpu9999' is not one trical knows: give one of mpu6050-2g"):
        parse_chips("mpu9999")
    with pytest.raises(LogFormatError, match=r"two parts for the magnetometer .ak8963-16bit, qmc5883l-2g."):
        parse_chips("ak8963-16bit,qmc5883l-2g")


# -- the accelerometer --------------------------------------------------------------------------


def test_a_g_header_over_m_s2_values_is_read_in_m_s2_with_a_warning_naming_both(tmp_path):
    log = _read(_write(tmp_path, "t,aX (g),aY (g),aZ (g)", [T, ACC]))
    assert log.units["acc"] == "m/s^2"
    np.testing.assert_allclose(log.acc, ACC, atol=5e-7)
    [w] = log.warnings
    assert w.startswith("the header said g for the accelerometer, but its readings rest at a median norm of 9.")
    assert w.endswith("about 1 g in m/s^2: calibrated in m/s^2")


def test_an_option_that_the_data_contradict_is_overridden_with_a_warning(tmp_path):
    log = _read(_write(tmp_path, "t,ax,ay,az", [T, ACC / G]), units={"acc": "m/s^2"})
    assert log.units["acc"] == "g"
    assert log.warnings[0].startswith("acc_unit said m/s^2 for the accelerometer, but its readings rest")


@pytest.mark.parametrize("lsb", [16384, 8192, 4096, 2048, 1000])
def test_counts_near_a_common_sensitivity_become_g(tmp_path, lsb):
    counts = np.round(ACC / G * lsb)
    log = _read(_write(tmp_path, "t,ax (g),ay (g),az (g)", [T, counts], "%.0f"))
    assert log.units["acc"] == "g"
    np.testing.assert_array_equal(log.acc, counts / lsb)
    [w] = log.warnings
    assert f"about {lsb} LSB per g" in w and "(the header said g)" in w and "divided by" in w


def test_counts_of_no_common_sensitivity_stay_counts_and_say_so(tmp_path):
    counts = np.round(ACC / G * 3000)
    log = _read(_write(tmp_path, "t,ax,ay,az", [T, counts], "%.0f"))
    assert log.units["acc"] == "raw"
    assert "calibrated in counts, and its figures are in counts; give lsb_per_g (or chip)" in log.warnings[0]


def test_acc_unit_raw_keeps_counts(tmp_path):
    counts = np.round(ACC / G * 16384)
    log = _read(_write(tmp_path, "t,ax,ay,az", [T, counts], "%.0f"), units={"acc": "raw"})
    assert log.units["acc"] == "raw"
    np.testing.assert_array_equal(log.acc, counts)


def test_a_chip_is_lsb_per_g_and_a_wrong_scale_names_the_right_one(tmp_path):
    counts = np.round(ACC / G * 8192)
    path = _write(tmp_path, "t,ax,ay,az", [T, counts], "%.0f")
    by_chip = _read(path, chip="mpu6050-4g")
    by_lsb = _read(path, lsb_per_g=8192)
    assert by_chip.units["acc"] == by_lsb.units["acc"] == "g" and not by_chip.warnings
    np.testing.assert_array_equal(by_chip.acc, by_lsb.acc)
    with pytest.raises(
        LogFormatError,
        match=r"with lsb_per_g=16384 the accelerometer rests at 0\.4\d+ g, not about "
        r"1 g: its counts rest at \d+, which fits 8192 LSB/g \(±4 g\): give "
        r"lsb_per_g=8192 or chip=mpu6050-4g",
    ):
        _read(path, lsb_per_g=16384)
    with pytest.raises(LogFormatError, match=r"chip mpu6050-2g .16384 LSB/g. and lsb_per_g=8192 disagree"):
        _read(path, lsb_per_g=8192, chip="mpu6050-2g")
    with pytest.raises(LogFormatError, match="already in m/s\\^2"):
        _read(_write(tmp_path, "t,ax,ay,az", [T, ACC], name="ms2.csv"), chip="mpu6050-2g")


def test_a_magnitude_no_unit_explains_is_refused_naming_the_units_to_give(tmp_path):
    path = _write(tmp_path, "t,ax (g),ay (g),az (g)", [T, ACC * 0.3])
    with pytest.raises(
        LogFormatError,
        match=r"rests at a median norm of 2\.\d+ \(the header said g\), which is "
        r"neither about 1 \(g\) nor about 9\.8 \(m/s²\).*give acc_unit \(g, m/s\^2\)",
    ):
        _read(path)


# -- the magnetometer ---------------------------------------------------------------------------


def test_the_field_is_read_free_of_the_hard_iron():
    assert field_magnitude(MAG) == pytest.approx(48.0, rel=0.04)  # soft iron of ±8 % skews the half-ranges
    assert field_magnitude(MAG + 300.0) == pytest.approx(field_magnitude(MAG), rel=1e-9)


def test_a_still_magnetometer_is_judged_by_its_norm_not_its_noise():
    still = MAG[0] + np.random.default_rng(5).normal(0.0, 0.3, (2000, 3))
    assert field_magnitude(still) == pytest.approx(np.linalg.norm(MAG[0]), rel=0.01)
    assert infer_mag_unit(still) == "uT"


@pytest.mark.parametrize("factor, unit", [(1.0, "uT"), (0.01, "gauss"), (1000.0, "nT")])
def test_the_magnetometer_unit_is_inferred_from_the_field(factor, unit):
    assert infer_mag_unit(MAG * factor) == unit
    assert infer_mag_unit(np.round(MAG / 0.15)) == "raw"


def test_gauss_becomes_ut_and_a_g_header_means_gauss_for_a_magnetometer(tmp_path):
    log = _read(_write(tmp_path, "mag_x (G),mag_y (G),mag_z (G)", [MAG / 100]), sampling_rate_hz=50)
    assert log.units["mag"] == "uT" and not log.warnings
    np.testing.assert_allclose(log.mag, MAG, atol=1e-4)
    unnamed = _read(_write(tmp_path, "mag_x,mag_y,mag_z", [MAG / 100], name="b.csv"), sampling_rate_hz=50)
    assert unnamed.units["mag"] == "uT"
    np.testing.assert_allclose(unnamed.mag, MAG, atol=1e-4)


def test_counts_under_a_ut_header_are_counts_and_a_chip_makes_them_ut(tmp_path):
    counts = np.round(MAG / 0.15)
    path = _write(tmp_path, "mag_x (uT),mag_y (uT),mag_z (uT)", [counts], "%.0f")
    log = _read(path, sampling_rate_hz=50)
    assert log.units["mag"] == "raw"
    assert log.warnings[0].startswith("the header said uT for the magnetometer, but its readings show a field of 3")
    assert "give chip (e.g. ak8963-16bit" in log.warnings[1]
    with pytest.raises(
        LogFormatError, match="chip ak8963-16bit converts counts of the magnetometer, but mag_unit says"
    ):
        _read(path, sampling_rate_hz=50, units={"mag": "uT"}, chip="ak8963-16bit")
    chip = _read(path, sampling_rate_hz=50, chip="ak8963-16bit")
    assert chip.units["mag"] == "uT" and not chip.warnings
    np.testing.assert_allclose(chip.mag, counts * 0.15, rtol=1e-12)


@pytest.mark.parametrize(
    "chip, lsb_per_gauss, zero",
    [
        ("qmc5883l-2g", 12000, 0),
        ("hmc5883l-1090", 1090, 0),
        ("lis3mdl-4g", 6842, 0),
        ("mmc5983ma-16bit", 4096, 32768),
        ("mmc5983ma-18bit", 16384, 131072),
    ],
)
def test_magnetometer_chips_turn_counts_into_the_earths_field(tmp_path, chip, lsb_per_gauss, zero):
    # The MMC5983MA's output is unsigned, zero field at mid-scale: a constant the compass fit's b takes.
    counts = np.round(MAG / 100 * lsb_per_gauss) + zero
    log = _read(_write(tmp_path, "mag_x,mag_y,mag_z", [counts], "%.0f"), sampling_rate_hz=50, chip=chip)
    assert log.units["mag"] == "uT" and not log.warnings
    assert field_magnitude(log.mag) == pytest.approx(field_magnitude(MAG), rel=0.01)


def test_a_gyroscope_chip_turns_counts_into_degrees_per_second(tmp_path):
    rate = np.random.default_rng(3).normal(0.0, 20.0, (len(T), 3))  # °/s
    counts = np.round(rate * 65.5)
    path = _write(tmp_path, "t,ax,ay,az,gx,gy,gz", [T, ACC, counts])
    log = _read(path, chip="mpu6050-500dps", units={"gyr": "raw"})
    assert log.units["gyr"] == "deg/s"
    np.testing.assert_allclose(log.gyr, counts / 65.5, rtol=1e-12)
    left = _read(path, units={"gyr": "raw"})
    assert left.units["gyr"] == "raw" and any("gyroscope's readings are counts" in w for w in left.warnings)


def test_a_gyroscope_in_whole_numbers_is_counts_unless_a_unit_in_degrees_says_otherwise(tmp_path):
    counts = np.round(np.random.default_rng(4).normal(0.0, 300.0, (len(T), 3)))  # an MPU-6050 at rest: bias, noise
    unnamed = _read(_write(tmp_path, "t,ax,ay,az,gx,gy,gz", [T, ACC, counts], name="a.csv"))
    assert unnamed.units["gyr"] == "raw"
    assert any(w.startswith("the gyroscope's readings are counts") for w in unnamed.warnings)
    radians = _read(_write(tmp_path, "t,ax,ay,az,gx (rad/s),gy (rad/s),gz (rad/s)", [T, ACC, counts], name="b.csv"))
    assert radians.units["gyr"] == "raw"
    assert radians.warnings[0].startswith("the header said rad/s for the gyroscope, but its readings are whole numbers")
    degrees = _read(
        _write(tmp_path, "t,ax,ay,az,gx (deg/s),gy (deg/s),gz (deg/s)", [T, ACC, np.round(counts / 100)], name="c.csv")
    )
    assert degrees.units["gyr"] == "deg/s" and degrees.warnings == ()
    # Fractions resting with a sample spread of 0.3 at 100 Hz: 0.04 per √Hz, 2.4 °/s/√Hz in rad/s (no MEMS
    # gyroscope's), 0.04 °/s/√Hz in °/s: the data say °/s, and a note says why.
    floats = _read(_write(tmp_path, "t,ax,ay,az,gx,gy,gz", [T, ACC, counts / 1000 + 0.0001], name="d.csv"))
    assert floats.units["gyr"] == "deg/s" and floats.warnings == ()
    assert any(n.startswith("gyroscope unit deg/s inferred from the data: a still noise") for n in floats.notes)


def test_a_magnetometer_field_no_unit_explains_is_labelled_counts(tmp_path):
    # Milligauss floats (a 480 mG field): neither µT, gauss nor nT, and not whole numbers.
    log = _read(_write(tmp_path, "mag_x (uT),mag_y (uT),mag_z (uT)", [MAG * 10 + 0.05]), sampling_rate_hz=50)
    assert log.units["mag"] == "raw"
    assert log.warnings[0].startswith("the magnetometer's readings show a field of 4")
    assert "(the header said uT), which fits no unit" in log.warnings[0] and "labelled counts" in log.warnings[0]
