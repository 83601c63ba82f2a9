"""Paste-ready examples of applying a stored calibration: lines of C at file scope over the C header (C89
and later: a function ``trical_<sensor>_calibrate`` per sensor around the header's ``trical_<sensor>_apply``,
the call for one reading in a comment), of Python over the JSON export, of JavaScript for a phone app over the
JSON export, each for the calibration's own sensor and unit.

A board's driver gives int16 counts; the C header maps the unit the calibration was made in (g, µT,
or counts when no scale was known). Where the calibration was not made in counts, the example first
scales the counts into that unit: by the part the upload named (``chip``, ``lsb_per_g``), else by
a constant the person sets from the datasheet, its line saying so.
"""

from __future__ import annotations

import numpy as np

from app.calibration import STANDARD_GRAVITY
from app.calibration.shared.headlines import SENSOR_WORDS

from ..readers.chips import CHIPS
from .common import result_class, sensor_corrections, unit_label
from .params import firmware_figures

_EXAMPLE_SCALE = {
    "acc": (16384.0, "16384 counts per g of an MPU-6050 at ±2 g (its datasheet, section 6.2)", "g"),
    "mag": (0.15, "0.15 µT per count of an AK8963 at 16 bit (its datasheet)", "uT"),
    "gyr": (131.0, "131 counts per °/s of an MPU-6050 at ±250 °/s (its datasheet, section 6.1)", "deg/s"),
}
"""A common part's sensitivity, offered when the calibration does not say which part it is."""


def _c_float(v: float) -> str:
    text = f"{v:.9g}"
    return (text if "e" in text or "." in text else text + ".0") + "f"


def input_scale(sensor: str, unit: str | None, read_with: dict | None, scales: dict | None = None) -> dict | None:
    """How the numbers a driver gives for ``sensor`` become the calibration's input ``unit``: ``{"op": "/" or
    "*", "value", "words", "known"}``; None when the input is already counts (``raw``), or the recording's
    numbers were in that unit.

    ``scales`` are the recording's (:attr:`app.io.log.LogData.scales`): the scale its numbers were read with, the
    part's, the counts per g or gauss's, never another part's; a sensor absent from them was read in its unit (a
    board printing g or µT, a phone's m/s²). Without them (a recording deleted, or stored before they were kept),
    the part the upload named, else a common part's figure the person sets."""
    if unit in (None, "raw"):
        return None
    if scales is not None:
        scale = scales.get(sensor)
        return None if scale is None else {**scale, "known": True}
    read_with = read_with or {}
    for name in str(read_with.get("chip") or "").split(","):
        chip = CHIPS.get(name.strip())
        if chip is not None and chip.sensor == sensor and chip.unit == unit:
            if sensor == "mag":
                return {"op": "*", "value": chip.scale, "words": f"the {chip.label}", "known": True}
            return {"op": "/", "value": 1.0 / chip.scale, "words": f"the {chip.label}", "known": True}
    if sensor == "acc" and unit == "g" and read_with.get("lsb_per_g"):
        return {
            "op": "/",
            "value": float(read_with["lsb_per_g"]),
            "words": "the counts per g the upload gave",
            "known": True,
        }
    value, words, example_unit = _EXAMPLE_SCALE.get(sensor, (None, None, None))
    if value is None or unit != example_unit:
        return None
    return {
        "op": "*" if sensor == "mag" else "/",
        "value": value,
        "known": False,
        "words": f"{words}: set your part's figure",
    }


def _sample(c, scale: dict | None, field_ut: float | None) -> list[float]:
    """What the sensor reads at rest with its z axis up, as the driver gives it (counts when a scale
    applies): the reading that calibrates to (0, 0, g), or (0, 0, F) for the compass."""
    up = {"g": 1.0, "m/s^2": STANDARD_GRAVITY}.get(c.output_unit, 0.0)
    if c.sensor == "mag":
        up = field_ut or 50.0
    elif c.sensor == "gyr":
        up = 0.0
    rest = c.o + np.linalg.solve(c.M, np.array([0.0, 0.0, up]))
    if scale is not None:
        rest = rest * scale["value"] if scale["op"] == "/" else rest / scale["value"]
    if (scale is not None and _read_in(scale) == "counts") or c.input_unit == "raw":
        return [float(v) for v in np.round(rest)]
    return [float(f"{v:.6g}") for v in rest]


