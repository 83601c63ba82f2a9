"""Every recording uploads (issue 22, point 2): any subset of the nine axes, with or without a time column,
temperature and other columns, in any header spelling and unit — the upload answers 201 or a 4xx that names
the problem, and so does every method on what was uploaded; never a 500.

A property test (hypothesis) through the real upload endpoint and the real calibration endpoint; its
examples are drawn deterministically (``derandomize``), :data:`EXAMPLES` of them.
"""

from __future__ import annotations

import io

import numpy as np
from fastapi.testclient import TestClient
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from app.main import create_app
from tests.conftest import make_settings

EXAMPLES = 120
"""Examples drawn: each uploads one file and runs the nine methods on it
(about 20 s in all on a shared 2-core machine)."""

AXES = "xyz"
SPELLINGS = {  # how loggers name the axes of each sensor
    "acc": ("acc_{a}", "a{a}", "Acceleration {a}", "accel{A}", "{a}", "AccelerometerAcceleration{A}"),
    "gyr": ("gyr_{a}", "g{a}", "gyro{A}", "Gyroscope {a}", "w{a}", "rotation_rate_{a}"),
    "mag": ("mag_{a}", "m{a}", "Magnetic field {a}", "mag{A}", "b{a}"),
}
# The name the data are in, how a header may spell it, and what one reading at rest is of.
UNITS = {
    "acc": {"m/s^2": ("m/s^2", "m/s²"), "g": ("g",), "raw": ("raw", "lsb")},
    "gyr": {"rad/s": ("rad/s",), "deg/s": ("deg/s", "dps", "°/s"), "raw": ("raw", "counts")},
    "mag": {"uT": ("uT", "µT"), "nT": ("nT",), "raw": ("raw",)},
}
SCALE = {
    "acc": {"m/s^2": 9.81, "g": 1.0, "raw": 16384.0},
    "gyr": {"rad/s": 1.0, "deg/s": 57.3, "raw": 131.0 * 57.3},
    "mag": {"uT": 48.0, "nT": 48_000.0, "raw": 48.0 / 0.15},
}
METHODS = (
    {"method": "auto"},
    {"method": "six_position"},
    {"method": "orientations"},
    {"method": "nonorthogonal"},
    {"method": "triangular"},
    {"method": "cube", "field_ut": 48.0},
    {"method": "autocal"},
    {"method": "noise"},
    {"method": "magnetometer"},
)
NEEDS = {
    "six_position": "acc",
    "orientations": "acc",
    "nonorthogonal": "acc",
    "triangular": "acc",
    "cube": "acc",
    "autocal": "acc",
    "magnetometer": "mag",
}
WORDS = {"acc": "accelerometer", "mag": "magnetometer", "gyr": "gyroscope"}
TIMES = (None, ("t", 1.0), ("time_ms", 1e3), ("timestamp", 1e6), ("time", "bursty_ms"))
EXTRA = ("temperature", "temp (C)", "pressure", "label", "i")


@st.composite
def recordings(draw):
    """A CSV log: columns, spellings, units, the kind of motion, a time column and extra columns."""
    # Whole sensors (often) and stray axes of others (sometimes): any subset of the nine axes.
    whole = draw(st.sets(st.sampled_from(list(SPELLINGS))))
    stray = draw(st.sets(st.sampled_from([f"{s}_{a}" for s in SPELLINGS for a in AXES]), max_size=2))
    axes = {f"{s}_{a}" for s in whole for a in AXES} | stray
    if not axes:
        axes = {draw(st.sampled_from([f"{s}_{a}" for s in SPELLINGS for a in AXES]))}
    sensors = [s for s in SPELLINGS if any(x.startswith(s) for x in axes)]
    spelling = {s: draw(st.sampled_from(SPELLINGS[s])) for s in sensors}
    unit = {s: draw(st.sampled_from(list(UNITS[s]))) for s in sensors}
    in_header = {s: draw(st.sampled_from((None, *UNITS[s][unit[s]]))) for s in sensors}
    n = draw(st.sampled_from((1, 3, 40, 700, 2400)))
    motion = draw(st.sampled_from(("still", "poses", "turning")))
    time = draw(st.sampled_from(TIMES))
    extra = draw(st.lists(st.sampled_from(EXTRA), unique=True, max_size=2))
    seed = draw(st.integers(0, 2**16))
    return dict(
        axes=sorted(axes),
        spelling=spelling,
        unit=unit,
        in_header=in_header,
        n=n,
        motion=motion,
        time=time,
        extra=extra,
        seed=seed,
    )


