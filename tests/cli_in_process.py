"""The trical command run in the test's own process: ``app.cli.main.main(argv)`` as ``python -m app.cli`` runs
it, with what tests/test_cli.py's subprocess is given (the working directory, TRICAL_DATABASE_URL as the only
TRICAL_* variable), and what it prints to stdout and stderr captured as the subprocess's text, exit status
included.

For the tests whose point is what a command prints, stores and exits with: each subprocess paid the import of
numpy, pandas, the store and the fits again (about a second of CPU, many times over in the suite). What only a
process of its own shows — the interpreter's exit and tracebacks, signals, a pipe closed early, the imports a
command makes — stays a subprocess (tests/test_cli.py, tests/test_cli_errors.py, tests/test_cli_capture.py,
the import checks of tests/test_cli_noise.py).

Python's warnings are shown on the captured stderr under a fresh interpreter's default filters (pytest's own
would keep them off it), so a test that counts the lines of stderr sees what a user's terminal would.
"""

from __future__ import annotations

import contextlib
import io
import os
import subprocess
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

FRESH_INTERPRETER_FILTERS = (
    ("default", DeprecationWarning, "__main__"),
    ("ignore", DeprecationWarning, ""),
    ("ignore", PendingDeprecationWarning, ""),
    ("ignore", ImportWarning, ""),
    ("ignore", ResourceWarning, ""),
)
"""``python -W``-less warning filters of CPython 3.11's release build, first match first."""


@contextlib.contextmanager
def environment(values: dict[str, str] | None):
    """``os.environ`` without any TRICAL_* variable but ``values`` for the duration (as it is for None: a subprocess
    that inherits it), restored after."""
    saved = dict(os.environ)
    try:
        if values is not None:
            for key in [k for k in os.environ if k.startswith("TRICAL_")]:
                del os.environ[key]
            os.environ.update(values)
        yield
    finally:
        os.environ.clear()
        os.environ.update(saved)


def run_main(argv: list[str], env: dict[str, str] | None, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    """``main(argv)`` with ``env`` as its TRICAL_* environment (None: this process's), in ``cwd``; its output as a
    subprocess's text (stdout through a byte buffer, as `trical export` writes a binary format there; universal
    newlines)."""
    from app.cli.main import main

    raw, raw_err = io.BytesIO(), io.BytesIO()
    out = io.TextIOWrapper(raw, encoding="utf-8", newline="", write_through=True)
    err = io.TextIOWrapper(raw_err, encoding="utf-8", newline="", write_through=True)
    with (
        environment(env),
        contextlib.chdir(cwd),
        contextlib.redirect_stdout(out),
        contextlib.redirect_stderr(err),
        warnings.catch_warnings(),
    ):
        warnings.resetwarnings()
        for action, category, module in reversed(FRESH_INTERPRETER_FILTERS):
            warnings.filterwarnings(action, category=category, module=module)
        try:
            status = main(argv)
        except SystemExit as exc:  # argparse's usage errors and --help, as the interpreter exits with them
            status = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
            if exc.code is not None and not isinstance(exc.code, int):
                print(exc.code, file=err)
        out.flush()
        err.flush()
    stdout, stderr = (io.TextIOWrapper(io.BytesIO(b.getvalue()), encoding="utf-8").read() for b in (raw, raw_err))
    return subprocess.CompletedProcess(["trical", *argv], status, stdout, stderr)


def trical(*args, tmp_path, check: bool = False, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    """tests/test_cli.py's ``trical(*args, tmp_path=...)`` in this process: a database file under ``tmp_path``;
    ``check`` raises on a status other than 0, as subprocess.run's."""
    ran = run_main([str(a) for a in args], {"TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'trical.db'}"}, cwd)
    if check:
        ran.check_returncode()
    return ran
