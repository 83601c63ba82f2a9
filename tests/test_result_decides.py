"""The result decides: outside the result classes and the method table (app/methods.py), no module of app/,
no page script (static/js) and no template compares a value with a method name, a model type or a metric key
that chooses a figure, reads such a metric by its key, or keys a table by a method or a model type.

Such a comparison (``body["model"]["type"] == "cube"``, ``method in ("six_position", "orientations")``,
``"cv_error_mg" in metrics``, a ``case "noise":``) is a
place that knows a method by name: the stored body's result (``registry.from_dict``) or the method
table answers instead. The names are taken from the code: the result registry's types and model types, the
methods the requests accept, and the metrics the results choose their figures by; in the page (templates and
scripts) the protocols' names too, from the protocol table. Four scanners: Python comparisons, Python reads of a
metric by its key (``.get("cv_error_mg")``, ``["cv_error_mg"]``), Python dicts keyed by a method or a model type,
and one for the page (comparisons, ``case``, ``includes(``, ``in``, object keys; Jinja's ``==`` and ``in``).
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

from app.calibration.registry import class_of, registered_types
from app.calibration.shared.result import FIGURE_METRICS
from app.guided.protocols import BOARD_PROTOCOLS, SESSION_PROTOCOLS
from app.methods import METHODS

ROOT = Path(__file__).resolve().parent.parent
APP = ROOT / "app"

EXEMPT = (
    "app/calibration/shared/result.py",
    "app/calibration/still/affine.py",
    "app/calibration/autocal.py",
    "app/calibration/cube/calibrate.py",
    "app/calibration/magnetometer/result.py",
    "app/calibration/temperature.py",
    "app/headlines.py",
    "app/calibration/still/trust.py",
    "app/calibration/still/comparison.py",
    "app/calibration/magnetometer/fit.py",
    "simulations/free_poses.py",
    "app/methods.py",
)
"""The files that may decide, named one by one (every other file of app/calibration is scanned too): the result
modules, which choose their figures by their metrics (result, affine, autocal, cube/calibrate, magnetometer/result,
temperature), the presenter that tells their headlines by result class (app/headlines.py), the core's modules that
write those metrics and read them back in the same fit (trust, comparison, magnetometer/fit; the free-pose
simulation's report), and the method table, which declares."""


NOT_A_RESULT = {"auto"}
"""Methods no stored result carries: ``auto`` chooses a method and the body names the one it chose; ``auto``
is also the value of every option read from the data (format, unit, sign, columns)."""

NOT_DECISIONS = {
    ("app/io/readers/sensor_logger.py", "magnetometer"): "a Sensor Logger file's name (MagnetometerUncalibrated.csv)",
    ("app/cli/parser.py", "autocal"): "the `trical autocal` command in the table of commands",
    ("app/cli/parser.py", "noise"): "the `trical noise` command in the table of commands",
    ("app/cli/parser.py", "temperature"): "the `trical temperature` command in the table of commands",
    ("app/cli/capture.py", "noise"): "`trical capture`'s noise protocol, which ends as `trical noise`",
}
"""(file, literal) pairs whose comparison is about something else that bears the same word."""


def decided_names() -> dict[str, str]:
    """Every literal that must not decide outside the results, with what it is."""
    names = dict.fromkeys(FIGURE_METRICS, "metric key")
    names.update({name: "method" for name in METHODS if name not in NOT_A_RESULT})
    for kind in registered_types():
        names[kind] = "model type"
        names[class_of({"model": {"type": kind}, "method": kind}).MODEL_TYPE] = "model type"
    return names


def _literals(node: ast.AST) -> list[ast.Constant]:
    """String constants a comparison operand stands for: itself, or the items of a literal tuple, list or set."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node]
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return [e for e in node.elts if isinstance(e, ast.Constant) and isinstance(e.value, str)]
    return []


def nodes_of(source: str | list[ast.AST]) -> list[ast.AST]:
    """Every node of a source (parsed once by the caller when several scanners read it)."""
    return list(ast.walk(ast.parse(source))) if isinstance(source, str) else source


def deciding_comparisons(source: str | list[ast.AST], names: dict[str, str]) -> list[tuple[int, str, str]]:
    """(line, literal, what it is) of every comparison in ``source`` that decides by one of ``names``:
    ``==``, ``!=``, ``in``, ``not in`` with such a literal on either side (or in a literal tuple, list or
    set), and ``case`` patterns of one."""
    found = []
    for node in nodes_of(source):
        if isinstance(node, ast.Compare):
            operands = [node.left, *node.comparators]
            if any(isinstance(op, (ast.Eq, ast.NotEq, ast.In, ast.NotIn)) for op in node.ops):
                found += [
                    (c.lineno, c.value, names[c.value]) for o in operands for c in _literals(o) if c.value in names
                ]
        elif isinstance(node, ast.match_case):
            found += [
                (p.value.lineno, p.value.value, names[p.value.value])
                for p in ast.walk(node.pattern)
                if isinstance(p, ast.MatchValue) and isinstance(p.value, ast.Constant) and p.value.value in names
            ]
    return sorted(set(found))


def metric_reads(source: str | list[ast.AST], names: dict[str, str]) -> list[tuple[int, str, str]]:
    """(line, key, what it is) of every read of a metric by its key: ``m.get("cv_error_mg")``, ``m["cv_error_mg"]``
    (a write, ``m["cv_error_mg"] = …``, produces the metric and is not a read)."""
    keys = {n for n, what in names.items() if what == "metric key"}
    found = []
    for node in nodes_of(source):
        key = None
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Attribute)
            and node.func.attr == "get"
            and node.args
            and isinstance(node.args[0], ast.Constant)
        ):
            key = node.args[0]
        elif (
            isinstance(node, ast.Subscript) and isinstance(node.ctx, ast.Load) and isinstance(node.slice, ast.Constant)
        ):
            key = node.slice
        if key is not None and key.value in keys:
            found.append((key.lineno, key.value, names[key.value]))
    return sorted(set(found))


def method_keyed_dicts(source: str | list[ast.AST], names: dict[str, str]) -> list[tuple[int, str, str]]:
    """(line, key, what it is) of every dict display keyed by a method name or a model type: a second table."""
    found = []
    for node in nodes_of(source):
        if isinstance(node, ast.Dict):
            found += [
                (k.lineno, k.value, names[k.value])
                for k in node.keys
                if isinstance(k, ast.Constant) and names.get(k.value) in ("method", "model type")
            ]
    return sorted(set(found))


def python_decisions(source: str, names: dict[str, str]) -> list[tuple[int, str, str]]:
    """The three Python scanners' findings, one list, with how each decides (a source that quotes none of the
    names is not parsed: that keeps the scan fast)."""
    if not re.search("|".join(f"['\"]{re.escape(n)}['\"]" for n in names), source):
        return []
    nodes = nodes_of(source)
    return sorted(
        [(line, lit, f"compares with the {what}") for line, lit, what in deciding_comparisons(nodes, names)]
        + [(line, lit, f"reads the {what}") for line, lit, what in metric_reads(nodes, names)]
        + [(line, lit, f"keys a table by the {what}") for line, lit, what in method_keyed_dicts(nodes, names)]
    )


STRING = re.compile(r"""'(?:[^'\\\n]|\\.)*'|"(?:[^"\\\n]|\\.)*"|`(?:[^`\\]|\\.)*`""")
JS_COMMENT = re.compile(r"//[^\n]*|/\*.*?\*/", re.S)
BEFORE = re.compile(r"(===|!==|==|!=|\bcase|\bincludes\s*\(|\bin)\s*$")
AFTER = re.compile(r"^\s*(===|!==|==|!=|in\b|not\s+in\b)")
IN_ITEMS = re.compile(r"""(\bin\s*)?[\[({]\s*(?:(?:"\s*"|'\s*')\s*,\s*)*$""")
ITEMS_AFTER = re.compile(r"""^\s*(?:,\s*(?:"\s*"|'\s*')\s*)*,?\s*[\])}]\s*(\.\s*includes\s*\()?""")
KEY_BEFORE = re.compile(r"[{,]\s*$")


