"""Every remedy is one its place accepts (issue 42, deliverable 2): a message that names a parameter names one the
place where it is read takes — the API's upload for that family of file (app.io.readers.read_options.UPLOAD_FIELDS)
or the calibration's request for that method, the command line's parser of the command that runs it — or one the
person gave (a refusal says which of theirs to leave out). Every message trical gives over the real recordings
(tests/data/real: the loose files, the folders of one file per pose or per sensor, the corpus's cases, the flight
controllers' logs) and the API tests' mistakes, each with every method it supports and the methods a person tries,
is checked; the page reads the same messages in its own words (tests/api/test_page_words.py), and offers a control
for each field of the upload's family (static/js/index.js)."""

from __future__ import annotations

from functools import cache
from pathlib import Path

import numpy as np

from app import methods
from app.io.readers.read_options import UPLOAD_FIELDS
from app.words import VOCABULARY, asked
from tests.api import test_units_api
from tests.api.test_page_words import _files, messages, real_uploads

REAL = Path(__file__).resolve().parent.parent / "data" / "real"
FLIGHT_ULOG = sorted((REAL / "flight").glob("*.ulg"))
FLIGHT_BIN = sorted((REAL / "flight").glob("*.bin"))
FLIGHT = FLIGHT_ULOG + FLIGHT_BIN
TRIED = ("auto", "noise", "magnetometer", "compass_flight", "temperature", "cube")
"""The methods a person tries on any recording (the page's buttons, ``trical calibrate --method``)."""


def family(names: list[str], body: dict | None) -> str:
    """The upload family of a recording (its stored format, else its files' names)."""
    fmt = (body or {}).get("format") or ""
    if fmt in ("ulog", "dataflash") or any(n.lower().endswith((".ulg", ".bin")) for n in names):
        return "flight"
    if fmt in ("npy", "parquet") or any(n.lower().endswith((".npy", ".parquet", ".pq")) for n in names):
        return "array"
    return "text"


@cache
def options_of(command: str) -> frozenset[str]:
    """The option strings of a ``trical`` command (its argparse parser)."""
    from app.cli.parser import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if hasattr(a, "_name_parser_map"))._name_parser_map[command]
    return frozenset(o for action in sub._actions for o in action.option_strings)


def wrong_remedies(message: str, *, fields: set[str], command: str, gave: set[str]) -> list[str]:
    """The parameters ``message`` asks for that its place does not take: not among ``fields`` (the API's) nor the
    option strings of ``command`` (the command line's), and not among those the person ``gave``."""
    out = []
    for name in asked(message):
        if name in gave:
            continue
        if name not in fields:
            out.append(f"{name} (not a field of this upload or request)")
        option = VOCABULARY[name].option if name in VOCABULARY else None
        if option and option.startswith("--") and option not in options_of(command):
            out.append(f"{option} (not an option of trical {command})")
    return out


def answer_problems(upload, calibration, *, names: list[str], form: dict, method: str) -> list[str]:
    """The remedies an upload's answer and its calibration's name that their places do not take (the upload's
    family, the method's request, its command; or what the person gave in ``form``)."""
    rec = upload.json()
    fields = set(UPLOAD_FIELDS[family(names, rec if upload.status_code == 201 else None)])
    entry = methods.BY_NAME[method]
    out = [
        f"upload: {w} in {m!r}"
        for m in messages(rec)
        for w in wrong_remedies(m, fields=fields, command="calibrate", gave=set(form))
    ]
    if calibration is not None:
        out += [
            f"{method}: {w} in {m!r}"
            for m in messages(calibration.json())
            for w in wrong_remedies(m, fields=fields | set(entry.options), command=entry.command, gave=set(form))
        ]
    return out


def uploads() -> list[tuple[str, list, dict, list[dict]]]:
    """(name, file parts, form, calibrations) of every real recording and flight log, and the upload mistakes of the
    API's unit tests."""
    out = [(name, _files(files), form, cals) for name, files, form, cals in real_uploads()]
    for path in FLIGHT:
        out.append((path.name, _files([path]), {}, [{"method": m} for m in TRIED]))
    # The options a flight log does not take, or takes out of range, on one log of each firmware (the words are
    # the firmware's reader's, whichever log it reads: a parse of every log for each cost seconds of the suite).
    for path in (FLIGHT_ULOG[0], FLIGHT_BIN[0]):
        out.append((f"{path.name} with a unit", _files([path]), {"acc_unit": "g", "chip": "mpu6050-2g"}, []))
        out.append((f"{path.name} compass 7", _files([path]), {"mag_instance": "7"}, []))
    for name, (content, form) in test_units_api.UPLOADS.items():
        form = dict(form)
        filename = form.pop("filename", "log.csv")
        out.append((name, [("file", (filename, content, "text/csv"))], form, [{"method": "auto"}]))
    return out


