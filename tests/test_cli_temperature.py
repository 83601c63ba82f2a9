"""``trical temperature LOG``: the verdict, the coefficients, the plot and the JSON of the API; a log without
temperature is one line on stderr and exit status 2."""

from __future__ import annotations

import json

from tests.cli_in_process import run_main
from tests.temperature_logs import warm_up_csv


def _run(*args, cwd):
    """`trical temperature ARGS` in ``cwd`` with this environment, run in this process (tests/cli_in_process.py)."""
    return run_main(["temperature", *map(str, args)], None, cwd)


def test_a_warm_up_from_the_command_line(tmp_path):
    path = tmp_path / "warm.csv"
    path.write_bytes(warm_up_csv(41, duration_s=900, sampling_rate_hz=20))
    r = _run(path, "--plot", tmp_path / "t.svg", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    body = json.loads(r.stdout)
    assert body["method"] == "temperature" and body["ok"] and body["label"] == "warm.csv"
    assert (tmp_path / "t.svg").read_text().startswith("<svg")
    r = _run(path, "--sensor", "gyr", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines()[1].startswith("Apply it: offset drift over 15–")
    assert "gyr (rad/s)" in r.stdout and "acc (" not in r.stdout and "samples per band" in r.stdout


def test_a_log_without_temperature_is_refused(tmp_path):
    text = warm_up_csv(42, duration_s=120, sampling_rate_hz=20).decode()
    path = tmp_path / "still.csv"
    path.write_text("\n".join(",".join(line.split(",")[:-1]) for line in text.splitlines()) + "\n")
    r = _run(path, cwd=tmp_path)
    assert r.returncode == 2
    assert r.stderr.startswith("trical: error: the recording has no temperature") and len(r.stderr.splitlines()) == 1


def test_a_span_too_small_exits_3_with_its_reason(tmp_path):
    path = tmp_path / "short.csv"
    path.write_bytes(warm_up_csv(43, duration_s=600, sampling_rate_hz=20, t_start_c=30.0, t_end_c=36.0))
    r = _run(path, cwd=tmp_path)
    assert r.returncode == 3, r.stderr
    assert "Don't apply it" in r.stdout and "under the 10 °C" in r.stdout
