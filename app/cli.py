"""The ``trical`` command: serve, calibrate, autocal, export.

``--json`` prints the same JSON as the API.  Errors are one line on stderr and exit status 2
(bad input) or 1 (anything else); never a traceback.
"""

from __future__ import annotations

import argparse
import json
import os
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
from app.tls import CertificateError

KNOWN_METHODS = ("six_position", "orientations")
UNKNOWN_METHODS = ("nonorthogonal", "triangular")
CUBE_METHODS = ("cube",)


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="trical", description="Calibrate accelerometers of phones and IMU boards.")
    p.add_argument("--version", action="version", version=f"trical {__version__}")
    sub = p.add_subparsers(dest="command", required=True)

    s = sub.add_parser("serve", help="serve the API and the pages")
    s.add_argument("--host", default=None,
                   help="address to listen on (default: HOST, else 127.0.0.1, or 0.0.0.0 with --https)")
    s.add_argument("--port", type=int, default=None, help="port (default: PORT or 8000)")
    s.add_argument("--https", action="store_true",
                   help="serve over TLS so that a phone on the LAN can use its motion sensors "
                        "(a self-signed certificate unless --cert and --key)")
    s.add_argument("--cert", type=Path, default=None, metavar="FILE", help="PEM certificate to serve (implies --https)")
    s.add_argument("--key", type=Path, default=None, metavar="FILE", help="PEM private key of --cert")

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

    a = sub.add_parser("autocal", help="auto-calibrate a long recording (or a folder of them), 002 pipeline")
    a.add_argument("path", type=Path, help=".npy (N×3 or N×4 with time), Parquet or CSV file, or a folder of them")
    a.add_argument("--sampling-rate-hz", type=float, default=None, help="needed when the file has no time column")
    a.add_argument("--unit", choices=workflow.AUTOCAL_UNITS, default=None, help="accelerometer unit (default: the file's, else m/s^2)")
    a.add_argument("--solver", choices=("lm", "gradient", "fixed16", "fixed32"), default="lm")
    a.add_argument("--gravity", type=float, default=None, help="reference gravity in m/s^2")
    a.add_argument("--latitude-deg", type=float, default=None, help="local normal gravity from latitude")
    a.add_argument("--all-axes", action="store_true", help="every axis must pass the max − min test (002: one is enough)")
    a.add_argument("--workers", type=int, default=None, help="parallel processes for a folder (default: CPU count)")
    a.add_argument("--dask-scheduler", default=None, metavar="ADDRESS",
                   help="run a folder on a Dask cluster (needs dask.distributed), e.g. tcp://host:8786")
    a.add_argument("--device-id", default=None)
    a.add_argument("--store", action="store_true", help="store the calibration(s) in the database")
    a.add_argument("--json", action="store_true", help="print the API's JSON (a list for a folder)")

    e = sub.add_parser("export", help="export a stored calibration")
    e.add_argument("id", help="calibration id (cal_...)")
    e.add_argument("--format", choices=tuple(EXPORTERS), default="json")
    e.add_argument("--output", "-o", type=Path, default=None, help="file to write (default: stdout)")
    return p


def _serve(args, settings: Settings) -> int:
    import uvicorn

    port = args.port or settings.port
    if args.https or args.cert or args.key:
        return _serve_https(args, settings, port)
    host = args.host or settings.host or "127.0.0.1"
    print(f"trical {__version__} on http://{host}:{port}  (database {settings.database_label})", flush=True)
    uvicorn.run("app.main:app", host=host, port=port, log_level="info")
    return 0


