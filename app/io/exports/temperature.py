"""Exports of a temperature calibration (method ``temperature``): the parameters each firmware applies,
its JSON, and the plot of offset against temperature.

Formats (the names ``px4`` and ``ardupilot`` are those of the other calibrations: :func:`export_calibration`
dispatches on the calibration's method, as for a noise characterisation):

- ``px4``: a QGroundControl ``.params`` file (``vehicle-id  component-id  name  value  type``, tab-separated,
  type 6 = MAV_PARAM_TYPE_INT32, 9 = MAV_PARAM_TYPE_REAL32, the layout PX4's
  ``Tools/process_sensor_caldata.py`` writes) with ``TC_A_ENABLE``, ``TC_A0_ID``, ``TC_A0_TREF``,
  ``TC_A0_TMIN``, ``TC_A0_TMAX``, ``TC_A0_X{0..3}_{0..2}`` and the same for ``TC_G``. PX4's
  ``TemperatureCompensation`` (``src/modules/sensors/temperature_compensation/TemperatureCompensation.cpp``,
  ``TemperatureCompensation::calc_thermal_offsets_1D``): dT = clamp(T, TMIN, TMAX) − TREF,
  offset = X0 + X1·dT + X2·dT² + X3·dT³, subtracted from the reading (m/s², rad/s). trical's model is
  that form: the coefficients are copied.
- ``ardupilot``: a ``.parm`` file with ``INS_TCAL1_ENABLE``, ``INS_TCAL1_TMIN``, ``INS_TCAL1_TMAX``,
  ``INS_TCAL1_ACC{1..3}_{X,Y,Z}`` and ``INS_TCAL1_GYR{1..3}_{X,Y,Z}``. ArduPilot
  (``libraries/AP_InertialSensor/AP_InertialSensor_tempcal.cpp``, ``TCal::correct_sensor`` and
  ``TCal::polynomial_eval``): with x = clamp(T) − 35 and P(x) = (c1·x + c2·x² + c3·x³)·1e-6 (no constant
  term, ``TEMP_REFERENCE`` 35 °C, ``SCALE_FACTOR`` 1e6), the reading becomes v − P(clamp(T) − 35) +
  P(clamp(T_cal) − 35), T_cal the temperature of the accelerometer's (gyroscope's) own calibration,
  ``INS_ACCn_CALTEMP`` (``INS_GYRn_CALTEMP``). trical's polynomial is re-expanded about 35 °C and its
  constant dropped: the correction then equals trical's offset relative to T_cal.
- ``json``: the body's model, intervals and figures; ``temperature_svg``: the plot.
"""

from __future__ import annotations

import json

import numpy as np

from app.calibration.shared.gravity import STANDARD_GRAVITY
from app.calibration.shared.result import DRIFT
from app.calibration.temperature import shift_polynomial

from ..errors import ExportError
from .allan_plot import COLOURS, DASHES, FONT, GLYPHS, svg_picture
from .common import JSON_SCHEMA, Export, result_class

PX4_SOURCE = (
    "src/modules/sensors/temperature_compensation/TemperatureCompensation.cpp "
    "(TemperatureCompensation::calc_thermal_offsets_1D)"
)
ARDUPILOT_SOURCE = (
    "libraries/AP_InertialSensor/AP_InertialSensor_tempcal.cpp "
    "(AP_InertialSensor::TCal::correct_sensor, polynomial_eval)"
)
ARDUPILOT_REFERENCE_C = 35.0
ARDUPILOT_SCALE = 1.0e6
ARDUPILOT_T_RANGE = (-70.0, 80.0)
"""``@Range`` of INS_TCALn_TMIN and _TMAX in AP_InertialSensor_tempcal.cpp."""
PX4_INT32, PX4_REAL32 = 6, 9
"""MAVLink's MAV_PARAM_TYPE_INT32 and MAV_PARAM_TYPE_REAL32, the type column of a QGroundControl .params file."""
PREFIX = {"acc": ("TC_A", "ACC"), "gyr": ("TC_G", "GYR")}

TEMPERATURE_FORMATS = {
    "px4": "PX4 (.params for QGroundControl)",
    "ardupilot": "ArduPilot (.parm)",
    "json": "JSON",
    "temperature_svg": "Offset against temperature (SVG)",
}


def _number(v: float) -> str:
    return f"{v:.9g}"


