"""The ``trical`` command: serve, calibrate, autocal, noise, temperature, export.

``--json`` prints the same JSON as the API.  Errors are one line on stderr and exit status 2
(bad input, including an option's value out of range: app.cli_options checks them while parsing) or
1 (anything else; TRICAL_DEBUG=1 adds the traceback); never a traceback otherwise.  Output into a pipe
closed early (``trical ... | head``) ends quietly with status 141, as a command killed by SIGPIPE does.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import traceback
import zipfile
from pathlib import Path

import numpy as np
from pydantic import ValidationError

from app import __version__, methods, workflow
from app import cli_options as opt
from app.calibration import CalibrationError
from app.calibration.angles import degrees_text, tilt_error_deg
from app.calibration.solvers import SOLVERS
from app.config import Settings, SettingsError
from app.io.board_formats import CAPTURE_PROTOCOLS, DEFAULT_BAUD
from app.io.plural import counted
from app.io.board_lines import FORMATS as BOARD_LINE_FORMATS
from app.io.errors import ExportError, LogFormatError
from app.io.formats import FORMATS, starts_like_flight_log
from app.io.formats.units import MAG_UNITS_IN
from app.io.log import GYR_TO_RAD_S, MAG_TO_UT, UNITS
from app.io.parts import refuse_repeated_names
from app.calibration_requests import CUBE_PROTOCOLS
from app.store import NotFoundError, open_store
from app.tls import CertificateError
from app.workflows.temperature import TEMPERATURE_SENSORS
from app.words import render, render_body

CALIBRATE_METHODS = methods.commanded_by("calibrate")
"""The choices of ``trical calibrate --method`` (the method table's; autocal, noise and temperature have
commands of their own)."""


def _takers(field: str) -> str:
    """The methods of ``trical calibrate`` whose request takes ``field``, for an option's help: "cube and
    magnetometer"."""
    return " and ".join(m for m in CALIBRATE_METHODS if field in methods.BY_NAME[m].options)


SCALED_UNITS = tuple(unit for units in UNITS.values() for unit in units if unit != "raw")
"""The units of ``trical noise --unit``: each sensor's, counts left out."""


class _Parser(argparse.ArgumentParser):
    """argparse with its errors on one line: ``trical calibrate: error: argument ...``."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="trical", description="Calibrate accelerometers of phones and IMU boards.")
    p.add_argument("--version", action="version", version=f"trical {__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    _add_serve(sub)
    _add_calibrate(sub)
    _add_autocal(sub)
    _add_noise(sub)
    _add_temperature(sub)
    _add_capture(sub)
    _add_export(sub)
    return p


def _add_serve(sub) -> None:
    """``trical serve``: the API and the pages."""
    s = sub.add_parser("serve", help="serve the API and the pages")
    s.add_argument("--host", type=opt.text("an address to listen on"), default=None,
                   help="address to listen on (default: HOST, else 127.0.0.1, or 0.0.0.0 with --https)")
    s.add_argument("--port", type=opt.PORT, default=None, help="port (default: PORT or 8000)")
    s.add_argument("--https", action="store_true",
                   help="serve over TLS so that a phone on the LAN can use its motion sensors "
                        "(a self-signed certificate unless --cert and --key)")
    s.add_argument("--cert", type=opt.input_path("a PEM certificate"), default=None, metavar="FILE", help="PEM certificate to serve (implies --https)")
    s.add_argument("--key", type=opt.input_path("the PEM private key of --cert"), default=None, metavar="FILE", help="PEM private key of --cert")


def _add_calibrate(sub) -> None:
    """``trical calibrate``: a log of still orientations (or a cube, a compass turn), by the method table's methods."""
    c = sub.add_parser("calibrate", help="calibrate from a log of still orientations")
    c.add_argument("log", type=opt.input_path("a log file"), nargs="+",
                   help="log: CSV with a header row, a phyphox / Sensor Logger zip, or several files (one per pose, "
                        "or a zip of them): one calibration, each reading naming its file")
    c.add_argument("--method", choices=CALIBRATE_METHODS, default="auto",
                   help="auto (default): six_position or orientations for axis-aligned poses, triangular for free ones")
    c.add_argument("--protocol", choices=CUBE_PROTOCOLS, default=CUBE_PROTOCOLS[0], help=f"{_takers('protocol')} only")
    c.add_argument("--field-ut", type=opt.FIELD_UT, default=None,
                   help=f"{_takers('field_ut')}: local magnetic field magnitude in µT (magnetometer: overrides the "
                        "model's)")
    c.add_argument("--sections", type=opt.input_path("a section list (JSON)"), default=None, metavar="FILE.json",
                   help=f"{_takers('sections')} with --protocol ferraris: imucal's annotated section list (x_p … z_rot, "
                        "sample indices)")
    c.add_argument("--gyr-unit", choices=UNITS["gyr"], default=None)
    c.add_argument("--mag-unit", choices=MAG_UNITS_IN, default=None)
    c.add_argument("--solver", choices=SOLVERS, default="lm",
                   help=f"{_takers('solver')} only: lm, or "
                        "Farago et al.'s descent in float, 16- or 32-bit fixed point")
    c.add_argument("--sampling-rate-hz", type=opt.SAMPLING_RATE, default=None, help="needed when the log has no time column")
    c.add_argument("--unit", choices=UNITS["acc"], default=None, help="accelerometer unit of the log")
    c.add_argument("--log-format", choices=FORMATS, default="auto", help="log format (default: from the header)")
    c.add_argument("--lsb-per-g", type=opt.LSB_PER_G, default=None, help="counts per g of a raw (LSB) accelerometer")
    _read_options(c)
    c.add_argument("--gravity", type=opt.GRAVITY, default=None, help="reference gravity in m/s^2")
    c.add_argument("--latitude-deg", type=opt.LATITUDE, default=None, help="local normal gravity from latitude (magnetometer: with --longitude-deg, the Earth's field there)")
    c.add_argument("--height-m", type=opt.HEIGHT, default=None, help="height above the ellipsoid, with --latitude-deg")
    c.add_argument("--longitude-deg", type=opt.LONGITUDE, default=None,
                   help=f"{_takers('longitude_deg')}: with --latitude-deg, the Earth's field there from IGRF")
    c.add_argument("--date", type=opt.DAY, default=None, help=f"{_takers('date')}: day of the recording (default today)")
    c.add_argument("--device-id", type=opt.text("a device id"), default=None)
    c.add_argument("--no-store", action="store_true", help="do not store the calibration in the database")
    c.add_argument("--json", action="store_true", help="print the API's JSON")


