"""A device's own calibration read from its firmware's files (app.io.imports): real files of ArduPilot and PX4,
and every export read back as the model it was written from."""

from __future__ import annotations

import base64
from pathlib import Path

import numpy as np
import pytest

from app import methods
from app.calibration.imported import ImportedCalibration
from app.calibration_requests import ImportIn, SixPositionIn
from app.io.errors import LogFormatError
from app.io.exports.cli_sets import ACC_1G, INAV_GAIN_ONE
from app.io.exports.exporters import export_calibration
from app.io.exports.params import offset_scale
from app.io.imports import read_calibration

REAL = Path(__file__).resolve().parents[1] / "data" / "real"
G = 9.80665


def stored(body: dict) -> dict:
    return {**body, "id": "cal_test", "created_at": "2026-12-07T13:00:00.000Z"}


def imported_body(path: Path, **options) -> dict:
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    return stored(methods.calibrate(ImportIn(method="imported", file_base64=data, **options)).body())


def corrections(result) -> dict:
    return {name: (c.M, c.o) for name, c in result.corrections().items()}


def again(body: dict, fmt: str):
    return read_calibration(export_calibration(body, fmt).content.encode()).result


def test_px4_qgc_params_of_a_real_vehicle_are_read_as_px4_applies_them():
    found = read_calibration((REAL / "imports" / "px4_1.12_flight1_cal.params").read_bytes())
    r = found.result
    assert isinstance(r, ImportedCalibration) and r.ok and r.firmware == "PX4" and r.version == "1.12.3"
    assert found.recognised == "QGroundControl .params of px4"
    c = r.corrections()
    np.testing.assert_allclose(np.diag(c["acc"].M), [0.995810866, 0.995575607, 0.975390375], atol=1e-9)
    np.testing.assert_allclose(c["acc"].o, [0.036703590, 0.202201366, -0.025263309], atol=1e-9)
    np.testing.assert_allclose(c["gyr"].o, [0.032453015, -0.020179773, 0.008140928], atol=1e-9)
    # CAL_MAG0_xOFF is in gauss: 100 µT each; the soft iron is the symmetric matrix of xSCALE and xODIAG.
    np.testing.assert_allclose(c["mag"].o, [16.8982610, 37.5440747, -5.5235256], atol=1e-6)
    assert c["mag"].M[0, 1] == c["mag"].M[1, 0] == pytest.approx(0.003681208)
    assert c["mag"].M[1, 2] == pytest.approx(-0.065976284)


def test_an_ardupilot_dataflash_log_s_parm_gives_the_compass_the_readme_records():
    r = read_calibration((REAL / "flight" / "arducopter_3.5_rtl_landing_dataflashlog.bin").read_bytes()).result
    assert r.firmware == "ArduPilot" and r.file_kind == "DataFlash log PARM" and r.ok
    mag = r.corrections()["mag"]
    # COMPASS_OFS (−86.5, −18.9, −17.1) mGauss: o = −OFS / 10 µT; DIA (0.947, 0.876, 1.104)
    np.testing.assert_allclose(mag.o, [8.65, 1.89, 1.71], atol=0.01)
    np.testing.assert_allclose(np.diag(mag.M), [0.947, 0.876, 1.104], atol=0.001)
    assert r.corrected_sensors() == ("acc", "gyr", "mag")


def test_a_mavproxy_parm_and_a_ulog_are_recognised_from_their_content():
    parm = read_calibration((REAL / "imports" / "ardupilot_sitl_copter.parm").read_bytes())
    assert parm.recognised == "MAVProxy .parm of ardupilot"
    np.testing.assert_allclose(parm.result.corrections()["acc"].o, [0.001] * 3)
    np.testing.assert_allclose(parm.result.corrections()["mag"].o, [-0.5, -1.3, 1.8])  # COMPASS_OFS 5, 13, -18 mG
    ulg = read_calibration((REAL / "flight" / "sample_log_small.ulg").read_bytes())
    assert ulg.result.firmware == "PX4" and ulg.result.version == "1.11"
    # the README's CAL_MAG0 offsets (−0.003, −0.222, 0.029) G
    np.testing.assert_allclose(ulg.result.corrections()["mag"].o, [-0.25, -22.17, 2.91], atol=0.01)
    # the external compass PX4 used, slot 1: the README's CAL_MAG1 offsets (0.029, 0.556, −0.388) G
    assert any("`instance` 1" in w for w in ulg.result.warnings)
    slot1 = read_calibration((REAL / "flight" / "sample_log_small.ulg").read_bytes(), instance=1).result
    np.testing.assert_allclose(slot1.corrections()["mag"].o, [2.90, 55.55, -38.80], atol=0.01)


