"""The ``trical`` command's entry: parse, run the command, and the one place that turns errors into exit codes.

``--json`` prints the same JSON as the API.  Errors are one line on stderr and exit status 2
(bad input, including an option's value out of range: app.cli.options checks them while parsing) or
1 (anything else; TRICAL_DEBUG=1 adds the traceback); never a traceback otherwise.  Output into a pipe
closed early (``trical ... | head``) ends quietly with status 141, as a command killed by SIGPIPE does.
"""

from __future__ import annotations

import importlib
import os
import sys
import traceback

from pydantic import ValidationError

from app.calibration import CalibrationError
from app.cli.parser import COMMANDS, build_parser
from app.config import Settings, SettingsError
from app.io.errors import ExportError, LogFormatError
from app.reach.tls import CertificateError
from app.store import NotFoundError


def command(name: str):
    """The function of ``trical NAME`` (``run(args, settings)``, returning the exit status), from its module
    ``app.cli.NAME``: imported when the command runs, so that one command does not load every other's
    dependencies (the method table's, the server's) before it starts."""
    return importlib.import_module(f"app.cli.{name}").run


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
    argv = sys.argv[1:] if argv is None else argv
    # Only the named command's options are built (all of them for `trical --help` or an unknown name).
    args = build_parser(argv[0] if argv and argv[0] in COMMANDS else None).parse_args(argv)
    # The error messages' words (app.words) are the method table's: loaded when an error is to be said.
    try:
        settings = Settings.from_env()
        return command(args.command)(args, settings)
    except (CalibrationError, LogFormatError, ExportError, SettingsError, CertificateError) as exc:
        from app.words import render

        print(f"trical: error: {render(str(exc), 'cli')}", file=sys.stderr)
        return 2
    except ValidationError as exc:
        from app import methods
        from app.words import render

        print(f"trical: error: {render(methods.describe_errors(exc.errors()), 'cli')}", file=sys.stderr)
        return 2
    except NotFoundError as exc:
        from app.words import render

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
