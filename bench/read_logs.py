"""Speed of reading large logs: a header row against none, and each separator of a logger's own file.

    python bench/read_logs.py [--rows 1000000]

Writes one seeded recording (time in ms, x, y, z in m/s²) in several layouts into a temporary
folder and times ``app.io.readers.read_log`` on each (best of three). Prints MB, seconds and
rows per second; nothing is asserted (the tests check what is read, not how fast).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
from app.io.readers import read_log

LAYOUTS = {
    "header, commas": ("time_ms,acc_x,acc_y,acc_z\n", ",", "%d,%.5f,%.5f,%.5f"),
    "no header, commas": ("", ",", "%d,%.5f,%.5f,%.5f"),
    "no header, tabs": ("", "\t", "%d\t%.5f\t%.5f\t%.5f"),
    "no header, one space": ("", " ", "%d %.5f %.5f %.5f"),
    "no header, aligned spaces": ("", " ", "%10d %12.5f %12.5f %12.5f"),
    "no header, ; and decimal comma": ("", ";", "%d;%.5f;%.5f;%.5f"),
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows", type=int, default=1_000_000)
    args = parser.parse_args()
    rng = np.random.default_rng(2025)
    data = np.column_stack([np.arange(args.rows) * 10, rng.normal([0.01, -0.02, 9.81], 0.02, (args.rows, 3))])
    with tempfile.TemporaryDirectory() as tmp:
        print(f"{args.rows} rows; best of 3")
        for label, (header, _, fmt) in LAYOUTS.items():
            path = Path(tmp) / "log.txt"
            with open(path, "w") as f:
                f.write(header)
                np.savetxt(f, data, fmt=fmt)
            if "decimal comma" in label:
                path.write_text(path.read_text().replace(".", ","))
            best = min(_timed(path) for _ in range(3))
            mb = path.stat().st_size / 1e6
            print(f"{label:32s} {mb:7.1f} MB {best:7.3f} s {args.rows / best / 1e6:6.2f} M rows/s")


def _timed(path: Path) -> float:
    start = time.perf_counter()
    log = read_log(path)
    elapsed = time.perf_counter() - start
    assert log.n_samples > 0
    return elapsed


if __name__ == "__main__":
    main()