@pytest.mark.parametrize(
    "path",
    [REAL / "imports" / "px4_1.12_flight1_cal.params", REAL / "flight" / "arducopter_3.5_rtl_landing_dataflashlog.bin"],
)
@pytest.mark.parametrize("fmt", ["ardupilot", "px4", "json"])
def test_an_imported_calibration_exported_and_read_again_is_the_same_within_1e_6(path, fmt):
    body = imported_body(path)
    back = again(body, fmt)
    before = corrections(read_calibration(path.read_bytes()).result)
    after = corrections(back)
    assert before.keys() == after.keys()
    for name in before:
        np.testing.assert_allclose(after[name][0], before[name][0], atol=1e-6)
        np.testing.assert_allclose(after[name][1], before[name][1], atol=1e-6)


SIX = [
    {"up": up, "mean": [v * 1.02 + 0.1 * (a == "x") for a, v in zip("xyz", vec)]}
    for up, vec in {
        "-x": (-G, 0.05, 0.0),
        "+x": (G, -0.03, 0.02),
        "-y": (0.0, -G, 0.04),
        "+y": (0.01, G, 0.0),
        "-z": (0.02, 0.0, -G),
        "+z": (0.0, 0.03, G),
    }.items()
]


def six_position() -> dict:
    return stored(methods.calibrate(SixPositionIn(method="six_position", readings=SIX)).body())


def test_trical_s_json_export_is_read_back_as_the_model_it_was_written_from():
    body = six_position()
    back = again(body, "json")
    assert type(back).__name__ == "AffineCalibration"
    from app.calibration import registry

    original = registry.from_dict(body).correction
    np.testing.assert_allclose(back.correction.M, original.M, atol=1e-9)
    np.testing.assert_allclose(back.correction.o, original.o, atol=1e-9)


@pytest.mark.parametrize(("fmt", "target"), [("ardupilot", "ArduPilot"), ("px4", "PX4")])
def test_a_fitted_calibration_s_firmware_export_reads_back_as_the_firmware_s_model_within_1e_6(fmt, target):
    body = six_position()
    back = again(body, fmt).corrections()["acc"]
    p = offset_scale(body, target)
    np.testing.assert_allclose(back.o, p["offset_mps2"], atol=1e-6)
    np.testing.assert_allclose(np.diag(back.M), p["scale"], atol=1e-6)


def test_betaflight_and_inav_exports_read_back_within_their_whole_numbers():
    body = imported_body(REAL / "imports" / "px4_1.12_flight1_cal.params")
    acc = read_calibration((REAL / "imports" / "px4_1.12_flight1_cal.params").read_bytes()).result.correction
    bf = again(body, "betaflight").corrections()["acc"]
    assert again(body, "betaflight").firmware == "Betaflight"
    np.testing.assert_allclose(bf.o, acc.o, atol=0.5 * G / ACC_1G)
    np.testing.assert_array_equal(bf.M, np.eye(3))  # Betaflight holds no scale
    inav = again(body, "inav").corrections()["acc"]
    np.testing.assert_allclose(inav.o, acc.o, atol=0.5 * G / ACC_1G)
    np.testing.assert_allclose(np.diag(inav.M), np.diag(acc.M), atol=0.5 / INAV_GAIN_ONE)
    # read again and written again, the whole numbers are the same: the round trip is exact from there on
    for fmt in ("betaflight", "inav"):
        first = export_calibration(body, fmt).content
        second = export_calibration(stored(imported_body_from_text(first)), fmt).content
        assert [line for line in first.splitlines() if line.startswith("set ")] == [
            line for line in second.splitlines() if line.startswith("set ")
        ]


