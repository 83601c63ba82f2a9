"""Exports of a noise characterisation (method ``noise``): the figures navigation filters take.

- ``kalibr``: Kalibr's ``imu.yaml`` (``accelerometer_noise_density``, ``accelerometer_random_walk``,
  ``gyroscope_noise_density``, ``gyroscope_random_walk``, ``update_rate``);
- ``openvins``: the same figures in OpenVINS's ``kalibr_imu_chain.yaml`` (``imu0: …``);
- ``vins``: VINS-Fusion's names ``acc_n``, ``gyr_n``, ``acc_w``, ``gyr_w``;
- ``json``: units, figures, intervals and the Allan table; ``csv``: the Allan table.

The filters take one figure per sensor: the largest of the three axes (the conservative choice).
"""

from __future__ import annotations

import csv
import io
import json

from ..errors import ExportError
from .allan_plot import to_allan_svg
from .common import JSON_SCHEMA, Export

NOISE_FORMATS = {
    "kalibr": "Kalibr imu.yaml",
    "openvins": "OpenVINS",
    "vins": "VINS-Fusion",
    "json": "JSON",
    "csv": "CSV (Allan table)",
    "allan_svg": "Allan plot (SVG)",
}


def _figure(body: dict, sensor: str, term: str) -> float:
    values = (body["model"].get(sensor) or {}).get(term)
    if values is None:
        raise ExportError(
            f"this noise characterisation has no {sensor} samples, which the {term} of this export "
            "needs: record the accelerometer and the gyroscope together, or use the json or csv export"
        )
    if any(v is None for v in values):
        raise ExportError(
            f"{sensor} {term} is null on some axes (the recording is too short to see it: see its "
            "warnings): record longer, or use the json or csv export"
        )
    return float(max(values))


def _filter_figures(body: dict) -> dict:
    return {(s, t): _figure(body, s, t) for s in ("acc", "gyr") for t in ("noise_density", "random_walk")}


def _header(body: dict) -> str:
    return (
        f"# trical noise characterisation {body['id']} ({body['created_at']}), device {body.get('device_id') or '-'}\n"
        f"# {body['duration_s']:.1f} s still at {body['sampling_rate_hz']:g} Hz; the largest axis of each figure;\n"
        "# continuous-time units: m/s^2/sqrt(Hz), m/s^3/sqrt(Hz), rad/s/sqrt(Hz), rad/s^2/sqrt(Hz)\n"
    )


def _kalibr_lines(body: dict, indent: str = "") -> str:
    """Kalibr's IMU keys, one a line."""
    f = _filter_figures(body)
    keys = {"rostopic": "/imu0", "update_rate": f"{body['sampling_rate_hz']:.6g}"}
    for sensor, word in (("acc", "accelerometer"), ("gyr", "gyroscope")):
        for term in ("noise_density", "random_walk"):
            keys[f"{word}_{term}"] = f"{f[sensor, term]:.6e}"
    return "".join(f"{indent}{k}: {v}\n" for k, v in keys.items())


def to_kalibr(body: dict) -> Export:
    return Export(_header(body) + _kalibr_lines(body), "application/yaml", "imu.yaml")


def to_openvins(body: dict) -> Export:
    text = "%YAML:1.0\n" + _header(body) + "imu0:\n" + _kalibr_lines(body, "  ")
    return Export(text, "application/yaml", "kalibr_imu_chain.yaml")


def to_vins(body: dict) -> Export:
    f = _filter_figures(body)
    text = _header(body) + (
        f"acc_n: {f['acc', 'noise_density']:.6e}\n"
        f"gyr_n: {f['gyr', 'noise_density']:.6e}\n"
        f"acc_w: {f['acc', 'random_walk']:.6e}\n"
        f"gyr_w: {f['gyr', 'random_walk']:.6e}\n"
    )
    return Export(text, "application/yaml", "vins_imu.yaml")


def to_noise_json(body: dict) -> Export:
    doc = {
        "$schema": JSON_SCHEMA,
        "schema_version": 1,
        "id": body["id"],
        "method": "noise",
        "created_at": body["created_at"],
        "device_id": body.get("device_id"),
        "label": body.get("label"),
        "sampling_rate_hz": body["sampling_rate_hz"],
        "duration_s": body["duration_s"],
        "model": body["model"],
        "uncertainty": body["uncertainty"],
        "adev": body["adev"],
        "metrics": body.get("metrics"),
        "ok": body.get("ok"),
        "warnings": body.get("warnings", []),
    }
    return Export(json.dumps(doc, indent=2), "application/json", f"{body['id']}.json")


def to_allan_csv(body: dict) -> Export:
    sensors = [s for s in ("acc", "gyr", "mag") if s in body["adev"]]
    tau = body["adev"][sensors[0]]["tau_s"]
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(["tau_s"] + [f"{s}_{a}" for s in sensors for a in "xyz"])
    for i, t in enumerate(tau):
        w.writerow([f"{t:.9g}"] + [f"{v:.9g}" for s in sensors for v in body["adev"][s]["value"][i]])
    return Export(out.getvalue(), "text/csv", f"{body['id']}_allan.csv")


NOISE_EXPORTERS = {
    "kalibr": to_kalibr,
    "openvins": to_openvins,
    "vins": to_vins,
    "json": to_noise_json,
    "csv": to_allan_csv,
    "allan_svg": to_allan_svg,
}
