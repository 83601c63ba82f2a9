"""`trical autocal FILE` and `trical autocal FOLDER` (issue 4)."""

from __future__ import annotations

import io
import json
import os

import numpy as np
import pytest

from app.cli.main import main
from app.io.readers.read_options import ReadOptions
from simulations.autocal import simulate_recording
from tests.processes import run_ok

FS = 25.0


@pytest.fixture(scope="module")
def recording():
    return simulate_recording(np.random.default_rng(11), duration_s=86400, sampling_rate_hz=FS)


def _run(argv, capsys):
    code = main(argv)
    out = capsys.readouterr()
    return code, out.out, out.err


def test_autocal_file_json(tmp_path, capsys, recording, monkeypatch):
    monkeypatch.setenv("TRICAL_DATABASE_URL", f"sqlite:///{tmp_path / 'db.sqlite'}")
    x, truth = recording
    f = tmp_path / "week.npy"
    np.save(f, x)
    code, out, err = _run(["autocal", str(f), "--sampling-rate-hz", str(FS), "--unit", "g", "--json"], capsys)
    assert code == 0, err
    assert err == ""  # no progress bar when stderr is not a terminal
    body = json.loads(out)
    assert body["method"] == "autocal" and body["ok"] is True
    assert body["model"]["type"] == "triangular" and body["unit"] == "g" and body["output_unit"] == "g"
    assert body["metrics"]["error_after_mg"] < 1.0 < 10.0 < body["metrics"]["error_before_mg"]
    assert set(body["comparison"]) >= {"ellipsoid_axes", "sphere_van_hees"}
    assert body["recording"]["n_samples"] == len(x) and body["label"] == "week.npy"
    K = np.array(body["model"]["K"])
    assert abs(K[1, 0] - truth.p[3]) < 3e-3


def test_autocal_text_summary_and_progress_bar(tmp_path, capsys, recording, monkeypatch):
    x, _ = recording
    f = tmp_path / "rec.npy"
    np.save(f, np.column_stack([np.arange(len(x)) / FS, x]))  # N×4, time first: no rate needed
    code, out, _ = _run(["autocal", str(f), "--unit", "g"], capsys)
    assert code == 0
    assert "triangular_002" in out and "sphere_van_hees" in out and "C_xn 2" in out

    class Tty(io.StringIO):
        def isatty(self):
            return True

    tty = Tty()
    monkeypatch.setattr("sys.stderr", tty)
    assert main(["autocal", str(f), "--unit", "g", "--json"]) == 0
    assert "100%" in tty.getvalue() and "M samples" in tty.getvalue()


def test_autocal_unreadable_file_is_one_line_error(tmp_path, capsys):
    f = tmp_path / "broken.npy"
    f.write_bytes(b"not numpy at all")
    code, out, err = _run(["autocal", str(f), "--sampling-rate-hz", "100", "--unit", "g"], capsys)
    assert code == 2 and out == ""
    assert err.startswith("trical: error:") and "not a readable .npy" in err and "Traceback" not in err
    code, _, err = _run(["autocal", str(tmp_path / "missing.npy")], capsys)
    assert code == 2 and "no such file" in err


def test_autocal_store_then_export(tmp_path, capsys, recording, monkeypatch):
    """`--store` keeps the calibration in the configured database; `trical export` reads it back."""
    monkeypatch.setenv("TRICAL_DATABASE_URL", f"sqlite:///{tmp_path / 'db.sqlite'}")
    f = tmp_path / "day.npy"
    np.save(f, recording[0][: int(FS * 6 * 3600)])
    code, out, err = _run(
        ["autocal", str(f), "--sampling-rate-hz", str(FS), "--unit", "g", "--store", "--json"], capsys
    )
    assert code in (0, 3), err
    stored = json.loads(out)
    assert stored["id"].startswith("cal_")
    code, out, err = _run(["export", stored["id"], "--format", "json"], capsys)
    assert code == 0, err
    assert json.loads(out)["model"] == stored["model"]


