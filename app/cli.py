"""The ``trical`` command: serve, calibrate, export.

``--json`` prints the same JSON as the API.  Errors are one line on stderr and exit status 2
(bad input) or 1 (anything else); never a traceback.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from app import __version__, workflow
from app.calibration import CalibrationError
from app.config import Settings, SettingsError
from app.io.errors import ExportError, LogFormatError
from app.io.exporters import EXPORTERS, export_calibration
from app.io.formats import FORMATS
from app.store import NotFoundError, open_store

KNOWN_METHODS = ("six_position", "orientations")
UNKNOWN_METHODS = ("nonorthogonal", "triangular")
CUBE_METHODS = ("cube",)


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="trical", description="Calibrate accelerometers of phones and IMU boards.")
    p.add_argument("--version", action="version", version=f"trical {__version__}")
    sub = p.add_subparsers(dest="command", required=True)

    s = sub.add_parser("serve", help="serve the API and the pages")
    s.add_argument("--host", default=None, help="address to listen on (default: HOST or 127.0.0.1)")
    s.add_argument("--port", type=int, default=None, help="port (default: PORT or 8000)")

    c = sub.add_parser("calibrate", help="calibrate from a log of still orientations")
    c.add_argument("log", type=Path, help="log: CSV with a header row, or a phyphox / Sensor Logger zip")
    c.add_argument("--method", choices=KNOWN_METHODS + UNKNOWN_METHODS + CUBE_METHODS, default="six_position")
    c.add_argument("--protocol", choices=("cube24", "ferraris"), default="cube24", help="cube only")
    c.add_argument("--field-ut", type=float, default=None, help="cube only: local magnetic field magnitude in µT")
    c.add_argument("--gyr-unit", choices=("rad/s", "deg/s", "raw"), default=None)
    c.add_argument("--mag-unit", choices=("uT", "nT", "raw"), default=None)
    c.add_argument("--solver", choices=("lm", "gradient", "fixed16", "fixed32"), default="lm",
                   help="triangular only: lm, or 002's descent in float, 16- or 32-bit fixed point")
    c.add_argument("--sampling-rate-hz", type=float, default=None, help="needed when the log has no time column")
    c.add_argument("--unit", choices=("m/s^2", "g", "raw"), default=None, help="accelerometer unit of the log")
    c.add_argument("--log-format", choices=FORMATS, default="auto", help="log format (default: from the header)")
    c.add_argument("--lsb-per-g", type=float, default=None, help="counts per g of a raw (LSB) accelerometer")
    c.add_argument("--gravity", type=float, default=None, help="reference gravity in m/s^2")
    c.add_argument("--latitude-deg", type=float, default=None, help="local normal gravity from latitude")
    c.add_argument("--height-m", type=float, default=None, help="height above the ellipsoid, with --latitude-deg")
    c.add_argument("--device-id", default=None)
    c.add_argument("--no-store", action="store_true", help="do not store the calibration in the database")
    c.add_argument("--json", action="store_true", help="print the API's JSON")

    e = sub.add_parser("export", help="export a stored calibration")
    e.add_argument("id", help="calibration id (cal_...)")
    e.add_argument("--format", choices=tuple(EXPORTERS), default="json")
    e.add_argument("--output", "-o", type=Path, default=None, help="file to write (default: stdout)")
    return p


def _serve(args, settings: Settings) -> int:
    import uvicorn

    host = args.host or settings.host
    port = args.port or settings.port
    print(f"trical {__version__} on http://{host}:{port}  (database {settings.database_label})", flush=True)
    uvicorn.run("app.main:app", host=host, port=port, log_level="info")
    return 0


def _calibrate(args, settings: Settings) -> int:
    units = {k: v for k, v in (("acc", args.unit), ("gyr", args.gyr_unit), ("mag", args.mag_unit)) if v}
    log = workflow.load_log(args.log, sampling_rate_hz=args.sampling_rate_hz, units=units, name=str(args.log),
                            format=args.log_format, lsb_per_g=args.lsb_per_g)
    recording = workflow.describe_log(log)
    unit = log.units["acc"]
    gravity, notes = workflow.reference_gravity(unit, args.gravity, args.latitude_deg, args.height_m)
    extra: dict = {}
    source: dict = {}
    if args.method in CUBE_METHODS:
        result = workflow.calibrate_cube_log(log, protocol=args.protocol, gravity=gravity, field_ut=args.field_ut)
        source = {"units": log.units}
    elif args.method in KNOWN_METHODS:
        readings, source["segments_used"] = workflow.readings_from_segments(recording, args.method, None)
        result, extra = workflow.calibrate_known(args.method, readings, unit=unit, gravity=gravity)
    else:
        means, source["segments_used"] = workflow.means_from_segments(recording, None)
        result, extra = workflow.calibrate_unknown(args.method, means, unit=unit, gravity=gravity, solver=args.solver)
    body = workflow.calibration_body(result, extra, unit=unit, notes=notes, device_id=args.device_id,
                                     label=str(args.log.name), **source)
    if not args.no_store:
        body = open_store(settings.database_url, settings.recordings_dir).add_calibration(body)
    if args.json:
        print(json.dumps(body, indent=2))
    else:
        _print_summary(body, recording)
    return 0 if body["ok"] else 3


def _print_summary(body: dict, recording: dict) -> None:
    print(f"{len(recording['segments'])} still segments in {recording['n_samples']} samples "
          f"at {recording['sampling_rate_hz']:g} Hz; used {body.get('segments_used', 'all')}")
    if body.get("id"):
        print(f"calibration {body['id']} ({body['method']}), ok = {body['ok']}")
    for name, value in body["model"].items():
        if name == "type" or isinstance(value, dict) or value is None:
            if isinstance(value, dict):
                print(f"{name}: S = {np.round(np.asarray(value['S']), 6).tolist()}, b = {np.round(value['b'], 6).tolist()}")
            continue
        arr = np.atleast_2d(np.asarray(value, dtype=float))
        print(f"{name} =" if arr.shape[0] > 1 else f"{name} = " + "  ".join(f"{v: .6f}" for v in arr[0]))
        if arr.shape[0] > 1:
            for row in arr:
                print("   " + "  ".join(f"{v: .6f}" for v in row))
    m = body["metrics"]
    if "fit_error_max" in m:
        print(f"fit error max {m['fit_error_max']:.6f} (raw {m['fit_error_max_raw']:.6f})")
    if "norm_error_max" in m:
        print(f"norm error max {m['norm_error_max']:.6f} (raw {m['norm_error_max_raw']:.6f})")
    for w in body["warnings"]:
        print(f"warning: {w}")


def _export(args, settings: Settings) -> int:
    body = open_store(settings.database_url, settings.recordings_dir).get_calibration(args.id)
    out = export_calibration(body, args.format)
    if args.output:
        args.output.write_text(out.content)
        print(f"wrote {args.output}", file=sys.stderr)
    else:
        sys.stdout.write(out.content)
    return 0


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    try:
        settings = Settings.from_env()
        command = {"serve": _serve, "calibrate": _calibrate, "export": _export}[args.command]
        return command(args, settings)
    except (CalibrationError, LogFormatError, ExportError, SettingsError) as exc:
        print(f"trical: error: {exc}", file=sys.stderr)
        return 2
    except NotFoundError as exc:
        print(f"trical: error: {exc.args[0]}", file=sys.stderr)
        return 2
    except FileNotFoundError as exc:
        print(f"trical: error: no such file: {exc.filename}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