def _usable(body: dict, target: str) -> dict:
    """The sensors' models, refused when the calibration failed its checks."""
    if not body.get("ok"):
        reasons = "; ".join(body.get("reasons") or ["it failed its checks"])
        raise ExportError(
            f"this temperature calibration failed its checks ({reasons}): {target} would apply a "
            "polynomial that does not hold — record the warm-up again, or use the json export to see it"
        )
    return {s: body["model"][s] for s in ("acc", "gyr") if s in body["model"]}


def _header(body: dict) -> list[str]:
    return [
        f"trical temperature calibration {body['id']} ({body['created_at']}), device {body.get('device_id') or '-'}",
        "Axes are those of the logged data: the numbers fit the firmware only if they are the IMU's sensor axes.",
        f"Verdict: {(body.get('verdict') or {}).get('words', '')}",
    ]


def px4_parameters(models: dict, ids: dict | None = None) -> list[tuple[str, float, int]]:
    """``(name, value, type)`` of PX4's thermal compensation parameters for the models (instance 0)."""
    out: list[tuple[str, float, int]] = []
    for sensor, model in models.items():
        p = PREFIX[sensor][0]
        out.append((f"{p}_ENABLE", 1, PX4_INT32))
        out.append((f"{p}0_ID", int((ids or {}).get(sensor, 0)), PX4_INT32))
        out += [
            (f"{p}0_TREF", model["t_ref_c"], PX4_REAL32),
            (f"{p}0_TMIN", model["t_min_c"], PX4_REAL32),
            (f"{p}0_TMAX", model["t_max_c"], PX4_REAL32),
        ]
        c = np.asarray(model["coefficients"], dtype=float)
        out += [(f"{p}0_X{k}_{axis}", float(c[axis, k]), PX4_REAL32) for k in range(4) for axis in range(3)]
    return out


def ardupilot_parameters(models: dict, instance: int = 1) -> list[tuple[str, float]]:
    """``(name, value)`` of ArduPilot's INS_TCALn parameters: each polynomial re-expanded about 35 °C, its
    constant dropped, ×1e6."""
    out: list[tuple[str, float]] = []
    t_min = min(m["t_min_c"] for m in models.values())
    t_max = max(m["t_max_c"] for m in models.values())
    lo, hi = ARDUPILOT_T_RANGE
    if t_min < lo or t_max > hi:
        raise ExportError(
            f"the calibrated range {t_min:.1f}–{t_max:.1f} °C is outside ArduPilot's {lo:g}…{hi:g} °C "
            "for INS_TCALn_TMIN and _TMAX: use the px4 or json export"
        )
    if len(models) == 2 and (
        abs(models["acc"]["t_min_c"] - models["gyr"]["t_min_c"]) > 1e-9
        or abs(models["acc"]["t_max_c"] - models["gyr"]["t_max_c"]) > 1e-9
    ):
        raise ExportError(
            "the accelerometer's and the gyroscope's ranges differ, and ArduPilot keeps one TMIN and "
            "TMAX per IMU: calibrate them on the same samples, or use the px4 export"
        )
    out += [(f"INS_TCAL{instance}_ENABLE", 1), (f"INS_TCAL{instance}_TMIN", t_min), (f"INS_TCAL{instance}_TMAX", t_max)]
    for sensor in ("acc", "gyr"):
        if sensor not in models:
            continue
        model = models[sensor]
        about35 = shift_polynomial(model["coefficients"], model["t_ref_c"], ARDUPILOT_REFERENCE_C)
        word = PREFIX[sensor][1]
        out += [
            (f"INS_TCAL{instance}_{word}{k}_{a}", float(about35[i, k] * ARDUPILOT_SCALE))
            for k in (1, 2, 3)
            for i, a in enumerate("XYZ")
        ]
    return out


def to_px4_params(body: dict) -> Export:
    """QGroundControl ``.params`` of PX4's thermal compensation (module docstring)."""
    models = _usable(body, "PX4")
    rows = px4_parameters(models, body.get("sensor_ids"))
    comments = _header(body) + [
        f"PX4 applies ({PX4_SOURCE}): dT = clamp(T, TMIN, TMAX) - TREF,",
        "  offset = X0 + X1*dT + X2*dT^2 + X3*dT^3 (m/s^2, rad/s), subtracted from the reading.",
        "The accelerometer's X0 is 0: its offsets are the drift relative to TREF; the normal accelerometer",
        "calibration (CAL_ACC*) made after loading these gives the offset at TREF.",
        "Set TC_A0_ID and TC_G0_ID to the sensors' device ids (CAL_ACC0_ID, CAL_GYRO0_ID) when they are 0:",
        "PX4 applies a slot only to the sensor whose id it names. Reboot after loading.",
        "",
        "Vehicle-Id Component-Id Name Value Type",
    ]
    lines = [f"# {c}" if c else "#" for c in comments]
    lines += [f"1\t1\t{name}\t{value if kind == PX4_INT32 else _number(value)}\t{kind}" for name, value, kind in rows]
    return Export("\n".join(lines) + "\n", "text/plain", f"trical_{body['id']}_px4_thermal.params")


