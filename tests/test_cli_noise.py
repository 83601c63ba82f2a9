"""`trical noise` end to end: a gyroscope array, the summary, --json, --plot (the command run in this process,
tests/cli_in_process.py; what it imports, in a subprocess of its own)."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np

from simulations.noise import simulate_still
from tests.cli_in_process import run_main


def _run(*args, cwd):
    """`trical noise ARGS` in ``cwd`` with this environment, run in this process (tests/cli_in_process.py)."""
    return run_main(["noise", *map(str, args)], None, cwd)


def test_noise_of_a_gyroscope_array(tmp_path):
    x = simulate_still(np.random.default_rng(4), n_samples=60_000, sampling_rate_hz=100.0, N=1e-3, B=2e-4, K=2e-5)
    path = tmp_path / "gyr.npy"
    np.save(path, x)
    r = _run(path, "--sensor", "gyr", "--sampling-rate-hz", 100, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "noise density N" in r.stdout and "rad/s/√Hz" in r.stdout
    r = _run(path, "--sensor", "gyr", "--sampling-rate-hz", 100, "--json", cwd=tmp_path)
    body = json.loads(r.stdout)
    np.testing.assert_allclose(body["model"]["gyr"]["noise_density"], 1e-3, rtol=0.1)
    assert list(body["model"]) == ["type", "gyr"]
    r = _run(path, "--sensor", "gyr", "--unit", "m/s^2", "--sampling-rate-hz", 100, cwd=tmp_path)
    assert r.returncode == 2 and "not a gyr unit" in r.stderr


def test_plot_writes_the_allan_svg(tmp_path):
    from app.io.exports.allan_plot import allan_svg  # noqa: F401  (written beside this branch; the lead merges both)

    x = simulate_still(np.random.default_rng(5), n_samples=20_000, sampling_rate_hz=100.0, N=1e-3, B=2e-4, K=2e-5)
    path = tmp_path / "gyr.npy"
    np.save(path, x)
    r = _run(path, "--sensor", "gyr", "--sampling-rate-hz", 100, "--plot", tmp_path / "allan.svg", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "allan.svg").read_text().lstrip().startswith("<")


def test_noise_of_a_serial_log_stamped_by_the_host_and_the_rate_option(tmp_path):
    # The case: t in host milliseconds, arriving in bursts; a 100 Hz gyroscope in deg/s.
    from simulations.serial import host_arrival_times

    n = 20_000
    t_ms = host_arrival_times(np.random.default_rng(6), n_samples=n, sampling_rate_hz=100.0) * 1e3 + 8_000.0
    gyr = simulate_still(np.random.default_rng(7), n_samples=n, sampling_rate_hz=100.0, N=0.01, B=0.0, K=0.0)
    path = tmp_path / "still.csv"
    np.savetxt(
        path,
        np.column_stack([np.round(t_ms, 3), gyr]),
        delimiter=",",
        header="t,gyr_x,gyr_y,gyr_z",
        comments="",
        fmt="%.7g",
    )
    r = _run(path, "--sensor", "gyr", "--unit", "deg/s", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    body = json.loads(r.stdout)
    assert abs(body["sampling_rate_hz"] / 100.0 - 1) < 3e-3
    np.testing.assert_allclose(body["model"]["gyr"]["noise_density"], np.deg2rad(0.01), rtol=0.05)
    assert any("irregular" in w and "from the span" in w for w in body["warnings"])
    r = _run(path, "--sensor", "gyr", "--unit", "deg/s", "--sampling-rate-hz", 100, "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["sampling_rate_hz"] == 100.0


def test_noise_of_one_recording_in_a_file_per_sensor_is_of_both_and_refused_when_the_phone_moved(tmp_path):
    """A real phyphox recording written one file per sensor (tests/data/real/corpus/phyphox_per_sensor_files): the
    two files are one recording of both sensors; the phone was in the hand, and its accelerometer's noise density
    (16.8 mg/√Hz) is no MEMS part's, so the figures are not to be used, saying the device was not still."""
    from tests.real_corpus import CORPUS

    folder = CORPUS / "phyphox_per_sensor_files"
    r = _run(folder / "Accelerometer.csv", folder / "Gyroscope.csv", "--json", cwd=tmp_path)
    assert r.returncode == 3, r.stderr  # trical noise and temperature end with 3 when the figures are not ok
    body = json.loads(r.stdout)
    assert sorted(body["model"]) == ["acc", "gyr", "type"] and body["label"] == "Accelerometer.csv, Gyroscope.csv"
    assert body["ok"] is False and any("not still" in x for x in body["reasons"]), body["reasons"]


def test_noise_loads_neither_the_other_commands_nor_the_other_models(tmp_path):
    """`trical noise` imports its own command only: the method table (with the exporters and the cube's
    models, ~0.9 s) and scipy (its χ² quantiles are app.calibration.shared.chi2's: scipy.special alone takes 0.2–0.3 s
    to import) are not loaded by a noise characterisation printed as JSON, nor pyarrow (the CSV reader's,
    ~0.16 s and 25 MiB) for a .npy, nor the settings (pydantic and pydantic-settings, ~0.15 s), which a
    characterisation that is not stored does not read."""
    from pathlib import Path

    x = simulate_still(np.random.default_rng(5), n_samples=20_000, sampling_rate_hz=100.0, N=1e-3, B=2e-4, K=2e-5)
    path = tmp_path / "gyr.npy"
    np.save(path, x)
    heavy = (
        "app.methods",
        "app.calibration.cube",
        "app.io.exports.exporters",
        "scipy",
        "pyarrow",
        "app.config",
        "pydantic",
        "pydantic_settings",
    )
    code = (
        "import contextlib, io, sys\n"
        "from app.cli.main import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        f"    status = main(['noise', {str(path)!r}, '--sensor', 'gyr', '--sampling-rate-hz', '100', '--json'])\n"
        f"print(status, sorted(m for m in {heavy!r} if m in sys.modules))\n"
    )
    r = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        cwd=Path(__file__).resolve().parents[1],
        timeout=300,
    )
    assert r.stdout.strip() == "0 []", r.stderr


def test_every_command_that_reads_a_file_takes_the_log_format(tmp_path):
    """The real x-io log whose header names each column's unit (tests/data/real/corpus/xio_fusion_units_in_header):
    `trical noise` reads every sensor of it, and `--log-format` is a flag of every command that reads a file."""
    from app.cli.parser import build_parser
    from tests.conftest import DATA

    log = DATA / "real" / "corpus" / "xio_fusion_units_in_header" / "sensor_data_excerpt.csv"
    r = _run(log, "--log-format", "csv", "--json", cwd=tmp_path)
    assert r.returncode in (0, 3), r.stderr
    body = json.loads(r.stdout)
    assert list(body["model"]) == ["type", "acc", "gyr", "mag"]  # no column dropped
    for command in ("calibrate", "autocal", "noise", "temperature"):
        options = {
            o
            for a in build_parser(command)._subparsers._group_actions[0].choices[command]._actions
            for o in a.option_strings
        }
        assert "--log-format" in options, command