def _read_in(scale: dict) -> str:
    """What a driver's numbers are before the scale: counts, or another unit (gauss)."""
    return scale.get("read_in", "counts")


def _c_lines(c, scale: dict | None, sample: list[float]) -> list[str]:
    """One sensor's C lines at file scope (C89 and later): a function ``trical_<sensor>_calibrate`` that takes
    a reading as the driver gives it (int16 counts, or floats in the header's unit) and calibrates it with the
    header's ``trical_<sensor>_apply``, then, in a comment, the call for one reading (what the sensor reads at
    rest with z up)."""
    name = f"trical_{c.sensor}"
    out, unit_in = unit_label(c.output_unit), unit_label(c.input_unit)
    if scale is None and c.input_unit != "raw":
        numbers = ", ".join(_c_float(v) for v in sample)
        return [
            f"/* One {SENSOR_WORDS[c.sensor]} reading m in {unit_in}, as the header takes it, "
            f"calibrated into f, in {out}. */",
            f"void {name}_calibrate(const float m[3], float f[3])",
            "{",
            f"    {name}_apply(m, f);",
            "}",
            "/* For each reading, e.g. at rest with z up:",
            f" *     float m[3] = {{{numbers}}};",
            f" *     float f[3];  {name}_calibrate(m, f);",
            " */",
        ]
    if scale is None:
        body = [
            f"    m[{i}] = (float)raw[{i}];" + ("  /* the header takes counts, as calibrated */" if i == 0 else "")
            for i in range(3)
        ]
    else:
        k, op, read_in = _c_float(scale["value"]), scale["op"], _read_in(scale)
        body = [
            f"    m[{i}] = raw[{i}] {op} {k};" + (f"  /* {read_in} to {unit_in}: {scale['words']} */" if i == 0 else "")
            for i in range(3)
        ]
    read_in = "counts" if scale is None else _read_in(scale)
    counts = read_in == "counts"
    kind, values = ("int16_t", [str(int(v)) for v in sample]) if counts else ("float", [_c_float(v) for v in sample])
    return [
        f"/* One {SENSOR_WORDS[c.sensor]} reading from your driver, in {read_in}, calibrated into f, in {out}. */",
        f"void {name}_calibrate(const {kind} raw[3], float f[3])",
        "{",
        "    float m[3];",
        *body,
        f"    {name}_apply(m, f);",
        "}",
        "/* For each reading, e.g. at rest with z up:",
        f" *     {kind} raw[3] = {{{', '.join(values)}}};",
        f" *     float f[3];  {name}_calibrate(raw, f);",
        " */",
    ]