def imported_body_from_text(text: str) -> dict:
    data = base64.b64encode(text.encode()).decode("ascii")
    return methods.calibrate(ImportIn(method="imported", file_base64=data)).body()


def test_a_betaflight_dump_s_version_line_and_its_older_names_are_read():
    dump = (
        "# Betaflight / STM32F405 (S405) 4.2.11 Dec 1 2021\n"
        "set acc_zero_x = 20\nset acc_zero_y = -4\nset acc_zero_z = 102\n"
    )
    r = read_calibration(dump.encode()).result
    assert r.firmware == "Betaflight" and r.version == "4.2.11"
    np.testing.assert_allclose(r.correction.o, np.array([20, -4, 102]) * G / ACC_1G)


@pytest.mark.parametrize(
    ("data", "words"),
    [
        (b"\x00\x01\x02binary", "binary but neither a DataFlash log nor a ULog"),
        (b'{"a": 1}', "not trical's export"),
        (b"WPNAV_SPEED,500\nRTL_ALT,1500\n", "2 parameters (Mission Planner .param) of no calibration"),
        (b"hello\n", "no parameter, set line or JSON"),
    ],
)
def test_a_file_of_no_accepted_kind_names_what_it_looked_like_and_what_is_accepted(data, words):
    with pytest.raises(LogFormatError) as caught:
        read_calibration(data)
    assert words in str(caught.value) and "ArduPilot parameter files" in str(caught.value)
    assert caught.value.code == "unrecognised_calibration" and caught.value.status == 422


def test_an_ardupilot_file_outside_the_firmware_s_ranges_is_not_ok():
    r = read_calibration(b"INS_ACCOFFS_X,4.0\nINS_ACCOFFS_Y,0\nINS_ACCOFFS_Z,0\nINS_ACCSCAL_X,1.3\n").result
    assert not r.ok
    assert any("INS_ACCOFFS_X = 4 m/s/s is outside" in reason for reason in r.reasons)
    assert any("INS_ACCSCAL_X = 1.3 is outside" in reason for reason in r.reasons)


def test_a_real_betaflight_4_0_diff_all_holds_its_zero_in_counts_at_2048_per_g():
    r = read_calibration((REAL / "imports" / "betaflight_4.0_dysf4pro_diff_all.txt").read_bytes()).result
    assert (r.firmware, r.version, r.file_kind) == ("Betaflight", "4.0.5", "Betaflight CLI diff/dump (DYSF4PRO (DYS4))")
    # set acc_calibration = -137,-40,-65 (three values in 4.0): counts of 2048 per g
    np.testing.assert_allclose(r.correction.o, np.array([-137, -40, -65]) * G / ACC_1G)
    np.testing.assert_array_equal(r.correction.M, np.eye(3))
    assert r.ok and r.sensors[0].parameters == {"acc_calibration": "-137,-40,-65"}


def test_a_real_inav_2_4_diff_all_holds_its_zero_and_gain():
    r = read_calibration((REAL / "imports" / "inav_2.4_matekf411_diff_all.txt").read_bytes()).result
    assert (r.firmware, r.version) == ("INAV", "2.4.0") and r.ok
    np.testing.assert_allclose(r.correction.o, np.array([94, -24, -125]) * G / ACC_1G)
    np.testing.assert_allclose(np.diag(r.correction.M), np.array([4100, 4111, 4041]) / INAV_GAIN_ONE)
    # written again, INAV gets the same whole numbers back: this file's round trip is exact
    body = stored(imported_body_from_text((REAL / "imports" / "inav_2.4_matekf411_diff_all.txt").read_text()))
    text = export_calibration(body, "inav").content
    for line in ("set acczero_x = 94", "set acczero_z = -125", "set accgain_y = 4111", "set accgain_z = 4041"):
        assert line in text.splitlines()


def test_the_families_an_import_may_be_forced_to_are_one_list():
    import typing

    from app.calibration_requests import ImportFirmware
    from app.io.imports import FIRMWARES

    assert typing.get_args(ImportFirmware) == FIRMWARES


