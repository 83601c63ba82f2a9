"""The ``trical`` command's entry: parse, run the command, and the one place that turns errors into exit codes.

``--json`` prints the same JSON as the API.  Errors are one line on stderr and exit status 2
(bad input, including an option's value out of range: app.cli.options checks them while parsing) or
1 (anything else; TRICAL_DEBUG=1 adds the traceback); never a traceback otherwise.  Output into a pipe
closed early (``trical ... | head``) ends quietly with status 141, as a command killed by SIGPIPE does.
"""

from __future__ import annotations

import functools
import importlib
import os
import sys
import traceback

from app.cli.parser import COMMANDS, build_parser
from app.store import NotFoundError


def command(name: str):
    """The function of ``trical NAME`` (``run(args, settings)``, returning the exit status; ``settings()`` gives
    the TRICAL_* environment's settings, read when first asked: :func:`environment_settings`), from its module
    ``app.cli.NAME``: imported when the command runs, so that one command does not load every other's
    dependencies (the method table's, the server's) before it starts; ``trical import``'s is ``app.cli.imports``
    (``import`` is Python's keyword)."""
    return importlib.import_module(f"app.cli.{MODULES.get(name, name)}").run


MODULES = {"import": "imports"}
"""The commands whose module is not named as the command."""


def environment_settings():
    """The settings of the TRICAL_* environment (app.config): loaded by the command that needs them (to store a
    calibration, to serve), so that one that does not — ``trical noise`` without ``--store`` — does not import
    pydantic-settings, a tenth of a second of a command that takes half a second."""
    from app.config import Settings

    return Settings.from_env()


BAD_INPUT = (
    ("app.calibration.shared.errors", "CalibrationError"),
    ("app.io.errors", "LogFormatError"),
    ("app.io.errors", "ExportError"),
    ("app.config", "SettingsError"),
    ("app.reach.tls", "CertificateError"),
)
"""The errors of bad input whose message is said as it is (status 2), by module and name."""


def _raised_by_loaded(exc: BaseException, module: str, name: str) -> bool:
    """Whether ``exc`` is a ``module.name``, looked up only when that module is loaded: an error of a module the
    command never imported cannot have been raised, and importing the module to catch its errors (pydantic,
    app.config, ssl through app.reach.tls) would cost every command its import."""
    loaded = sys.modules.get(module)
    return loaded is not None and isinstance(exc, getattr(loaded, name))


def _bad_input_words(exc: Exception) -> str | None:
    """The one line that says what was wrong with the input (its words rendered for the command line), or None
    when ``exc`` is not bad input."""
    if any(_raised_by_loaded(exc, module, name) for module, name in BAD_INPUT):
        text = str(exc)
    elif _raised_by_loaded(exc, "pydantic", "ValidationError"):
        from app import methods

        text = methods.describe_errors(exc.errors())  # type: ignore[attr-defined]
    elif isinstance(exc, NotFoundError):
        text = str(exc.args[0])
    else:
        return None
    from app.words import render  # the method table's words: loaded when an error is to be said

    return render(text, "cli")


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
    try:
        try:
            return command(args.command)(args, functools.cache(environment_settings))
        except Exception as exc:
            words = _bad_input_words(exc)
            if words is None:
                raise
            print(f"trical: error: {words}", file=sys.stderr)
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
