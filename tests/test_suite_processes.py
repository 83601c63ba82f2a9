"""The suite itself: no process a test runs to its end may wait without a bound, so that a hang of
anything the suite starts is a failure naming the test, never a run that stops moving."""

from __future__ import annotations

import ast
from pathlib import Path

TESTS = Path(__file__).parent
BLOCKING = {"run", "call", "check_call", "check_output", "communicate"}


def unbounded_calls(source: str) -> list[int]:
    """Lines of `subprocess.run(...)`-like calls and `.communicate(...)` without a `timeout=`."""
    lines = []
    for node in ast.walk(ast.parse(source)):
        if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)):
            continue
        name, owner = node.func.attr, node.func.value
        is_subprocess = isinstance(owner, ast.Name) and owner.id == "subprocess" and name in BLOCKING
        if (is_subprocess or name == "communicate") and not any(k.arg == "timeout" for k in node.keywords):
            lines.append(node.lineno)
    return lines


def test_the_check_finds_an_unbounded_run():
    assert unbounded_calls("import subprocess\nsubprocess.run(['true'])\np.communicate()\n") == [2, 3]
    assert unbounded_calls("subprocess.run(['true'], timeout=5)\np.communicate(timeout=5)\n") == []


def test_every_process_a_test_runs_has_a_time_bound():
    found = {
        f"{path.relative_to(TESTS)}:{line}"
        for path in TESTS.rglob("*.py")
        for line in unbounded_calls(path.read_text())
    }
    assert not found, f"subprocess calls without timeout= (a hang there would stop the suite): {sorted(found)}"
