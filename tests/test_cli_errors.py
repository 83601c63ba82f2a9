"""The installed ``trical`` command never prints a traceback: bad option values, closed pipes, failures.

The bad values come from the parser itself (every option that takes a value, of every subcommand),
so an option added later is checked without editing this file.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import subprocess
import sys
from pathlib import Path

import pytest

from app.cli.main import main
from app.cli.parser import build_parser
from tests.conftest import DATA
from tests.live_server import ROOT

TRICAL = Path(sys.executable).parent / "trical"
LOG = DATA / "six_orientations_150hz.csv"
VALID_POSITIONALS = {
    "log": str(LOG),
    "path": str(LOG),
    "id": "cal_missing",
    "other": "cal_missing",
    "port": "/dev/ttyACM0",
    "calibration": "cal_missing",
    "file": str(LOG),
}
REQUIRED_OPTIONS = {"apply": {"output": ["-o", str(ROOT / "never-written.csv")]}}
"""Options a command cannot run without, given valid where another option's bad value is tried (the bad value is
refused before anything is written)."""


@pytest.fixture(scope="module")
def env(tmp_path_factory):
    assert TRICAL.exists(), f"the console script {TRICAL} is missing: run `make install-test`"
    db = tmp_path_factory.mktemp("cli-errors") / "trical.db"
    return {"PATH": "/usr/bin:/bin", "TRICAL_DATABASE_URL": f"sqlite:///{db}"}


def run(args: list[str], env: dict, **kw) -> subprocess.CompletedProcess:
    return subprocess.run([str(TRICAL), *args], cwd=ROOT, env=env, capture_output=True, text=True, timeout=60, **kw)


def subcommands() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


def bad_values(action: argparse.Action) -> list[str]:
    if action.choices:
        return ["not-a-choice"]
    return list(getattr(action.type, "refuses", ()))


def value_actions(parser: argparse.ArgumentParser):
    for action in parser._actions:
        if action.nargs == 0:  # flags, --help
            continue
        yield action


def bad_invocations() -> list[list[str]]:
    cases = []
    for name, parser in subcommands().items():
        positionals = [a for a in parser._actions if not a.option_strings]
        for action in value_actions(parser):
            values = bad_values(action)
            assert values, (
                f"trical {name} {action.option_strings or action.dest}: no value check; give it "
                "choices or a type from app.cli.options"
            )
            for value in values:
                args = [name]
                for p in positionals:
                    args.append(value if p is action else VALID_POSITIONALS[p.dest])
                if action.option_strings:
                    args.insert(1, f"{action.option_strings[0]}={value}")
                for dest, given in REQUIRED_OPTIONS.get(name, {}).items():
                    if dest != action.dest:
                        args += given
                cases.append(args)
    return cases


def run_in_process(args: list[str], env: dict) -> subprocess.CompletedProcess:
    """``trical ARGS`` as the console script runs it (``sys.exit(main())``), in this process: the same
    parser, messages and exit status, without a new interpreter's imports for each of the many cases. The
    installed script itself runs in the tests below."""
    out, err = io.StringIO(), io.StringIO()
    saved = {k: os.environ.get(k) for k in env if k != "PATH"}
    os.environ.update({k: v for k, v in env.items() if k != "PATH"})
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                status = main(args)
            except SystemExit as exc:  # argparse's refusals exit 2 from the parser
                status = exc.code
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    return subprocess.CompletedProcess(args, status, out.getvalue(), err.getvalue())


def test_every_option_of_every_subcommand_refuses_bad_values_in_one_line(env):
    cases = bad_invocations()
    assert len(cases) > 50 and {c[0] for c in cases} == {
        "serve",
        "calibrate",
        "autocal",
        "noise",
        "temperature",
        "export",
        "apply",
        "capture",
        "check",
        "compare",
        "import",
    }
    results = [run_in_process(args, env) for args in cases]
    failures = []
    for args, out in zip(cases, results):
        lines = out.stderr.splitlines()
        # The one line names the option (or the bad value given to it): a refusal for another reason (a
        # log the command could not read) would pass a check it never made.
        option, value = (args[1].split("=", 1) + [""])[:2] if args[1].startswith("--") else ("", args[1])
        named = (option and option in out.stderr) or (value and value in out.stderr) or "argument" in out.stderr
        if (
            out.returncode != 2
            or len(lines) != 1
            or "Traceback" in out.stderr
            or not lines[0].startswith("trical")
            or not named
        ):
            failures.append(f"trical {' '.join(args)!r}: status {out.returncode}, stderr {out.stderr!r}")
    assert not failures, "\n".join(failures)


def test_the_message_names_the_option_and_its_range(env):
    out = run(["calibrate", str(LOG), "--latitude-deg", "100"], env)
    assert out.returncode == 2 and out.stdout == ""
    assert out.stderr == (
        "trical calibrate: error: argument --latitude-deg: 100 is out of range: give a latitude "
        "in degrees, from -90 to 90 (see trical calibrate --help)\n"
    )
    assert "argument --port" in run(["serve", "--port", "70000"], env).stderr
    assert "from 0.1 to 100" in run(["autocal", str(DATA), "--gravity", "0"], env).stderr


@pytest.mark.parametrize("extra", [["--json"], []], ids=["json", "summary"])
def test_output_into_a_closed_pipe_ends_quietly(env, extra):
    reader, writer = os.pipe()
    os.close(reader)  # the reader is gone before the command writes a byte, as after `| head -c 10`
    try:
        out = subprocess.run(
            [str(TRICAL), "calibrate", str(LOG), "--sampling-rate-hz", "150", "--no-store", *extra],
            cwd=ROOT,
            env=env,
            stdout=writer,
            stderr=subprocess.PIPE,
            text=True,
            timeout=60,
        )
    finally:
        os.close(writer)
    assert out.stderr == "" and out.returncode == 141


def test_output_through_head_is_cut_without_a_traceback(env):
    out = subprocess.run(
        f"'{TRICAL}' calibrate '{LOG}' --sampling-rate-hz 150 --no-store --json | head -c 10",
        shell=True,
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert out.returncode == 0 and out.stdout == '{\n  "schem' and "Traceback" not in out.stderr


def test_an_unexpected_failure_is_one_line_and_status_1(env):
    down = {**env, "TRICAL_DATABASE_URL": "postgresql://nobody@127.0.0.1:1/trical"}  # nothing listens on port 1
    out = run(["export", "cal_x"], down)
    assert out.returncode == 1 and "Traceback" not in out.stderr
    assert out.stderr.count("\n") == 1 and out.stderr.startswith("trical: error: OperationalError: ")
    assert "TRICAL_DEBUG=1" in out.stderr
    debug = run(["export", "cal_x"], {**down, "TRICAL_DEBUG": "1"})
    assert debug.returncode == 1 and "Traceback" in debug.stderr
