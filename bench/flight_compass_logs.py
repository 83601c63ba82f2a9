"""The compass calibrated from a flight, end to end through both firmwares' logs: seeded flights written as an
ArduPilot DataFlash log and a PX4 ULog, read and calibrated by the method ``compass_flight``.

    PYTHONPATH=. python bench/flight_compass_logs.py [--flights 200] [--seed 2000]

Each flight (simulations.flight_compass.simulate_flight: 3 min at 25 Hz, a yaw turn a minute,
±20° of pitch and roll, current 12–33 A, 0.3 µT of compass noise, the attitude off by 0.3° per axis wandering
over 3 s; known offsets, soft iron and motor coefficients) is flown under the geomagnetic model's field at the
log's place and date, with the compass mounted at an orientation cycling through 2, 8, 4, 16, 25, 6 while
each firmware stored 0 (a wrong orientation) and stale offsets (tests/flight_compass_logs.py). Both logs are
written with the tests' writers and calibrated through the workflow (app.methods.calibrate, the handler the
HTTP API and the CLI run, with the logs as recordings), the model chosen by the method itself on segments
left out.

Printed per firmware: the share of the parameters inside their 95 % intervals per class (offsets b, the
matrix M's six entries, the motor coefficients k; an entry counts where the model chosen fits it — a zero
half-width is an entry held at zero, off the diagonal of the ``scale`` structure — and again over the flights
where the full model, soft iron and motor, was chosen), the
orientation found (the firmware's rotation number equal to the truth's), how many were ok, the models chosen,
and the median heading error on segments left out before (the firmware's stored calibration) and after.
Nothing passes or fails.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from app import calibration_requests as rq  # noqa: E402 - after sys.path.insert
from app.io.readers import read_log  # noqa: E402 - after sys.path.insert
from app.io.readers.read_options import ReadOptions  # noqa: E402 - after sys.path.insert
from app.methods import calibrate  # noqa: E402 - after sys.path.insert
from app.workflows.recordings import RecordingSource, describe_log  # noqa: E402 - after sys.path.insert
from tests.flight_compass_logs import seeded_flight, write_flight_compass_logs  # noqa: E402 - after sys.path.insert

MOUNTINGS = (2, 8, 4, 16, 25, 6)
FIRMWARES = (("ardupilot", "dataflash", 0), ("px4", "ulog", 1))
UPPER = np.triu_indices(3)


def _array(values) -> np.ndarray:
    """A half-width as floats, None (an entry the model does not fit) as NaN."""
    return np.array(
        [
            [np.nan if v is None else v for v in row] if isinstance(row, list) else (np.nan if row is None else row)
            for row in values
        ],
        dtype=float,
    )


def calibrate_log(path: Path, fmt: str, fields: dict | None = None) -> dict:
    """The method ``compass_flight`` on a log file, as the API runs it on a stored recording (``fields``: the
    request's other fields)."""
    request = rq.CompassFlightIn(method="compass_flight", recording_id="bench", **(fields or {}))
    options = ReadOptions(format=fmt)
    log = read_log(path, options, name=path.name)  # read and described as an upload is (the flight's sensors)
    meta = {**describe_log(log, options), "filename": path.name}
    return calibrate(request, RecordingSource(meta=meta, path=path, log=log)).body()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--flights", type=int, default=200)
    parser.add_argument("--seed", type=int, default=2000)
    args = parser.parse_args()
    start = time.perf_counter()
    tally = {
        fw: {
            "offsets": [],
            "matrix": [],
            "motor": [],
            "found": 0,
            "ok": 0,
            "models": Counter(),
            "full": [],
            "before": [],
            "after": [],
            "seconds": 0.0,
        }
        for fw, _, _ in FIRMWARES
    }
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(args.flights):
            orientation = MOUNTINGS[i % len(MOUNTINGS)]
            flight = seeded_flight(args.seed + i, orientation=orientation)
            truth = flight["truth"]
            paths = write_flight_compass_logs(tmp, flight)
            for fw, fmt, which in FIRMWARES:
                t0 = time.perf_counter()
                body = calibrate_log(paths[which], fmt)
                t = tally[fw]
                t["seconds"] += time.perf_counter() - t0
                model, half = body["model"], body["uncertainty"]
                t["found"] += body["flight"]["rotation_nearest"][fw] == orientation
                t["ok"] += bool(body["ok"])
                chosen = f"{body['flight']['structure']}+{body['flight']['motor']}"
                t["models"][chosen] += 1
                for cls, key, sel in (
                    ("offsets", "b", slice(None)),
                    ("matrix", "M", UPPER),
                    ("motor", "k", slice(None)),
                ):
                    if half.get(key) is None:
                        continue
                    hw = _array(half[key])[sel]
                    err = np.abs(np.asarray(model[key], dtype=float) - truth[key])[sel]
                    fitted = np.isfinite(hw) & (hw > 0)
                    t[cls] += list(err[fitted] <= hw[fitted])
                    if chosen == "soft_iron+current":
                        t["full"] += list(err[fitted] <= hw[fitted])
                t["before"].append(body["metrics"]["heading_error_before_deg"])
                t["after"].append(body["metrics"]["heading_error_after_deg"])
    n = args.flights
    print(
        f"{n} seeded flights (seeds {args.seed}..{args.seed + n - 1}), mountings {MOUNTINGS} with 0 stored, "
        f"each written as both firmwares' logs and calibrated by compass_flight; {time.perf_counter() - start:.0f} s"
    )
    for fw, _, _ in FIRMWARES:
        t = tally[fw]
        shares = ", ".join(
            f"{cls} {np.mean(t[cls]):.3f} of {len(t[cls])}" if t[cls] else f"{cls} -"
            for cls in ("offsets", "matrix", "motor")
        )
        overall = np.mean(t["offsets"] + t["matrix"] + t["motor"])
        print(
            f"{fw:9s}: inside the 95 % intervals: {shares}; overall {overall:.3f}; "
            f"over the flights fitted with soft iron and motor {np.mean(t['full']):.3f}"
        )
        print(f"{'':9s}  orientation found {t['found']}/{n}; ok {t['ok']}/{n}; models {dict(t['models'])}")
        print(
            f"{'':9s}  heading error rms on segments left out, median: before {np.median(t['before']):.2f}°, "
            f"after {np.median(t['after']):.2f}° (after: 95th percentile over flights "
            f"{np.percentile(t['after'], 95):.2f}°); {t['seconds'] / n:.2f} s a log"
        )


if __name__ == "__main__":
    main()