def _add_autocal(sub) -> None:
    """``trical autocal``: a long recording, or a folder of them."""
    a = sub.add_parser("autocal", help="auto-calibrate a long recording (or a folder of them), Farago et al. pipeline")
    a.add_argument("path", type=opt.input_path("a recording or a folder of them"), help=".npy (N×3 or N×4 with time), Parquet or CSV file, or a folder of them")
    a.add_argument("--sampling-rate-hz", type=opt.SAMPLING_RATE, default=None, help="needed when the file has no time column")
    a.add_argument("--unit", choices=workflow.AUTOCAL_UNITS, default=None, help="accelerometer unit (default: the file's, else m/s^2)")
    a.add_argument("--solver", choices=SOLVERS, default="lm")
    _read_options(a)
    a.add_argument("--gravity", type=opt.GRAVITY, default=None, help="reference gravity in m/s^2")
    a.add_argument("--latitude-deg", type=opt.LATITUDE, default=None, help="local normal gravity from latitude")
    a.add_argument("--all-axes", action="store_true", help="every axis must pass the max − min test (Farago et al.: one is enough)")
    a.add_argument("--workers", type=opt.WORKERS, default=None, help="parallel processes for a folder (default: CPU count)")
    a.add_argument("--dask-scheduler", type=opt.text("a scheduler address"), default=None, metavar="ADDRESS",
                   help="run a folder on a Dask cluster (needs dask.distributed), e.g. tcp://host:8786")
    a.add_argument("--device-id", type=opt.text("a device id"), default=None)
    a.add_argument("--store", action="store_true", help="store the calibration(s) in the database")
    a.add_argument("--json", action="store_true", help="print the API's JSON (a list for a folder)")


def _add_noise(sub) -> None:
    """``trical noise``: a still recording's Allan deviation."""
    n = sub.add_parser("noise", help="noise density, random walk and bias instability of a still recording (Allan deviation)")
    n.add_argument("path", type=opt.input_path("a still recording"), nargs="+",
                   help=".npy (N×3 with --sensor, or N×4 with time first), Parquet, CSV or any log format trical "
                        "reads; several files, one per sensor (accelerometer.csv gyroscope.csv), are one recording")
    n.add_argument("--sampling-rate-hz", type=opt.SAMPLING_RATE, default=None, help="needed when the file has no time column")
    n.add_argument("--sensor", choices=tuple(UNITS), default=None,
                   help="the sensor a three-column array holds (default acc); with a log: characterise only this one")
    n.add_argument("--unit", choices=SCALED_UNITS, default=None, help="unit of the array's sensor (acc: m/s^2 or g; gyr: rad/s or deg/s; mag: uT or nT)")
    _read_options(n)
    n.add_argument("--plot", type=opt.output_file("an SVG file to write"), default=None, metavar="FILE.svg",
                   help="write the log-log Allan plot with the fitted slopes")
    n.add_argument("--device-id", type=opt.text("a device id"), default=None)
    n.add_argument("--store", action="store_true", help="store the characterisation in the database")
    n.add_argument("--json", action="store_true", help="print the API's JSON")


