"""The result decides: outside the result classes (app/calibration) and the method table (app/methods.py),
no module of app/ compares a value with a method name, a model type or a metric key that chooses a figure.

Such a comparison (``body["model"]["type"] == "cube"``, ``method in ("six_position", "orientations")``,
``"cv_error_mg" in metrics``, a ``case "noise":``) is a
place that knows a method by name: the stored body's result (``CalibrationResult.from_dict``) or the method
table answers instead. The names are taken from the code: the result registry's types and model types, the
methods the requests accept, and the metrics the results choose their figures by.
"""

from __future__ import annotations

import ast
from pathlib import Path

from app.calibration.result import CalibrationResult, registered_types
from app.calibration.result import FIGURE_METRICS
from app.methods import METHODS

ROOT = Path(__file__).resolve().parent.parent
APP = ROOT / "app"

EXEMPT = ("app/calibration/", "app/methods.py")
"""The result classes, which decide, and the method table, which declares."""

NOT_A_RESULT = {"auto"}
"""Methods no stored result carries: ``auto`` chooses a method and the body names the one it chose; ``auto``
is also the value of every option read from the data (format, unit, sign, columns)."""

NOT_DECISIONS = {
    ("app/io/formats/sensor_logger.py", "magnetometer"): "a Sensor Logger file's name (MagnetometerUncalibrated.csv)",
}
"""(file, literal) pairs whose comparison is about something else that bears the same word."""


def decided_names() -> dict[str, str]:
    """Every literal that must not decide outside the results, with what it is."""
    names = {name: "metric key" for name in FIGURE_METRICS}
    names.update({name: "method" for name in METHODS if name not in NOT_A_RESULT})
    for kind in registered_types():
        names[kind] = "model type"
        names[CalibrationResult.class_of({"model": {"type": kind}, "method": kind}).MODEL_TYPE] = "model type"
    return names


def _literals(node: ast.AST) -> list[ast.Constant]:
    """String constants a comparison operand stands for: itself, or the items of a literal tuple, list or set."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node]
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return [e for e in node.elts if isinstance(e, ast.Constant) and isinstance(e.value, str)]
    return []


def deciding_comparisons(source: str, names: dict[str, str]) -> list[tuple[int, str, str]]:
    """(line, literal, what it is) of every comparison in ``source`` that decides by one of ``names``:
    ``==``, ``!=``, ``in``, ``not in`` with such a literal on either side (or in a literal tuple, list or
    set), and ``case`` patterns of one."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Compare):
            operands = [node.left, *node.comparators]
            if any(isinstance(op, (ast.Eq, ast.NotEq, ast.In, ast.NotIn)) for op in node.ops):
                found += [(c.lineno, c.value, names[c.value]) for o in operands for c in _literals(o)
                          if c.value in names]
        elif isinstance(node, ast.match_case):
            found += [(p.value.lineno, p.value.value, names[p.value.value]) for p in ast.walk(node.pattern)
                      if isinstance(p, ast.MatchValue) and isinstance(p.value, ast.Constant)
                      and p.value.value in names]
    return sorted(set(found))


def scanned_files() -> list[Path]:
    return [p for p in sorted(APP.rglob("*.py"))
            if not str(p.relative_to(ROOT)).startswith(EXEMPT) and "migrations" not in p.parts]


def test_the_names_come_from_the_code():
    names = decided_names()
    assert {"six_position", "orientations", "autocal", "cube", "noise", "temperature", "magnetometer"} <= set(names)
    assert {"affine", "triangular", "nonorthogonal"} <= set(names)
    assert {"cv_error_mg", "cv_error_ut", "holdout_error_after_mg", "count_control"} <= set(names)


def test_no_module_outside_the_results_decides_by_a_method_a_model_type_or_a_metric_key():
    names = decided_names()
    found = []
    for path in scanned_files():
        rel = str(path.relative_to(ROOT))
        for line, literal, what in deciding_comparisons(path.read_text(encoding="utf-8"), names):
            if (rel, literal) in NOT_DECISIONS:
                continue
            found.append(f"{rel}:{line}: compares with the {what} {literal!r}")
    assert not found, "the result (or the method table) decides, not these:\n" + "\n".join(found)


def test_the_checker_catches_each_kind_of_comparison_it_looks_for():
    names = {"cube": "model type", "six_position": "method", "cv_error_mg": "metric key"}
    source = (
        "def f(body, method, m):\n"
        "    if body['model']['type'] == 'cube':\n"
        "        return 1\n"
        "    if method in ('six_position', 'orientations'):\n"
        "        return 2\n"
        "    if 'cv_error_mg' in m or m.get('cv_error_mg') is not None:  # the key probed, not its value\n"
        "        return 3\n"
        "    match method:\n"
        "        case 'six_position':\n"
        "            return 4\n"
        "    return {'cube': 5}.get(method, method != 'free')\n"
    )
    assert deciding_comparisons(source, names) == [
        (2, "cube", "model type"), (4, "six_position", "method"), (6, "cv_error_mg", "metric key"),
        (9, "six_position", "method"),
    ]