def to_ardupilot_parm(body: dict) -> Export:
    """ArduPilot ``.parm`` of its IMU temperature calibration (module docstring)."""
    models = _usable(body, "ArduPilot")
    rows = ardupilot_parameters(models)
    comments = _header(body) + [
        f"ArduPilot applies ({ARDUPILOT_SOURCE}), x = clamp(T, TMIN, TMAX) - 35:",
        "  v -= P(x) - P(clamp(T_cal, TMIN, TMAX) - 35), P(x) = (C1*x + C2*x^2 + C3*x^3) * 1e-6,",
        "  T_cal = INS_ACC1_CALTEMP (INS_GYR1_CALTEMP), set by ArduPilot's own accelerometer calibration.",
        "The correction is relative to the temperature of that calibration: calibrate the accelerometer again",
        "after loading these. Reboot after loading.",
    ]
    lines = [f"# {c}" for c in comments]
    lines += [f"{name} {int(v) if name.endswith('_ENABLE') else _number(v)}" for name, v in rows]
    return Export("\n".join(lines) + "\n", "text/plain", f"trical_{body['id']}_ardupilot_tcal.parm")


def to_temperature_json(body: dict) -> Export:
    doc = {
        "$schema": JSON_SCHEMA,
        "schema_version": 1,
        "id": body["id"],
        "method": "temperature",
        "created_at": body["created_at"],
        "device_id": body.get("device_id"),
        "label": body.get("label"),
        "formula": "o(T) = X0 + X1 dT + X2 dT^2 + X3 dT^3, dT = clamp(T, t_min_c, t_max_c) - t_ref_c; "
        "corrected = m - o(T)",
        "model": body["model"],
        "uncertainty": body["uncertainty"],
        "metrics": body.get("metrics"),
        "ok": body.get("ok"),
        "warnings": body.get("warnings", []),
    }
    return Export(json.dumps(doc, indent=2), "application/json", f"{body['id']}.json")


# -- the plot ---------------------------------------------------------------------------------------

WIDTH, PANEL_H = 440, 275
LEFT, RIGHT, TOP, BOTTOM = 64, 12, 34, 85
LEGEND_LINE = 13
"""The legend's three lines (one per axis) stand under the axis's title, outside the plot, so that they never
cover a curve; BOTTOM holds the ticks, the title and the legend."""


def _f(v: float) -> str:
    return f"{v:.1f}"


def ticks(lo: float, hi: float, n: int = 5) -> list[float]:
    """Round values (1, 2, 5 × 10ⁿ apart) for about ``n`` ticks between ``lo`` and ``hi``."""
    span = hi - lo if hi > lo else 1.0
    raw = span / n
    mag = 10 ** np.floor(np.log10(raw))
    step = min((m * mag for m in (1, 2, 5, 10) if m * mag >= raw), default=raw)
    first = np.ceil(lo / step) * step
    return [float(v) for v in np.arange(first, hi + step * 1e-9, step)]


