"""The examples that can be built and run here: the Arduino example's correction (examples/arduino/
apply_trical_header: calibrate.h over trical's exported C header) compiled for the host by gcc and
checked against the API's apply, and examples/python/board_to_api.py run against `trical serve` with a
simulated board on a pseudo-terminal. The sketches themselves need the Arduino toolchain
(examples/README.md says why it is not used here)."""

from __future__ import annotations

import os
import re
import select
import shutil
import subprocess
import sys

import httpx
import numpy as np
import pytest

from app.calibration import CANONICAL_SIX
from tests.conftest import seed_table
from tests.live_server import ROOT, live_server
from tests.processes import run_ok
from tests.test_cli_capture import board_script, pty_board  # noqa: F401 (the fixture)

EXAMPLE = ROOT / "examples" / "arduino" / "apply_trical_header"
CANONICAL = ["-x", "+x", "-y", "+y", "-z", "+z"]


@pytest.fixture
def client(tmp_path):
    from fastapi.testclient import TestClient

    from app.main import create_app
    from tests.conftest import make_settings

    with TestClient(create_app(make_settings(tmp_path)), raise_server_exceptions=False) as c:
        yield c


def test_the_arduino_example_correction_built_for_the_host(client, tmp_path):
    cc = shutil.which("gcc")
    assert cc, "gcc is needed to build the example's correction"
    table = seed_table(1)
    r = client.post(
        "/api/v1/calibrations",
        json={
            "method": "six_position",
            "unit": "m/s^2",
            "readings": [{"up": u, "mean": m.tolist()} for u, m in zip(CANONICAL, table[:6])],
        },
    )
    assert r.status_code == 201, r.text
    cal = r.json()
    header = client.get(f"/api/v1/calibrations/{cal['id']}/export", params={"format": "c"})
    assert header.status_code == 200
    (tmp_path / "trical_calibration.h").write_text(header.text)
    exe = tmp_path / "host_check"
    run_ok(
        [
            cc,
            "-std=c99",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-I",
            str(tmp_path),
            "-I",
            str(EXAMPLE),
            "-o",
            str(exe),
            str(EXAMPLE / "host_check.c"),
        ],
        timeout_s=60,
    )
    samples = np.random.default_rng(6).normal(0, 6, size=(40, 3))
    out = run_ok([str(exe)], timeout_s=10, input="\n".join(" ".join(f"{v:.9g}" for v in s) for s in samples))
    board = np.array([[float(v) for v in ln.split()] for ln in out.stdout.splitlines()])
    api = client.post(f"/api/v1/calibrations/{cal['id']}/apply", json={"samples": samples.tolist()})
    assert api.status_code == 200
    np.testing.assert_allclose(board, api.json()["samples"], atol=2e-5)  # float32 on the board


# pty_board is the fixture imported above, which pytest passes: not a redefinition (F811).
def test_the_python_example_reads_a_board_and_calibrates_over_the_api(tmp_path, pty_board):  # noqa: F811
    port, make = pty_board
    # 41 s of lines; rests of four times the detector's 1.5 s, so that a rest split by a gap or shortened by a
    # burst of late lines (below) leaves a part long enough to be found (rests of 4.5 s came out as 4 of 6 twice
    # on this machine, three workers on two cores beside another test run)
    board = make(board_script(11, first_s=3.0, still_s=6.0, turn_s=0.4))
    env = {"TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'trical.db'}"}
    with live_server(env) as server:
        proc = subprocess.Popen(
            [
                sys.executable,
                str(ROOT / "examples" / "python" / "board_to_api.py"),
                port,
                "--seconds",
                "48",
                "--api",
                server.url,
            ],
            cwd=tmp_path,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        try:
            # The board starts once the script has opened the port (opening flushes what arrived before): its
            # first count of readings is printed after the port's first read. A fixed pause lost the first rest
            # on a loaded machine (the script's start-up took longer), and the log then held 5 rests.
            # The script records 48 s: the board's lines then come late and in bursts, stamped by their arrival.
            # Rests of 2 s in a 19 s window once came out as 4; rests of 3 s in 30 s once as 3 (CI, three
            # workers on two cores).
            ready, _, _ = select.select([proc.stdout], [], [], 30)
            assert ready, "the example printed nothing within 30 s of its start"
            first = os.read(proc.stdout.fileno(), 256).decode()
            board.start()
            stdout, stderr = proc.communicate(timeout=75)
            stdout = first + stdout
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait(timeout=10)
        assert proc.returncode == 0, stderr
        # Each of the six rests is found. A loaded host that holds the port for long enough leaves a gap in the
        # arrival-stamped log, and a rest split at that gap is two segments of the one pose (CI once saw 8).
        recording = re.search(r"recording (rec_\w+): (\d+) still segments", stdout)
        assert recording, stdout
        segments = httpx.get(f"{server.url}/api/v1/recordings/{recording[1]}", timeout=10).json()["segments"]
        assert {s["up"] for s in segments if s["up"]} == set(CANONICAL_SIX), (segments, stdout)
    assert "calibration cal_" in stdout and "wrote trical_cal_" in stdout
    assert list(tmp_path.glob("trical_cal_*.h"))