def _add_temperature(sub) -> None:
    """``trical temperature``: the offsets' drift with temperature."""
    t = sub.add_parser("temperature", help="each axis's offset as a polynomial of temperature, from a still recording "
                                           "while the board warms up (a temp_c column, or a flight log)")
    t.add_argument("path", type=opt.input_path("a still recording with the sensor's temperature"),
                   help="a CSV with a temp_c (temp, temperature, T (°C)) column beside the readings, or any log "
                        "format trical reads that records the temperature")
    t.add_argument("--sampling-rate-hz", type=opt.SAMPLING_RATE, default=None, help="needed when the file has no time column")
    t.add_argument("--sensor", choices=TEMPERATURE_SENSORS, default=None,
                   help="calibrate only this sensor (default: the accelerometer and the gyroscope the log has)")
    _read_options(t)
    t.add_argument("--plot", type=opt.output_file("an SVG file to write"), default=None, metavar="FILE.svg",
                   help="write the plot of offset against temperature (binned readings, fit, 95 %% band)")
    t.add_argument("--device-id", type=opt.text("a device id"), default=None)
    t.add_argument("--store", action="store_true", help="store the calibration in the database (then trical export "
                                                        "ID --format px4 or ardupilot)")
    t.add_argument("--json", action="store_true", help="print the API's JSON")


def _add_capture(sub) -> None:
    """``trical capture``: the guided calibration of a board on a serial port."""
    b = sub.add_parser("capture", help="the guided calibration of a board on a serial port (pyserial): capture, "
                                       "log, calibrate, verdict")
    b.add_argument("port", type=opt.text("a serial port"), help="the board's serial port, e.g. /dev/ttyACM0 or COM3")
    b.add_argument("--baud", type=opt.BAUD, default=DEFAULT_BAUD, help=f"the port's rate (default {DEFAULT_BAUD})")
    b.add_argument("--protocol", choices=CAPTURE_PROTOCOLS, default="six",
                   help="six (default), free poses, cube24, compass (turn it) or noise (leave it still)")
    b.add_argument("--minutes", type=opt.MINUTES, default=None,
                   help="compass and noise: the length recorded (default 1); poses: the time allowed (default 10)")
    b.add_argument("--capture-s", type=opt.CAPTURE_S, default=None,
                   help="seconds captured per pose (default: the wizard's; within the range a session accepts)")
    b.add_argument("--format", choices=BOARD_LINE_FORMATS, default="auto",
                   help="the board's lines: auto (default), raw (MotionCal Raw:), uni (Uni:), csv, numbers")
    b.add_argument("--unit", choices=UNITS["acc"], default=None,
                   help="the accelerometer's unit (checked against the data at rest)")
    b.add_argument("--out", type=opt.output_file("a log file to write"), default=None, metavar="LOG.csv",
                   help="the log written as received (default trical-capture-DATE-TIME.csv)")
    b.add_argument("--send", action="store_true",
                   help="write MotionCal's 68-byte calibration packet to the board (Adafruit Sensor Calibration)")
    b.add_argument("--device-id", type=opt.text("a device id"), default=None)
    b.add_argument("--no-store", action="store_true", help="do not store the calibration in the database")
    b.add_argument("--json", action="store_true", help="print the API's JSON (the steps go to stderr)")


def _add_export(sub) -> None:
    """``trical export``: a stored calibration, in one of the formats."""
    e = sub.add_parser("export", help="export a stored calibration")
    e.add_argument("id", type=opt.text("a calibration id"), help="calibration id (cal_...)")
    e.add_argument("--format", choices=methods.ALL_FORMATS, default="json")
    e.add_argument("--output", "-o", type=opt.output_file("a file to write"), default=None, help="file to write (default: stdout)")


