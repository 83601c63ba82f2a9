"""``trical capture``: the guided calibration of a board on a serial port — the port opened, the capture on it
(:mod:`app.cli.board`), then the log calibrated or characterised as ``trical calibrate`` or ``trical noise``
does, and the calibration sent to the board with ``--send``."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from app.calibration import CalibrationError
from app.cli import noise
from app.cli.calibrate import calibrated
from app.cli.parser import defaults_of
from app.cli.printers import print_summary
from app.io.errors import LogFormatError
from app.words import render

if TYPE_CHECKING:
    from collections.abc import Callable

    from app.config import Settings


def run(args, settings: Callable[[], Settings]) -> int:
    """``trical capture PORT``: the board's lines captured hands-free into a log, then calibrated (app.cli.board)."""
    import serial  # pyserial

    from app.guided.capture_rules import CAPTURE_S_DEFAULT, CAPTURE_S_RANGE

    capture_s = CAPTURE_S_DEFAULT if args.capture_s is None else args.capture_s
    low, high = CAPTURE_S_RANGE
    if not low <= capture_s <= high:
        raise CalibrationError(
            f"--capture-s {capture_s:g} is out of range: give the seconds captured per pose, from "
            f"{low:g} to {high:g} (the wizard's default is {CAPTURE_S_DEFAULT:g})"
        )
    try:
        port = serial.Serial(args.port, args.baud, timeout=0.1)
    except (serial.SerialException, ValueError) as exc:
        raise LogFormatError(
            f"cannot open {args.port} at {args.baud} baud ({exc}): check the port's name (ls /dev/tty* "
            "on Linux, COM3 on Windows) and that no other program (a serial monitor) holds it"
        ) from None
    with port:
        return capture_on_port(port, args, settings, capture_s=capture_s)


def capture_on_port(port, args, settings: Callable[[], Settings], *, capture_s: float, clock=None) -> int:
    """The steps of ``trical capture`` on an open port (``read(n)``, ``write``, ``flush``: pyserial's
    ``Serial``), on ``clock`` (``time.monotonic`` unless given)."""
    import time

    from app.cli.board import Capture

    steps = sys.stderr if args.json else sys.stdout
    tty = steps.isatty()

    def say(text: str) -> None:
        print(("\r\033[K" if tty else "") + text, file=steps, flush=True)

    def bell() -> None:
        steps.write("\a")

    def live(text: str) -> None:
        steps.write("\r\033[K" + text[:110])
        steps.flush()

    out = args.out or Path(time.strftime("trical-capture-%Y%m%d-%H%M%S.csv"))
    say(f"{args.port} open at {args.baud} baud; waiting for the board's lines")
    capture = Capture(
        port,
        protocol=args.protocol,
        out_path=out,
        fmt=args.format,
        units={"acc": args.unit} if args.unit else None,
        minutes=args.minutes,
        capture_s=capture_s,
        baud=args.baud,
        say=say,
        bell=bell,
        live=live if tty else None,
        clock=clock or time.monotonic,
    )
    outcome = capture.run()
    finish = f"trical {capture.protocol.command} {out}"
    if outcome.status == "interrupted":
        bell()
        say(
            f"stopped: {out} keeps the {outcome.readings} readings received; finish it with: {finish}"
            if outcome.log_path
            else "stopped before any reading arrived: nothing was written"
        )
        return 130
    if outcome.status != "finished":
        if outcome.log_path:
            say(f"{out} keeps the {outcome.readings} readings received; calibrate what it holds with: {finish}")
        return 2
    rate = f" at {outcome.rate_hz:.4g} Hz" if outcome.rate_hz else ""
    say(f"wrote {out}: {outcome.readings} readings{rate}")
    return _CAPTURE_FINISH[capture.protocol.command](capture, outcome, args, settings)


def _capture_noise(capture, outcome, args, settings: Callable[[], Settings]) -> int:
    """``trical capture --protocol noise``'s end: the log characterised as ``trical noise LOG`` does."""
    noise_args = argparse.Namespace(
        **{**defaults_of("noise"), "path": [capture.out_path], "json": args.json, "store": not args.no_store}
    )
    return noise.run(noise_args, settings)


def _capture_calibration(capture, outcome, args, settings: Callable[[], Settings]) -> int:
    """The end of ``trical capture``'s other protocols: the log calibrated with the protocol's method (from its
    captures' rows where the protocol says so), printed, and sent to the board with ``--send``."""
    from app.io.exports.motioncal_packet import packet_of

    protocol, out, port, say, bell = capture.protocol, capture.out_path, capture.port, capture.say, capture.bell
    cal_args = argparse.Namespace(
        **{
            **defaults_of("calibrate"),
            "log": [out],
            "method": protocol.method,
            "unit": args.unit,
            "device_id": args.device_id,
            "no_store": args.no_store,
        }
    )
    captures = outcome.rows if protocol.from_captures else None
    say(f"calibrating {out} ({protocol.method}{f' on its {len(captures)} captures' if captures else ''})")
    calibration, body, recording = calibrated(cal_args, settings, out, captures)
    if args.json:
        print(json.dumps(body, indent=2))
    else:
        print_summary(calibration, body, recording, verbose=getattr(args, "verbose", False))
    bell()
    if args.send:
        if not body["ok"]:
            say("not sent to the board: the calibration is not ok (see the reasons)")
            return 3
        compass = None if args.without_compass else _latest_compass(body, args.device_id, settings)
        if compass is not None:
            say(
                f"including the compass calibration of {args.device_id} from {compass['created_at']} "
                f"({compass['id']}), so that the board keeps it (--without-compass leaves it out)"
            )
        packet, notes = packet_of(body, compass)
        port.write(packet)
        port.flush()
        say(f"sent MotionCal's {len(packet)}-byte calibration packet to the board")
        for note in notes:
            say(f"note: {render(note, 'cli')}")
    return 0 if body["ok"] else 3


def _latest_compass(body: dict, device_id: str | None, settings: Callable[[], Settings]) -> dict | None:
    """The device's latest stored compass calibration that is ok, for a packet whose own calibration has no compass
    (the page's latestCompass): None without a device name, or where the calibration has its own compass."""
    from app.cli.finish import store_of

    if not device_id or "mag" in _sensors(body):
        return None
    listed = store_of(settings).list_calibrations(owner=None, device_id=device_id)
    return next((cal for cal in listed if cal.get("ok") and _sensors(cal) == {"mag"}), None)


def _sensors(body: dict) -> set[str]:
    """The sensors a calibration corrects (none for a noise or temperature characterisation)."""
    from app.io.errors import ExportError
    from app.io.exports.common import sensor_corrections

    try:
        return {c.sensor for c in sensor_corrections(body)}
    except ExportError:
        return set()


_CAPTURE_FINISH = {"noise": _capture_noise, "calibrate": _capture_calibration}
"""How ``trical capture`` ends, by the command its protocol finishes with (app.guided.protocols)."""
