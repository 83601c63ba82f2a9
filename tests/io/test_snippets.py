"""The paste-ready examples of /api/v1/calibrations/{id}/use, run for real: the C lines compiled by
gcc over the calibration's own C header and run on a reading, the Python lines run over its JSON export,
the JavaScript lines run by node over the same JSON; each must give what the API's apply gives."""

from __future__ import annotations

import json
import shutil
import sys

import numpy as np
import pytest

from tests.processes import run_ok

G = 9.80665
UPS = {"-x": [-1, 0, 0], "+x": [1, 0, 0], "-y": [0, -1, 0], "+y": [0, 1, 0], "-z": [0, 0, -1], "+z": [0, 0, 1]}
X_TRUE = np.array([[1.02, 0.004, -0.003], [0.002, 0.985, 0.006], [-0.004, 0.003, 1.01]])
Y_TRUE = np.array([0.021, -0.034, 0.045])  # g


def counts_log(lsb_per_g: float, seed: int) -> bytes:
    """Six still poses of an accelerometer logged in int16 counts at 100 Hz, 2 s each with a turn between."""
    rng = np.random.default_rng(seed)
    rows, t = [], 0.0
    for up in UPS.values():
        m = X_TRUE @ np.array(up, float) + Y_TRUE
        for k in range(300):
            moving = k >= 200  # a turn between the poses: not still
            g = m + (rng.normal(0, 0.2, 3) if moving else rng.normal(0, 0.002, 3))
            rows.append((t, *np.round(g * lsb_per_g)))
            t += 0.01
    return ("t,ax,ay,az\n" + "\n".join(f"{r[0]:.2f},{r[1]:.0f},{r[2]:.0f},{r[3]:.0f}" for r in rows)).encode()


def calibrate(client, content: bytes, **fields) -> dict:
    r = client.post("/api/v1/recordings", files={"file": ("six.csv", content, "text/csv")}, data=fields)
    assert r.status_code == 201, r.text
    r = client.post("/api/v1/calibrations", json={"method": "six_position", "recording_id": r.json()["id"]})
    assert r.status_code == 201, r.text
    return r.json()


C_FLAGS = ("-std=c89", "-pedantic", "-Wall", "-Wextra", "-Werror")
"""The C lines and the header build as C89 (no inline, no declaration after a statement, no // comment), every
warning an error; C99 and later accept C89."""


def example_reading(snippet: str, sensor: str = "acc") -> list[float]:
    """The reading the lines' comment calls ``trical_<sensor>_calibrate`` with (at rest, z up)."""
    block = snippet[snippet.index(f"trical_{sensor}_calibrate(") :]
    numbers = block.split("[3] = {")[1].split("}")[0]
    return [float(v.strip().rstrip("f")) for v in numbers.split(",")]


def run_c(client, cal: dict, snippet: str, tmp_path, sensor: str = "acc") -> np.ndarray:
    """The C lines as pasted at file scope over the exported header, and a main() that calls their function on
    the comment's reading and prints the result, built by gcc as C89 with every warning an error."""
    cc = shutil.which("gcc")
    assert cc, "gcc is needed to build the C example"
    header = client.get(f"/api/v1/calibrations/{cal['id']}/export", params={"format": "c"})
    (tmp_path / f"trical_{cal['id']}.h").write_text(header.text)
    reading = example_reading(snippet, sensor)
    counts = f"void trical_{sensor}_calibrate(const int16_t raw[3]" in snippet
    scaled_floats = f"void trical_{sensor}_calibrate(const float raw[3]" in snippet  # gauss, scaled into µT
    declare = (
        f"    int16_t raw[3] = {{{', '.join(str(int(v)) for v in reading)}}};"
        if counts
        else f"    float {'raw' if scaled_floats else 'm'}[3] = {{{', '.join(f'{v!r}f' for v in reading)}}};"
    )
    source = "\n".join(
        [
            "#include <stdio.h>",
            snippet,
            "",
            "int main(void)",
            "{",
            declare,
            "    float f[3];",
            f"    trical_{sensor}_calibrate({'raw' if counts or scaled_floats else 'm'}, f);",
            '    printf("%.9g %.9g %.9g\\n", f[0], f[1], f[2]);',
            "    return 0;",
            "}",
            "",
        ]
    )
    (tmp_path / "example.c").write_text(source)
    exe = tmp_path / "example"
    run_ok([cc, *C_FLAGS, "-I", str(tmp_path), "-o", str(exe), str(tmp_path / "example.c")], timeout_s=60)
    return np.array([float(v) for v in run_ok([str(exe)], timeout_s=10).stdout.split()])