def _read_options(parser: argparse.ArgumentParser) -> None:
    """The options that say how to read a log, as the upload's form fields do."""
    parser.add_argument("--columns", type=opt.text("column names or a mapping"), default=None, metavar="NAMES",
                        help="name every column in order, e.g. t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z (- skips "
                             "one; for logs without a header row), or map unrecognised ones, e.g. acc_x:north,…")
    parser.add_argument("--chip", type=opt.CHIP, default=None, metavar="PARTS",
                        help="the parts (and ranges) of sensors logged in counts, separated by commas, e.g. "
                             "mpu6050-4g,mpu6050-500dps,ak8963-16bit: their counts become g, deg/s and uT "
                             "(the list: README, Units)")
    parser.add_argument("--sign", type=int, choices=(1, -1), default=None,
                        help="factor on the log's accelerations: -1 for iOS Core Motion's sign (-g up), 1 to keep "
                             "them (default: detected from the header)")
    parser.add_argument("--instance", type=opt.INSTANCE, default=None, metavar="N",
                        help="a flight controller's log (PX4 .ulg, ArduPilot .bin): the IMU instance to read (PX4 "
                             "multi_id, ArduPilot I; default: PX4 the source with the most samples, ArduPilot 0)")
    parser.add_argument("--mag-instance", type=opt.INSTANCE, default=None, metavar="N",
                        help="a flight controller's log: the compass instance the compass methods read (default: "
                             "the first)")


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
    with tempfile.TemporaryDirectory(prefix="trical-") as tmp:
        return _calibrate_files(args, settings, _one_recording(args.log, Path(tmp)))


def _one_recording(paths: list[Path], tmp: Path) -> Path:
    """The log to read: the one path, or the pose files put together, each under its name, in a zip that
    is read as one recording in parts (app.io.parts), as the API stores several uploaded files."""
    if len(paths) == 1:
        return paths[0]
    refuse_repeated_names([p.name for p in paths])
    joined = tmp / "poses.zip"
    with zipfile.ZipFile(joined, "w", compression=zipfile.ZIP_STORED) as zf:
        for p in paths:
            if not p.is_file():
                raise FileNotFoundError(2, "No such file", str(p))
            zf.write(p, p.name)
    return joined


def _calibrate_files(args, settings: Settings, path: Path) -> int:
    body, recording = _calibrated(args, settings, path)
    if args.json:
        print(json.dumps(body, indent=2))
    else:
        _print_summary(body, recording)
    return 0 if body["ok"] else 3


def _calibrated(args, settings: Settings, path: Path, captures: list | None = None) -> tuple[dict, dict]:
    """The calibration of the log at ``path`` as ``trical calibrate``'s options ask (stored unless
    ``--no-store``), and the recording's description; ``captures`` (``trical capture``'s rows of each
    capture) stand for the still segments the log's detector would find."""
    units = {k: v for k, v in (("acc", args.unit), ("gyr", args.gyr_unit), ("mag", args.mag_unit)) if v}
    read_with = dict(format=args.log_format, units=units, lsb_per_g=args.lsb_per_g, columns=args.columns,
                     sign=args.sign, chip=args.chip, instance=args.instance, mag_instance=args.mag_instance)
    name = ", ".join(str(p) for p in args.log)
    log = workflow.load_log(path, sampling_rate_hz=args.sampling_rate_hz, name=name, **read_with)
    recording = workflow.describe_log(log, {**read_with, "sampling_rate_hz": args.sampling_rate_hz})
    if captures:
        from app.board_capture import capture_segments

        recording["segments"] = capture_segments(log.acc, captures)
        recording["notes"].append(f"the still segments are the {len(captures)} captures, rows "
                                  + ", ".join(f"{a}–{b - 1}" for _, a, b in captures))
    request = methods.parse_calibration_request(_calibration_request(args, unit=log.units.get("acc", "m/s^2")))
    body = methods.calibrate(request, workflow.RecordingSource(meta=recording, path=path, log=log))
    if captures:  # each capture's rows of the log and its reading, as a wizard session's body lists its captures
        body["captures"] = [{"position": seg["capture"], "rows": [seg["start"], seg["end"]], "up": seg["up"],
                             "mean": seg["acc_mean"], "std": seg["acc_std"], "count": seg["count"]}
                            for seg in recording["segments"]]
    if not args.no_store:
        body = open_store(settings.database_url, settings.recordings_dir).add_calibration(body, owner=None)
    return body, recording


def _calibration_request(args, *, unit: str) -> dict:
    """The request of POST /api/v1/calibrations that ``trical calibrate`` makes of its options: each field the
    method's request model takes (app.methods) from the option of its name (``--field-ut``: ``field_ut``); the
    log file stands in for the stored recording, and ``unit`` is the log's accelerometer unit."""
    # Read whatever the method: a section list that cannot be read is an error, not an option ignored.
    sections = None if args.sections is None else _read_sections(args.sections)
    given = {**vars(args), "recording_id": ", ".join(str(p) for p in args.log),
             "label": ", ".join(p.name for p in args.log), "unit": unit, "sections": sections}
    return {"method": args.method, **{name: given[name] for name in methods.BY_NAME[args.method].options
                                      if given.get(name) is not None}}


