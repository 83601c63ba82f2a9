"""Full-matrix text exports: a flat YAML document and a CSV table of ``o`` and ``M``.

Both carry every number as Python's shortest round-trip decimal (``repr``), so a reader gets the
exact float64 correction ``a = M (m − o)``.  The YAML is written by hand (it is flat): strings are
double-quoted JSON strings and sequences are flow sequences, so any YAML 1.1 or 1.2 parser reads it,
and so does a line-by-line ``key: json`` reader.
"""

from __future__ import annotations

import csv
import io
import json
import math

from app.calibration.shared.headlines import SENSOR_WORDS

from ..errors import ExportError
from .common import FRAME, JSON_SCHEMA, Export, describe, sensor_corrections


def yaml_number(v: float) -> str:
    """A float that YAML 1.1 (PyYAML) and 1.2 both read as a float: repr, with a dot in the mantissa."""
    if not math.isfinite(v):
        raise ExportError(f"the correction holds a non-finite number ({v}): the calibration is degenerate")
    text = repr(float(v))
    mantissa, _, exponent = text.partition("e")
    if "." not in mantissa:
        mantissa += ".0"
    return mantissa + ("e" + exponent if exponent else "")


def _yaml_value(v) -> str:
    if v is None:
        return "null"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return yaml_number(float(v)) if isinstance(v, float) else str(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_yaml_value(x) for x in v) + "]"
    return json.dumps(str(v), ensure_ascii=False)


def _prefix(sensor: str) -> str:
    """Keys of the accelerometer stay unprefixed (``offset``, ``matrix``); the cube's other sensors
    carry theirs (``gyr_offset``, ``mag_matrix``)."""
    return "" if sensor == "acc" else f"{sensor}_"


def to_yaml(body: dict) -> Export:
    """A flat YAML document: identity, units, frame, gravity and each sensor's correction ``M``, ``o``."""
    corrections = sensor_corrections(body)
    fields = {
        "schema": JSON_SCHEMA,
        "schema_version": 1,
        "id": body["id"],
        "method": body["method"],
        "created_at": body["created_at"],
        "device_id": body.get("device_id"),
        "sensor": ", ".join(SENSOR_WORDS[c.sensor] for c in corrections),
        "frame": FRAME,
        "input_unit": body.get("unit"),
        "output_unit": body.get("output_unit"),
        "gravity": None if body.get("gravity") is None else float(body["gravity"]),
        "formula": "a = M (m - o)",
        "source": corrections[0].source,
    }
    for c in corrections:
        p = _prefix(c.sensor)
        if p:
            fields[p + "input_unit"], fields[p + "output_unit"] = c.input_unit, c.output_unit
        fields[p + "offset"] = [float(v) for v in c.o]
        fields[p + "matrix"] = [[float(v) for v in row] for row in c.M]
    lines = [f"# {c}" for c in describe(body, corrections[0].source)]
    lines += [f"{k}: {_yaml_value(v)}" for k, v in fields.items()]
    return Export("\n".join(lines) + "\n", "application/yaml", f"trical_{body['id']}.yaml")


def to_csv(body: dict) -> Export:
    """A CSV table: the row ``offset`` holds ``o``, rows ``M_x``, ``M_y``, ``M_z`` the rows of ``M``
    (a cube calibration's gyroscope and magnetometer rows are prefixed ``gyr_``, ``mag_``)."""
    corrections = sensor_corrections(body)
    for c in corrections:
        for v in [*c.o, *c.M.ravel()]:
            yaml_number(float(v))  # refuses non-finite numbers
    out = io.StringIO()
    for line in describe(body, corrections[0].source) + [
        "a = M (m - o): row offset is o, rows M_x, M_y, M_z are the rows of M"
    ]:
        out.write(f"# {line}\n")
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["quantity", "x", "y", "z"])
    for c in corrections:
        p = _prefix(c.sensor)
        writer.writerow([p + "offset", *(repr(float(v)) for v in c.o)])
        for axis, row in zip("xyz", c.M):
            writer.writerow([f"{p}M_{axis}", *(repr(float(v)) for v in row)])
    return Export(out.getvalue(), "text/csv", f"trical_{body['id']}.csv")
