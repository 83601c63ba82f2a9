"""Reading speed of a ~100 MB flight log: trical's reader beside pyulog's and pymavlink's own dump tools.

    python bench/flight_logs.py [--mb 100] [--dir /tmp] [--keep]

Writes, with the tests' writers (tests/flight_logs.py), a seeded PX4 ULog (two IMU instances,
sensor_accel and sensor_gyro at 1 kHz, a sensor_mag at 100 Hz) and an ArduPilot DataFlash log (two
``IMU`` instances at 1 kHz with ``T``, the batch sampler's ``ACC``/``GYR`` of instance 0 at 1 kHz, a
``MAG`` at 100 Hz), each of about ``--mb`` MB, under ``--dir`` (deleted afterwards unless ``--keep``).
Then runs, each as a whole process under ``/usr/bin/time -v`` (wall time, peak resident memory):

- trical: ``read_log`` of the file (the default IMU on its clock, the instances listed);
- ``ulog2csv`` (pyulog) of the ULog, every topic to CSV;
- ``mavlogdump.py --format csv --types IMU`` (pymavlink) of the DataFlash log.

The tools do more than trical's read (they write every field as text), so the figures say what a
user waits for either way, not that one parser is faster. Nothing is asserted.
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from tests.flight_logs import (  # noqa: E402 - after sys.path.insert
    ardupilot_batch,
    ardupilot_imu,
    ardupilot_mag,
    px4_sensor,
    write_dataflash,
    write_ulog,
)

BIN = Path(sys.executable).parent
TIMEOUT_S = 1800
ULOG_BYTES_PER_S = 4 * 1000 * 45 + 100 * 45
"""Two sensor_accel and two sensor_gyro messages of 45 bytes at 1 kHz, a sensor_mag at 100 Hz."""
DATAFLASH_BYTES_PER_S = 2 * 1000 * 54 + 2 * 1000 * 32 + 100 * 19
"""Two IMU messages of 54 bytes and an ACC and a GYR of 32 at 1 kHz, a MAG of 19 at 100 Hz."""


def _still(rng, n, mean, sigma):
    return mean + rng.normal(0.0, sigma, (n, 3))


def write_px4(path: Path, seconds: int, rng) -> Path:
    t = (1_000_000 + np.arange(seconds * 1000) * 1000).astype(np.uint64)
    tm = (1_000_000 + np.arange(seconds * 100) * 10_000).astype(np.uint64)
    temp = np.linspace(30.0, 45.0, len(t))
    topics = []
    for k in range(2):
        topics.append(
            px4_sensor("sensor_accel", k, t, _still(rng, len(t), [0.05, -0.03, -9.81], 0.02), temp + k, 2424842 + k)
        )
        topics.append(
            px4_sensor("sensor_gyro", k, t + 100, _still(rng, len(t), [0.01, 0.0, -0.01], 0.003), temp + k, 2424842 + k)
        )
    topics.append(px4_sensor("sensor_mag", 0, tm, _still(rng, len(tm), [0.2, 0.05, 0.4], 0.003), None, 592905))
    return write_ulog(path, topics)


def write_ardupilot(path: Path, seconds: int, rng) -> Path:
    t = (1_000_000 + np.arange(seconds * 1000) * 1000).astype(np.uint64)
    tm = (1_000_000 + np.arange(seconds * 100) * 10_000).astype(np.uint64)
    temp = np.linspace(30.0, 45.0, len(t))
    messages = [
        ardupilot_imu(
            k,
            t,
            _still(rng, len(t), [0.05, -0.03, -9.81], 0.02),
            _still(rng, len(t), [0.01, 0.0, -0.01], 0.003),
            temp + k,
        )
        for k in range(2)
    ]
    messages += [
        ardupilot_batch("ACC", 0, t, _still(rng, len(t), [0.05, -0.03, -9.81], 0.02)),
        ardupilot_batch("GYR", 0, t, _still(rng, len(t), [0.01, 0.0, -0.01], 0.003)),
        ardupilot_mag(0, tm, _still(rng, len(tm), [200.0, 50.0, 400.0], 3.0)),
    ]
    return write_dataflash(path, messages)


def timed(command: list[str], cwd: Path) -> tuple[float, float, int]:
    """Wall seconds, peak RSS in MB and exit status of ``command`` under /usr/bin/time -v."""
    r = subprocess.run(["/usr/bin/time", "-v", *command], cwd=cwd, capture_output=True, text=True, timeout=TIMEOUT_S)
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", r.stderr).group(1)
    parts = [float(p) for p in wall.split(":")]
    seconds = sum(p * 60**i for i, p in enumerate(reversed(parts)))
    rss_kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", r.stderr).group(1))
    if r.returncode:
        print(f"  ({command[0]} exited {r.returncode}: {r.stderr.strip().splitlines()[0][:160]})")
    return seconds, rss_kb / 1024, r.returncode


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mb", type=float, default=100.0)
    parser.add_argument("--dir", type=Path, default=Path(tempfile.gettempdir()))
    parser.add_argument("--keep", action="store_true")
    args = parser.parse_args()
    work = Path(tempfile.mkdtemp(prefix="trical-flight-bench-", dir=args.dir))
    rng = np.random.default_rng(2026)
    try:
        ulg = write_px4(work / "bench.ulg", int(args.mb * 1e6 / ULOG_BYTES_PER_S), rng)
        binlog = write_ardupilot(work / "bench.bin", int(args.mb * 1e6 / DATAFLASH_BYTES_PER_S), rng)
        read = (
            "import sys; from pathlib import Path; from app.io.readers import read_log; "
            "log = read_log(Path(sys.argv[1])); print(log.n_samples, len(log.flight.instances))"
        )
        rows = []
        for label, path, command in (
            ("trical read_log (ULog)", ulg, [sys.executable, "-c", read, str(ulg)]),
            ("pyulog ulog2csv", ulg, [str(BIN / "ulog2csv"), "-o", str(work / "csv"), str(ulg)]),
            ("trical read_log (DataFlash)", binlog, [sys.executable, "-c", read, str(binlog)]),
            (
                "pymavlink mavlogdump.py --format csv --types IMU",
                binlog,
                ["sh", "-c", f"{sys.executable} {BIN / 'mavlogdump.py'} --format csv --types IMU {binlog} > /dev/null"],
            ),
        ):
            (work / "csv").mkdir(exist_ok=True)
            seconds, rss, status = timed(command, ROOT)
            rows.append((label, path.stat().st_size / 1e6, seconds, rss, status))
            print(f"  done: {label}", file=sys.stderr)
        print(f"{'reader':52s} {'file MB':>8s} {'wall s':>8s} {'MB/s':>7s} {'peak RSS MB':>12s}")
        for label, mb, seconds, rss, status in rows:
            flag = "" if status == 0 else f"  (exit {status})"
            print(f"{label:52s} {mb:8.1f} {seconds:8.2f} {mb / seconds:7.1f} {rss:12.0f}{flag}")
    finally:
        if args.keep:
            print(f"kept {work}")
        else:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
