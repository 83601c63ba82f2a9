"""The corpus of real recordings (tests/data/real/corpus/*/case.json): each case's files, where they come
from, and what trical must answer — the peer's or the firmware's own figure where there is one, else the
right question or refusal.

A case folder holds the data (excerpts of public recordings, verbatim) and ``case.json``::

    {"title": …, "device": …,
     "source": {"repository": …, "path": …, "commit": <40 hex>, "licence": …, "kept": …},
     "files": ["gyro.csv"],                   # uploaded as `file` parts in this order, as the page does
     "form": {"sampling_rate_hz": "100"},     # the upload's form fields, as the page sends them
     "upload": {"status": 201, "code": …, "units": {…}, "channels": […], "detail_contains": […],
                "warnings_contain": […], "notes_contain": […],
                "runs_first": "noise"},      # the supported calibration the page runs first (null: none ready)
     "calibrate": {"method": "noise"},        # POST /api/v1/calibrations (recording_id filled in)
     "expect": {"status": 201, "ok": true, "reasons_contain": […],
                "values": [{"path": "model.gyr.bias", "value": […], "rtol": 0.05, "atol": 0}]},
     "reference": "what the peer, the firmware or the maker says, and where"}

Used by ``tests/api/test_real_corpus.py`` (the upload over HTTP, as the page sends it) and the property
test of the plausibility gate; ``python -m tests.real_corpus`` writes the corpus's README (its table of cases).
"""

from __future__ import annotations

import dataclasses
import json
import re
from pathlib import Path

CORPUS = Path(__file__).parent / "data" / "real" / "corpus"
SOURCE_KEYS = ("repository", "path", "commit", "licence", "kept")
MAX_FILE_BYTES = 400_000
"""An excerpt, not a whole log: a case's file stays small (the repository's size, the suite's time)."""


@dataclasses.dataclass(frozen=True)
class Case:
    name: str
    folder: Path
    spec: dict

    @property
    def files(self) -> list[Path]:
        return [self.folder / f for f in self.spec["files"]]

    @property
    def form(self) -> dict:
        return {k: str(v) for k, v in self.spec.get("form", {}).items()}

    def upload_parts(self) -> list[tuple[str, tuple[str, bytes, str]]]:
        """The multipart ``file`` parts, in order, as the page's file chooser sends them."""
        return [("file", (p.name, p.read_bytes(), "application/octet-stream")) for p in self.files]


def cases() -> list[Case]:
    """Every case of the corpus, by folder name."""
    return [Case(p.parent.name, p.parent, json.loads(p.read_text())) for p in sorted(CORPUS.glob("*/case.json"))]


def problems(case: Case) -> list[str]:
    """What a case's description lacks (its source, its files, its expectations)."""
    out = []
    source = case.spec.get("source", {})
    out += [f"source.{k} missing" for k in SOURCE_KEYS if not source.get(k)]
    if source.get("commit") and not re.fullmatch(r"[0-9a-f]{40}", source["commit"]):
        out.append(f"source.commit {source['commit']!r} is not a 40-hex commit")
    if not case.spec.get("files"):
        out.append("no files")
    for p in case.files:
        if not p.is_file():
            out.append(f"file {p.name} missing")
        elif p.stat().st_size > MAX_FILE_BYTES:
            out.append(f"file {p.name} is {p.stat().st_size} bytes, over {MAX_FILE_BYTES}")
    if "upload" not in case.spec:
        out.append("no upload expectation")
    if "calibrate" in case.spec and "expect" not in case.spec:
        out.append("a calibration without an expectation")
    for key in ("title", "device", "reference"):
        if not case.spec.get(key):
            out.append(f"{key} missing")
    return out


def at(body, path: str):
    """The value at a dot path of a JSON body (``model.gyr.bias``, ``readings.0.up``)."""
    value = body
    for part in path.split("."):
        value = value[int(part)] if isinstance(value, list) else value[part]
    return value


def _answer(spec: dict) -> str:
    """What trical must answer, in a few words: the calibration's status and ok, else the upload's."""
    exp = spec.get("expect") if "calibrate" in spec else spec.get("upload", {})
    said = f"{exp.get('status', '')}" + (f" ok={str(exp['ok']).lower()}" if "ok" in exp else "")
    return said + (f" {exp['code']}" if exp.get("code") else "")


def _runs_first(spec: dict) -> str:
    """What the page runs first on the upload (the first supported calibration that is ready), in a few words."""
    upload = spec.get("upload", {})
    if "runs_first" not in upload:
        return "—"
    return upload["runs_first"] or "nothing ready"


def table() -> str:
    """The corpus as a Markdown table (tests/data/real/corpus/README.md): case, device, files, what trical is
    asked and must answer, the reference, and the source with its commit and licence."""
    rows = [
        "| case | device | files | runs first | asked | must answer | reference | source (repository, path, commit) "
        "| licence |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for c in cases():
        s, src = c.spec, c.spec.get("source", {})
        method = s.get("calibrate", {}).get("method", "upload")
        cells = [
            c.name,
            s.get("device", ""),
            ", ".join(s.get("files", [])),
            _runs_first(s),
            method,
            _answer(s),
            s.get("reference", ""),
            f"{src.get('repository', '')}, {src.get('path', '')}, {src.get('commit', '')}",
            src.get("licence", ""),
        ]
        rows.append("| " + " | ".join(str(x).replace("|", "\\|").replace("\n", " ") for x in cells) + " |")
    return "\n".join(rows)


README_HEAD = """# The corpus of real recordings

Public recordings of real phones, boards and flight controllers, kept as excerpts with their source, each with
what trical must answer: the peer's, the maker's or the firmware's own figure where there is one, else the right
question or refusal. `tests/api/test_real_corpus.py` sends every case through the upload as the page does and
checks that answer; `tests/api/test_plausible_mistakes.py` reads them again with the mistakes a person can make
(a wrong unit, chip or columns) and `tests/api/test_page_words.py` reads every message they give as the page
shows it. Each folder's `case.json` holds the case; what each was found to answer before trical read it right,
and why, is in [FINDINGS.md](FINDINGS.md). This page is made by `python -m tests.real_corpus` (a test checks
it is up to date).

"""


def readme() -> str:
    """The corpus's README: its head and :func:`table`."""
    return README_HEAD + table() + "\n"


if __name__ == "__main__":
    (CORPUS / "README.md").write_text(readme(), encoding="utf-8")
    print(table())