def _serve_https(args, settings: Settings, port: int) -> int:
    import uvicorn

    from app import tls
    from app.qr import qr_terminal

    if bool(args.cert) != bool(args.key):
        raise tls.CertificateError("--cert and --key go together: give both, or neither for a self-signed certificate")
    host = args.host or settings.host or "0.0.0.0"
    everywhere = host in ("0.0.0.0", "::")
    lan_ip = tls.lan_addresses()[0]
    url_host = lan_ip if everywhere else (f"[{host}]" if ":" in host else host)
    url = f"https://{url_host}:{port}/wizard?protocol=six"
    print(f"trical {__version__} on https://{host}:{port}  (database {settings.database_label})")
    if everywhere:
        print(f"listening on every interface ({host}) so that a phone on this network can connect; "
              "--host 127.0.0.1 keeps it to this machine")
    if args.cert:
        tls.check_certificate_files(args.cert, args.key)
        cert, key = args.cert, args.key
        print(f"certificate {cert} (SHA-256 {tls.fingerprint(cert)})")
    else:
        hosts = tls.certificate_hosts([] if everywhere else [host])
        cert, key, made = tls.self_signed_certificate(settings.tls_dir, hosts)
        print(f"{'made a' if made else 'reusing the'} self-signed certificate {cert} for {', '.join(hosts)}")
        print("The browser will warn that this certificate is not trusted (it signed itself). Proceed when its\n"
              "SHA-256 fingerprint is the one below (Chrome: Advanced → Proceed; Safari: Show Details → visit):\n"
              f"  {tls.fingerprint(cert)}")
    if not settings.public_url:
        os.environ["TRICAL_PUBLIC_URL"] = url  # app.main builds its settings from the environment
    print(f"Open {url} on your phone")
    _print_qr(qr_terminal(url))
    uvicorn.run("app.main:app", host=host, port=port, log_level="info", ssl_certfile=str(cert), ssl_keyfile=str(key))
    return 0


def _print_qr(drawing: str) -> None:
    try:
        sys.stdout.write(drawing)
    except UnicodeEncodeError:  # a terminal that cannot show block characters
        print("(this terminal cannot draw the QR code: type the address above)")
    sys.stdout.flush()


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
        body = open_store(settings.database_url, settings.recordings_dir).add_calibration(body, owner=None)
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


class _ProgressBar:
    """A one-line progress bar on stderr, drawn only on a terminal."""

    def __init__(self, label: str, stream=None):
        self.stream = stream or sys.stderr
        self.label = label
        self.last = -1

    def __call__(self, done: int, total: int) -> None:
        pct = int(100 * done / total) if total else 100
        if pct == self.last:
            return
        self.last = pct
        filled = pct * 30 // 100
        self.stream.write(f"\r{self.label} [{'#' * filled}{'.' * (30 - filled)}] {pct:3d}% "
                          f"{done / 1e6:.1f}/{total / 1e6:.1f} M samples")
        if done >= total:
            self.stream.write("\n")
        self.stream.flush()


def _autocal_options(args) -> dict:
    return dict(sampling_rate_hz=args.sampling_rate_hz, unit=args.unit, solver=args.solver, gravity=args.gravity,
                latitude_deg=args.latitude_deg, detection={"all_axes": True} if args.all_axes else None,
                device_id=args.device_id)


def _autocal_job(path: str, options: dict) -> dict:
    """One file of a folder run (top level, so that worker processes can pickle it)."""
    try:
        return workflow.autocalibrate_file(path, **options)
    except (CalibrationError, LogFormatError) as exc:
        return {"label": Path(path).name, "ok": False, "error": str(exc)}
    except Exception as exc:  # a worker must report, never take the run down
        return {"label": Path(path).name, "ok": False, "error": f"{type(exc).__name__}: {exc}"}


def _autocal(args, settings: Settings) -> int:
    options = _autocal_options(args)
    if args.path.is_dir():
        return _autocal_folder(args, settings, options)
    progress = _ProgressBar(args.path.name) if sys.stderr.isatty() else None
    body = workflow.autocalibrate_file(args.path, progress=progress, **options)
    if args.store:
        body = open_store(settings.database_url, settings.recordings_dir).add_calibration(body, owner=None)
    if args.json:
        print(json.dumps(body, indent=2))
    else:
        _print_autocal(body)
    return 0 if body["ok"] else 3