def _read_sections(path) -> object:
    """The JSON of ``--sections``; the request model validates its keys and regions."""
    try:
        return json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise CalibrationError(f"--sections {path}: not a readable JSON section list ({exc}); write it as imucal "
                               "does: {\"x_p\": {\"start\": 540, \"end\": 1271}, …}") from None


def _print_summary(body: dict, recording: dict) -> None:
    body = render_body(body, "cli")
    rate = recording["sampling_rate_hz"]
    files = f" of {len(recording['parts'])} files" if recording.get("parts") else ""
    flight = body.get("flight")  # a compass from a flight: the log's facts, and no still segments read
    if flight:
        print(f"{flight['generation']}: compass {flight['instance']}, {body['metrics']['n_samples']} samples "
              f"({flight['raw_how']}), attitude from {flight['attitude_source']}")
    else:
        print(f"{counted(len(recording['segments']), 'still segment')} in {recording['n_samples']} samples{files} "
              f"{'without a sampling rate' if rate is None else f'at {rate:g} Hz'}; "
              f"used {body.get('segments_used', 'all')}")
    if body.get("id"):
        print(f"calibration {body['id']} ({body['method']}), ok = {body['ok']}")
    _print_verdict(body)
    if recording.get("parts"):  # one file per pose: what each file gave
        used = body.get("segments_used") or []
        for r, i in zip(body.get("readings") or [], used):
            up = recording["segments"][i]["up"]
            print(f"{r.get('source')}: {up + ' up' if up else 'no axis within 20°'}, mean "
                  + "  ".join(f"{v:.4f}" for v in r["mean"]))
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
    if body.get("choice"):
        print(f"method auto chose {body['choice']['method']}: {body['choice']['why']}")
    if body.get("headline"):
        print(body["headline"])
    if "fit_error_max" in m:
        print(f"fit error max {m['fit_error_max']:.6f} (raw {m['fit_error_max_raw']:.6f})")
    if "norm_error_max" in m:
        print(f"norm error max {m['norm_error_max']:.6f} (raw {m['norm_error_max_raw']:.6f})")
    for a in body.get("advice") or []:
        print(f"next pose: {a['words']} (shrinks the parameters' generalized variance by {100 * a['gain']:.0f} %)")
    for w in body["warnings"]:
        print(f"warning: {w}")


def _print_verdict(body: dict) -> None:
    """The verdict first (app.verdict): whether to apply the calibration, and why."""
    v = body.get("verdict")
    if v:
        print(v["words"])
        if v["why"]:
            print(f"  {v['why']}")


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
                device_id=args.device_id, columns=args.columns, sign=args.sign, chip=args.chip, instance=args.instance)


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
    body = render_body(body, "cli")
    det = body["detection"]
    print(f"{body['label']}: {det['n_rest']} rest segments of {det['n_segments']} ({det['segment_s']:g} s; "
          f"{det['n_moving']} moving, {det['n_nan']} NaN, {det['n_idle']} idle sleep); ok = {body['ok']}")
    _print_verdict(body)
    if body.get("headline"):
        print(body["headline"])
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
    bodies = [render_body(b, "cli") for b in bodies]
    name_w = max(8, *(len(b.get("label") or "") for b in bodies))
    # "tilt": the worst tilt a level reads with the cv error (app.calibration.angles).
    print(f"{'file':<{name_w}}  {'ok':<5}{'rest':>7}{'points':>7}{'cv mg':>8}{'tilt':>8}{'before mg':>10}{'after mg':>10}"
          f"{'R %':>8}  note")
    for b in bodies:
        if "error" in b:
            print(f"{b['label']:<{name_w}}  {'error':<5}{'':>7}{'':>7}{'':>8}{'':>8}{'':>10}{'':>10}{'':>8}  "
                  f"{render(b['error'], 'cli')}")
            continue
        m = b["metrics"]
        cv = "-" if m.get("cv_error_mg") is None else f"{m['cv_error_mg']:.2f}"
        tilt = "-" if m.get("cv_error_mg") is None else degrees_text(tilt_error_deg(m["cv_error_mg"]))
        before = "-" if m.get("error_before_mg") is None else f"{m['error_before_mg']:.2f}"
        after = "-" if m.get("error_after_mg") is None else f"{m['error_after_mg']:.2f}"
        r = "-" if not m.get("improvement_pct") else f"{m['improvement_pct']:.0f}"
        note = b["reasons"][0] if b["reasons"] else ""
        print(f"{b['label']:<{name_w}}  {str(b['ok']):<5}{b['detection']['n_rest']:>7}{m['count']:>7}{cv:>8}{tilt:>8}"
              f"{before:>10}{after:>10}{r:>8}  {note[:100]}")
    n_ok = sum(1 for b in bodies if b.get("ok"))
    print(f"{n_ok} of {len(bodies)} recordings calibrated")


