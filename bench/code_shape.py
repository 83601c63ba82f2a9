"""The shape of the code: where strings decide, and the longest functions.

Prints, for ``app/`` (Python) and ``static/js`` (the page):

- the places that compare a method, a model type, a protocol or a flow with a literal
  (``method == "six_position"``, ``body["model"]["type"] == "cube"``, ``protocol == "free"``,
  ``if (cube)``), and the places that choose a figure by which metric key is present
  (``"cv_error_mg" in metrics``), per file, as ``git grep -c`` counts them;
- the longest Python functions and the longest page functions, in lines.

Run from the repository's root: ``python bench/code_shape.py [--top 15]``. It reads files only.
"""

from __future__ import annotations

import argparse
import ast
import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

BRANCH_PATTERNS = {
    "method/model-type/protocol literal": (
        r"(method|protocol|\[\"type\"\]|get\(\"type\"\)|\.type)\"?\]?\)?\s*(==|!=|===|!==)\s*[\"']"
    ),
    "metric key probed": r"\"(cv_error_ut|cv_error_mg|holdout_error_after_mg|count_control)\" in ",
    "page flow or model branch": r"(if \((cube|free)\)|(type|method|protocol|flow) !?==+ [\"'])",
}


def grep_counts(pattern: str, paths: list[str]) -> dict[str, int]:
    """``git grep -c -E pattern -- paths`` as {file: count}."""
    out = subprocess.run(
        ["git", "grep", "-c", "-E", pattern, "--", *paths], cwd=ROOT, capture_output=True, text=True, timeout=60
    )
    counts = {}
    for line in out.stdout.splitlines():
        name, _, count = line.rpartition(":")
        counts[name] = int(count)
    return counts


def python_functions() -> list[tuple[int, str]]:
    """(lines, place) of every function of app/."""
    found = []
    for path in sorted((ROOT / "app").rglob("*.py")):
        if "migrations" in path.parts:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                found.append((node.end_lineno - node.lineno + 1, f"{path.relative_to(ROOT)}:{node.lineno} {node.name}"))
    return sorted(found, reverse=True)


def js_functions() -> list[tuple[int, str]]:
    """(lines, place) of the page's top-level functions: from the ``function`` line to the first line after it
    that closes at the margin (the modules' style), or one line when it closes where it opens. Counting braces
    miscounted a function whose regular expression holds one (``/^\\s*[[{]/``)."""
    found = []
    for path in sorted((ROOT / "static" / "js").glob("*.js")):
        lines = path.read_text(encoding="utf-8").splitlines()
        for i, line in enumerate(lines):
            match = re.match(r"^(export\s+)?(async\s+)?function\s*\*?\s*(\w+)", line)
            if not match:
                continue
            one_line = line.rstrip().endswith("}") and line.count("{") == line.count("}")
            end = i if one_line else next((j for j in range(i + 1, len(lines)) if lines[j].startswith("}")), i)
            found.append((end - i + 1, f"{path.relative_to(ROOT)}:{i + 1} {match.group(3)}"))
    return sorted(found, reverse=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--top", type=int, default=12, help="how many of the longest functions to print")
    args = parser.parse_args()
    for name, pattern in BRANCH_PATTERNS.items():
        paths = ["static/js"] if name.startswith("page") else ["app"]
        counts = grep_counts(pattern, paths)
        print(f"{name}: {sum(counts.values())} in {len(counts)} files")
        for file, count in sorted(counts.items(), key=lambda kv: (-kv[1], kv[0])):
            print(f"  {count:3d}  {file}")
    for title, functions in (
        ("longest Python functions (app/)", python_functions()),
        ("longest page functions (static/js)", js_functions()),
    ):
        lengths = [n for n, _ in functions]
        median = sorted(lengths)[len(lengths) // 2] if lengths else 0
        print(f"{title}: {len(lengths)} functions, median {median} lines")
        for n, place in functions[: args.top]:
            print(f"  {n:4d}  {place}")


if __name__ == "__main__":
    main()