def _print_autocal(body: dict) -> None:
    det, m = body["detection"], body["metrics"]
    print(f"{body['label']}: {det['n_rest']} rest segments of {det['n_segments']} ({det['segment_s']:g} s; "
          f"{det['n_moving']} moving, {det['n_nan']} NaN, {det['n_idle']} idle sleep); ok = {body['ok']}")
    print("points per subset C_ij: " + ", ".join(f"{k} {v}" for k, v in body["selection"].items()))
    model = body["model"]
    print("K =")
    for row in model["K"]:
        print("   " + "  ".join(f"{v: .6f}" for v in row))
    print("o = " + "  ".join(f"{v: .6f}" for v in model["o"]))
    if body["comparison"]:
        print(f"{'method':<22}{'before mg':>10}{'after mg':>10}{'R %':>9}  points")
        for name, row in body["comparison"].items():
            if row.get("error_after_mg") is None:
                print(f"{name:<22}{'-':>10}{'-':>10}{'-':>9}  {row.get('count')}")
                continue
            print(f"{name:<22}{row['error_before_mg']:>10.2f}{row['error_after_mg']:>10.2f}"
                  f"{row['improvement_pct'] or 0:>9.0f}  {row.get('count')}")
    for w in body["warnings"]:
        print(f"warning: {w}")


def _folder_files(folder: Path) -> list[Path]:
    from app.io.arrays import SUFFIXES

    files = sorted(p for p in folder.iterdir() if p.is_file() and p.suffix.lower() in SUFFIXES)
    if not files:
        raise LogFormatError(f"{folder} holds no .npy, .parquet or .csv recordings")
    return files


def _autocal_folder(args, settings: Settings, options: dict) -> int:
    files = _folder_files(args.path)
    paths = [str(p) for p in files]
    if args.dask_scheduler:
        try:
            from dask.distributed import Client
        except ImportError:
            raise CalibrationError(
                "--dask-scheduler needs dask.distributed, which is not installed: pip install 'dask[distributed]' "
                "(or leave --dask-scheduler out to use local processes)"
            ) from None
        with Client(args.dask_scheduler) as client:
            futures = client.map(_autocal_job, paths, options=options, pure=False)
            bodies = client.gather(futures)
    else:
        from concurrent.futures import ProcessPoolExecutor

        workers = args.workers or min(len(paths), os.cpu_count() or 1)
        if workers <= 1:
            bodies = [_autocal_job(p, options) for p in paths]
        else:
            with ProcessPoolExecutor(max_workers=workers) as pool:
                bodies = list(pool.map(_autocal_job, paths, [options] * len(paths)))
    if args.store:
        store = open_store(settings.database_url, settings.recordings_dir)
        bodies = [store.add_calibration(b, owner=None) if "error" not in b else b for b in bodies]
    if args.json:
        print(json.dumps(bodies, indent=2))
    else:
        _print_folder_table(bodies)
    return 0 if all(b.get("ok") for b in bodies) else 3


def _print_folder_table(bodies: list[dict]) -> None:
    name_w = max(8, *(len(b.get("label") or "") for b in bodies))
    print(f"{'file':<{name_w}}  {'ok':<5}{'rest':>7}{'points':>7}{'before mg':>10}{'after mg':>10}{'R %':>8}  note")
    for b in bodies:
        if "error" in b:
            print(f"{b['label']:<{name_w}}  {'error':<5}{'':>7}{'':>7}{'':>10}{'':>10}{'':>8}  {b['error']}")
            continue
        m = b["metrics"]
        before = "-" if m.get("error_before_mg") is None else f"{m['error_before_mg']:.2f}"
        after = "-" if m.get("error_after_mg") is None else f"{m['error_after_mg']:.2f}"
        r = "-" if not m.get("improvement_pct") else f"{m['improvement_pct']:.0f}"
        note = b["reasons"][0] if b["reasons"] else ""
        print(f"{b['label']:<{name_w}}  {str(b['ok']):<5}{b['detection']['n_rest']:>7}{m['count']:>7}"
              f"{before:>10}{after:>10}{r:>8}  {note[:100]}")
    n_ok = sum(1 for b in bodies if b.get("ok"))
    print(f"{n_ok} of {len(bodies)} recordings calibrated")


def _export(args, settings: Settings) -> int:
    body = open_store(settings.database_url, settings.recordings_dir).get_calibration(args.id, owner=None)
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
        command = {"serve": _serve, "calibrate": _calibrate, "autocal": _autocal, "export": _export}[args.command]
        return command(args, settings)
    except (CalibrationError, LogFormatError, ExportError, SettingsError, CertificateError) as exc:
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