def _blank(text: str, pattern: re.Pattern) -> str:
    return pattern.sub(lambda m: re.sub(r"[^\n]", " ", m.group()), text)


def code_decisions(code: str, names: dict[str, str], offset: int, text: str) -> list[tuple[int, str, str]]:
    """Findings in one piece of script or template code (comments already blanked), lines counted in ``text``
    from ``offset``: a string equal to a name next to a comparison, ``case``, ``includes(``, ``in`` or inside
    the items of such a test, or keying an object; and an unquoted object key that is a name."""
    strings = list(STRING.finditer(code))
    blank = code
    for m in reversed(strings):  # the strings' insides blanked: only code is matched around them
        blank = blank[: m.start() + 1] + " " * (m.end() - m.start() - 2) + blank[m.end() - 1 :]
    found = []

    def line(pos: int) -> int:
        return text.count("\n", 0, offset + pos) + 1

    for m in strings:
        value = m.group()[1:-1]
        if value not in names:
            continue
        before, after = blank[: m.start()], blank[m.end() :]
        items_before, items_after = IN_ITEMS.search(before), ITEMS_AFTER.match(after)
        if (
            BEFORE.search(before)
            or AFTER.match(after)
            or (items_before and items_after and (items_before.group(1) or items_after.group(1)))
        ):
            how = "compares with the"
        elif KEY_BEFORE.search(before) and re.match(r"\s*:", after):
            how = "keys a table by the"
        else:
            continue
        found.append((line(m.start()), value, f"{how} {names[value]}"))
    for m in re.finditer(r"[{,]\s*([A-Za-z_]\w*)\s*:(?!:)", blank):
        if m.group(1) in names:
            found.append((line(m.start(1)), m.group(1), f"keys a table by the {names[m.group(1)]}"))
    return found