def test_every_remedy_names_an_option_its_place_takes(client):
    checked, named, wrong = 0, 0, []
    for name, parts, form, calibrations in uploads():
        gave = set(form)
        r = client.post("/api/v1/recordings", files=parts, data=form)
        rec = r.json()
        names = [p[1][0] for p in parts]
        fields = set(UPLOAD_FIELDS[family(names, rec if r.status_code == 201 else None)])
        for m in messages(rec) + [q["detail"] for q in rec.get("questions") or []]:
            checked, named = checked + 1, named + bool(asked(m))
            wrong += [
                f"upload {name}: {w} in {m!r}" for w in wrong_remedies(m, fields=fields, command="calibrate", gave=gave)
            ]
        for s in rec.get("supports") or []:  # what each supported calibration lacks, and what would make it ready
            entry = methods.BY_NAME[s["method"]]
            checked, named = checked + 1, named + bool(asked(s["why"]))
            wrong += [
                f"supports {name}: {w} in {s['why']!r}"
                for w in wrong_remedies(s["why"], fields=fields | set(entry.options), command="calibrate", gave=gave)
            ]
            assert set(s["asks"]) <= set(asked(s["why"])), s  # what it asks for, its words name
        if r.status_code != 201:
            continue
        tried = {c["method"]: c for c in calibrations}
        tried.update(
            {s["method"]: {"method": s["method"]} for s in rec.get("supports") or [] if s["method"] not in tried}
        )
        for method, body in tried.items():
            c = client.post("/api/v1/calibrations", json={**body, "recording_id": rec["id"]})
            entry = methods.BY_NAME[method]
            place = fields | set(entry.options)
            for m in messages(c.json()):
                checked, named = checked + 1, named + bool(asked(m))
                wrong += [
                    f"{method} of {name}: {w} in {m!r}"
                    for w in wrong_remedies(m, fields=place, command=entry.command, gave=gave | set(body))
                ]
    print(f"{checked} messages checked, {named} naming a parameter")
    assert checked > 400, checked
    assert not wrong, "\n".join(wrong)


def test_the_check_catches_a_remedy_its_place_refuses():
    # Planted: what the issue found (a ULog asked for a unit; trical noise told of an option it lacked).
    flight = set(UPLOAD_FIELDS["flight"])
    assert wrong_remedies("give acc_unit or chip for the counts", fields=flight, command="calibrate", gave=set())
    assert wrong_remedies("give --sections as JSON", fields=flight, command="noise", gave=set()) == []  # no param
    assert wrong_remedies("give mag_instance as one of them", fields=flight, command="calibrate", gave=set()) == []
    assert wrong_remedies("give field_ut", fields=set(UPLOAD_FIELDS["text"]), command="noise", gave=set())


def _turned_by_hand(seconds: float = 20.0, rate: float = 100.0) -> bytes:
    """An accelerometer in g turned by hand without a rest (seeded): gravity's direction sweeps on, at about 1 g."""
    rng = np.random.default_rng(42)
    t = np.arange(int(seconds * rate)) / rate
    a, b = 0.9 * t + 0.3 * np.sin(2.1 * t), 0.6 * t + 0.4 * np.cos(1.3 * t)
    g = np.column_stack([np.sin(a) * np.cos(b), np.sin(a) * np.sin(b), np.cos(a)])
    acc = g + rng.normal(0.0, 0.004, g.shape)
    rows = "\n".join(f"{ti:.3f},{x:.5f},{y:.5f},{z:.5f}" for ti, (x, y, z) in zip(t, acc))
    return ("t,acc_x (g),acc_y (g),acc_z (g)\n" + rows + "\n").encode()


def test_an_accelerometer_that_never_rested_is_told_so_not_to_check_its_unit(client):
    # Its unit is read right (g) from the data: the cause is that it never rested, and no unit can change that.
    r = client.post("/api/v1/recordings", files={"file": ("turned.csv", _turned_by_hand(), "text/csv")})
    assert r.status_code == 201 and r.json()["units"]["acc"] == "g", r.text
    rec = r.json()
    assert [s["ready"] for s in rec["supports"]] and not any(s["ready"] for s in rec["supports"]), rec["supports"]
    c = client.post("/api/v1/calibrations", json={"method": "six_position", "recording_id": rec["id"]})
    assert c.status_code == 422, c.text
    detail = c.json()["detail"]
    assert detail.startswith("the recording has no still segments: it never rested"), detail
    assert not asked(detail), detail  # no unit, chip or counts per g to give: none would change the answer


def test_a_compass_asked_of_a_log_without_one_says_to_leave_the_choice_out(client, tmp_path):
    from tests.api.test_flight_log_temperature import warm_instances
    from tests.flight_logs import px4_file

    log = px4_file(tmp_path / "no_compass.ulg", warm_instances(44)[:1])
    r = client.post("/api/v1/recordings", files=_files([log]), data={"mag_instance": "0"})
    assert r.status_code == 422, r.text
    detail = r.json()["detail"]
    assert "holds no magnetometer" in detail and "leave mag_instance out" in detail and "as one of them" not in detail
