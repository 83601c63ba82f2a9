"""`trical noise` end to end as a subprocess: a gyroscope array, the summary, --json, --plot."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np

from app.calibration.simulations.noise import simulate_still


def _run(*args, cwd):
    return subprocess.run([sys.executable, "-m", "app.cli", "noise", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=300)


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
    from app.io.allan_plot import allan_svg  # noqa: F401  (written beside this branch; the lead merges both)

    x = simulate_still(np.random.default_rng(5), n_samples=20_000, sampling_rate_hz=100.0, N=1e-3, B=2e-4, K=2e-5)
    path = tmp_path / "gyr.npy"
    np.save(path, x)
    r = _run(path, "--sensor", "gyr", "--sampling-rate-hz", 100, "--plot", tmp_path / "allan.svg", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "allan.svg").read_text().lstrip().startswith("<")
