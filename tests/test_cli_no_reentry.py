"""One command never reaches another through a command line: the ``trical`` package parses its argv once, in its
entry (app/cli/main.py), and ``trical capture`` ends as ``trical calibrate`` or ``trical noise`` by calling them with
values (app.cli.parser.defaults_of and its own)."""

from __future__ import annotations

import ast
from pathlib import Path

from app.cli.parser import build_parser, defaults_of

CLI = Path(__file__).resolve().parent.parent / "app" / "cli"
ENTRIES = ("main.py", "__main__.py")
"""The entry, and ``python -m app.cli`` running it."""
REENTRY = ("parse_args", "parse_known_args", "main", "_run")
"""What reaches a command through a command line: argparse's parsing, or the entry itself."""


def reentries(source: str) -> list[str]:
    """The calls in ``source`` that parse a command line or run the entry."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Call):
            f = node.func
            name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", None)
            if name in REENTRY:
                found.append(f"line {node.lineno}: {name}()")
    return found


def test_only_the_entry_parses_a_command_line():
    found = {
        f.name: reentries(f.read_text(encoding="utf-8")) for f in sorted(CLI.glob("*.py")) if f.name not in ENTRIES
    }
    assert not any(found.values()), {k: v for k, v in found.items() if v}


def test_the_guard_sees_a_command_run_through_its_parser():
    planted = (
        'def end(out):\n    args = build_parser().parse_args(["calibrate", str(out)])\n'
        '    return _run(["noise", str(out)])\n'
    )
    assert reentries(planted) == ["line 2: parse_args()", "line 3: _run()"]


def test_the_defaults_a_capture_ends_with_are_what_the_parser_gives_a_command_line():
    for command, argv, values in (
        (
            "calibrate",
            ["calibrate", "board.csv", "--method", "six_position", "--unit", "g", "--no-store"],
            {"log": [Path("board.csv")], "method": "six_position", "unit": "g", "no_store": True},
        ),
        (
            "noise",
            ["noise", "board.csv", "--json", "--store"],
            {"path": [Path("board.csv")], "json": True, "store": True},
        ),
    ):
        parsed = vars(build_parser().parse_args(argv))
        assert parsed.pop("command") == command
        assert {**defaults_of(command), **values} == parsed
