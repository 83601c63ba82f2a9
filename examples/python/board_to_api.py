"""Read a board's lines with pyserial and calibrate them with trical's REST API.

The board prints Adafruit's ``Uni:`` lines (the sketches of static/sketches); this script records them for a while as
the board rests in its six poses, uploads them as a log and asks
for a calibration (method ``auto``), then prints the verdict and saves the C header.

    pip install "pyserial>=3.5"
    python board_to_api.py /dev/ttyACM0 --seconds 60 --api http://localhost:8000

Only the standard library and pyserial: the board's host (a Raspberry Pi) need not have trical; the
server may run elsewhere. ``trical capture PORT`` does the same in one command, with hands-free cues.
"""

from __future__ import annotations

import argparse
import json
import time
import urllib.error
import urllib.request
import uuid

import serial  # pyserial

UNI_HEADER = (
    "time_s,acc_x (m/s^2),acc_y (m/s^2),acc_z (m/s^2),gyr_x (rad/s),gyr_y (rad/s),gyr_z (rad/s),"
    "mag_x (uT),mag_y (uT),mag_z (uT)"
)


def record(port: str, baud: int, seconds: float) -> str:
    """The board's Uni: lines as a CSV log, each stamped with its arrival (s): trical takes the rate from the
    span of the arrivals, which the bursts of a serial port do not change."""
    rows = [UNI_HEADER]
    skipped = 0
    start = shown = time.monotonic()
    with serial.Serial(port, baud, timeout=0.5) as board:
        while time.monotonic() - start < seconds:
            line = board.readline().decode("utf-8", errors="replace").strip()
            now = time.monotonic()
            if line.startswith("Uni:") and line.count(",") == 8:
                rows.append(f"{now - start:.4f},{line[4:].strip()}")
            elif line:
                skipped += 1  # boot text, a truncated line
            if now - shown >= 0.25 or len(rows) == 1:  # the count a few times a second: printing every line of
                shown = now  # a board at 100 Hz slows a small host's reading into bursts
                print(f"\r{len(rows) - 1} readings, {skipped} other lines", end="", flush=True)
    print(f"\r{len(rows) - 1} readings, {skipped} other lines")
    if len(rows) == 1:
        raise SystemExit(f"no Uni: line arrived at {baud} baud: check the rate and that the board prints readings")
    return "\n".join(rows) + "\n"


def post(url: str, body: bytes, content_type: str) -> dict:
    request = urllib.request.Request(url, data=body, headers={"Content-Type": content_type}, method="POST")
    try:
        with urllib.request.urlopen(request, timeout=120) as answer:
            return json.load(answer)
    except urllib.error.HTTPError as exc:  # trical's errors say what to fix: show them
        raise SystemExit(f"{url}: {exc.code} {json.load(exc).get('detail', '')}") from None


def upload(api: str, log: str) -> dict:
    boundary = uuid.uuid4().hex
    body = (
        f'--{boundary}\r\nContent-Disposition: form-data; name="file"; filename="board.csv"\r\n'
        f"Content-Type: text/csv\r\n\r\n{log}\r\n--{boundary}--\r\n"
    ).encode()
    return post(f"{api}/api/v1/recordings", body, f"multipart/form-data; boundary={boundary}")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("port")
    p.add_argument("--baud", type=int, default=115200)
    p.add_argument("--seconds", type=float, default=60.0, help="how long to record (rest the board in six poses)")
    p.add_argument("--api", default="http://localhost:8000")
    args = p.parse_args()
    log = record(args.port, args.baud, args.seconds)
    recording = upload(args.api, log)
    print(f"recording {recording['id']}: {len(recording.get('segments', []))} still segments")
    cal = post(
        f"{args.api}/api/v1/calibrations",
        json.dumps({"recording_id": recording["id"], "method": "auto"}).encode(),
        "application/json",
    )
    print(f"calibration {cal['id']} ({cal['method']}): {cal['verdict']['words']}")
    with urllib.request.urlopen(f"{args.api}/api/v1/calibrations/{cal['id']}/export?format=c", timeout=60) as answer:
        header = answer.read()
    with open(f"trical_{cal['id']}.h", "wb") as f:
        f.write(header)
    print(f"wrote trical_{cal['id']}.h (examples/arduino/apply_trical_header shows how to use it)")


if __name__ == "__main__":
    main()
