"""Exports of a stored calibration for firmware and analysis code.

Every export of an affine calibration carries the correction in the form firmware applies,
``a = M (m − o)`` with ``M = X⁻¹`` and ``o = y`` (Georgieva et al., ESGI'95, eq. (20)).
"""

from __future__ import annotations

import json
import re

from app.calibration.shared.headlines import SENSOR_WORDS
from app.calibration.shared.result import DRIFT, FIGURES

from ..errors import ExportError
from ..plural import counted
from .cli_sets import ACCELEROMETER_ONLY, to_betaflight, to_inav
from .common import FRAME, JSON_SCHEMA, Export, result_class, sensor_corrections, unit_label
from .compass import FLIGHT_COMPASS_EXPORTS, FLIGHT_COMPASS_METHOD, export_flight_compass
from .noise import NOISE_EXPORTERS, NOISE_FORMATS
from .params import to_ardupilot, to_px4
from .tables import to_csv, to_yaml
from .temperature import TEMPERATURE_EXPORTERS, TEMPERATURE_FORMATS


def to_json(body: dict) -> Export:
    """Versioned JSON: units, frame, gravity, counts, intervals, method, created_at, device_id; a ``gyroscope``
    block (bias and its 95 % half-width, rad/s) when the calibration has a ``gyroscope_bias``."""
    doc = {
        "$schema": JSON_SCHEMA,
        "schema_version": 1,
        "id": body["id"],
        "method": body["method"],
        "created_at": body["created_at"],
        "device_id": body.get("device_id"),
        "label": body.get("label"),
        "sensor": "accelerometer",
        "frame": FRAME,
        "input_unit": body.get("unit"),
        "output_unit": body.get("output_unit"),
        "gravity": body.get("gravity"),
        "model": body["model"],
        "uncertainty": body.get("uncertainty"),
        "metrics": body.get("metrics"),
        "count": (body.get("metrics") or {}).get("count"),
        "ok": body.get("ok"),
        "warnings": body.get("warnings", []),
    }
    corrections = sensor_corrections(body)
    if result_class(body).PER_SENSOR:  # the cube: one correction per sensor (Särkkä et al., eq. (1))
        doc["sensor"] = ", ".join(SENSOR_WORDS[c.sensor] for c in corrections)
        doc["corrections"] = {
            c.sensor: {
                "formula": "f = M (m - o)",
                "M": c.M.tolist(),
                "o": c.o.tolist(),
                "input_unit": c.input_unit,
                "output_unit": c.output_unit,
                "source": c.source,
            }
            for c in corrections
        }
    elif corrections[0].sensor == "mag":  # the compass: h = M (m − b), o = b the hard iron
        c = corrections[0]
        doc["sensor"] = SENSOR_WORDS["mag"]
        doc["correction"] = {
            "formula": "h = M (m - o), o = b (hard iron)",
            "M": c.M.tolist(),
            "o": c.o.tolist(),
            "source": c.source,
        }
    else:
        c = corrections[0]
        doc["correction"] = {"formula": "a = M (m - o)", "M": c.M.tolist(), "o": c.o.tolist(), "source": c.source}
    if body.get("read_from"):  # what a device's own calibration was read from (app.io.imports)
        doc["read_from"] = body["read_from"]
    gyro = body.get("gyroscope_bias")
    if gyro:  # a wizard session's still captures (app.calibration.still.gyro_bias)
        doc["gyroscope"] = {
            "formula": "w = m - b",
            "unit": "rad/s",
            "bias": gyro["rad_s"],
            "half_width": gyro["half_width_rad_s"],
            "confidence": gyro["confidence"],
            "count": gyro["count"],
            "interval_from": gyro["interval_from"],
        }
    return Export(json.dumps(doc, indent=2), "application/json", f"{body['id']}.json")


def _c_number(v: float) -> str:
    # 9 significant digits round-trip an IEEE single exactly; 'f' makes it a float literal.
    text = f"{v:.9g}"
    if "e" not in text and "." not in text:
        text += ".0"
    return text + "f"


def _c_sensor(c) -> str:
    rows = ",\n".join("    {" + ", ".join(_c_number(v) for v in row) + "}" for row in c.M)
    name = f"trical_{c.sensor}"
    return f"""/* {SENSOR_WORDS[c.sensor]}: {unit_label(c.input_unit)} in, {unit_label(c.output_unit)} out */
static const float {name}_offset[3] = {{{", ".join(_c_number(v) for v in c.o)}}};

static const float {name}_matrix[3][3] = {{
{rows}
}};

/* Calibrate one raw reading m into f = M (m - o). */
static TRICAL_INLINE void {name}_apply(const float m[3], float f[3])
{{
    float d[3];
    int i;
    for (i = 0; i < 3; ++i) d[i] = m[i] - {name}_offset[i];
    for (i = 0; i < 3; ++i)
        f[i] = {name}_matrix[i][0] * d[0] + {name}_matrix[i][1] * d[1] + {name}_matrix[i][2] * d[2];
}}
"""