def _noise(args, settings: Settings) -> int:
    with tempfile.TemporaryDirectory(prefix="trical-") as tmp:
        return _noise_of(args, settings, _one_recording(args.path, Path(tmp)), ", ".join(p.name for p in args.path))


def _noise_of(args, settings: Settings, path: Path, label: str) -> int:
    array = path.suffix.lower() in (".npy", ".parquet", ".pq")
    sensor = args.sensor or "acc"
    units = {}
    if args.unit:
        if args.unit not in UNITS[sensor]:
            raise CalibrationError(f"--unit {args.unit} is not a {sensor} unit: use one of {', '.join(UNITS[sensor])}")
        units = {sensor: args.unit}
    read_units = {"acc": units[sensor]} if array and units and sensor == "acc" else ({} if array else units)
    # A flight controller's compass is on its own clock (app.io.formats.flight_log): --sensor mag reads it there.
    clock = "mag" if args.sensor == "mag" and not array and starts_like_flight_log(path) else "imu"
    name = str(args.path[0]) if len(args.path) == 1 else label
    log = workflow.load_log(path, sampling_rate_hz=args.sampling_rate_hz, units=read_units, name=name,
                            columns=args.columns, sign=args.sign, chip=args.chip, instance=args.instance,
                            mag_instance=args.mag_instance, clock=clock)
    if array and sensor != "acc" and units:
        log = _relabel_units(log, units[sensor])
    body = workflow.characterise_log(log, sensors=None if array or not args.sensor else [args.sensor],
                                     array_sensor=sensor if array else None, device_id=args.device_id,
                                     label=label)
    from app.io.allan_plot import allan_svg

    return _finish(args, settings, body, plot=allan_svg, summary=_print_noise)


def _finish(args, settings: Settings, body: dict, *, plot, summary) -> int:
    """The end of ``trical noise`` and ``trical temperature``: the body stored (``--store``), its plot written
    (``--plot``, by ``plot(body)``), the JSON or the summary printed; status 0, or 3 when ``ok`` is false."""
    if args.store:
        body = open_store(settings.database_url, settings.recordings_dir).add_calibration(body, owner=None)
    if args.plot:
        args.plot.write_text(plot(body), encoding="utf-8")
        print(f"wrote {args.plot}", file=sys.stderr)
    if args.json:
        print(json.dumps(body, indent=2))
    else:
        summary(body)
    return 0 if body["ok"] else 3


def _temperature(args, settings: Settings) -> int:
    log = workflow.load_log(args.path, sampling_rate_hz=args.sampling_rate_hz, units={}, name=str(args.path),
                            columns=args.columns, sign=args.sign, chip=args.chip, instance=args.instance)
    body = workflow.temperature_log(log, sensors=[args.sensor] if args.sensor else None, device_id=args.device_id,
                                    label=args.path.name)
    from app.io.export_temperature import temperature_svg

    return _finish(args, settings, body, plot=temperature_svg, summary=_print_temperature)


def _print_temperature(body: dict) -> None:
    body = render_body(body, "cli")
    stored = f", id {body['id']}" if body.get("id") else ""
    print(f"{body.get('label') or ''}: ok = {body['ok']}{stored}")
    _print_verdict(body)
    for reason in body.get("reasons") or []:
        print(f"  reason: {reason}")
    for sensor, model in body["model"].items():
        if sensor == "type":
            continue
        m, unc = body["metrics"][sensor], body["uncertainty"][sensor]
        print(f"{sensor} ({model['unit']}), {model['t_min_c']:.1f}–{model['t_max_c']:.1f} °C, T_ref "
              f"{model['t_ref_c']:.2f} °C, offset = X0 + X1 dT + X2 dT^2 + X3 dT^3:")
        for i, axis in enumerate("xyz"):
            cells = "  ".join(f"X{k} {c:.4g} ± {h:.2g}" for k, (c, h) in
                              enumerate(zip(model["coefficients"][i], unc["coefficients"][i])))
            print(f"  {axis}: order {model['order'][i]}  {cells}  drift {m['drift_raw'][i]:.3g} → {m['drift_cv'][i]:.3g} "
                  f"{m['unit']} (bands left out)")
        print(f"  samples per band: {', '.join(str(n) for n in m['samples_per_band'])}")


