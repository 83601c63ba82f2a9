"""Handlers read typed requests (issue 46, deliverable 1): a handler takes the protocol of the fields it reads
(app/workflows/requests.py), and the method table binds each request model to its handler where mypy checks
that the model gives every field the handler reads. Planted: a handler that misspells a field, and a table
entry whose model lacks a field its handler reads, each fail mypy with the repository's settings."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


PLANTED: dict[str, str] = {}
"""The planted modules by name, checked together in one run of mypy (:func:`findings`)."""


@pytest.fixture(scope="module")
def findings(tmp_path_factory) -> dict[str, str]:
    """mypy's findings on each planted module (each imports the application), with the repository's settings
    (pyproject.toml; its cache makes this quick after `make test`'s type check): by module, its lines."""
    folder = tmp_path_factory.mktemp("planted")
    for name, source in PLANTED.items():
        (folder / f"{name}.py").write_text(source)
    done = subprocess.run(
        [sys.executable, "-m", "mypy", *sorted(str(p) for p in folder.glob("*.py"))],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode in (0, 1), f"mypy could not run:\n{done.stdout}\n{done.stderr}"
    return {name: "\n".join(line for line in done.stdout.splitlines() if f"{name}.py:" in line) for name in PLANTED}


ENTRY = """
from app import calibration_requests as rq
from app.methods import Method
from app.workflows import still

PLANTED = Method(
    "planted",
    request=rq.{model},
    handler=still.{handler},
    response=None,
    command="calibrate",
    formats=(),
    kind="",
    words="",
    page_words="",
)
"""


PLANTED["right_entry"] = ENTRY.format(model="TriangularIn", handler="triangular")
# nonorthogonal's model has no solver, which triangular's handler reads.
PLANTED["wrong_entry"] = ENTRY.format(model="NonOrthogonalIn", handler="triangular")
PLANTED["misspelled"] = """
from app.workflows.calibration import Calibration
from app.workflows.recordings import RecordingSource
from app.workflows.requests import SolvedRequest


def planted(request: SolvedRequest, recording: RecordingSource | None) -> Calibration:
    print(request.solvr)
    raise NotImplementedError
"""


def test_planted_an_entry_whose_model_gives_its_handler_what_it_reads_passes(findings):
    assert findings["right_entry"] == ""


def test_planted_an_entry_whose_model_lacks_a_field_its_handler_reads_fails(findings):
    assert 'Argument "handler" to "Method" has incompatible type' in findings["wrong_entry"], findings


def test_planted_a_handler_that_misspells_a_field_fails(findings):
    assert '"SolvedRequest" has no attribute "solvr"' in findings["misspelled"], findings
