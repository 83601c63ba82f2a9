"""The page never names an API parameter or a command-line option (issue 31): every message the upload and
the calibrations can answer — refusals, the reader's warnings and notes, a calibration's reasons, warnings,
notes and verdict — for every real recording (tests/data/real, the corpus's cases included) and for the
bad input of the API's tests, asked for with the page's header, is in the page's words. The API keeps its
own words. The names are the upload's form fields and the request models' fields, read from the API's
own schema, so that a new parameter is guarded the day it is added."""

from __future__ import annotations

import re
from functools import lru_cache
from pathlib import Path

from app import methods
from app.words import CLIENT_HEADER, VOCABULARY, render
from tests.api import test_bad_input, test_units_api
from tests.real_corpus import cases as corpus_cases

REAL = Path(__file__).resolve().parent.parent / "data" / "real"
PAGE = {CLIENT_HEADER: "page"}


@lru_cache(maxsize=1)
def parameter_names() -> frozenset[str]:
    """Every field of the upload's form, the apply-file form and the API's request bodies (its schema's ``…In``
    models)."""
    import tempfile

    from app.config import Settings
    from app.main import create_app

    folder = tempfile.mkdtemp()
    schemas = create_app(Settings(database_url=f"sqlite:///{folder}/trical.db")).openapi()["components"]["schemas"]
    names = set()
    for name, schema in schemas.items():
        if (
            name.startswith("Body_upload_recording")
            or name in ("UploadOptions", "ApplyFileOptions")
            or name.endswith("In")
        ):
            names.update(schema.get("properties", {}))
    return frozenset(names - {"file"})


def api_words(text: str) -> list[str]:
    """What in ``text`` is the API's or the command line's way of naming a parameter: an identifier of the
    API (``acc_unit``), any parameter in code form (```columns```, ``sign=-1``, a validation error's
    ``gravity: …``), ``method auto``, or a command-line option (``--unit``)."""
    names = parameter_names()
    alternatives = "|".join(sorted(map(re.escape, names), key=len, reverse=True))
    found = re.findall(rf"(?<![\w.\-])(?:{'|'.join(re.escape(n) for n in names if '_' in n)})(?![\w-])", text)
    found += re.findall(rf"`(?:{alternatives})`|(?<![\w.\-])(?:{alternatives})=", text)
    found += re.findall(rf"(?:^|; )(?:{alternatives})(?:\[\d+\]|\.\w+)*: ", text)
    found += re.findall(rf"\bmethod `?(?:{'|'.join(methods.METHODS)})\b", text)
    found += re.findall(r"(?<![\w-])--[a-z][a-z0-9-]+", text)
    return found


def messages(body) -> list[str]:
    """The messages of an answer: its detail, warnings, notes, reasons and verdict."""
    if not isinstance(body, dict):
        return []
    out = [body["detail"]] if isinstance(body.get("detail"), str) else []
    for key in ("warnings", "notes", "reasons"):
        out += [m for m in body.get(key) or [] if isinstance(m, str)]
    verdict = body.get("verdict") or {}
    return out + [verdict.get("words") or "", verdict.get("why") or ""]


def _files(paths):
    return [("file", (p.name, p.read_bytes(), "text/csv")) for p in paths]


def real_uploads() -> list[tuple[str, list[Path], dict, list[dict]]]:
    """(name, files, form, calibrations) of every real recording: the loose files, the folders of one file per
    pose (uploaded together, as the page does), and the corpus's cases; each also with the mistakes a person
    makes on the page (the unit menus, the part menu)."""
    loose = sorted(p for p in REAL.rglob("*.csv") if "corpus" not in p.parts and not p.parent.name.endswith("files"))
    groups = [(p.name, [p]) for p in loose]
    groups += [
        (d.name, sorted(d.glob("*.csv"))) for d in sorted(REAL.iterdir()) if d.is_dir() and d.name.endswith("files")
    ]
    calibrations = [{"method": m} for m in ("auto", "noise", "magnetometer", "temperature")]
    cases = []
    for name, files in groups:
        for form in ({}, {"acc_unit": "raw", "gyr_unit": "raw", "mag_unit": "raw"}):
            cases.append((f"{name} {form}", files, form, calibrations if not form else [{"method": "auto"}]))
    for case in corpus_cases():
        cases.append(
            (case.name, case.files, case.form, [c for c in (case.spec.get("calibrate"), {"method": "auto"}) if c])
        )
    return cases