def _relabel_units(log, unit: str):
    """An array of gyroscope or magnetometer samples in deg/s or nT: read as acc, converted by the workflow."""
    import dataclasses

    factor = {"deg/s": GYR_TO_RAD_S["deg/s"], "nT": MAG_TO_UT["nT"]}.get(unit)
    if factor is None:
        return log
    return dataclasses.replace(log, acc=np.asarray(log.acc, dtype=float) * factor)


def _print_noise(body: dict) -> None:
    body = render_body(body, "cli")
    still = body.get("still") or {}
    print(f"{body.get('label') or ''}: {body['duration_s']:.1f} s still at {body['sampling_rate_hz']:g} Hz "
          f"({100 * still.get('fraction', 1):.0f} % of the recording); ok = {body['ok']}")
    _print_verdict(body)
    names = {"noise_density": "noise density N", "random_walk": "random walk K", "bias_instability": "bias instability B"}
    for sensor in ("gyr", "acc", "mag"):
        model = body["model"].get(sensor)
        if not model:
            continue
        unc = body["uncertainty"][sensor]
        print(f"{sensor} ({model['unit']}):")
        for term, label in names.items():
            unit = model[f"{term}_unit"]
            cells = []
            for v, iv in zip(model[term], unc[term]):
                cells.append("null" if v is None else f"{v:.4g} [{iv[0]:.3g}, {iv[1]:.3g}]")
            print(f"  {label:<20} {unit:<12} x {cells[0]}  y {cells[1]}  z {cells[2]}")
        print(f"  {'bias':<20} {model['unit']:<12} " + "  ".join(f"{a} {v:.6g}" for a, v in zip("xyz", model["bias"])))
    for r in body["reasons"]:
        print(f"reason: {r}")
    for w in body["warnings"]:
        print(f"warning: {w}")


def _export(args, settings: Settings) -> int:
    body = open_store(settings.database_url, settings.recordings_dir).get_calibration(args.id, owner=None)
    out = methods.export(body, args.format)
    binary = isinstance(out.content, bytes)
    if args.output:
        if binary:
            args.output.write_bytes(out.content)
        else:
            args.output.write_text(out.content)
        print(f"wrote {args.output}", file=sys.stderr)
    elif binary:
        sys.stdout.flush()
        sys.stdout.buffer.write(out.content)
    else:
        sys.stdout.write(out.content)
    for note in out.notes:  # what the format does not carry (motioncal: the accelerometer's scales)
        print(f"note: {render(note, 'cli')}", file=sys.stderr)
    return 0


def _capture(args, settings: Settings) -> int:
    """``trical capture PORT``: the board's lines captured hands-free into a log, then calibrated (app.board_capture)."""
    import serial  # pyserial

    from app.capture_rules import CAPTURE_S_DEFAULT, CAPTURE_S_RANGE

    capture_s = CAPTURE_S_DEFAULT if args.capture_s is None else args.capture_s
    low, high = CAPTURE_S_RANGE
    if not low <= capture_s <= high:
        raise CalibrationError(f"--capture-s {capture_s:g} is out of range: give the seconds captured per pose, from "
                               f"{low:g} to {high:g} (the wizard's default is {CAPTURE_S_DEFAULT:g})")
    try:
        port = serial.Serial(args.port, args.baud, timeout=0.1)
    except (serial.SerialException, ValueError) as exc:
        raise LogFormatError(f"cannot open {args.port} at {args.baud} baud ({exc}): check the port's name (ls /dev/tty* "
                             "on Linux, COM3 on Windows) and that no other program (a serial monitor) holds it") from None
    with port:
        return capture_on_port(port, args, settings, capture_s=capture_s)


def capture_on_port(port, args, settings: Settings, *, capture_s: float, clock=None) -> int:
    """The steps of ``trical capture`` on an open port (``read(n)``, ``write``, ``flush``: pyserial's
    ``Serial``), on ``clock`` (``time.monotonic`` unless given)."""
    import time

    from app.board_capture import Capture

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
    capture = Capture(port, protocol=args.protocol, out_path=out, fmt=args.format,
                      units={"acc": args.unit} if args.unit else None, minutes=args.minutes,
                      capture_s=capture_s, baud=args.baud, say=say, bell=bell, live=live if tty else None,
                      clock=clock or time.monotonic)
    outcome = capture.run()
    finish = f"trical {capture.protocol.command} {out}"
    if outcome.status == "interrupted":
        bell()
        say(f"stopped: {out} keeps the {outcome.readings} readings received; finish it with: {finish}"
            if outcome.log_path else "stopped before any reading arrived: nothing was written")
        return 130
    if outcome.status != "finished":
        if outcome.log_path:
            say(f"{out} keeps the {outcome.readings} readings received; calibrate what it holds with: {finish}")
        return 2
    rate = f" at {outcome.rate_hz:.4g} Hz" if outcome.rate_hz else ""
    say(f"wrote {out}: {outcome.readings} readings{rate}")
    return _CAPTURE_FINISH[capture.protocol.command](capture, outcome, args, settings)