def usage_snippets(body: dict, read_with: dict | None = None, read_scales: dict | None = None) -> dict:
    """The examples of one calibration.

    Parameters
    ----------
    body : dict
        The stored calibration (``id``, ``model``, ``unit``, ``output_unit``).
    read_with : dict, optional
        What its recording was read with (``chip``, ``lsb_per_g``), to scale counts exactly.
    read_scales : dict, optional
        How its recording's numbers became each sensor's unit (:func:`input_scale`'s ``scales``).

    Returns
    -------
    dict
        ``c`` (lines at file scope over the C header, C89 and later: the ``#include`` lines, then each sensor's
        function ``trical_<sensor>_calibrate`` calling the header's ``trical_<sensor>_apply``, with the call for
        one reading in a comment), ``python`` (numpy
        over the JSON export), ``javascript`` (over the JSON export, for a phone app), ``functions``
        (the C functions by sensor), ``scales`` (how counts become each sensor's input unit; None
        where none applies) and ``corrections`` (each sensor's ``M``, ``o``, units and the source of
        the correction ``f = M (m − o)``: what the lines apply, as the page shows it), and ``firmware``
        (what ArduPilot's and PX4's offsets and scales reach: app.io.exports.params.firmware_figures).
    """
    corrections = sensor_corrections(body)
    if read_scales is None and body.get("source") == "phone":
        read_scales = {}  # a phone's readings come in their unit (m/s², rad/s, µT), never in a part's counts
    header = f"trical_{body['id']}.h"
    json_name = f"{body['id']}.json"
    cube = result_class(body).PER_SENSOR
    c_blocks, py_lines, js_lines, scales = [], [], [], {}
    py_lines += ["import json", "import numpy as np", f'cal = json.load(open("{json_name}"))']
    js_lines += [f'const cal = await (await fetch("{json_name}")).json();  // the JSON file, served with your app']
    for c in corrections:
        scale = input_scale(c.sensor, c.input_unit, read_with, read_scales)
        scales[c.sensor] = scale
        sample = _sample(c, scale, (body.get("metrics") or {}).get("field_ut"))
        c_blocks += ["", *_c_lines(c, scale, sample)]
        where = f'cal["corrections"]["{c.sensor}"]' if cube else 'cal["correction"]'
        numbers = ", ".join(f"{v:g}" for v in sample)
        to_unit = ""
        if scale is not None:
            to_unit = (
                f" {scale['op']} {scale['value']:g}  # {_read_in(scale)} to {unit_label(c.input_unit)}: "
                f"{scale['words']}"
            )
        suffix = "" if len(corrections) == 1 else f"_{c.sensor}"
        py_lines += [
            f"M{suffix}, o{suffix} = np.array({where}['M']), np.array({where}['o'])".replace("'", '"'),
            f"m{suffix} = np.array([{numbers}]){to_unit or f'  # one reading in {unit_label(c.input_unit)}'}",
            f"f{suffix} = M{suffix} @ (m{suffix} - o{suffix})  # calibrated, in {unit_label(c.output_unit)}",
        ]
        js_where = f"cal.corrections.{c.sensor}" if cube else "cal.correction"
        names = f"M: M{suffix}, o: o{suffix}" if suffix else "M, o"
        js_lines += [
            f"const {{ {names} }} = {js_where};",
            f"const m{suffix} = [{numbers}];  // one reading from the {SENSOR_WORDS[c.sensor]}, in "
            f"{unit_label(c.input_unit) if scale is None else _read_in(scale) + ': scale it as below'}",
        ]
        if scale is not None:
            js_lines.append(
                f"const s{suffix} = m{suffix}.map((v) => v {scale['op']} {scale['value']:g});  "
                f"// {_read_in(scale)} to {unit_label(c.input_unit)}: {scale['words']}"
            )
        arg = f"s{suffix}" if scale is not None else f"m{suffix}"
        js_lines.append(
            f"const f{suffix} = M{suffix}.map((row) => row.reduce((sum, k, j) => sum + k * ({arg}[j] - "
            f"o{suffix}[j]), 0));  // calibrated, in {unit_label(c.output_unit)}"
        )
    corrections_out = {
        c.sensor: {
            "M": c.M.tolist(),
            "o": c.o.tolist(),
            "input_unit": c.input_unit,
            "output_unit": c.output_unit,
            "source": c.source,
        }
        for c in corrections
    }
    counts = any(  # int16_t
        ((scale := scales[c.sensor]) is not None and _read_in(scale) == "counts") or c.input_unit == "raw"
        for c in corrections
    )
    c_lines = ["#include <stdint.h>  /* int16_t */", f'#include "{header}"'] if counts else [f'#include "{header}"']
    c_lines += c_blocks
    return {
        "corrections": corrections_out,
        "c": "\n".join(c_lines),
        "python": "\n".join(py_lines),
        "javascript": "\n".join(js_lines),
        "functions": {c.sensor: f"trical_{c.sensor}_apply" for c in corrections},
        "calibrate": {c.sensor: f"trical_{c.sensor}_calibrate" for c in corrections},
        "scales": scales,
        "firmware": firmware_figures(body),
    }
