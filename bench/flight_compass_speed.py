"""The compass from a flight, from upload to verdict, on a large ArduPilot and a large PX4 log, beside the firmwares'
own Python readers reading the messages it uses.

    PYTHONPATH=. python bench/flight_compass_speed.py [--mb 100]

Writes one seeded flight (tests/flight_compass_logs.py: a compass, its attitude, current, throttle and GPS at 25 Hz,
hours of it) as an ArduPilot DataFlash log and a PX4 ULog of about ``--mb`` MB each, then times, once each:

- trical: ``POST /api/v1/recordings`` with the file, then ``POST /api/v1/calibrations {"method": "compass_flight"}``,
  in process (the app, SQLite, the upload's reading and the fit; no network);
- pymavlink's ``DFReader_binary`` reading every message trical uses on the way (``recv_match``): the IMU the
  upload reads (IMU), the compass (MAG), the attitude (ATT), the power (BAT, CTUN), the fix (GPS), the parameters;
- pyulog's ``ULog`` reading the topics trical uses on the way (``app.io.flight.ulog.TOPICS`` and
  ``CONTEXT_TOPICS``: the IMU the upload reads, the compass, attitude, power and fix).

It prints the sizes, the seconds and trical's time over the peer's; nothing passes or fails.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import tempfile
import time
from pathlib import Path

from tests.flight_compass_logs import seeded_flight, write_flight_compass_logs

BYTES_PER_SECOND_PROBE_S = 60.0


def _write(directory: Path, megabytes: float) -> tuple[Path, Path]:
    """The two logs of one flight long enough for ``megabytes`` each (the larger of the two on the size)."""
    probe = write_flight_compass_logs(directory, seeded_flight(3, duration_s=BYTES_PER_SECOND_PROBE_S), stem="probe")
    per_s = max(p.stat().st_size for p in probe) / BYTES_PER_SECOND_PROBE_S
    for p in probe:
        p.unlink()
    duration = megabytes * 1e6 / per_s
    return write_flight_compass_logs(directory, seeded_flight(3, duration_s=duration), stem="big")


def _trical(path: Path, db: Path) -> tuple[float, str]:
    os.environ["TRICAL_DATABASE_URL"] = f"sqlite:///{db}"
    os.environ.setdefault("TRICAL_MAX_UPLOAD_MB", "2000")
    from fastapi.testclient import TestClient

    from app.main import create_app

    with TestClient(create_app()) as client:
        start = time.perf_counter()
        with open(path, "rb") as f:
            rec = client.post("/api/v1/recordings", files={"file": (path.name, f)})
        rec.raise_for_status()
        answer = client.post(
            "/api/v1/calibrations", json={"method": "compass_flight", "recording_id": rec.json()["id"]}
        )
        seconds = time.perf_counter() - start
    answer.raise_for_status()
    return seconds, answer.json()["verdict"]["words"]


def _pymavlink(path: Path) -> float:
    from pymavlink import DFReader

    start = time.perf_counter()
    with contextlib.redirect_stdout(io.StringIO()):
        reader = DFReader.DFReader_binary(str(path), zero_time_base=True)
        kinds = ["IMU", "ACC", "GYR", "MAG", "ATT", "BAT", "CTUN", "GPS", "PARM"]
        while reader.recv_match(type=kinds) is not None:
            pass
    return time.perf_counter() - start


def _pyulog(path: Path) -> float:
    from pyulog import ULog

    from app.io.flight.ulog import CONTEXT_TOPICS, TOPICS

    start = time.perf_counter()
    with contextlib.redirect_stdout(io.StringIO()):
        ULog(str(path), message_name_filter_list=list(TOPICS + CONTEXT_TOPICS))
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mb", type=float, default=100.0)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        directory = Path(tmp)
        ardupilot, px4 = _write(directory, args.mb)
        print(f"{'log':<34}{'MB':>8}{'trical upload → verdict (s)':>30}{'peer read (s)':>16}{'ratio':>8}")
        for path, peer, read in ((ardupilot, "pymavlink", _pymavlink), (px4, "pyulog", _pyulog)):
            ours, words = _trical(path, directory / f"{path.stem}{path.suffix}.db")
            theirs = read(path)
            label = f"{path.suffix[1:]} ({peer})"
            print(f"{label:<34}{path.stat().st_size / 1e6:>8.1f}{ours:>30.1f}{theirs:>16.1f}{ours / theirs:>8.2f}")
            print(f"  verdict: {words}")


if __name__ == "__main__":
    main()