def _capture_noise(capture, outcome, args, settings: Settings) -> int:
    """``trical capture --protocol noise``'s end: the log characterised as ``trical noise LOG`` does."""
    return _run([capture.protocol.command, str(capture.out_path), *(["--json"] if args.json else []),
                 *(["--store"] if not args.no_store else [])])


def _capture_calibration(capture, outcome, args, settings: Settings) -> int:
    """The end of ``trical capture``'s other protocols: the log calibrated with the protocol's method (from its
    captures' rows where the protocol says so), printed, and sent to the board with ``--send``."""
    from app.io.motioncal_packet import packet_of

    protocol, out, port, say, bell = capture.protocol, capture.out_path, capture.port, capture.say, capture.bell
    argv = [protocol.command, str(out), "--method", protocol.method]
    argv += ["--unit", args.unit] if args.unit else []
    argv += ["--device-id", args.device_id] if args.device_id else []
    argv += ["--no-store"] if args.no_store else []
    cal_args = _parser().parse_args(argv)
    captures = outcome.rows if protocol.from_captures else None
    say(f"calibrating {out} ({protocol.method}{f' on its {len(captures)} captures' if captures else ''})")
    body, recording = _calibrated(cal_args, settings, out, captures)
    if args.json:
        print(json.dumps(body, indent=2))
    else:
        _print_summary(body, recording)
    bell()
    if args.send:
        if not body["ok"]:
            say("not sent to the board: the calibration is not ok (see the reasons)")
            return 3
        packet, notes = packet_of(body)
        port.write(packet)
        port.flush()
        say(f"sent MotionCal's {len(packet)}-byte calibration packet to the board")
        for note in notes:
            say(f"note: {render(note, 'cli')}")
    return 0 if body["ok"] else 3


_CAPTURE_FINISH = {"noise": _capture_noise, "calibrate": _capture_calibration}
"""How ``trical capture`` ends, by the command its protocol finishes with (app.protocols)."""


def main(argv: list[str] | None = None) -> int:
    """Run the command; bad input is one line and status 2, a closed pipe 141, anything else one line and 1."""
    try:
        status = _run(argv)
        sys.stdout.flush()  # a closed pipe shows here, not as a message at interpreter exit
        return status
    except BrokenPipeError:
        # The reader went away (`trical ... | head`): say nothing, and let the interpreter's last flush
        # of stdout go to /dev/null. 141 = 128 + SIGPIPE, what a shell reports for `cat` in that case.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 141
    except Exception as exc:
        if os.environ.get("TRICAL_DEBUG") == "1":
            traceback.print_exc()
        reason = str(exc).splitlines()[0] if str(exc) else "no message"
        print(f"trical: error: {type(exc).__name__}: {reason} (TRICAL_DEBUG=1 shows the traceback)", file=sys.stderr)
        return 1


def _run(argv: list[str] | None) -> int:
    args = _parser().parse_args(argv)
    try:
        settings = Settings.from_env()
        command = {"serve": _serve, "calibrate": _calibrate, "autocal": _autocal, "noise": _noise,
                   "temperature": _temperature, "export": _export, "capture": _capture}[args.command]
        return command(args, settings)
    except (CalibrationError, LogFormatError, ExportError, SettingsError, CertificateError) as exc:
        print(f"trical: error: {render(str(exc), 'cli')}", file=sys.stderr)
        return 2
    except ValidationError as exc:
        print(f"trical: error: {render(methods.describe_errors(exc.errors()), 'cli')}", file=sys.stderr)
        return 2
    except NotFoundError as exc:
        print(f"trical: error: {render(str(exc.args[0]), 'cli')}", file=sys.stderr)
        return 2
    except FileNotFoundError as exc:
        print(f"trical: error: no such file: {exc.filename}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        raise  # main() ends quietly
    except OSError as exc:  # a file that cannot be read or written, a port in use
        print(f"trical: error: {exc.strerror or exc}{f': {exc.filename}' if exc.filename else ''}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