def to_c_header(body: dict) -> Export:
    """A C header (C89 and later: it builds with ``gcc -std=c89 -pedantic``) with each sensor's correction
    matrix, offset and an apply function (inline where the compiler has it), and
    ``TRICAL_GYRO_BIAS_RAD_S`` when the calibration has a ``gyroscope_bias``."""
    corrections = sensor_corrections(body)
    guard = "TRICAL_" + re.sub(r"[^A-Za-z0-9]", "_", body["id"]).upper() + "_H"
    sensors = "\n".join(_c_sensor(c) for c in corrections)
    gyro = body.get("gyroscope_bias")
    if gyro:  # a wizard session's still captures (app.calibration.still.gyro_bias)
        half = ", ".join(f"{v:.3g}" for v in gyro["half_width_rad_s"])
        sensors += (
            f"\n/* gyroscope bias at rest, rad/s, over {counted(gyro['count'], 'still capture')} (95 % half-widths "
            f"{half}): w = m - TRICAL_GYRO_BIAS_RAD_S */\n"
            f"#define TRICAL_GYRO_BIAS_RAD_S {{{', '.join(_c_number(v) for v in gyro['rad_s'])}}}\n"
        )
    unit_in, unit_out = unit_label(body.get("unit")), unit_label(body.get("output_unit"))
    text = f"""/* trical calibration {body["id"]}
 * method: {body["method"]}, created {body["created_at"]}, device: {body.get("device_id") or "-"}
 * input unit: {unit_in}, output unit: {unit_out}, gravity: {body.get("gravity")}
 * calibrated f = M (m - o): {corrections[0].source}
 */
#ifndef {guard}
#define {guard}

/* inline where the compiler has it (C99, or GCC's __inline__ in C89), so that an apply function left unused
 * costs nothing and warns of nothing; plain static in strict C89 elsewhere. */
#ifndef TRICAL_INLINE
#if defined(__STDC_VERSION__) && __STDC_VERSION__ >= 199901L
#define TRICAL_INLINE inline
#elif defined(__GNUC__)
#define TRICAL_INLINE __inline__
#else
#define TRICAL_INLINE
#endif
#endif

{sensors}
#endif /* {guard} */
"""
    return Export(text, "text/x-c", f"trical_{body['id']}.h")


def to_motioncal(body: dict) -> Export:
    """MotionCal's 68-byte calibration packet (app.io.exports.motioncal_packet), for a board running Adafruit's
    Sensor Calibration library: the offsets, and the compass's hard iron, field and soft iron; the
    notes say what it does not carry (the accelerometer's scales and cross terms)."""
    from .motioncal_packet import packet_of

    packet, notes = packet_of(body)
    return Export(packet, "application/octet-stream", f"trical_{body['id']}.motioncal", notes)


EXPORTERS = {
    "json": to_json,
    "c": to_c_header,
    "ardupilot": to_ardupilot,
    "px4": to_px4,
    "yaml": to_yaml,
    "csv": to_csv,
    "motioncal": to_motioncal,
    "betaflight": to_betaflight,
    "inav": to_inav,
}
"""Export formats by their query name."""

FORMAT_NAMES = {
    "json": "JSON",
    "c": "C header",
    "ardupilot": "ArduPilot",
    "px4": "PX4",
    "betaflight": "Betaflight",
    "inav": "INAV",
    "yaml": "YAML",
    "csv": "CSV",
}
"""The page's download links; ``motioncal`` (bytes for a board, not a file to keep) is left out: the page
writes it to the board with *Send to the board*, and the API and ``trical export`` give it."""

COMPASS_FORMAT_NAMES = {key: name for key, name in FORMAT_NAMES.items() if key not in ACCELEROMETER_ONLY}
"""The page's download links for a compass's calibration: the formats that carry a compass (:data:`FORMAT_NAMES` but
Betaflight's and INAV's, which the export refuses for it)."""

ALL_FORMATS = tuple(dict.fromkeys([*EXPORTERS, *NOISE_EXPORTERS, *TEMPERATURE_EXPORTERS, *FLIGHT_COMPASS_EXPORTS]))
"""Every format name of any calibration (the CLI's choices)."""

__all__ = [
    "ALL_FORMATS",
    "COMPASS_FORMAT_NAMES",
    "EXPORTERS",
    "FLIGHT_COMPASS_EXPORTS",
    "FORMAT_NAMES",
    "FRAME",
    "JSON_SCHEMA",
    "NOISE_FORMATS",
    "TEMPERATURE_FORMATS",
    "Export",
    "export_calibration",
]


def export_calibration(body: dict, fmt: str) -> Export:
    """Render a stored calibration in ``fmt``.

    Raises
    ------
    ExportError
        Unknown format, or a format that does not fit this calibration's model.
    """
    if body.get("method") == FLIGHT_COMPASS_METHOD:  # its model is a flight's, with a rotation and the motors' term
        return export_flight_compass(body, fmt)
    kind = result_class(body).KIND
    if kind == DRIFT:  # its own px4, ardupilot, json: the firmwares' thermal parameters
        if fmt not in TEMPERATURE_EXPORTERS:
            raise ExportError(
                f"format {fmt!r} does not fit this calibration: a temperature calibration's offsets "
                f"depend on the temperature; use one of {', '.join(TEMPERATURE_EXPORTERS)}"
            )
        return TEMPERATURE_EXPORTERS[fmt](body)
    noise = kind == FIGURES
    table, other = (NOISE_EXPORTERS, EXPORTERS) if noise else (EXPORTERS, NOISE_EXPORTERS)
    if fmt not in table:
        if fmt == "temperature_svg":
            raise ExportError(
                f"format {fmt!r} draws a temperature calibration (method temperature); use one of {', '.join(table)}"
            )
        if fmt in other:
            kind = (
                "a noise characterisation holds no correction to write"
                if noise
                else f"{fmt} writes a noise characterisation (method noise)"
            )
            raise ExportError(f"format {fmt!r} does not fit this calibration: {kind}; use one of {', '.join(table)}")
        raise ExportError(f"unknown export format {fmt!r}: use one of {', '.join(table)}")
    return table[fmt](body)