def page_decisions(text: str, names: dict[str, str], template: bool) -> list[tuple[int, str, str]]:
    """The page's scanner: a script's code, or a template's Jinja tags and ``<script>`` blocks."""
    if not template:
        return sorted(set(code_decisions(_blank(text, JS_COMMENT), names, 0, text)))
    text = _blank(text, re.compile(r"\{#.*?#\}|<!--.*?-->", re.S))
    found = []
    for m in re.finditer(r"\{%.*?%\}|\{\{.*?\}\}|<script\b[^>]*>(.*?)</script>", text, re.S):
        start = m.start(1) if m.group(1) is not None else m.start()
        code = _blank(m.group(1) if m.group(1) is not None else m.group(), JS_COMMENT)
        found += code_decisions(code, names, start, text)
    return sorted(set(found))


def page_names() -> dict[str, str]:
    """The names the page must not decide by: the results' and the method table's, and the protocols'."""
    names = decided_names()
    names.update({p: "protocol" for p in [*SESSION_PROTOCOLS, *BOARD_PROTOCOLS] if p not in names})
    return names


def scanned_files() -> list[Path]:
    return [
        p for p in sorted(APP.rglob("*.py")) if str(p.relative_to(ROOT)) not in EXEMPT and "migrations" not in p.parts
    ]


def page_files() -> list[Path]:
    return sorted((ROOT / "static" / "js").glob("*.js")) + sorted((ROOT / "templates").glob("*.html"))


def test_the_names_come_from_the_code():
    names = decided_names()
    assert {"six_position", "orientations", "autocal", "cube", "noise", "temperature", "magnetometer"} <= set(names)
    assert {"affine", "triangular", "nonorthogonal"} <= set(names)
    assert {"cv_error_mg", "cv_error_ut", "holdout_error_after_mg", "count_control"} <= set(names)


def findings() -> list[tuple[str, int, str, str]]:
    """(file, line, name, how) of every decision the four scanners find in app/, static/js and templates/."""
    names, on_page = decided_names(), page_names()
    found = []
    for path in scanned_files():
        rel = str(path.relative_to(ROOT))
        source = path.read_text(encoding="utf-8")
        found += [
            (rel, line, literal, how)
            for line, literal, how in python_decisions(source, names)
            if (rel, literal) not in NOT_DECISIONS
        ]
    for path in page_files():
        rel = str(path.relative_to(ROOT))
        found += [(rel, *f) for f in page_decisions(path.read_text(encoding="utf-8"), on_page, path.suffix == ".html")]
    return found