def test_autocal_no_rest_exits_3_with_reason(tmp_path, capsys):
    x, _ = simulate_recording(np.random.default_rng(2), duration_s=3600, sampling_rate_hz=FS, rest_median_s=0)
    f = tmp_path / "moving.npy"
    np.save(f, x)
    code, out, _ = _run(["autocal", str(f), "--sampling-rate-hz", str(FS), "--unit", "g", "--json"], capsys)
    assert code == 3
    body = json.loads(out)
    assert body["ok"] is False and body["reasons"][0].startswith("it never rested: all 720 segments of 5 s moved")


def test_autocal_folder_in_parallel(tmp_path, capsys, recording):
    x, _ = recording
    np.save(tmp_path / "a.npy", x[: len(x) // 2])
    np.save(tmp_path / "b.npy", x[len(x) // 2 :])
    (tmp_path / "c.npy").write_bytes(b"garbage")
    (tmp_path / "notes.md").write_text("ignored")
    code, out, err = _run(
        ["autocal", str(tmp_path), "--sampling-rate-hz", str(FS), "--unit", "g", "--workers", "2"], capsys
    )
    assert code == 3, err  # c.npy failed
    lines = out.splitlines()
    assert lines[0].split()[:3] == ["file", "ok", "rest"]
    rows = {line.split()[0]: line for line in lines[1:4]}
    assert set(rows) == {"a.npy", "b.npy", "c.npy"}
    assert "True" in rows["a.npy"] and "True" in rows["b.npy"]
    assert "error" in rows["c.npy"] and "not a readable .npy" in rows["c.npy"]
    assert lines[-1] == "2 of 3 recordings calibrated"


def test_autocal_folder_equals_one_by_one_with_a_line_per_file(tmp_path, capsys):
    """A folder on two processes gives each file's body as `trical autocal FILE` does alone (its detection on
    one thread there, on every core alone: the same to the bit), in the files' order; stderr has one line per
    file, numbered in the order they finish."""
    for k in range(3):  # six hours each: enough rest in every orientation
        x, _ = simulate_recording(np.random.default_rng(k + 1), duration_s=6 * 3600, sampling_rate_hz=FS)
        np.save(tmp_path / f"r{k}.npy", x)
    x, _ = simulate_recording(np.random.default_rng(4), duration_s=1800, sampling_rate_hz=FS)
    np.save(tmp_path / "short.npy", x)  # too little rest: ok False with its reason
    (tmp_path / "z.npy").write_bytes(b"garbage")
    argv = ["--sampling-rate-hz", str(FS), "--unit", "g", "--json"]
    code, out, err = _run(["autocal", str(tmp_path), *argv, "--workers", "2"], capsys)
    assert code == 3, err
    folder = json.loads(out)
    names = ["r0.npy", "r1.npy", "r2.npy", "short.npy", "z.npy"]
    assert [b["label"] for b in folder] == names
    lines = err.splitlines()
    assert [line.split("] ")[0] for line in lines] == [f"[{k}/5" for k in range(1, 6)]
    assert sorted(line.split("] ")[1].split(":")[0] for line in lines) == names
    by_name = {line.split("] ")[1].split(":")[0]: line for line in lines}
    assert ": ok, " in by_name["r0.npy"] and " mg after (" in by_name["r0.npy"]
    assert ": not ok" in by_name["short.npy"] and ": error: " in by_name["z.npy"]
    for name, body in zip(names[:4], folder[:4]):
        code, out, err = _run(["autocal", str(tmp_path / name), *argv], capsys)
        assert code in (0, 3), err
        assert json.loads(out) == body, name
    assert [b["ok"] for b in folder] == [True, True, True, False, False]
    assert "not a readable .npy" in folder[4]["error"]


def test_autocal_dask_missing_is_a_clear_error(tmp_path, capsys, recording, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "dask", None)  # as on a machine without the dask extra
    monkeypatch.setitem(sys.modules, "dask.distributed", None)
    np.save(tmp_path / "a.npy", recording[0][:100_000])
    code, _, err = _run(
        ["autocal", str(tmp_path), "--sampling-rate-hz", str(FS), "--dask-scheduler", "tcp://127.0.0.1:8786"], capsys
    )
    assert code == 2 and "dask" in err and "pip install" in err


@pytest.mark.parametrize("n", [0, 10, 300])
def test_autocal_tiny_or_empty_recordings_never_crash(tmp_path, capsys, n):
    f = tmp_path / "tiny.npy"
    np.save(f, np.tile([0.0, 0.0, 1.0], (n, 1)))
    code, out, err = _run(["autocal", str(f), "--sampling-rate-hz", "50", "--unit", "g", "--json"], capsys)
    assert code in (2, 3) and "Traceback" not in err
    if code == 3:
        body = json.loads(out)
        assert body["ok"] is False and body["reasons"]
    else:
        assert err.startswith("trical: error:")


def test_autocal_raw_unit_is_refused_with_advice(tmp_path):
    from app.calibration import CalibrationError
    from app.workflows.autocal import autocalibrate_file

    f = tmp_path / "raw.csv"
    f.write_text("acc_x,acc_y,acc_z\n" + "\n".join("0,0,1000" for _ in range(100)))
    with pytest.raises(CalibrationError, match="g or m/s\\^2"):
        autocalibrate_file(f, ReadOptions(sampling_rate_hz=50.0, units={"acc": "raw"}))


def _printed_in_the_checkout(code: str) -> str:
    """What ``python -c code`` prints, run in the checkout with its ``app`` first on the path."""
    import sys
    from pathlib import Path

    out = run_ok(
        [sys.executable, "-c", code],
        timeout_s=120,
        cwd=Path(__file__).resolve().parents[1],
        env={**os.environ, "PYTHONPATH": "."},
    )
    return out.stdout.strip()


def test_cli_start_does_not_import_scipy_optimize_or_stats():
    """`trical autocal` on a week imports scipy.optimize (~0.4 s) only when the detection is done, and
    scipy.stats (~0.7 s) never: keep them out of app.cli.main's imports.
    (pyarrow, ~20 ms, is imported: it reads the CSV.)"""
    code = "import sys, app.cli.main; print(sorted(m for m in ('scipy.optimize', 'scipy.stats') if m in sys.modules))"
    assert _printed_in_the_checkout(code) == "[]"


def _options(parser) -> dict:
    import argparse

    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return {
        name: [(a.dest, a.option_strings, a.default, a.choices, a.nargs, a.help) for a in cmd._actions]
        for name, cmd in sub.choices.items()
    }


def test_one_commands_parser_is_the_whole_parsers_part():
    """build_parser(command), which the entry uses when the line starts with a command, has that command's
    options exactly as the whole parser has them."""
    from app.cli.parser import build_parser

    whole = _options(build_parser())
    assert {"autocal", "calibrate", "noise", "export"} <= set(whole)
    for name in whole:
        assert _options(build_parser(name)) == {name: whole[name]}


def test_autocal_command_start_imports_neither_the_method_table_nor_scipy_stats(tmp_path, recording):
    """`trical autocal FILE --json` runs without the method table (~0.4 s of imports) and without scipy.stats
    (~0.7 s): what it imports is its own."""
    f = tmp_path / "day.npy"
    np.save(f, recording[0][: int(FS * 3 * 3600)])
    code = (
        "import contextlib, io, sys\n"
        "from app.cli.main import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        f"    main(['autocal', {str(f)!r}, '--sampling-rate-hz', '{FS}', '--unit', 'g', '--json'])\n"
        "print(sorted(m for m in ('app.methods', 'app.words', 'scipy.stats', 'app.calibration.cube') "
        "if m in sys.modules))\n"
    )
    assert _printed_in_the_checkout(code) == "[]"