def applied(client, cal: dict, reading) -> np.ndarray:
    r = client.post(f"/api/v1/calibrations/{cal['id']}/apply", json={"samples": [list(map(float, reading))]})
    assert r.status_code == 200, r.text
    return np.array(r.json()["samples"][0])


def json_export(client, cal, tmp_path):
    r = client.get(f"/api/v1/calibrations/{cal['id']}/export", params={"format": "json"})
    (tmp_path / f"{cal['id']}.json").write_text(r.text)


def test_counts_of_a_named_part_are_scaled_into_g_and_the_c_lines_compile_and_run(client, tmp_path):
    cal = calibrate(client, counts_log(8192, seed=24), chip="mpu6050-4g")
    assert cal["unit"] == "g"
    s = client.get(f"/api/v1/calibrations/{cal['id']}/use").json()
    assert s["functions"] == {"acc": "trical_acc_apply"}
    assert s["scales"]["acc"] == {
        "op": "/",
        "value": 8192.0,
        "known": True,
        "words": "the MPU-6050/6500/9250, ICM-20948 accelerometer ±4 g (8192 LSB/g)",
        "read_in": "counts",
    }
    lines = s["c"].splitlines()
    # File scope: the #include lines first, then a function, never an #include among a body's lines.
    assert lines[:2] == ["#include <stdint.h>  /* int16_t */", f'#include "trical_{cal["id"]}.h"']
    assert not any(line.startswith("#include") for line in lines[2:])
    assert (
        "void trical_acc_calibrate(const int16_t raw[3], float f[3])" in lines
        and "    trical_acc_apply(m, f);" in lines
    )
    assert "    m[0] = raw[0] / 8192.0f;" in s["c"]
    assert s["calibrate"] == {"acc": "trical_acc_calibrate"}
    raw = example_reading(s["c"])
    f = run_c(client, cal, s["c"], tmp_path)
    want = applied(client, cal, np.array(raw) / 8192.0)
    np.testing.assert_allclose(f, want, atol=1e-6)  # float32 in the C code, in g
    np.testing.assert_allclose(np.linalg.norm(f), 1.0, atol=2e-3)  # the reading at rest, z up: 1 g calibrated

    json_export(client, cal, tmp_path)
    out = run_ok([sys.executable, "-c", s["python"] + "\nprint(*f)"], timeout_s=60, cwd=tmp_path)
    np.testing.assert_allclose([float(v) for v in out.stdout.split()], want, atol=1e-12)
    node = shutil.which("node")
    assert node, "node is needed to run the JavaScript example"
    js = (
        "globalThis.fetch = async (name) => ({ json: async () => JSON.parse(require('fs').readFileSync(name)) });\n"
        "(async () => {\n" + s["javascript"] + "\nconsole.log(f.join(' '));\n})();\n"
    )
    (tmp_path / "example.js").write_text(js)
    out = run_ok([node, str(tmp_path / "example.js")], timeout_s=60, cwd=tmp_path)
    np.testing.assert_allclose([float(v) for v in out.stdout.split()], want, atol=1e-12)


def test_counts_of_an_unnamed_part_are_scaled_as_the_data_showed(client, tmp_path):
    cal = calibrate(client, counts_log(16384, seed=25))  # the data say counts of 16384 per g: into g
    s = client.get(f"/api/v1/calibrations/{cal['id']}/use").json()
    assert s["scales"]["acc"] == {
        "op": "/",
        "value": 16384.0,
        "known": True,
        "words": "16384 counts per g, as the data showed",
        "read_in": "counts",
    }
    raw = example_reading(s["c"])
    np.testing.assert_allclose(
        run_c(client, cal, s["c"], tmp_path), applied(client, cal, np.array(raw) / 16384.0), atol=2e-6
    )


def test_counts_kept_as_counts_go_in_as_they_are(client, tmp_path):
    cal = calibrate(client, counts_log(16384, seed=26), acc_unit="raw")
    assert cal["unit"] == "raw"
    s = client.get(f"/api/v1/calibrations/{cal['id']}/use").json()
    assert (
        s["scales"]["acc"] is None
        and "    m[0] = (float)raw[0];  /* the header takes counts, as calibrated */" in s["c"]
    )
    raw = example_reading(s["c"])
    f = run_c(client, cal, s["c"], tmp_path)
    np.testing.assert_allclose(f, applied(client, cal, raw), atol=2e-5)  # float32 of m/s²
    np.testing.assert_allclose(np.linalg.norm(f), G, rtol=2e-3)  # counts calibrate into m/s²


