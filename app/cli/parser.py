"""The ``trical`` command's argparse tree: one ``_add_*`` per command, the options that say how to read a log,
and each command's defaults (what one command sets on top when it runs another)."""

from __future__ import annotations

import argparse

from app import __version__
from app.cli import options as opt
from app.io.log import UNITS, UNITS_IN

# Each command's options import what their choices come from (the method table, the solvers, the log
# formats, the protocols) in the function that adds them: the parser of one command loads only its own.


def _calibrate_methods():
    """The choices of ``trical calibrate --method`` (the method table's; autocal, noise and temperature have
    commands of their own)."""
    from app import methods

    return methods.commanded_by("calibrate")


def _takers(field: str) -> str:
    """The methods of ``trical calibrate`` whose request takes ``field``, for an option's help: "cube and
    magnetometer"."""
    from app import methods

    return " and ".join(m for m in _calibrate_methods() if field in methods.BY_NAME[m].options)


SCALED_UNITS = tuple(unit for units in UNITS.values() for unit in units if unit != "raw")
"""The units of ``trical noise --unit``: each sensor's, counts left out."""


class _Parser(argparse.ArgumentParser):
    """argparse with its errors on one line: ``trical calibrate: error: argument ...``."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The ``trical`` command's parser: its subcommands and their options (only ``command``'s, when given:
    what ``trical COMMAND …`` parses, without loading the other commands' choices)."""
    p = _Parser(prog="trical", description="Calibrate accelerometers of phones and IMU boards.")
    p.add_argument("--version", action="version", version=f"trical {__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    for name, add in _ADDERS.items():
        if command is None or name == command:
            add(sub)
    return p


def _add_serve(sub) -> None:
    """``trical serve``: the API and the pages."""
    s = sub.add_parser("serve", help="serve the API and the pages")
    s.add_argument(
        "--host",
        type=opt.text("an address to listen on"),
        default=None,
        help="address of the desktop's listener (default: HOST, else 127.0.0.1)",
    )
    s.add_argument("--port", type=opt.PORT, default=None, help="port of the desktop's listener (default: PORT or 8000)")
    s.add_argument(
        "--phone-port",
        type=opt.number("a TCP port, or 0 for none", low=0, high=65535, integer=True),
        default=None,
        help="port of the phone's door: HTTPS on every interface for the phone that scans the start page's QR code "
        "only (default: TRICAL_PHONE_PORT or 8443; 0: none)",
    )
    s.add_argument(
        "--https",
        action="store_true",
        help="serve the desktop's listener over TLS too (a self-signed certificate unless --cert and --key)",
    )
    s.add_argument(
        "--cert",
        type=opt.input_path("a PEM certificate"),
        default=None,
        metavar="FILE",
        help="PEM certificate to serve, at the phone's door and (it implies --https) the desktop's listener",
    )
    s.add_argument(
        "--key",
        type=opt.input_path("the PEM private key of --cert"),
        default=None,
        metavar="FILE",
        help="PEM private key of --cert",
    )


def _add_calibrate(sub) -> None:
    """``trical calibrate``: a log of still orientations (or a cube, a compass turn), by the method table's methods."""
    from app.calibration.still.solvers import SOLVERS
    from app.calibration_requests import CUBE_PROTOCOLS

    c = sub.add_parser("calibrate", help="calibrate from a log of still orientations")
    c.add_argument(
        "log",
        type=opt.input_path("a log file"),
        nargs="+",
        help="log: CSV with a header row, a phyphox / Sensor Logger zip, or several files (one per pose, "
        "or a zip of them): one calibration, each reading naming its file",
    )
    c.add_argument(
        "--method",
        choices=_calibrate_methods(),
        default=None,
        help="default: what the recording supports first, said with why (still poses: auto, which picks "
        "six_position or orientations for axis-aligned poses and triangular for free ones; a compass turn: "
        "magnetometer; a flight log: compass_flight)",
    )
    c.add_argument("--protocol", choices=CUBE_PROTOCOLS, default=CUBE_PROTOCOLS[0], help=f"{_takers('protocol')} only")
    c.add_argument(
        "--field-ut",
        type=opt.FIELD_UT,
        default=None,
        help=f"{_takers('field_ut')}: local magnetic field magnitude in µT (magnetometer: overrides the model's)",
    )
    c.add_argument(
        "--sections",
        type=opt.input_path("a section list (JSON)"),
        default=None,
        metavar="FILE.json",
        help=f"{_takers('sections')} with --protocol ferraris: imucal's annotated section list (x_p … z_rot, "
        "sample indices)",
    )
    c.add_argument(
        "--solver",
        choices=SOLVERS,
        default="lm",
        help=f"{_takers('solver')} only: lm, or Farago et al.'s descent in float, 16- or 32-bit fixed point",
    )
    c.add_argument(
        "--sampling-rate-hz", type=opt.SAMPLING_RATE, default=None, help="needed when the log has no time column"
    )
    c.add_argument("--unit", choices=UNITS_IN["acc"], default=None, help="accelerometer unit of the log")
    _unit_options(c)
    _read_options(c)
    c.add_argument("--gravity", type=opt.GRAVITY, default=None, help="reference gravity in m/s^2")
    c.add_argument(
        "--latitude-deg",
        type=opt.LATITUDE,
        default=None,
        help="local normal gravity from latitude (magnetometer: with --longitude-deg, the Earth's field there)",
    )
    c.add_argument("--height-m", type=opt.HEIGHT, default=None, help="height above the ellipsoid, with --latitude-deg")
    c.add_argument(
        "--longitude-deg",
        type=opt.LONGITUDE,
        default=None,
        help=f"{_takers('longitude_deg')}: with --latitude-deg, the Earth's field there from IGRF",
    )
    c.add_argument(
        "--date", type=opt.DAY, default=None, help=f"{_takers('date')}: day of the recording (default today)"
    )
    c.add_argument(
        "--attitude",
        choices=("ATT", "AHR2", "XKF1", "NKF1", "EKF1", "vehicle_attitude"),
        default=None,
        help=f"{_takers('attitude')}: the attitude estimate to judge the compass by (default ATT, or vehicle_attitude)",
    )
    c.add_argument(
        "--window",
        choices=("flying", "all"),
        default=None,
        help=f"{_takers('window')}: the part of the log fitted, the flying part (default) or every sample",
    )
    c.add_argument(
        "--from-s", type=opt.SECONDS, default=None, help=f"{_takers('from_s')}: seconds from the log's start"
    )
    c.add_argument("--to-s", type=opt.SECONDS, default=None, help=f"{_takers('to_s')}: seconds from the log's start")
    c.add_argument("--device-id", type=opt.text("a device id"), default=None)
    c.add_argument("--no-store", action="store_true", help="do not store the calibration in the database")
    c.add_argument("--json", action="store_true", help="print the API's JSON")
    c.add_argument("--verbose", action="store_true", help=f"print every note (default: the first {opt.NOTES_SHOWN})")


def _add_autocal(sub) -> None:
    """``trical autocal``: a long recording, or a folder of them."""
    from app.calibration.still.solvers import SOLVERS
    from app.workflows.autocal import AUTOCAL_UNITS

    a = sub.add_parser("autocal", help="auto-calibrate a long recording (or a folder of them), Farago et al. pipeline")
    a.add_argument(
        "path",
        type=opt.input_path("a recording or a folder of them"),
        help=".npy (N×3 or N×4 with time), Parquet or CSV file, or a folder of them",
    )
    a.add_argument(
        "--sampling-rate-hz", type=opt.SAMPLING_RATE, default=None, help="needed when the file has no time column"
    )
    a.add_argument(
        "--unit", choices=AUTOCAL_UNITS, default=None, help="accelerometer unit (default: the file's, else m/s^2)"
    )
    a.add_argument("--solver", choices=SOLVERS, default="lm")
    _read_options(a)
    a.add_argument("--gravity", type=opt.GRAVITY, default=None, help="reference gravity in m/s^2")
    a.add_argument("--latitude-deg", type=opt.LATITUDE, default=None, help="local normal gravity from latitude")
    a.add_argument(
        "--all-axes", action="store_true", help="every axis must pass the max − min test (Farago et al.: one is enough)"
    )
    a.add_argument(
        "--workers", type=opt.WORKERS, default=None, help="parallel processes for a folder (default: CPU count)"
    )
    a.add_argument(
        "--dask-scheduler",
        type=opt.text("a scheduler address"),
        default=None,
        metavar="ADDRESS",
        help="run a folder on a Dask cluster (needs dask.distributed), e.g. tcp://host:8786",
    )
    a.add_argument("--device-id", type=opt.text("a device id"), default=None)
    a.add_argument("--store", action="store_true", help="store the calibration(s) in the database")
    a.add_argument("--json", action="store_true", help="print the API's JSON (a list for a folder)")
    a.add_argument("--verbose", action="store_true", help=f"print every note (default: the first {opt.NOTES_SHOWN})")


def _add_noise(sub) -> None:
    """``trical noise``: a still recording's Allan deviation."""
    n = sub.add_parser(
        "noise", help="noise density, random walk and bias instability of a still recording (Allan deviation)"
    )
    n.add_argument(
        "path",
        type=opt.input_path("a still recording"),
        nargs="+",
        help=".npy (N×3 with --sensor, or N×4 with time first), Parquet, CSV or any log format trical "
        "reads; several files, one per sensor (accelerometer.csv gyroscope.csv), are one recording",
    )
    n.add_argument(
        "--sampling-rate-hz", type=opt.SAMPLING_RATE, default=None, help="needed when the file has no time column"
    )
    n.add_argument(
        "--sensor",
        choices=tuple(UNITS),
        default=None,
        help="the sensor a three-column array holds (default acc); with a log: characterise only this one",
    )
    n.add_argument(
        "--unit",
        choices=SCALED_UNITS,
        default=None,
        help="unit of the array's sensor, or of a log's accelerometer (acc: m/s^2 or g; gyr: rad/s or deg/s; "
        "mag: uT or nT)",
    )
    _unit_options(n)
    _read_options(n)
    n.add_argument(
        "--plot",
        type=opt.output_file("an SVG file to write"),
        default=None,
        metavar="FILE.svg",
        help="write the log-log Allan plot with the fitted slopes",
    )
    n.add_argument("--device-id", type=opt.text("a device id"), default=None)
    n.add_argument("--store", action="store_true", help="store the characterisation in the database")
    n.add_argument("--json", action="store_true", help="print the API's JSON")
    n.add_argument("--verbose", action="store_true", help=f"print every note (default: the first {opt.NOTES_SHOWN})")


def _add_temperature(sub) -> None:
    """``trical temperature``: the offsets' drift with temperature."""
    from app.workflows.temperature import TEMPERATURE_SENSORS

    t = sub.add_parser(
        "temperature",
        help="each axis's offset as a polynomial of temperature, from a still recording "
        "while the board warms up (a temp_c column, or a flight log)",
    )
    t.add_argument(
        "path",
        type=opt.input_path("a still recording with the sensor's temperature"),
        help="a CSV with a temp_c (temp, temperature, T (°C)) column beside the readings, or any log "
        "format trical reads that records the temperature",
    )
    t.add_argument(
        "--sampling-rate-hz", type=opt.SAMPLING_RATE, default=None, help="needed when the file has no time column"
    )
    t.add_argument(
        "--sensor",
        choices=TEMPERATURE_SENSORS,
        default=None,
        help="calibrate only this sensor (default: the accelerometer and the gyroscope the log has)",
    )
    t.add_argument("--unit", choices=UNITS_IN["acc"], default=None, help="the accelerometer's unit in the log")
    _unit_options(t)
    _read_options(t)
    t.add_argument(
        "--plot",
        type=opt.output_file("an SVG file to write"),
        default=None,
        metavar="FILE.svg",
        help="write the plot of offset against temperature (binned readings, fit, 95 %% band)",
    )
    t.add_argument("--device-id", type=opt.text("a device id"), default=None)
    t.add_argument(
        "--store",
        action="store_true",
        help="store the calibration in the database (then trical export ID --format px4 or ardupilot)",
    )
    t.add_argument("--json", action="store_true", help="print the API's JSON")
    t.add_argument("--verbose", action="store_true", help=f"print every note (default: the first {opt.NOTES_SHOWN})")


def _add_capture(sub) -> None:
    """``trical capture``: the guided calibration of a board on a serial port."""
    from app.guided.capture_rules import CAPTURE_PROTOCOLS, WIZARD_PROTOCOLS
    from app.io.board.formats import DEFAULT_BAUD
    from app.io.board.lines import FORMATS as BOARD_LINE_FORMATS

    b = sub.add_parser(
        "capture",
        help="the guided calibration of a board on a serial port (pyserial): capture, log, calibrate, verdict",
    )
    b.add_argument("port", type=opt.text("a serial port"), help="the board's serial port, e.g. /dev/ttyACM0 or COM3")
    b.add_argument("--baud", type=opt.BAUD, default=DEFAULT_BAUD, help=f"the port's rate (default {DEFAULT_BAUD})")
    b.add_argument(
        "--protocol",
        choices=CAPTURE_PROTOCOLS,
        default=CAPTURE_PROTOCOLS[0],
        help="; ".join(f"{p.name}: {p.words}" for p in WIZARD_PROTOCOLS) + f" (default {CAPTURE_PROTOCOLS[0]})",
    )
    b.add_argument(
        "--minutes",
        type=opt.MINUTES,
        default=None,
        help="compass and noise: the length recorded (default 1); poses: the time allowed (default 10)",
    )
    b.add_argument(
        "--capture-s",
        type=opt.CAPTURE_S,
        default=None,
        help="seconds captured per pose (default: the wizard's; within the range a session accepts)",
    )
    b.add_argument(
        "--format",
        choices=BOARD_LINE_FORMATS,
        default="auto",
        help="the board's lines: auto (default), raw (MotionCal Raw:), uni (Uni:), csv, numbers",
    )
    b.add_argument(
        "--unit", choices=UNITS["acc"], default=None, help="the accelerometer's unit (checked against the data at rest)"
    )
    b.add_argument(
        "--out",
        type=opt.output_file("a log file to write"),
        default=None,
        metavar="LOG.csv",
        help="the log written as received (default trical-capture-DATE-TIME.csv)",
    )
    b.add_argument(
        "--send",
        action="store_true",
        help="write MotionCal's 68-byte calibration packet to the board (Adafruit Sensor Calibration); with "
        "--device-id, an accelerometer's packet carries that device's latest stored compass calibration, as the "
        "page's Send to the board does",
    )
    b.add_argument(
        "--without-compass",
        action="store_true",
        help="with --send: leave the device's stored compass calibration out (the board's is then reset)",
    )
    b.add_argument("--device-id", type=opt.text("a device id"), default=None)
    b.add_argument("--no-store", action="store_true", help="do not store the calibration in the database")
    b.add_argument("--json", action="store_true", help="print the API's JSON (the steps go to stderr)")
    b.add_argument("--verbose", action="store_true", help=f"print every note (default: the first {opt.NOTES_SHOWN})")


def _add_export(sub) -> None:
    """``trical export``: a stored calibration, in one of the formats."""
    from app import methods

    e = sub.add_parser("export", help="export a stored calibration")
    e.add_argument("id", type=opt.text("a calibration id"), help="calibration id (cal_...)")
    e.add_argument("--format", choices=methods.ALL_FORMATS, default="json")
    e.add_argument(
        "--output", "-o", type=opt.output_file("a file to write"), default=None, help="file to write (default: stdout)"
    )


def _place_options(parser: argparse.ArgumentParser) -> None:
    """The place's field and inclination a compass's heading is told at (``trical check``, ``trical compare``)."""
    parser.add_argument(
        "--field-ut",
        type=opt.FIELD_UT,
        default=None,
        help="the place's field in uT (default: the calibration's own, else the turn's)",
    )
    parser.add_argument(
        "--inclination-deg",
        type=opt.INCLINATION,
        default=None,
        help="the place's inclination in degrees, for the heading (default: 60 assumed)",
    )


def _add_check(sub) -> None:
    """``trical check``: a stored calibration checked on a new recording of the device."""
    c = sub.add_parser(
        "check",
        help="check a calibration on a new recording: keep it, calibrate again, or move the compass",
    )
    c.add_argument(
        "id",
        type=opt.text("a calibration id or file"),
        help="calibration id (cal_...) or a calibration's JSON file (trical calibrate --json)",
    )
    c.add_argument("log", type=opt.input_path("a recording"), help="the new recording: still poses, a turn, a rest")
    c.add_argument(
        "--sampling-rate-hz", type=opt.SAMPLING_RATE, default=None, help="needed when the log has no time column"
    )
    c.add_argument("--unit", choices=UNITS_IN["acc"], default=None, help="accelerometer unit of the log")
    _unit_options(c)
    _read_options(c)
    _place_options(c)
    c.add_argument("--json", action="store_true", help="print the API's JSON")


def _add_compare(sub) -> None:
    """``trical compare``: two stored calibrations of a device, parameter by parameter."""
    c = sub.add_parser("compare", help="compare two calibrations of a device, parameter by parameter")
    c.add_argument("id", type=opt.text("a calibration id or file"), help="the first calibration, A (id or JSON file)")
    c.add_argument(
        "other", type=opt.text("a calibration id or file"), help="the second, B (id or JSON file): B − A is told"
    )
    _place_options(c)
    c.add_argument("--json", action="store_true", help="print the API's JSON")


def _add_import(sub) -> None:
    """``trical import``: a device's own calibration, from its firmware's file."""
    from app.io.imports import FIRMWARES

    i = sub.add_parser(
        "import",
        help="import the calibration a device already holds (ArduPilot, PX4, Betaflight, INAV, trical JSON)",
    )
    i.add_argument("path", type=opt.input_path("the device's parameter file, log or CLI dump"), help="the file")
    i.add_argument(
        "--firmware",
        choices=FIRMWARES,
        default=None,
        help="the file's family (default: recognised from its content)",
    )
    i.add_argument(
        "--instance",
        type=opt.INSTANCE,
        default=0,
        metavar="N",
        help="which IMU and compass of a file holding several (ArduPilot 0-2, PX4's slot; default 0)",
    )
    i.add_argument("--device-id", type=opt.text("a device id"), default=None, help="the device it is stored for")
    i.add_argument("--label", type=opt.text("a label"), default=None, help="its label (default: the file's name)")
    i.add_argument("--no-store", action="store_true", help="do not store the calibration in the database")
    i.add_argument("--json", action="store_true", help="print the API's JSON")
    i.add_argument("--verbose", action="store_true", help=f"print every note (default: the first {opt.NOTES_SHOWN})")


def _add_apply(sub) -> None:
    """``trical apply``: a calibration applied to every sample of a recording, written as CSV, Parquet or .npy."""
    from app.io.writers.samples import FORMATS

    a = sub.add_parser(
        "apply", help="apply a calibration to a recording and write the calibrated samples (read in chunks)"
    )
    a.add_argument(
        "calibration",
        type=opt.text("a calibration id or file"),
        metavar="CAL",
        help="a stored calibration's id (cal_...), or a JSON file of a calibration (trical calibrate --json, "
        "trical export --format json)",
    )
    a.add_argument("file", type=opt.input_path("a recording"), metavar="FILE", help="the recording to calibrate")
    a.add_argument("--output", "-o", type=opt.output_file("a file to write"), required=True, help="the file to write")
    a.add_argument(
        "--format",
        choices=FORMATS,
        default=None,
        help="the output's format (default: its suffix: .csv, .parquet, .npy)",
    )
    a.add_argument(
        "--sampling-rate-hz", type=opt.SAMPLING_RATE, default=None, help="the recording's rate, if it has no time"
    )
    a.add_argument("--unit", choices=UNITS_IN["acc"], default=None, help="the accelerometer's unit in the recording")
    _unit_options(a)
    _read_options(a)
    a.add_argument("--json", action="store_true", help="print what was written as JSON (rows, columns, units)")


def _unit_options(parser: argparse.ArgumentParser) -> None:
    """The units of a text log's gyroscope and magnetometer and the counts per g of its accelerometer, as the
    upload's ``gyr_unit``, ``mag_unit`` and ``lsb_per_g`` say them (every command that reads a log takes them: a
    message that asks for one names an option of the command it is read in)."""
    parser.add_argument("--gyr-unit", choices=UNITS_IN["gyr"], default=None, help="the gyroscope's unit in the log")
    parser.add_argument("--mag-unit", choices=UNITS_IN["mag"], default=None, help="the magnetometer's unit in the log")
    parser.add_argument(
        "--lsb-per-g", type=opt.LSB_PER_G, default=None, help="counts per g of a raw (LSB) accelerometer"
    )


def _read_options(parser: argparse.ArgumentParser) -> None:
    """The options that say how to read a log, as the upload's form fields do (app.cli.reading builds them)."""
    from app.io.readers import FORMATS

    parser.add_argument(
        "--log-format",
        choices=FORMATS,
        default="auto",
        help="the log's format (default: recognised from the file)",
    )
    parser.add_argument(
        "--columns",
        type=opt.text("column names or a mapping"),
        default=None,
        metavar="NAMES",
        help="name every column in order, e.g. t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z (- skips "
        "one; for logs without a header row), or map unrecognised ones, e.g. acc_x:north,…",
    )
    parser.add_argument(
        "--chip",
        type=opt.CHIP,
        default=None,
        metavar="PARTS",
        help="the parts (and ranges) of sensors logged in counts, separated by commas, e.g. "
        "mpu6050-4g,mpu6050-500dps,ak8963-16bit: their counts become g, deg/s and uT "
        "(the list: README, Units)",
    )
    parser.add_argument(
        "--sign",
        type=int,
        choices=(1, -1),
        default=None,
        help="factor on the log's accelerations: -1 for iOS Core Motion's sign (-g up), 1 to keep "
        "them (default: detected from the header)",
    )
    parser.add_argument(
        "--instance",
        type=opt.INSTANCE,
        default=None,
        metavar="N",
        help="a flight controller's log (PX4 .ulg, ArduPilot .bin): the IMU instance to read (PX4 "
        "multi_id, ArduPilot I; default: PX4 the source with the most samples, ArduPilot 0)",
    )
    parser.add_argument(
        "--mag-instance",
        type=opt.INSTANCE,
        default=None,
        metavar="N",
        help="a flight controller's log: the compass instance the compass methods read (default: the first)",
    )


_ADDERS = {
    "serve": _add_serve,
    "calibrate": _add_calibrate,
    "autocal": _add_autocal,
    "noise": _add_noise,
    "temperature": _add_temperature,
    "capture": _add_capture,
    "export": _add_export,
    "check": _add_check,
    "compare": _add_compare,
    "import": _add_import,
    "apply": _add_apply,
}

COMMANDS = tuple(_ADDERS)
"""The commands, in the order of ``trical --help``; each runs as ``app.cli.NAME.run(args, settings)``."""


def defaults_of(command: str) -> dict:
    """Every option of ``trical COMMAND`` at its default, by its name in the parsed arguments (``no_store``), as
    argparse gives it when the option is left out: what a command that ends as another (``trical capture`` as
    ``trical calibrate`` or ``trical noise``) sets its own values on, with no command line to parse again."""
    sub = next(a for a in build_parser(command)._actions if isinstance(a, argparse._SubParsersAction))
    return {
        a.dest: a.type(a.default) if isinstance(a.default, str) and a.type else a.default
        for a in sub.choices[command]._actions
        if a.default is not argparse.SUPPRESS
    }
