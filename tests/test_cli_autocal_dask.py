"""`trical autocal FOLDER --dask-scheduler ADDRESS` on a real Dask cluster (two worker processes).

The installed command runs the folder twice, on local processes and on a LocalCluster, and both
summaries must agree: the same files, the same ok and reasons, K and o to 1e-12.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import dask
import numpy as np
import pytest
from dask.distributed import Client, LocalCluster

from simulations.autocal import simulate_recording
from tests.live_server import ROOT

TRICAL = Path(sys.executable).parent / "trical"
FS = 25.0


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    path = tmp_path_factory.mktemp("autocal-folder")
    for seed in (1, 2, 3):  # six hours each: enough rest in every orientation
        x, _ = simulate_recording(np.random.default_rng(seed), duration_s=6 * 3600, sampling_rate_hz=FS)
        np.save(path / f"wrist_{seed}.npy", x)
    x, _ = simulate_recording(np.random.default_rng(4), duration_s=3600, sampling_rate_hz=FS)
    np.save(path / "short.npy", x)  # too little rest: ok False with a reason
    (path / "broken.npy").write_bytes(b"not an array")  # an error entry
    return path


START_TIMEOUT_S = 60


@pytest.fixture(scope="module")
def cluster():
    """Two worker processes, each bound to end itself when its scheduler is gone for a minute; the
    test waits a bounded time for both before it uses them, and fails naming the cluster otherwise."""
    with (
        dask.config.set({"distributed.comm.timeouts.connect": f"{START_TIMEOUT_S}s"}),
        LocalCluster(
            n_workers=2,
            processes=True,
            threads_per_worker=1,
            host="127.0.0.1",
            dashboard_address=None,
            death_timeout=START_TIMEOUT_S,
        ) as c,
        Client(c) as client,
    ):
        try:
            client.wait_for_workers(2, timeout=START_TIMEOUT_S)
        except TimeoutError:
            pytest.fail(
                f"the LocalCluster had {len(c.scheduler.workers)} of 2 workers after {START_TIMEOUT_S} s: "
                f"{c.get_logs()}"
            )
        yield c


def autocal(folder: Path, tmp_path: Path, *extra: str) -> list[dict]:
    assert TRICAL.exists(), f"the console script {TRICAL} is missing: run `make install-test`"
    env = {"PATH": "/usr/bin:/bin", "TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'trical.db'}"}
    out = subprocess.run(
        [str(TRICAL), "autocal", str(folder), "--sampling-rate-hz", str(FS), "--unit", "g", "--json", *extra],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 3, out.stderr  # short.npy and broken.npy do not calibrate
    assert "Traceback" not in out.stderr
    return json.loads(out.stdout)


def test_a_folder_on_a_local_cluster_matches_local_processes(folder, cluster, tmp_path):
    local = autocal(folder, tmp_path, "--workers", "2")
    assert len(cluster.scheduler.workers) == 2, f"the cluster lost a worker: {cluster.get_logs()}"
    dask = autocal(folder, tmp_path, "--dask-scheduler", cluster.scheduler_address)
    assert (
        [b["label"] for b in dask]
        == [b["label"] for b in local]
        == ["broken.npy", "short.npy", "wrist_1.npy", "wrist_2.npy", "wrist_3.npy"]
    )
    for a, b in zip(local, dask):
        assert a["ok"] == b["ok"], a["label"]
        if "error" in a:
            assert b["error"] == a["error"] and "not a readable .npy" in a["error"]
            continue
        assert a["reasons"] == b["reasons"]
        np.testing.assert_allclose(b["model"]["K"], a["model"]["K"], rtol=0, atol=1e-12)
        np.testing.assert_allclose(b["model"]["o"], a["model"]["o"], rtol=0, atol=1e-12)
    assert [b["ok"] for b in dask] == [False, False, True, True, True]
    assert dask[1]["reasons"] and "fewer than" in dask[1]["reasons"][0]
    # The files went to the cluster: its scheduler ran the folder's job (app.cli.autocal._autocal_job), once a file.
    prefix = cluster.scheduler.task_prefixes["autocal_job"]
    assert prefix.state_counts["memory"] == len(dask), dict(prefix.state_counts)  # transitions into memory