def test_a_phone_s_readings_in_m_s2_need_no_scale(client, tmp_path):
    readings = [{"up": up, "mean": (G * (X_TRUE @ np.array(v, float) + Y_TRUE)).tolist()} for up, v in UPS.items()]
    r = client.post("/api/v1/calibrations", json={"method": "six_position", "readings": readings})
    cal = r.json()
    s = client.get(f"/api/v1/calibrations/{cal['id']}/use").json()
    assert s["scales"]["acc"] is None and "int16_t" not in s["c"]
    assert "void trical_acc_calibrate(const float m[3], float f[3])" in s["c"].splitlines()
    f = run_c(client, cal, s["c"], tmp_path)
    m = example_reading(s["c"])
    np.testing.assert_allclose(f, applied(client, cal, m), atol=2e-5)
    np.testing.assert_allclose(f, [0, 0, G], atol=2e-3)  # the reading at rest, z up, calibrated


def test_a_phone_s_compass_turn_in_ut_needs_no_scale(client):
    """The compass page's turn (its readings sent as the phone read them, in µT; no recording to say so): the example
    reading is the phone's own µT, not a part's counts scaled."""
    from simulations.magnetometer import simulate_session

    m = simulate_session(5, n=300)[0]
    body = {"method": "magnetometer", "mag": m.tolist(), "field_ut": 48.0, "source": "phone"}
    cal = client.post("/api/v1/calibrations", json=body).json()
    s = client.get(f"/api/v1/calibrations/{cal['id']}/use").json()
    assert s["scales"]["mag"] is None and "counts" not in s["javascript"], s["javascript"]
    board = client.post("/api/v1/calibrations", json={**body, "source": "board"}).json()
    assert client.get(f"/api/v1/calibrations/{board['id']}/use").json()["scales"]["mag"]["known"] is False


@pytest.mark.parametrize("chip", ["qmc5883l-8g"])
def test_a_compass_in_counts_of_a_named_part_is_scaled_into_ut(client, tmp_path, chip):
    from tests.conftest import DATA

    content = (DATA / "real" / "magnetometer" / "tomisuarez2_qmc5883l_turn_every10.csv").read_bytes()
    r = client.post("/api/v1/recordings", files={"file": ("turn.csv", content, "text/csv")}, data={"chip": chip})
    assert r.status_code == 201, r.text
    r = client.post("/api/v1/calibrations", json={"method": "magnetometer", "recording_id": r.json()["id"]})
    assert r.status_code == 201, r.text
    cal = r.json()
    s = client.get(f"/api/v1/calibrations/{cal['id']}/use").json()
    assert s["functions"] == {"mag": "trical_mag_apply"} and s["scales"]["mag"]["op"] == "*"
    assert s["scales"]["mag"]["value"] == pytest.approx(100 / 3000)
    raw = example_reading(s["c"], "mag")
    np.testing.assert_allclose(
        run_c(client, cal, s["c"], tmp_path, "mag"),
        applied_mag(client, cal, np.array(raw) * s["scales"]["mag"]["value"]),
        atol=1e-3,
    )


def applied_mag(client, cal, reading):
    r = client.post(
        f"/api/v1/calibrations/{cal['id']}/apply", json={"samples": [list(map(float, reading))], "sensor": "mag"}
    )
    assert r.status_code == 200, r.text
    return np.array(r.json()["samples"][0])


def test_a_noise_characterisation_has_no_example_to_apply(client):
    r = client.get("/api/v1/calibrations/cal_0123456789abcdef0123456789abcdef/use")
    assert r.status_code == 404 and json.loads(r.text)["code"] == "not_found"