def test_a_dataflash_log_s_banner_gives_the_version_and_an_old_dump_is_warned_of():
    r = read_calibration((REAL / "flight" / "arducopter_4.6_backend_log_80k.bin").read_bytes()).result
    assert (r.firmware, r.version, r.corrected_sensors()) == ("ArduPilot", "4.6.2", ("acc", "gyr", "mag"))
    old = read_calibration(b"# INAV/SPRACINGF3 1.9.1 Dec 21 2020\nset acczero_x = 12\n").result
    assert old.version == "1.9.1" and any("older than 2.0" in w for w in old.warnings) and old.ok
    bare = read_calibration(b"set acc_calibration = 1,2,3,1\n").result
    assert bare.firmware == "Betaflight" and any("no version line" in w for w in bare.warnings)


def test_a_real_mission_planner_param_file_with_two_imus_and_two_compasses():
    path = REAL / "imports" / "ardupilot_holybro_x650_mandatory_hardware.param"
    first = read_calibration(path.read_bytes())
    assert first.recognised == "Mission Planner .param of ardupilot" and first.result.ok
    c = first.result.corrections()
    np.testing.assert_allclose(np.diag(c["acc"].M), [0.995622, 0.996019, 0.999418])
    np.testing.assert_allclose(c["gyr"].o, [0.010204, -0.034151, 0.004063])
    # COMPASS_DIA_* left out (0: never set) is 1, so the matrix is COMPASS_SCALE's; OFS in mGauss, o = -OFS / 10 µT
    np.testing.assert_allclose(c["mag"].M, 1.025156 * np.eye(3))
    np.testing.assert_allclose(c["mag"].o, [-2.363675, -1.5930922, -7.305943])
    assert any("`instance` 1" in w for w in first.result.warnings)
    second = read_calibration(path.read_bytes(), instance=1).result.corrections()
    np.testing.assert_allclose(second["acc"].o, [-0.260936, 0.439903, 0.182458])
    # COMPASS_SCALE2 times the symmetric matrix of DIA2 and ODI2
    np.testing.assert_allclose(second["mag"].M[0], 0.941493 * np.array([1.041821, -0.010626, 0.091521]))
    np.testing.assert_allclose(second["mag"].o, [-7.704732, 2.4457249, -6.897945])
    body = imported_body(path, instance=1)
    back = again(body, "ardupilot").corrections()
    for name in second:
        np.testing.assert_allclose(back[name].M, second[name].M, atol=1e-6)
        np.testing.assert_allclose(back[name].o, second[name].o, atol=1e-6)


def test_the_device_ids_a_calibration_belongs_to_are_kept_and_an_unused_px4_slot_is_said():
    path = REAL / "imports" / "ardupilot_holybro_x650_mandatory_hardware.param"
    r = read_calibration(path.read_bytes()).result
    assert r.parameters["INS_ACC_ID"] == 3408650 and r.parameters["COMPASS_DEV_ID"] == 658953
    px4 = read_calibration((REAL / "imports" / "px4_1.12_flight1_cal.params").read_bytes()).result
    assert px4.parameters["CAL_ACC0_ID"] == 3932170 and px4.parameters["CAL_MAG0_ROT"] == -1
    unused = read_calibration(b"1\t1\tCAL_ACC0_ID\t0\t6\n1\t1\tCAL_ACC0_XOFF\t0.1\t9\n").result
    assert any(w.startswith("CAL_ACC0_ID 0: PX4 applies") for w in unused.warnings)


def test_a_dump_s_calibration_line_that_is_not_a_number_is_named():
    with pytest.raises(LogFormatError) as caught:
        read_calibration(b"# INAV/MATEKF411 2.4.0 Feb 11 2020\nset acczero_x = abc\n")
    assert str(caught.value) == (
        "the file is an INAV CLI dump with 1 set line but `set acczero_x = abc` is not a number: give it the number "
        "INAV's CLI printed"
    )
    with pytest.raises(LogFormatError, match="trical's JSON export but the JSON export lacks part of its model"):
        read_calibration(b'{"$schema": "https://trical.dev/schema/calibration/v1", "model": [1, 2]}')
