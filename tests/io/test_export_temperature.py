"""A temperature calibration's firmware exports: each firmware's formula, written here from its source's
description, applied to the exported parameters, reproduces trical's correction to 1e-6 over the range.

- PX4, TemperatureCompensation (src/modules/sensors/temperature_compensation): dT = clamp(T, TMIN, TMAX) − TREF,
  offset = X0 + X1·dT + X2·dT² + X3·dT³, subtracted from the reading.
- ArduPilot, AP_InertialSensor_tempcal.cpp (TCal::correct_sensor, polynomial_eval): T and the calibration
  temperature clamped to [TMIN, TMAX], P(x) = (C1·x + C2·x² + C3·x³)·1e-6 with x = T − 35, and
  v ← v − P(T − 35) + P(T_cal − 35).
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from app.calibration.shared.result import CalibrationResult
from app.io.errors import ExportError
from app.io.exports.exporters import export_calibration
from app.io.log import LogData
from app.workflows.temperature import temperature_log
from tests.temperature_logs import warm_up


def _body(seed: int = 21, **kw) -> dict:
    w = warm_up(seed, duration_s=1200, sampling_rate_hz=20, **kw)
    log = LogData(
        acc=w.acc,
        gyr=w.gyr,
        mag=None,
        time_s=w.time_s,
        sampling_rate_hz=20.0,
        units={"acc": "m/s^2", "gyr": "rad/s"},
        format="csv",
        columns=[],
        temperature_c=w.temperature_c,
    )
    body = temperature_log(log, label="warm.csv").body()
    body.update(id="cal_test", created_at="2026-12-03T12:00:00.000Z")
    return body


@pytest.fixture(scope="module")
def body() -> dict:
    b = _body()
    assert b["ok"], b["reasons"]
    return b


def _temperatures(model: dict) -> np.ndarray:
    return np.linspace(model["t_min_c"] - 8.0, model["t_max_c"] + 8.0, 97)  # beyond both ends: the clamp


def _px4_rows(text: str) -> dict:
    rows = {}
    for line in text.splitlines():
        if line.startswith("#") or not line.strip():
            continue
        vehicle, component, name, value, kind = line.split("\t")
        assert (vehicle, component) == ("1", "1") and kind in ("6", "9")
        rows[name] = int(value) if kind == "6" else float(value)
    return rows


def test_px4_params_reproduce_trical_s_correction(body):
    text = export_calibration(body, "px4").content
    p = _px4_rows(text)
    result = CalibrationResult.from_dict(body)
    for sensor, prefix in (("acc", "TC_A"), ("gyr", "TC_G")):
        assert p[f"{prefix}_ENABLE"] == 1
        model = body["model"][sensor]
        T = _temperatures(model)
        m = np.random.default_rng(1).normal(0.0, 1.0, (len(T), 3))
        dT = np.clip(T, p[f"{prefix}0_TMIN"], p[f"{prefix}0_TMAX"]) - p[f"{prefix}0_TREF"]
        px4 = np.empty_like(m)
        for axis in range(3):
            offset = sum(p[f"{prefix}0_X{k}_{axis}"] * dT**k for k in range(4))
            px4[:, axis] = m[:, axis] - offset
        np.testing.assert_allclose(px4, result.correct(sensor, m, T), rtol=0, atol=1e-6)
    assert p["TC_A0_X0_0"] == 0.0 and p["TC_G0_X0_0"] != 0.0  # the accelerometer's offsets are relative to TREF
    assert len([k for k in p if k.startswith("TC_A0_X")]) == 12
    assert "1\t1\tTC_A_ENABLE\t1\t6" in text


def _ardupilot_rows(text: str) -> dict:
    rows = {}
    for line in text.splitlines():
        if line.startswith("#") or not line.strip():
            continue
        name, value = line.split()
        rows[name] = float(value)
    return rows


@pytest.mark.parametrize("cal_offset_c", [0.0, -6.5, 40.0])
def test_ardupilot_parm_reproduces_trical_s_correction_relative_to_the_calibration_temperature(body, cal_offset_c):
    p = _ardupilot_rows(export_calibration(body, "ardupilot").content)
    assert p["INS_TCAL1_ENABLE"] == 1
    result = CalibrationResult.from_dict(body)
    for sensor, word in (("acc", "ACC"), ("gyr", "GYR")):
        model = body["model"][sensor]
        T = _temperatures(model)
        cal_temp = model["t_ref_c"] + cal_offset_c  # INS_ACC1_CALTEMP / INS_GYR1_CALTEMP
        m = np.random.default_rng(2).normal(0.0, 1.0, (len(T), 3))

        # P is called within this iteration only: B023's late binding cannot happen.
        def P(x, axis):
            c1, c2, c3 = (p[f"INS_TCAL1_{word}{k}_{'XYZ'[axis]}"] for k in (1, 2, 3))  # noqa: B023
            return (c1 * x + c2 * x**2 + c3 * x**3) * 1e-6

        t = np.clip(T, p["INS_TCAL1_TMIN"], p["INS_TCAL1_TMAX"])
        tc = np.clip(cal_temp, p["INS_TCAL1_TMIN"], p["INS_TCAL1_TMAX"])
        ardupilot = np.column_stack([m[:, a] - P(t - 35.0, a) + P(tc - 35.0, a) for a in range(3)])
        # trical's correction, relative to the (clamped) calibration temperature
        trical = result.correct(sensor, m, T) - result.correct(sensor, np.zeros((1, 3)), [cal_temp])
        np.testing.assert_allclose(ardupilot, trical, rtol=0, atol=1e-6)


def test_exports_of_a_failed_calibration_are_refused_with_its_reason():
    failed = _body(22, t_start_c=30.0, t_end_c=36.0)
    assert not failed["ok"]
    for fmt in ("px4", "ardupilot"):
        with pytest.raises(ExportError, match="under the 10 °C"):
            export_calibration(failed, fmt)
    assert export_calibration(failed, "json").content.count('"ok": false') == 1


def test_affine_formats_are_refused_and_the_others_name_the_temperature_formats(body):
    with pytest.raises(ExportError, match="px4, ardupilot, json, temperature_svg"):
        export_calibration(body, "c")
    with pytest.raises(ExportError, match="px4, ardupilot, json, temperature_svg"):
        export_calibration(body, "kalibr")


def test_the_plot_draws_the_bins_the_fit_and_its_band_per_axis_and_sensor(body):
    svg = export_calibration(body, "temperature_svg")
    assert svg.media_type == "image/svg+xml"
    text = svg.content
    assert text.count('class="band"') == 6 and text.count('class="fit"') == 6
    n_bins = sum(len(body["bins"][s]["t_c"]) for s in ("acc", "gyr"))
    assert text.count('class="bin"') == 3 * n_bins
    assert "<desc>Accelerometer: offset against temperature" in text
    # The legend stands under each panel's plot, never over its curves: every legend line below the plot's frame.
    frames = [
        float(y) + float(h)
        for y, h in re.findall(
            r'<rect x="\d+" y="([\d.]+)" width="\d+" height="([\d.]+)" '
            r'fill="none"',
            text,
        )
    ]
    legends = [float(y) for y in re.findall(r'<text class="legend" x="\d+" y="([\d.]+)"', text)]
    assert len(frames) == 2 and len(legends) == 6
    assert all(frames[0] < y < frames[0] + 85 for y in legends[:3]) and all(y > frames[1] for y in legends[3:])
    desc = re.search(r"<desc>(.*)</desc>", text).group(1)
    assert f"{body['metrics']['acc']['drift_raw'][2]:.3g}" in desc