def _panel(body: dict, sensor: str, top: float) -> tuple[list[str], str]:
    metrics = body["metrics"][sensor]
    scale = 1000.0 / STANDARD_GRAVITY if sensor == "acc" else 180.0 / np.pi
    unit = "mg" if sensor == "acc" else "°/s"
    bins, curve = body["bins"][sensor], body["curve"][sensor]
    t_b, y_b = np.asarray(bins["t_c"]), np.asarray(bins["offset"]) * scale
    t_c = np.asarray(curve["t_c"])
    y_c, h_c = np.asarray(curve["offset"]) * scale, np.asarray(curve["half_width"]) * scale
    x0, x1 = float(t_c.min()), float(t_c.max())
    lo = float(min(y_b.min(), (y_c - h_c).min()))
    hi = float(max(y_b.max(), (y_c + h_c).max()))
    pad = 0.05 * (hi - lo or 1.0)
    lo, hi = lo - pad, hi + pad
    w, h = WIDTH - LEFT - RIGHT, PANEL_H - TOP - BOTTOM

    def X(t):
        return LEFT + (np.asarray(t) - x0) / ((x1 - x0) or 1.0) * w

    def Y(v):
        return top + TOP + (hi - np.asarray(v)) / ((hi - lo) or 1.0) * h

    name = {"acc": "Accelerometer", "gyr": "Gyroscope"}[sensor]
    rel = " (relative to T_ref)" if body["model"][sensor].get("relative") else ""
    out = [
        f'<text x="{LEFT}" y="{top + 20}" font-size="13" font-weight="bold" {FONT}>{name} offset{rel}, {unit}</text>',
        f'<rect x="{LEFT}" y="{_f(top + TOP)}" width="{w}" height="{h}" fill="none" stroke="#888"/>',
    ]
    for v in ticks(lo, hi):
        y = float(Y(v))
        out.append(f'<line x1="{LEFT}" x2="{LEFT + w}" y1="{_f(y)}" y2="{_f(y)}" stroke="#e4e4e4"/>')
        out.append(f'<text x="{LEFT - 4}" y="{_f(y + 4)}" font-size="10" text-anchor="end" {FONT}>{v:g}</text>')
    for v in ticks(x0, x1):
        x = float(X(v))
        out.append(
            f'<text x="{_f(x)}" y="{_f(top + TOP + h + 14)}" font-size="10" text-anchor="middle" {FONT}>{v:g}</text>'
        )
    out.append(
        f'<text x="{LEFT + w / 2}" y="{_f(top + TOP + h + 30)}" font-size="11" text-anchor="middle" {FONT}>'
        "temperature, °C</text>"
    )
    for i, axis in enumerate("xyz"):
        colour = COLOURS[axis]
        band = [f"{float(X(t)):.1f},{float(Y(v)):.1f}" for t, v in zip(t_c, y_c[:, i] + h_c[:, i])] + [
            f"{float(X(t)):.1f},{float(Y(v)):.1f}" for t, v in zip(t_c[::-1], (y_c[:, i] - h_c[:, i])[::-1])
        ]
        out.append(
            f'<polygon class="band" points="{" ".join(band)}" fill="{colour}" fill-opacity="0.18" stroke="none"/>'
        )
        out += [
            f'<circle class="bin" cx="{float(X(t)):.1f}" cy="{float(Y(v)):.1f}" r="1.8" fill="{colour}"/>'
            for t, v in zip(t_b, y_b[:, i])
        ]
        dash = f' stroke-dasharray="{DASHES[axis]}"' if DASHES[axis] else ""
        line = " ".join(f"{float(X(t)):.1f},{float(Y(v)):.1f}" for t, v in zip(t_c, y_c[:, i]))
        out.append(f'<polyline class="fit" points="{line}" fill="none" stroke="{colour}" stroke-width="1.8"{dash}/>')
        out.append(
            f'<text class="legend" x="{LEFT}" y="{_f(top + TOP + h + 48 + LEGEND_LINE * i)}" font-size="10" '
            f'fill="{colour}" {FONT}>{GLYPHS[axis]} {axis}: order {body["model"][sensor]["order"][i]}, drift '
            f"{metrics['drift_raw'][i]:.3g} → {metrics['drift_cv'][i]:.3g} {unit}</text>"
        )
    said = (
        f"{name}: offset against temperature {x0:.1f}–{x1:.1f} °C, binned readings, the fitted polynomial and its "
        f"95 % band per axis; drift raw {', '.join(f'{v:.3g}' for v in metrics['drift_raw'])} {unit}, on bands left "
        f"out {', '.join(f'{v:.3g}' for v in metrics['drift_cv'])} {unit}."
    )
    return out, said


def temperature_svg(body: dict) -> str:
    """The offset of each axis against temperature, one panel per sensor: the binned readings (dots), the
    fit (line) and its 95 % band (shaded), with a ``<title>`` and a ``<desc>`` stating the figures."""
    sensors = [s for s in ("acc", "gyr") if s in (body.get("bins") or {})]
    if result_class(body).KIND != DRIFT or not sensors:
        raise ExportError("temperature_svg draws a temperature calibration (method temperature)")
    parts, said = [], []
    for k, sensor in enumerate(sensors):
        p, s = _panel(body, sensor, k * PANEL_H)
        parts += p
        said.append(s)
    height = PANEL_H * len(sensors)
    return svg_picture(WIDTH, height, f"Offset against temperature, {body.get('id', '')}", " ".join(said), parts)


def to_temperature_svg(body: dict) -> Export:
    return Export(temperature_svg(body), "image/svg+xml", f"{body['id']}_temperature.svg")


TEMPERATURE_EXPORTERS = {
    "px4": to_px4_params,
    "ardupilot": to_ardupilot_parm,
    "json": to_temperature_json,
    "temperature_svg": to_temperature_svg,
}
