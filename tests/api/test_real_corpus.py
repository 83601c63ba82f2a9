"""Every real recording of the corpus (tests/data/real/corpus), sent through the upload exactly as the page
sends it, answers what its case says: the peer's or the firmware's figure, or the right question or
refusal (issue 31). The cases and their sources: tests/real_corpus.py, ``python -m tests.real_corpus``.
"""

from __future__ import annotations

import numpy as np
import pytest

from app.workflows.supports import first_ready
from tests.api.test_one_verdict import disagreement
from tests.real_corpus import CORPUS, at, cases, problems, readme

CASES = cases()


def test_the_corpus_holds_real_cases_each_with_its_source_and_expectation():
    assert len(CASES) >= 1
    bad = {c.name: problems(c) for c in CASES if problems(c)}
    assert not bad, bad


def test_the_corpus_readme_is_its_cases_table():
    assert (CORPUS / "README.md").read_text(encoding="utf-8") == readme(), "run python -m tests.real_corpus"


def _contains_all(texts: list[str], wanted: list[str], what: str) -> None:
    joined = "\n".join(texts)
    missing = [w for w in wanted if w.lower() not in joined.lower()]
    assert not missing, f"{what} lack {missing}: {texts}"


def _check(body: dict, status: int, want: dict, what: str) -> None:
    assert status == want.get("status", status), f"{what}: {status} {body}"
    if "code" in want:
        assert body.get("code") == want["code"], f"{what}: {body}"
    if "units" in want:
        assert body["units"] == want["units"], f"{what}: {body.get('units')} {body.get('warnings')}"
    if "ok" in want:
        assert body["ok"] is want["ok"], f"{what}: ok={body['ok']} reasons={body.get('reasons')}"
    if "runs_first" in want:  # what the recording supports that the page runs first (null: nothing is ready)
        first = (first_ready(body["supports"]) or {}).get("method")
        assert first == want["runs_first"], f"{what}: runs {first} first; supports {body['supports']}"
    _contains_all([body.get("detail", "")], want.get("detail_contains", []), f"{what} detail")
    _contains_all(body.get("warnings", []), want.get("warnings_contain", []), f"{what} warnings")
    _contains_all(body.get("notes", []), want.get("notes_contain", []), f"{what} notes")
    if "channels" in want:
        assert body["channels"] == want["channels"], f"{what}: channels {body.get('channels')} {body.get('notes')}"
    _contains_all(body.get("reasons", []), want.get("reasons_contain", []), f"{what} reasons")
    for v in want.get("values", []):
        if isinstance(v["value"], str):
            assert at(body, v["path"]) == v["value"], f"{what}: {v['path']}"
            continue
        np.testing.assert_allclose(
            at(body, v["path"]),
            v["value"],
            rtol=v.get("rtol", 0),
            atol=v.get("atol", 0),
            err_msg=f"{what}: {v['path']}",
        )


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_a_real_recording_answers_as_its_case_says(client, case):
    r = client.post("/api/v1/recordings", files=case.upload_parts(), data=case.form)
    assert r.status_code < 500, r.text
    rec = r.json()
    _check(rec, r.status_code, case.spec["upload"], f"{case.name} upload")
    if "calibrate" not in case.spec:
        return
    assert r.status_code == 201, "a case that calibrates needs its upload stored"
    r = client.post("/api/v1/calibrations", json={**case.spec["calibrate"], "recording_id": rec["id"]})
    assert r.status_code < 500, r.text
    _check(r.json(), r.status_code, case.spec["expect"], f"{case.name} calibration")
    if r.status_code == 201:  # one verdict, from the final result: ok, reasons and verdict agree
        assert disagreement(r.json()) == "", case.name


@pytest.mark.parametrize(
    "name, source",
    [
        ("hmc5883l_esp32_still_counts", "board"),  # an ESP32's CSV of counts: a board, whose use is its firmware
        ("tagged_lines_six_position", "board"),
        ("phyphox_turntable_zip", "phone"),
        ("hyperimu_lsm6ds3_phone_still", None),  # a plain CSV in m/s²: nothing says where it came from
    ],
)
def test_a_calibration_says_where_its_readings_came_from(client, name, source):
    """Where a calibration's readings came from decides the use the page offers first (app/web/uses.py): a phone
    app's format says phone, a recording of counts a board (no phone app logs counts)."""
    case = next(c for c in CASES if c.name == name)
    rec = client.post("/api/v1/recordings", files=case.upload_parts(), data=case.form).json()
    method = (case.spec.get("calibrate") or {}).get("method", "noise")
    body = client.post("/api/v1/calibrations", json={"method": method, "recording_id": rec["id"]}).json()
    assert body.get("source") == source, body.get("source")