def test_the_triangular_model_s_o_is_applied_with_its_sign_turned(client, tmp_path):
    """Farago et al. write a = K (v + o): the correction the person applies is f = M (m − o) with M = K and
    o = −o_model, and the C lines, the JSON's correction and /use all carry that o."""
    from app.calibration.still.advice import fibonacci_sphere

    ups = fibonacci_sphere(14)
    means = [(G * (X_TRUE @ u) + G * Y_TRUE).tolist() for u in ups]
    r = client.post("/api/v1/calibrations", json={"method": "triangular", "means": means})
    assert r.status_code == 201, r.text
    cal = r.json()
    use = client.get(f"/api/v1/calibrations/{cal['id']}/use").json()
    c = use["corrections"]["acc"]
    np.testing.assert_allclose(c["M"], cal["model"]["K"], rtol=1e-12, atol=1e-15)  # K through correction_of
    np.testing.assert_allclose(c["o"], -np.array(cal["model"]["o"]), rtol=1e-12, atol=1e-12)
    doc = client.get(f"/api/v1/calibrations/{cal['id']}/export", params={"format": "json"}).json()
    assert doc["correction"]["o"] == c["o"] and doc["correction"]["M"] == c["M"]
    m = example_reading(use["c"])
    f = run_c(client, cal, use["c"], tmp_path)
    np.testing.assert_allclose(f, np.array(cal["model"]["K"]) @ (np.array(m) + np.array(cal["model"]["o"])), atol=2e-5)


def test_without_its_recording_a_common_part_s_figure_is_offered_to_set():
    """A calibration whose recording is gone (or was stored before the recording kept its scales): counts in g
    are scaled by a common part's figure, which the person is told to set."""
    from app.io.exports.snippets import input_scale

    scale = input_scale("acc", "g", None, None)
    assert scale["known"] is False and "set your part's figure" in scale["words"] and scale["value"] == 16384.0
    assert input_scale("acc", "g", None, {}) is None  # its recording read it in g: no scale


def test_a_compass_read_in_gauss_is_scaled_from_gauss_not_by_another_part_s_counts(client, tmp_path):
    """A real x-IMU whose header gives the magnetometer in gauss (G), read into µT (tests/data/real/corpus/
    ximu_packet_number_no_time): its lines take the driver's gauss and multiply by 100 — never an AK8963's
    0.15 µT per count, a 1.6x error for this board — and the C lines give what the API's apply gives."""
    from tests.conftest import DATA

    log = DATA / "real" / "corpus" / "ximu_packet_number_no_time" / "straightLine_CalInertialAndMag_excerpt.csv"
    r = client.post(
        "/api/v1/recordings", files={"file": (log.name, log.read_bytes(), "text/csv")}, data={"sampling_rate_hz": "256"}
    )
    assert r.status_code == 201 and r.json()["scales"]["mag"]["read_in"] == "gauss", r.text
    cal = client.post("/api/v1/calibrations", json={"method": "magnetometer", "recording_id": r.json()["id"]}).json()
    s = client.get(f"/api/v1/calibrations/{cal['id']}/use").json()
    assert s["scales"]["mag"] == {
        "op": "*",
        "value": 100.0,
        "known": True,
        "words": "100 µT per gauss",
        "read_in": "gauss",
    }
    assert "void trical_mag_calibrate(const float raw[3], float f[3])" in s["c"] and "int16_t" not in s["c"]
    raw = example_reading(s["c"], "mag")
    np.testing.assert_allclose(
        run_c(client, cal, s["c"], tmp_path, "mag"), applied_mag(client, cal, np.array(raw) * 100.0), atol=1e-3
    )


def test_a_board_printing_g_needs_no_scale(client, tmp_path):
    """A real board's six-position test printed in g (tests/data/real/corpus/tagged_lines_six_position): its
    lines take floats in g, not an MPU-6050's counts."""
    from tests.conftest import DATA

    folder = DATA / "real" / "corpus" / "tagged_lines_six_position"
    files = [
        ("file", (n, (folder / n).read_bytes(), "text/plain"))
        for n in ("up.txt", "down.txt", "left.txt", "right.txt", "front.txt", "back.txt")
    ]
    rec = client.post("/api/v1/recordings", files=files).json()
    assert rec["scales"] == {}
    cal = client.post("/api/v1/calibrations", json={"method": "six_position", "recording_id": rec["id"]}).json()
    s = client.get(f"/api/v1/calibrations/{cal['id']}/use").json()
    assert s["scales"]["acc"] is None and "void trical_acc_calibrate(const float m[3], float f[3])" in s["c"]
    m = example_reading(s["c"])
    np.testing.assert_allclose(run_c(client, cal, s["c"], tmp_path), applied(client, cal, m), atol=2e-6)