def collect(client) -> list[tuple[str, str]]:
    """(where, message) of every answer of the real recordings and of the API tests' bad input."""
    said = []
    for name, files, form, calibrations in real_uploads():
        r = client.post("/api/v1/recordings", files=_files(files), data=form)
        said += [(f"upload {name}", m) for m in messages(r.json())]
        if r.status_code != 201:
            continue
        for body in calibrations:
            c = client.post("/api/v1/calibrations", json={**body, "recording_id": r.json()["id"]})
            said += [(f"{body['method']} of {name}", m) for m in messages(c.json())]
    for name, (content, form) in test_units_api.UPLOADS.items():
        form = dict(form)
        r = test_units_api._upload(client, content, form.pop("filename", "log.csv"), **form)
        said += [(f"upload {name}", m) for m in messages(r.json())]
    for name, request in test_units_api.REQUESTS.items():
        said += [(name, m) for m in messages(request(client).json())]
    for payload, *_ in test_bad_input.test_bad_calibration_requests.pytestmark[0].args[1]:
        said += [
            (f"calibrate {payload}"[:80], m) for m in messages(client.post("/api/v1/calibrations", json=payload).json())
        ]
    return [(where, m) for where, m in said if m]


def test_the_page_reads_no_api_parameter_and_no_command_line_option(client):
    client.headers.update(PAGE)
    said = collect(client)
    assert len(said) > 100, len(said)
    named = [(where, m, api_words(m)) for where, m in said if api_words(m)]
    assert not named, "\n".join(f"{where}: {words} in {m!r}" for where, m, words in named[:20])


def test_the_api_keeps_its_own_words(client):
    r = test_units_api._upload(client, test_units_api.SIX_CSV, lsb_per_g=16384)
    assert r.status_code == 422 and "lsb_per_g=16384" in r.json()["detail"], r.text
    page = client.post(
        "/api/v1/recordings",
        headers=PAGE,
        data={"lsb_per_g": "16384"},
        files={"file": ("log.csv", test_units_api.SIX_CSV, "text/csv")},
    ).json()["detail"]
    assert page == render(r.json()["detail"], "page") and "part menu" in page and not api_words(page), page


def test_the_guard_catches_a_parameter_named_in_any_form():
    planted = [
        "give acc_unit=raw",
        "the upload field `columns`",
        "method auto needs still poses",
        "(sampling_rate_hz)",
        "gravity: Input should be greater",
        "upload it with --chip mpu6050-2g",
    ]
    assert all(api_words(text) for text in planted), [t for t in planted if not api_words(t)]
    assert not api_words("the accelerometer's unit menu, the columns of the file, the sign of the readings")


def test_every_parameter_of_the_vocabulary_is_one_of_the_api_and_its_option_one_of_the_command():
    from app.cli.parser import build_parser

    options = set()

    def walk(parser):
        for action in parser._actions:
            options.update(action.option_strings)
            for sub in (getattr(action, "choices", None) or {}).values() if hasattr(action, "_name_parser_map") else ():
                walk(sub)

    walk(build_parser())
    assert set(VOCABULARY) <= parameter_names() | {"mag"}, set(VOCABULARY) - parameter_names()
    for term in VOCABULARY.values():
        assert term.option in options or not term.option.startswith("--"), term
        assert not api_words(term.page) and not api_words(term.page_value or ""), term


def test_one_message_in_its_three_readers_words_and_a_page_whose_control_differs(client):
    said = (
        "the accelerometer's readings are counts (acc_unit=raw): its figures are in counts; give chip or "
        "lsb_per_g to calibrate in g"
    )
    assert render(said, "api") == said
    assert render(said, "cli") == (
        "the accelerometer's readings are counts (--unit raw): its figures are in counts; "
        "give --chip or --lsb-per-g to calibrate in g"
    )
    assert render(said, "page") == (
        "the accelerometer's readings are counts (counts in the accelerometer's unit menu (in “Units, as the data "
        "show them”)): its figures are in counts; give the sensor's part menu to calibrate in g"
    )
    place = "give `date`, latitude_deg and longitude_deg (or field_ut) for the Earth's field there"
    assert render(place, "page", "/") == (
        "give the Date of the turn, the Latitude and the Longitude (or the field's "
        "strength (µT)) for the Earth's field there"
    )
    assert render(place, "page", "/wizard") == (
        "give today's date (the page sends it with your location), your "
        "location (“Use my location for the reference field”) for the "
        "Earth's field there"
    )
    # The error body lists what its detail asks for, in the API's names, for every reader.
    r = client.post(
        "/api/v1/recordings",
        headers=PAGE,
        data={"lsb_per_g": "16384"},
        files={"file": ("log.csv", test_units_api.SIX_CSV, "text/csv")},
    )
    assert r.json()["asks"] == ["lsb_per_g"], r.json()