def test_no_module_script_or_template_outside_the_results_decides_by_a_method_a_model_type_or_a_metric_key():
    # scanned here, not at the module's import: every worker of the suite imports it, one runs this test
    found = [f"{rel}:{line}: {how} {literal!r}" for rel, line, literal, how in findings()]
    assert not found, "the result (or the method table) decides, not these:\n" + "\n".join(found)


def test_every_pair_that_is_about_something_else_is_still_found():
    names, on_page = decided_names(), page_names()
    stale = []
    for rel, literal in NOT_DECISIONS:
        path = ROOT / rel
        found = path.is_file() and any(
            lit == literal
            for _, lit, _ in (
                python_decisions(path.read_text(encoding="utf-8"), names)
                if rel.endswith(".py")
                else page_decisions(path.read_text(encoding="utf-8"), on_page, rel.endswith(".html"))
            )
        )
        if not found:
            stale.append(f"{rel}: {literal!r}")
    assert not stale, "no longer found; strike them from NOT_DECISIONS:\n" + "\n".join(stale)


def test_the_exemption_names_files_that_exist():
    assert all((ROOT / f).is_file() for f in EXEMPT), [f for f in EXEMPT if not (ROOT / f).is_file()]


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
        (2, "cube", "model type"),
        (4, "six_position", "method"),
        (6, "cv_error_mg", "metric key"),
        (9, "six_position", "method"),
    ]


# Planted examples, one per scanner: a violation, found with its line, beside a look-alike that is not one.

PLANTED = {"cube": "model type", "six_position": "method", "cv_error_mg": "metric key", "cube24": "protocol"}


def test_planted_python_comparison():
    source = "if body['model']['type'] == 'cube':\n    pass\nlabel = 'cube'\nif kind is 'cube' or x < 'cube': pass\n"
    assert deciding_comparisons(source, PLANTED) == [(1, "cube", "model type")]


def test_planted_python_metric_read():
    source = "best = m.get('cv_error_mg')\nm['cv_error_mg'] = 3.0\nlabel = words.get('cube')\n"
    assert metric_reads(source, PLANTED) == [(1, "cv_error_mg", "metric key")]


def test_planted_python_dict_keyed_by_method():
    source = "NAMES = {\n    'six_position': 'Six positions',\n}\nUNITS = {'mg': 1, 'cv_error_mg': 2}\nx = ['cube']\n"
    assert method_keyed_dicts(source, PLANTED) == [(2, "six_position", "method")]


def test_planted_javascript():
    source = (
        "// if (type === 'cube') in a comment\n"
        "const KINDS = { cube: 1, plain: 2 };\n"
        'if (cal.model.type === "cube") draw();\n'
        "switch (p) { case 'cube24': go(); }\n"
        "if (['six_position', 'x'].includes(m)) go();\n"
        "const title = 'cube'; el('p', {}, `the cube`);\n"
        "const t = a ? cube : b;\n"
        "if ('cube' in KINDS) go();\n"
    )
    assert page_decisions(source, PLANTED, template=False) == [
        (2, "cube", "keys a table by the model type"),
        (3, "cube", "compares with the model type"),
        (4, "cube24", "compares with the protocol"),
        (5, "six_position", "compares with the method"),
        (8, "cube", "compares with the model type"),
    ]


def test_planted_template():
    source = (
        '<p class="cube">the cube\'s sides</p>\n'
        "{# {% if protocol == 'cube24' %} in a comment #}\n"
        '{% if protocol == "cube24" %}<p>24</p>{% endif %}\n'
        '<a href="/wizard?protocol=cube24">cube24</a>\n'
        "{% if protocol in ('six', 'cube24') %}x{% endif %}\n"
        "<script>const x = {{ protocol|tojson }}; if (x !== 'cube24') go();</script>\n"
    )
    assert page_decisions(source, PLANTED, template=True) == [
        (3, "cube24", "compares with the protocol"),
        (5, "cube24", "compares with the protocol"),
        (6, "cube24", "compares with the protocol"),
    ]