def _directions(rng, n: int, motion: str) -> np.ndarray:
    if motion == "still":
        return np.tile([0.0, 0.0, 1.0], (n, 1))
    if motion == "poses":  # six rests, 100 samples of turn between them
        ups = np.repeat(np.vstack([np.eye(3), -np.eye(3)]), -(-n // 6), axis=0)[:n]
        return ups / np.linalg.norm(ups, axis=1, keepdims=True)
    d = np.cumsum(rng.normal(scale=0.05, size=(n, 3)), axis=0) + [0.0, 0.0, 1.0]
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def _csv(case: dict) -> bytes:
    rng = np.random.default_rng(case["seed"])
    n = case["n"]
    up = _directions(rng, n, case["motion"])
    names, columns = [], []
    if case["time"] is not None:
        name, scale = case["time"]
        if scale == "bursty_ms":
            from simulations.serial import host_arrival_times

            t = host_arrival_times(rng, n_samples=n, sampling_rate_hz=100.0) * 1e3 if n > 1 else np.zeros(1)
        else:
            t = np.arange(n) / 100.0 * scale
        names.append(name)
        columns.append(np.round(t, 3))
    for axis_name in case["axes"]:
        sensor, axis = axis_name.split("_")
        k = AXES.index(axis)
        unit = case["unit"][sensor]
        value = SCALE[sensor][unit] * (up[:, k] if sensor != "gyr" else rng.normal(scale=0.01, size=n))
        value = value + rng.normal(scale=0.01 * SCALE[sensor][unit], size=n)
        label = case["spelling"][sensor].format(a=axis, A=axis.upper())
        if case["in_header"][sensor]:
            label += f" ({case['in_header'][sensor]})"
        names.append(label)
        columns.append(np.round(value) if unit == "raw" else value)
    for name in case["extra"]:
        names.append(name)
        columns.append(25.0 + rng.normal(scale=0.1, size=n) if "temp" in name else np.arange(n, dtype=float))
    buf = io.StringIO()
    np.savetxt(buf, np.column_stack(columns), delimiter=",", header=",".join(names), comments="", fmt="%.6g")
    return buf.getvalue().encode()


def _refusal_is_plain(r) -> str:
    assert r.status_code < 500, f"{r.status_code}: {r.text}"
    body = r.json()
    assert r.status_code in (201, 413, 415, 422), r.text
    if r.status_code != 201:
        assert body["code"] != "internal_error" and len(body["detail"]) > 20, body
        assert "Traceback" not in body["detail"] and "shape" not in body["detail"], body["detail"]
    return body.get("detail", "")


def _check(client, case: dict, seen: dict) -> None:
    """One drawn log through the upload, then every method on it."""
    seen["cases"] += 1
    r = client.post("/api/v1/recordings", files={"file": ("board.csv", _csv(case), "text/csv")})
    detail = _refusal_is_plain(r)
    complete = {s for s in SPELLINGS if all(f"{s}_{a}" in case["axes"] for a in AXES)}
    if r.status_code != 201:
        if not complete:  # no sensor with its three axes: the refusal says what to name
            assert "acc_x" in detail, detail
        return
    rec = r.json()
    seen["uploaded"] += 1
    assert set(rec["channels"]) <= complete and rec["channels"], (rec["channels"], complete)
    assert rec["overview"]["sensor"] in rec["channels"]
    assert (rec["sampling_rate_hz"] is None) == (case["time"] is None or case["n"] < 2)
    for request in METHODS:
        r = client.post("/api/v1/calibrations", json={**request, "recording_id": rec["id"]})
        detail = _refusal_is_plain(r)
        seen["calibrated" if r.status_code == 201 else "refused"] += 1
        needs = NEEDS.get(request["method"])
        if needs and needs not in rec["channels"]:  # refused by the name of the sensor it lacks
            assert r.status_code == 422 and WORDS[needs] in detail, (request, detail)
        if request["method"] == "noise" and rec["sampling_rate_hz"] is None:  # the one method here that needs it
            assert r.status_code == 422 and "sampling rate" in detail, (request, detail)


def test_any_columns_upload_and_every_method_answers_without_a_500(tmp_path):
    seen = {"cases": 0, "uploaded": 0, "calibrated": 0, "refused": 0}
    with TestClient(create_app(make_settings(tmp_path)), raise_server_exceptions=False) as client:

        @settings(
            max_examples=EXAMPLES,
            deadline=None,
            derandomize=True,
            database=None,
            suppress_health_check=[HealthCheck.too_slow],
        )
        @given(case=recordings())
        def check(case):
            _check(client, case, seen)

        check()
    # Every drawn case was tried, and the draws reached both outcomes of the upload and of the methods.
    assert seen["cases"] >= EXAMPLES
    assert seen["uploaded"] > EXAMPLES // 3 and seen["calibrated"] > 0 and seen["refused"] > 0, seen
    print(f"\nproperty test: {seen}")
