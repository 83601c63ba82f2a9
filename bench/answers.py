"""Every endpoint's answers on a fixed set of requests, recorded to a folder, and two recordings compared.

A refactor of the plumbing promises that no answer changes. This records what the service answers to a fixed,
deterministic list of requests, so that a recording made before the refactor and one made after it can be
compared request by request::

    PYTHONPATH=. python bench/answers.py record DIR
    PYTHONPATH=. python bench/answers.py compare DIR_A DIR_B

``record`` builds the application in process (``app.main.create_app`` with its settings read from the
environment: a fresh SQLite file and data folder in a temporary directory, no phone's door) and drives it with
FastAPI's TestClient. Each answer is written to ``DIR/<family>/<request>.<ext>`` (the body's bytes, normalised
as below), and ``DIR/index.json`` lists every request in the order sent: its name, method, address, status,
content type, ``Content-Disposition`` and file. ``compare`` reads two such folders and prints each request
whose status, content type, disposition or body differs, with a short unified diff of the body (JSON
pretty-printed); it says how many requests it compared and exits 1 when any differs, 0 when all are equal.

The requests, by family (the names in ``index.json`` say which is which):

- ``real``: every real recording of tests/data/real uploaded through POST /api/v1/recordings with the form
  fields its tests use — the corpus's cases (tests/real_corpus.py), the loose files and the folders of one
  file per pose (as tests/api/test_page_words.py and the pose files' and boards' tests send them, the unit
  menus' mistake too), the flight controllers' logs (as tests/api/test_flight_corpus_api.py,
  test_compass_flight.py and test_remedies.py send them). For each stored upload: GET of the recording (the
  API's words and the page's), then the calibrations its tests ask for, every one its answer's ``supports``
  lists as ready, and for a flight log every method a person tries (test_remedies.py's ``TRIED``).
- ``still``: still readings sent as JSON: the seed tables of Georgieva et al. (six_position, orientations,
  triangular, nonorthogonal, auto), the real still means of tests/real_recordings.py, a seeded free-pose
  session (simulations.free_poses), the apply route and the list of calibrations.
- ``sim``: seeded simulations uploaded as files: a cube24 session (simulations.cube, seed 21), a compass turn
  (simulations.magnetometer, seed 21, inline, with a given field and with the model's at a place and day), a
  still board's noise (tests/api/test_noise_api.py's log, seed 21, still and moved), a warm-up for temperature
  (tests/temperature_logs.py, seed 31), a 6-hour wrist recording for autocal (simulations.autocal, seed 11)
  and one that never rests (seed 2), a flight for the compass (tests/flight_compass_logs.py, seed 9, both
  firmwares' logs), and flight controllers' logs of six poses, a warm-up, a compass tumble and a still board
  (tests/flight_logs.py).
- ``sessions``: the guided wizard's sessions: six poses (tests/phone_poses.py, seed 6), free poses until the
  target (seed 11), the cube's 24 positions (tests/cube_phone.py, seed 1), each created, captured, solved and
  read with its token; a short link made, opened and read; a few refusals (no token, a pose done twice).
- ``bad``: the bad calibration requests of tests/api/test_bad_input.py, the upload mistakes of
  tests/api/test_units_api.py, an unreadable file, a missing field, unknown ids and formats, broken JSON.
- ``pages``: the start page, every wizard page the start page offers (and refused ones), the history, the
  calibration pages' refusals, /docs, /redoc, /openapi.json, /healthz and the 404 page.

Every stored calibration is read back: GET in the API's words and in the page's, every export format its
method offers, its ``/use`` and its page ``/c/{id}``.

Normalised (only what differs between two runs by nature; figures never are): the ids the store makes (``rec_``,
``cal_``, ``ses_`` and 32 hexadecimal digits) become ``<rec-1>``, ``<cal-1>`` … numbered per kind in the order they
first appear in the run, in bodies, addresses and file names alike (in capitals, as a C header's guard writes them,
``<CAL-1>``); a session's token (``tks_…``) ``<token-N>``; a short link's code (learnt from the answer that made it,
either case) ``<link-N>``, and that answer's QR code of it ``<qr>``; a timestamp of the store's form
(``2025-01-31T12:34:56.789Z``) that falls within the run (from its start to the end of a link's lifetime)
``<time>``; the temporary data folder ``<data-dir>``; the version in /openapi.json's ``info``. The store orders
lists by creation time to the millisecond and then by the random id, so ``record`` waits 2 ms after each request: no
two resources share a millisecond, and the lists' order is the run's. Headers beside the content type and
disposition (dates, ETags, lengths) are not kept. What would change with the day is not normalised but avoided: a
request that would take the Earth's field of the day it is sent (a flight log whose fix has no date) is given a day
(:data:`UNDATED`).

Left out, for the time or because they are not answers of the service: the static files (/static/…), the
rate limit and API keys (settings of another server), the phone's door (``trical serve`` only), PostgreSQL; a
recording has no page of its own. No request kind was left out for the time: ``record`` sends about 2 200
requests in about two minutes on this project's 2-core machine. It needs the test extras (tests/ and
simulations/ build the requests); the builders it imports from there are the request list, so a change to them
shows in ``compare`` as requests only in one recording or as a different answer.
"""

from __future__ import annotations

import argparse
import contextlib
import difflib
import io
import json
import os
import re
import sys
import tempfile
import time
from collections.abc import Iterable
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

REAL = ROOT / "tests" / "data" / "real"
FLIGHT = REAL / "flight"
PAGE = {"X-Trical-Client": "page", "X-Trical-Page": "/"}
"""The headers the pages' fetch wrapper sends: the answer's messages in the page's words (app.words)."""

CORRECTION = ("json", "c", "ardupilot", "px4", "yaml", "csv", "motioncal")
FORMATS = {
    "noise": ("kalibr", "openvins", "vins", "json", "csv", "allan_svg"),
    "temperature": ("px4", "ardupilot", "json", "temperature_svg"),
    "compass_flight": ("json", "ardupilot", "px4", "flight_svg"),
}
"""The export formats each method's calibrations offer (app/methods.py's table; any other method: CORRECTION).
Written out here so that the requests do not depend on where the refactor puts the table."""

TRIED = ("auto", "noise", "magnetometer", "compass_flight", "temperature", "cube")
"""The methods a person tries on a flight log (tests/api/test_remedies.py)."""

RAW_MENUS = {"acc_unit": "raw", "gyr_unit": "raw", "mag_unit": "raw"}
"""The unit menus' mistake the page-words test uploads every loose file with (tests/api/test_page_words.py)."""

WAIT_S = 0.002
"""Between requests: a new millisecond for every stored resource's ``created_at``."""

LINK_TTL_MIN = 60.0
"""A link's lifetime (the default TRICAL_LINK_TTL_MIN): its ``expires_at`` is still a time of the run."""

STORE_ID = re.compile(r"(?<![A-Za-z0-9])(rec|cal|ses)_[0-9a-f]{32}(?![0-9a-f])")
STORE_ID_UPPER = re.compile(r"(?<![A-Za-z0-9])(REC|CAL|SES)_[0-9A-F]{32}(?![0-9A-F])")
"""A store's id, and the same in capitals (a C header's guard: ``TRICAL_CAL_3F9C…_H``)."""
TOKEN = re.compile(r"\btks_[A-Za-z0-9_-]{32}")
STAMP = re.compile(r"\b\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z")
QR = re.compile(r'"qr"\s*:\s*"data:[^"]*"')
OPENAPI_VERSION = re.compile(r'("info"\s*:\s*\{[^{}]*?"version"\s*:\s*")[^"]*(")')
TEXT_TYPES = ("application/json", "text/", "application/yaml", "image/svg+xml", "application/problem+json")
EXTENSIONS = {
    "application/json": "json",
    "application/problem+json": "json",
    "text/html": "html",
    "text/plain": "txt",
    "text/csv": "csv",
    "text/x-c": "h",
    "application/yaml": "yaml",
    "image/svg+xml": "svg",
}


# --- normalising -------------------------------------------------------------------------------------------------


class Normaliser:
    """Stable placeholders for what differs between two runs by nature (the module's docstring says which).

    Parameters
    ----------
    started : datetime
        When the run started: a store's timestamp from then to the end of a link's lifetime is the run's.
    data_dir : str
        The run's temporary data folder.
    """

    def __init__(self, started: datetime, data_dir: str):
        self.names: dict[str, str] = {}
        self.counts: dict[str, int] = {}
        self.codes: dict[str, str] = {}
        self.earliest = started - timedelta(minutes=1)
        self.data_dir = data_dir

    def _placeholder(self, value: str, kind: str) -> str:
        """``<kind-N>`` for ``value``: the same each time, N counting the kind's values in their first order."""
        if value not in self.names:
            self.counts[kind] = self.counts.get(kind, 0) + 1
            self.names[value] = f"<{kind}-{self.counts[kind]}>"
        return self.names[value]

    def learn_link(self, code: str) -> None:
        """A short link's code, from the answer that made it: replaced wherever it appears, in either case."""
        placeholder = self._placeholder(code.upper(), "link")
        self.codes[code.upper()] = placeholder
        self.codes[code.lower()] = placeholder

    def _stamp(self, match: re.Match) -> str:
        when = datetime.strptime(match.group(0), "%Y-%m-%dT%H:%M:%S.%fZ").replace(tzinfo=UTC)
        latest = datetime.now(UTC) + timedelta(minutes=LINK_TTL_MIN + 1)
        return "<time>" if self.earliest <= when <= latest else match.group(0)

    def text(self, text: str) -> str:
        """``text`` with the run's ids, tokens, link codes, timestamps and data folder replaced."""
        text = STORE_ID.sub(lambda m: self._placeholder(m.group(0), m.group(1)), text)
        text = STORE_ID_UPPER.sub(lambda m: self._placeholder(m.group(0).lower(), m.group(1).lower()).upper(), text)
        text = TOKEN.sub(lambda m: self._placeholder(m.group(0), "token"), text)
        for code, placeholder in self.codes.items():
            text = text.replace(code, placeholder)
        text = STAMP.sub(self._stamp, text)
        return text.replace(self.data_dir, "<data-dir>")


def is_text(content_type: str) -> bool:
    """Whether an answer of ``content_type`` is text (normalised, diffed by lines) rather than bytes."""
    return content_type.startswith(TEXT_TYPES)


def extension(content_type: str) -> str:
    """The recorded file's extension for an answer of ``content_type``."""
    return EXTENSIONS.get(content_type.split(";")[0].strip(), "bin")


def slug(name: str) -> str:
    """A request's name as a file name: letters, digits, dots, dashes and underscores."""
    out = re.sub(r"[^A-Za-z0-9._+-]+", "-", name).strip("-")
    return out[:150] or "request"


# --- recording ---------------------------------------------------------------------------------------------------


class Recorder:
    """Sends the requests through a TestClient and writes each answer, normalised, under ``out``.

    Parameters
    ----------
    client : fastapi.testclient.TestClient
        The application's client.
    out : pathlib.Path
        The recording's folder (created).
    normaliser : Normaliser
        The run's placeholders.
    """

    def __init__(self, client, out: Path, normaliser: Normaliser):
        self.client = client
        self.out = out
        self.norm = normaliser
        self.index: list[dict[str, Any]] = []
        self.files: set[str] = set()
        self.stored: dict[str, list[str]] = {}
        """The ids of the stored calibrations by method, in the order made."""

    def send(self, family: str, name: str, method: str, url: str, **kw):
        """One request: sent, its answer written as ``family/name``; returns the response (raw, for the ids)."""
        response = self.client.request(method, url, **kw)
        time.sleep(WAIT_S)
        if method == "POST" and url.endswith("/links") and response.status_code == 201:
            self.norm.learn_link(response.json()["code"])
        content_type = response.headers.get("content-type", "")
        body = response.content
        if is_text(content_type):
            text = self.norm.text(body.decode("utf-8"))
            if method == "POST" and url.endswith("/links"):
                text = QR.sub('"qr":"<qr>"', text)
            if url.startswith("/openapi.json"):
                text = OPENAPI_VERSION.sub(r"\1<version>\2", text, count=1)
            body = text.encode("utf-8")
        file = f"{family}/{slug(name)}.{extension(content_type)}"
        if file in self.files:
            raise ValueError(f"two requests named {family}/{name}")
        self.files.add(file)
        (self.out / family).mkdir(parents=True, exist_ok=True)
        (self.out / file).write_bytes(body)
        query = kw.get("params")
        address = url + ("?" + "&".join(f"{k}={v}" for k, v in query.items()) if query else "")
        self.index.append(
            {
                "name": f"{family}/{name}",
                "method": method,
                "url": self.norm.text(address),
                "status": response.status_code,
                "content_type": content_type,
                "content_disposition": self.norm.text(response.headers.get("content-disposition", "")),
                "file": file,
            }
        )
        return response

    def write_index(self) -> None:
        """``index.json``: every request in the order sent, with its status, content type and file."""
        (self.out / "index.json").write_text(
            json.dumps({"count": len(self.index), "requests": self.index}, indent=1, ensure_ascii=False) + "\n",
            encoding="utf-8",
        )


def answer(response) -> dict:
    """A response's JSON object, or an empty one (an answer that is not one: a failure the recording shows)."""
    try:
        body = response.json()
    except ValueError:
        return {}
    return body if isinstance(body, dict) else {}


def read_calibration(rec: Recorder, family: str, name: str, body: dict, headers: dict | None = None) -> None:
    """A stored calibration read back: GET in both readers' words, every export its method offers, its use and
    its page."""
    cal, method = body["id"], body.get("method", "")
    base = f"/api/v1/calibrations/{cal}"
    rec.send(family, f"{name} - get", "GET", base, headers=headers)
    rec.send(family, f"{name} - get page words", "GET", base, headers={**PAGE, **(headers or {})})
    for fmt in FORMATS.get(method, CORRECTION):
        rec.send(family, f"{name} - export {fmt}", "GET", f"{base}/export", params={"format": fmt}, headers=headers)
    rec.send(family, f"{name} - use", "GET", f"{base}/use", headers=headers)
    rec.send(family, f"{name} - page", "GET", f"/c/{cal}")


def calibrate(rec: Recorder, family: str, name: str, body: dict, headers: dict | None = None) -> dict | None:
    """POST a calibration and, when stored, read it back; returns the stored calibration."""
    r = rec.send(family, name, "POST", "/api/v1/calibrations", json=body, headers=headers)
    if r.status_code != 201:
        return None
    rec.stored.setdefault(r.json().get("method", ""), []).append(r.json()["id"])
    read_calibration(rec, family, name, r.json(), headers)
    return r.json()


def label(body: dict) -> str:
    """A calibration request in a few words: its method and its other fields."""
    extra = " ".join(f"{k}={v}" for k, v in sorted(body.items()) if k not in ("method", "recording_id"))
    return re.sub(r"[\[\]'\"]", "", f"{body['method']} {extra}".strip())


def unique(bodies: Iterable[dict]) -> list[dict]:
    """The calibration requests once each, in their first order."""
    out: list[dict] = []
    for body in bodies:
        if body not in out:
            out.append(body)
    return out


def upload_and_calibrate(
    rec: Recorder, family: str, name: str, parts: list, form: dict, asked: Iterable[dict] = ()
) -> str | None:
    """Upload a recording; read it back; calibrate it as ``asked``, then by every method its answer lists as ready.
    Returns the recording's id when stored."""
    r = rec.send(family, f"{name} - upload", "POST", "/api/v1/recordings", files=parts, data=form)
    if r.status_code != 201:
        return None
    recording = r.json()
    rid = recording["id"]
    rec.send(family, f"{name} - recording", "GET", f"/api/v1/recordings/{rid}")
    rec.send(family, f"{name} - recording page words", "GET", f"/api/v1/recordings/{rid}", headers=PAGE)
    ready = [{"method": s["method"]} for s in recording.get("supports") or [] if s.get("ready")]
    for body in unique([*asked, *ready]):
        calibrate(rec, family, f"{name} - {label(body)}", {**body, "recording_id": rid})
    return rid


# --- the requests: real recordings ---------------------------------------------------------------------------------


def file_parts(paths: Iterable[Path], content_type: str = "text/csv") -> list:
    """The multipart ``file`` parts of ``paths``, in order, as the page's file chooser sends them."""
    return [("file", (p.name, p.read_bytes(), content_type)) for p in paths]


def loose_groups() -> list[tuple[str, list[Path]]]:
    """The real recordings outside the corpus: each loose CSV, and each folder of one file per pose (sorted), as
    tests/api/test_page_words.py uploads them."""
    loose = sorted(p for p in REAL.rglob("*.csv") if "corpus" not in p.parts and not p.parent.name.endswith("files"))
    groups = [(p.name, [p]) for p in loose]
    groups += [
        (d.name, sorted(d.glob("*.csv"))) for d in sorted(REAL.iterdir()) if d.is_dir() and d.name.endswith("files")
    ]
    return groups


def real_test_forms() -> list[tuple[str, list, dict, list[dict]]]:
    """The uploads of real files with the form fields their own tests give (name, parts, form, calibrations)."""
    poses = REAL / "mpu6050_pose_files"
    esp32 = REAL / "mpu6050_esp32_pose_files"
    pose_order = ("x_axis_pos", "x_axis_neg", "y_axis_pos", "y_axis_neg", "z_axis_pos", "z_axis_neg")
    esp32_order = ("posX", "negX", "posY", "negY", "posZ", "negZ")
    still = REAL / "mpu6050_session2_still_30s.csv"
    turn = REAL / "magnetometer" / "tomisuarez2_qmc5883l_turn_every10.csv"
    return [
        (
            "mpu6050_pose_files m-s2",
            file_parts(poses / f"{s}.csv" for s in pose_order),
            {"acc_unit": "m/s^2"},
            [{"method": "auto"}, {"method": "six_position"}, {"method": "noise", "sensors": ["acc"]}],
        ),
        (
            "mpu6050_esp32_pose_files counts",
            file_parts(esp32 / f"imu_data_{s}.csv" for s in esp32_order),
            {"acc_unit": "raw", "lsb_per_g": "16384"},
            [{"method": "six_position"}],
        ),
        (
            "mpu6050_session2_still_30s columns",
            file_parts([still]),
            {"columns": "acc_x,acc_y,acc_z", "acc_unit": "raw", "lsb_per_g": "16384", "sampling_rate_hz": "100"},
            [{"method": "noise"}],
        ),
        (
            "tomisuarez2_qmc5883l columns",
            file_parts([turn]),
            {"columns": "mag_x,mag_y,mag_z", "mag_unit": "raw", "sampling_rate_hz": "5"},
            [{"method": "magnetometer"}],
        ),
    ]


FLIGHT_ASKED = {
    "log171.bin": [{"method": "compass_flight", "mag_instance": k} for k in range(3)]
    + [{"method": "compass_flight", "mag_instance": 0, "window": "all"}],
    "px4_1.9_esc_status_log.ulg": [{"method": "compass_flight", "mag_instance": 0}],
    "sample_appended_multiple.ulg": [
        {"method": "compass_flight", "latitude_deg": 47.4, "longitude_deg": 8.5, "date": "2017-01-01"}
    ],
    "arduplane_4.2_center_0003.bin": [{"method": "compass_flight", "date": "2025-01-03"}],
    "arducopter_3.5_rtl_landing_dataflashlog.bin": [{"method": "compass_flight", "mag_instance": 1}],
    "ardusub_4.1_small.bin": [
        {
            "method": "compass_flight",
            "mag_instance": 1,
            "latitude_deg": 48.386,
            "longitude_deg": -124.631,
            "date": "2023-05-04",
        }
    ],
}
"""The calibrations tests/api/test_compass_flight.py and test_superseded.py ask of the real flight logs."""


UNDATED = {"arduplane_4.2_center_0003.bin": {"date": "2025-01-03"}}
"""A log whose GPS fix has no date: the Earth's field there would be the model's of the day the request is sent
(the answer would change with the day), so the methods that read the model are given the day
(test_compass_flight.py gives this one to the compass from the flight)."""

DATED_METHODS = ("auto", "magnetometer", "compass_flight")
"""The methods that take a ``date`` for the Earth's field."""


def tried_on(log: str) -> list[dict]:
    """The methods a person tries on a flight log, with the day where the log lacks it (:data:`UNDATED`)."""
    return [{"method": m, **(UNDATED.get(log, {}) if m in DATED_METHODS else {})} for m in TRIED]


def flight_uploads() -> list[tuple[str, list, dict, list[dict]]]:
    """The real flight controllers' logs: each as it is, with the methods a person tries and those its tests ask;
    log171.bin also with its second IMU and each compass chosen at the upload (test_flight_corpus_api.py,
    test_compass_flight.py)."""
    logs = sorted(FLIGHT.glob("*.ulg")) + sorted(FLIGHT.glob("*.bin"))
    out = [
        (
            p.name,
            file_parts([p], "application/octet-stream"),
            {},
            [*FLIGHT_ASKED.get(p.name, []), *tried_on(p.name)],
        )
        for p in logs
    ]
    log171 = [FLIGHT / "log171.bin"]
    out.append(
        (
            "log171.bin instance 1",
            file_parts(log171, "application/octet-stream"),
            {"instance": "1", "mag_instance": "1"},
            [],
        )
    )
    for k in range(3):
        out.append(
            (
                f"log171.bin compass {k}",
                file_parts(log171, "application/octet-stream"),
                {"mag_instance": str(k)},
                [{"method": "magnetometer"}],
            )
        )
    return out


def real_family(rec: Recorder) -> None:
    """Every real recording uploaded with its tests' form fields, and calibrated (the module's docstring)."""
    from tests.real_corpus import cases

    for case in cases():
        asked = [case.spec["calibrate"]] if "calibrate" in case.spec else []
        upload_and_calibrate(rec, "real", f"corpus {case.name}", case.upload_parts(), case.form, asked)
    tried = [{"method": m} for m in ("auto", "noise", "magnetometer", "temperature")]
    for name, paths in loose_groups():
        upload_and_calibrate(rec, "real", name, file_parts(paths), {}, tried)
        upload_and_calibrate(rec, "real", f"{name} raw menus", file_parts(paths), RAW_MENUS, [{"method": "auto"}])
    for name, parts, form, asked in real_test_forms() + flight_uploads():
        upload_and_calibrate(rec, "real", name, parts, form, asked)


# --- the requests: still readings as JSON --------------------------------------------------------------------------


def real_means_body(recording, method: str) -> dict:
    """A real recording's still means as a calibration request (tests/api/test_real_recordings.py's ``post``)."""
    body: dict = {"method": method, "unit": recording.unit}
    if recording.unit != "g":
        body["gravity"] = recording.gravity
    if recording.ups is None:
        body["means"] = np.asarray(recording.means).tolist()
    else:
        body["readings"] = [{"mean": list(m), "up": u} for m, u in zip(recording.means.tolist(), recording.ups)]
    return body


def still_family(rec: Recorder) -> None:
    """Still readings sent as JSON: the seed tables, the real still means, a seeded free-pose session."""
    from simulations.free_poses import free_pose_session
    from tests.api.test_calibrations import CANONICAL, GT_ORDER, six_request
    from tests.conftest import seed_table
    from tests.real_recordings import mpu9250_sessions, recordings

    t1, t3 = seed_table(1), seed_table(3)
    table1 = calibrate(
        rec, "still", "table1 six_position", six_request(t1, CANONICAL, holdout=t1.tolist(), device_id="huawei")
    )
    calibrate(rec, "still", "table3 six_position", six_request(t3, GT_ORDER, holdout=t3.tolist()))
    calibrate(rec, "still", "table1 orientations", {**six_request(t1, CANONICAL), "method": "orientations"})
    at_place = {k: v for k, v in six_request(t1, CANONICAL, device_id="huawei").items() if k != "gravity"}
    calibrate(rec, "still", "table1 six_position at a place", {**at_place, "latitude_deg": 45.0, "height_m": 200.0})
    for recording in recordings():
        methods = ("six_position", "orientations") if recording.ups else ("triangular", "nonorthogonal", "auto")
        for method in methods:
            calibrate(rec, "still", f"{recording.name} {method}", real_means_body(recording, method))
    readings = [{"up": u, "mean": m.tolist()} for ups, means in mpu9250_sessions().values() for u, m in zip(ups, means)]
    calibrate(
        rec, "still", "mpu9250 24 readings orientations", {"method": "orientations", "unit": "g", "readings": readings}
    )
    _, means = free_pose_session(np.random.default_rng(5), 14)
    for method, extra in (
        ("triangular", {}),
        ("auto", {}),
        ("nonorthogonal", {}),
        *(("triangular", {"solver": s}) for s in ("gradient", "fixed16", "fixed32")),
    ):
        body = {"method": method, **extra}
        calibrate(rec, "still", f"free poses seed 5 {label(body)}", {**body, "unit": "g", "means": means.tolist()})
    if table1 is not None:
        url = f"/api/v1/calibrations/{table1['id']}/apply"
        rec.send("still", "table1 six_position - apply", "POST", url, json={"samples": t1[:3].tolist()})
        rec.send("still", "table1 six_position - apply a bad sample", "POST", url, json={"samples": [[1, 2]]})
    rec.send("still", "list of huawei", "GET", "/api/v1/calibrations", params={"device_id": "huawei"})
    rec.send(
        "still",
        "list of huawei page words",
        "GET",
        "/api/v1/calibrations",
        params={"device_id": "huawei"},
        headers=PAGE,
    )


# --- the requests: seeded simulations ------------------------------------------------------------------------------


def npy_bytes(x: np.ndarray) -> bytes:
    """``x`` as the bytes of a .npy file."""
    buf = io.BytesIO()
    np.save(buf, x)
    return buf.getvalue()


def sim_files(rec: Recorder) -> None:
    """Seeded simulations uploaded as text files: the cube, the noise, the temperature, autocal's .npy."""
    from simulations.autocal import simulate_recording
    from simulations.cube import FIELD_UT, simulate_session
    from tests.api.test_cube import session_csv
    from tests.api.test_noise_api import _csv as noise_csv
    from tests.temperature_logs import warm_up_csv

    cube = simulate_session(np.random.default_rng(21), sampling_rate_hz=100.0)
    cube_form = {"sampling_rate_hz": "100.0", "acc_unit": "raw", "gyr_unit": "raw", "mag_unit": "raw"}
    asked = [{"method": "cube", "protocol": "cube24", "field_ut": FIELD_UT}]
    upload_and_calibrate(
        rec, "sim", "cube24 seed 21", [("file", ("cube.csv", session_csv(cube), "text/csv"))], cube_form, asked
    )
    for moved in (False, True):
        parts = [("file", ("still.csv", noise_csv(moved), "text/csv"))]
        upload_and_calibrate(rec, "sim", f"noise seed 21{' moved' if moved else ''}", parts, {}, [{"method": "noise"}])
    warm = warm_up_csv(31, temperature_header="temp_c", acc_in_g=True, duration_s=900, sampling_rate_hz=20)
    asked = [{"method": "temperature", "device_id": "fc1"}]
    rid = upload_and_calibrate(rec, "sim", "warm-up seed 31", [("file", ("warm.csv", warm, "text/csv"))], {}, asked)
    autocal_form = {"sampling_rate_hz": "10.0", "acc_unit": "g"}
    wrist, _ = simulate_recording(
        np.random.default_rng(11),
        duration_s=6 * 3600,
        sampling_rate_hz=10.0,
        rest_median_s=30,
        move_median_s=10,
        posture_fraction=0.3,
    )
    moving, _ = simulate_recording(np.random.default_rng(2), duration_s=600, sampling_rate_hz=10.0, rest_median_s=0)
    for name, x in (("wrist 6 h seed 11", wrist), ("never rests seed 2", moving)):
        parts = [("file", (f"{name.split()[0]}.npy", npy_bytes(x), "application/octet-stream"))]
        upload_and_calibrate(rec, "sim", f"autocal {name}", parts, autocal_form, [{"method": "autocal"}])
    if rid is not None and rec.stored.get("temperature"):  # applied without temperatures: refused
        cal = rec.stored["temperature"][-1]
        rec.send(
            "sim",
            "warm-up seed 31 - apply without temperature",
            "POST",
            f"/api/v1/calibrations/{cal}/apply",
            json={"samples": [[0, 0, 9.8]]},
        )


def sim_compass(rec: Recorder) -> None:
    """A seeded compass turn sent inline: with a given field, and with the model's at a place and day."""
    from simulations.magnetometer import simulate_session

    m, _, _ = simulate_session(21, n=300, hard_iron_ut=80.0)
    given = {"method": "magnetometer", "mag": m.tolist(), "field_ut": 48.0, "device_id": "phone-c"}
    cal = calibrate(rec, "sim", "magnetometer seed 21 field given", given)
    place = {
        "method": "magnetometer",
        "mag": m.tolist(),
        "latitude_deg": 47.4,
        "longitude_deg": 8.5,
        "date": "2025-06-01",
    }
    calibrate(rec, "sim", "magnetometer seed 21 at a place", place)
    if cal is not None:
        samples = {"samples": m[:3].tolist(), "sensor": "mag"}
        rec.send(
            "sim",
            "magnetometer seed 21 field given - apply",
            "POST",
            f"/api/v1/calibrations/{cal['id']}/apply",
            json=samples,
        )


def sim_flight_logs(rec: Recorder, folder: Path) -> None:
    """Seeded flight controllers' logs written by tests/flight_logs.py and tests/flight_compass_logs.py."""
    from tests.api.test_flight_log_temperature import warm_instances
    from tests.flight_compass_logs import seeded_flight, write_flight_compass_logs
    from tests.flight_logs import ardupilot_file, compass_tumble, imu_instances, px4_file, still_board

    bin_path, ulg_path = write_flight_compass_logs(folder, seeded_flight(9, orientation=12))
    for path in (bin_path, ulg_path):
        parts = file_parts([path], "application/octet-stream")
        upload_and_calibrate(
            rec, "sim", f"flight compass seed 9 {path.suffix}", parts, {}, [{"method": "compass_flight"}]
        )
    tumble = compass_tumble(5)
    for write, suffix in ((px4_file, ".ulg"), (ardupilot_file, ".bin")):
        logs = (
            (
                "six poses seed 3",
                write(folder / f"six{suffix}", imu_instances(3)),
                {"instance": "1"},
                [{"method": "six_position"}],
            ),
            (
                "warm-up seed 41",
                write(folder / f"warm{suffix}", warm_instances(41)),
                {"instance": "1"},
                [{"method": "temperature"}],
            ),
            (
                "tumble seed 5",
                write(folder / f"tumble{suffix}", tumble[0], tumble[1]),
                {"mag_instance": "1"},
                [{"method": "magnetometer", "field_ut": 48.0}],
            ),
        )
        for name, path, form, asked in logs:
            upload_and_calibrate(
                rec, "sim", f"{name} {suffix}", file_parts([path], "application/octet-stream"), form, asked
            )
    still = px4_file(folder / "still.ulg", still_board(9))
    upload_and_calibrate(
        rec,
        "sim",
        "still board seed 9 .ulg",
        file_parts([still], "application/octet-stream"),
        {"instance": "1"},
        [{"method": "noise"}],
    )


def sim_family(rec: Recorder, folder: Path) -> None:
    """The seeded simulations (the module's docstring)."""
    sim_files(rec)
    sim_compass(rec)
    sim_flight_logs(rec, folder)


# --- the requests: guided sessions and links -----------------------------------------------------------------------


def bearer(token: str) -> dict:
    """The header that sends ``token``."""
    return {"Authorization": f"Bearer {token}"}


def session_flow(rec: Recorder, name: str, fields: dict, captures: Iterable[dict]) -> tuple[dict, dict | None]:
    """A session created, each capture posted until the target is reached (free), solved and read with its token;
    returns the session and its calibration."""
    created = rec.send("sessions", f"{name} - create", "POST", "/api/v1/sessions", json=fields)
    s = answer(created)
    if created.status_code != 201:
        return s, None
    auth = bearer(s["token"])
    url = f"/api/v1/sessions/{s['id']}"
    for k, body in enumerate(captures, start=1):
        captured = answer(
            rec.send("sessions", f"{name} - capture {k:02d}", "POST", f"{url}/captures", json=body, headers=auth)
        )
        progress = (captured.get("session") or {}).get("progress") or {}
        if progress.get("target_reached"):
            break
    rec.send("sessions", f"{name} - session", "GET", url, headers=auth)
    solved = rec.send("sessions", f"{name} - solve", "POST", f"{url}/solve", headers=auth)
    rec.send("sessions", f"{name} - session solved", "GET", url, headers=auth)
    rec.send("sessions", f"{name} - session page words", "GET", url, headers={**auth, **PAGE})
    if solved.status_code != 201:
        return s, None
    read_calibration(rec, "sessions", f"{name} - calibration", solved.json(), auth)
    return s, solved.json()


def link_flow(rec: Recorder, s: dict, cal: dict) -> None:
    """A short link of a session's calibration: made with its token, opened, read with the link, its page."""
    made = rec.send(
        "sessions", "six - link", "POST", f"/api/v1/calibrations/{cal['id']}/links", headers=bearer(s["token"])
    )
    if made.status_code != 201:
        return
    code = made.json()["code"]
    opened = answer(rec.send("sessions", "six - link opened", "GET", f"/api/v1/links/{code.lower()}"))
    if "token" not in opened:
        return
    as_link = bearer(opened["token"])
    rec.send("sessions", "six - read with the link", "GET", f"/api/v1/calibrations/{cal['id']}", headers=as_link)
    rec.send(
        "sessions",
        "six - export c with the link",
        "GET",
        f"/api/v1/calibrations/{cal['id']}/export",
        params={"format": "c"},
        headers=as_link,
    )
    rec.send("sessions", "six - list with the link", "GET", "/api/v1/calibrations", headers=as_link)
    rec.send("sessions", "six - a link of the link", "POST", f"/api/v1/calibrations/{cal['id']}/links", headers=as_link)
    rec.send("sessions", "six - link page", "GET", f"/s/{code}")


def sessions_family(rec: Recorder) -> None:
    """The guided sessions: six poses, free poses, the cube's 24 positions; a link; a few refusals."""
    from tests.api.test_free_sessions import UPS
    from tests.cube_phone import phone_cube
    from tests.phone_poses import direction_samples, pose_samples

    rng = np.random.default_rng(6)
    six = [pose_samples(label, rng) for label in ("+z", "-x", "+y", "-z", "+x", "-y")]
    s, cal = session_flow(rec, "six", {"protocol": "six", "capture_s": 5, "device_id": "phone-1"}, six)
    if cal is not None:
        rec.send("sessions", "six - calibration without the token", "GET", f"/api/v1/calibrations/{cal['id']}")
        link_flow(rec, s, cal)
    if "token" in s:
        again, url = pose_samples("+z", np.random.default_rng(7)), f"/api/v1/sessions/{s['id']}/captures"
        rec.send("sessions", "six - a pose captured twice", "POST", url, json=again, headers=bearer(s["token"]))
        rec.send("sessions", "six - capture without a token", "POST", url, json=again)
    rng = np.random.default_rng(11)
    free = (dict(direction_samples(up, rng, noise=0.05)) for up in UPS)
    session_flow(rec, "free", {"protocol": "free", "capture_s": 5}, free)
    phone = phone_cube(1)
    session_flow(rec, "cube24", {"protocol": "cube24"}, (phone.capture(k) for k in range(1, 25)))
    rec.send("sessions", "unknown protocol", "POST", "/api/v1/sessions", json={"protocol": "dance"})


# --- the requests: bad input and the pages -------------------------------------------------------------------------


def bad_family(rec: Recorder) -> None:
    """A 4xx each: the bad calibration requests and upload mistakes of the API's tests, and a few more."""
    from tests.api import test_bad_input, test_units_api

    for payload, _status, fragment in test_bad_input.test_bad_calibration_requests.pytestmark[0].args[1]:
        rec.send("bad", f"calibration {fragment}", "POST", "/api/v1/calibrations", json=payload)
    for name, (content, form) in test_units_api.UPLOADS.items():
        form = dict(form)
        filename = form.pop("filename", "log.csv")
        parts = [("file", (filename, content, "text/csv"))]
        rec.send(
            "bad",
            f"upload {name}",
            "POST",
            "/api/v1/recordings",
            files=parts,
            data={k: str(v) for k, v in form.items()},
        )
    json_type = {"Content-Type": "application/json"}
    for name, text in (
        ("broken JSON", '{"method": "six_position", "readings": ['),
        ("empty body", ""),
        ("NaN", '{"method": "six_position", "readings": [{"up": "-x", "mean": [NaN, 0, 0]}]}'),
    ):
        rec.send("bad", f"calibration {name}", "POST", "/api/v1/calibrations", content=text, headers=json_type)
    pdf = [("file", ("scan.pdf", b"%PDF-1.4\n\x00\x01\x02\xff" * 50, "application/pdf"))]
    rec.send("bad", "upload an unreadable file", "POST", "/api/v1/recordings", files=pdf)
    rec.send("bad", "upload without a file", "POST", "/api/v1/recordings", data={"acc_unit": "g"})
    rec.send(
        "bad",
        "upload with an unknown unit",
        "POST",
        "/api/v1/recordings",
        files=[("file", ("log.csv", b"t,ax,ay,az\n0,0,0,1\n", "text/csv"))],
        data={"acc_unit": "furlong"},
    )
    rec.send("bad", "calibration of an unknown method", "POST", "/api/v1/calibrations", json={"method": "bogus"})
    rec.send("bad", "noise without its recording", "POST", "/api/v1/calibrations", json={"method": "noise"})
    rec.send("bad", "unknown calibration", "GET", "/api/v1/calibrations/cal_missing")
    rec.send("bad", "unknown recording", "GET", "/api/v1/recordings/rec_missing")
    rec.send("bad", "unknown session", "GET", "/api/v1/sessions/ses_missing")
    rec.send("bad", "unknown link", "GET", "/api/v1/links/ABCDEFGHJK")
    rec.send("bad", "list with a bad limit", "GET", "/api/v1/calibrations", params={"limit": "0"})


def refused_exports(rec: Recorder) -> None:
    """Exports a calibration's method does not offer, and an unknown format."""
    for method, fmt in (
        ("six_position", "allan_svg"),
        ("six_position", "docx"),
        ("noise", "c"),
        ("temperature", "c"),
        ("compass_flight", "c"),
    ):
        for cal in rec.stored.get(method, [])[:1]:
            rec.send(
                "bad",
                f"export {fmt} of a {method}",
                "GET",
                f"/api/v1/calibrations/{cal}/export",
                params={"format": fmt},
            )


WIZARD = [
    {},
    *({"protocol": p, "source": s} for s in ("phone", "board") for p in ("six", "cube24", "free", "compass", "noise")),
    {"protocol": "six", "capture_s": "10"},
    {"protocol": "six", "capture_s": "99"},
    {"protocol": "dance"},
    {"protocol": "six", "source": "toaster"},
]
"""The wizard's addresses: every source and protocol (a phone has no noise page: refused), and refused ones."""


def pages_family(rec: Recorder) -> None:
    """The pages, the documentation and the health check; last, the whole list of calibrations and the earlier
    ones each superseded."""
    html = {"Accept": "text/html"}
    rec.send("pages", "start page", "GET", "/")
    for query in WIZARD:
        name = "wizard " + " ".join(f"{k}={v}" for k, v in query.items())
        rec.send("pages", name.strip(), "GET", "/wizard", params=query or None)
    rec.send("pages", "history", "GET", "/history")
    rec.send("pages", "history of huawei", "GET", "/history", params={"device": "huawei"})
    rec.send("pages", "latest of huawei", "GET", "/c/latest", params={"device": "huawei"})
    rec.send("pages", "latest without a device", "GET", "/c/latest")
    rec.send("pages", "calibration page of no id", "GET", "/c/not-an-id")
    rec.send("pages", "link page of no code", "GET", "/s/nope")
    rec.send("pages", "unknown page", "GET", "/nowhere", headers=html)
    rec.send("pages", "unknown address for the API", "GET", "/api/v1/nowhere")
    for path in ("/docs", "/redoc", "/openapi.json", "/healthz"):
        rec.send("pages", path.strip("/").split(".")[0], "GET", path)
    everything = answer(rec.send("pages", "list of all", "GET", "/api/v1/calibrations", params={"limit": "1000"}))
    for item in everything.get("items", []):
        if item.get("earlier"):
            rec.send(
                "pages",
                f"superseded by {rec.norm.text(item['id'])}",
                "GET",
                "/api/v1/calibrations",
                params={"superseded_by": item["id"]},
            )


# --- record --------------------------------------------------------------------------------------------------------


def record(out: Path) -> int:
    """Start the application on a fresh store, send every family's requests and write their answers to ``out``."""
    if out.exists() and any(out.iterdir()):
        print(f"{out} is not empty: record into a new folder", file=sys.stderr)
        return 2
    out.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="trical-answers-") as tmp:
        data = Path(tmp) / "data"
        os.environ.update(
            TRICAL_DATABASE_URL=f"sqlite:///{data / 'trical.db'}",
            TRICAL_DATA_DIR=str(data),
            TRICAL_PHONE_PORT="0",
        )
        for variable in ("TRICAL_API_KEYS", "TRICAL_RATE_LIMIT_PER_MINUTE", "TRICAL_PUBLIC_URL", "TRICAL_LINK_TTL_MIN"):
            os.environ.pop(variable, None)
        from fastapi.testclient import TestClient

        from app.main import create_app

        normaliser = Normaliser(datetime.now(UTC), tmp)
        with TestClient(create_app(), raise_server_exceptions=False) as client:
            rec = Recorder(client, out, normaliser)
            counts = {}
            for family, run in (
                ("real", real_family),
                ("still", still_family),
                ("sim", lambda r: sim_family(r, Path(tmp))),
                ("sessions", sessions_family),
                ("bad", lambda r: (bad_family(r), refused_exports(r))),
                ("pages", pages_family),
            ):
                before, began = len(rec.index), time.perf_counter()
                run(rec)
                counts[family] = len(rec.index) - before
                print(f"{family}: {counts[family]} requests, {time.perf_counter() - began:.0f} s", flush=True)
            rec.write_index()
    seconds = time.perf_counter() - started
    failed = [e["name"] for e in rec.index if e["status"] >= 500]
    print(
        f"recorded {len(rec.index)} requests in {seconds:.0f} s to {out}: "
        + ", ".join(f"{k} {v}" for k, v in counts.items())
    )
    for name in failed:
        print(f"  answered 5xx: {name}")
    return 0


# --- compare -------------------------------------------------------------------------------------------------------


def load(folder: Path) -> dict[str, dict]:
    """A recording's index by request name."""
    index = json.loads((folder / "index.json").read_text(encoding="utf-8"))
    return {entry["name"]: entry for entry in index["requests"]}


def readable(folder: Path, entry: dict) -> list[str]:
    """A recorded body as lines to diff: JSON pretty-printed, text as it is, other bytes as their size."""
    body = (folder / entry["file"]).read_bytes()
    if not is_text(entry["content_type"]):
        return [f"<{len(body)} bytes>"]
    text = body.decode("utf-8")
    if "json" in entry["content_type"]:
        with contextlib.suppress(ValueError):  # a body that says it is JSON and is not: shown as it is
            text = json.dumps(json.loads(text), indent=1, ensure_ascii=False)
    return text.splitlines()


def differences(a: Path, b: Path, ea: dict, eb: dict, lines: int) -> list[str]:
    """How two recordings' answers to one request differ (empty when they are equal)."""
    out = [
        f"{key}: {ea[key]!r} -> {eb[key]!r}"
        for key in ("status", "content_type", "content_disposition")
        if ea[key] != eb[key]
    ]
    if (a / ea["file"]).read_bytes() != (b / eb["file"]).read_bytes():
        diff = list(
            difflib.unified_diff(
                readable(a, ea), readable(b, eb), str(a / ea["file"]), str(b / eb["file"]), n=2, lineterm=""
            )
        )
        if not diff:
            diff = ["the bodies' bytes differ, their JSON does not (spacing or escapes)"]
        out += diff[:lines] + ([f"… {len(diff) - lines} more lines of diff"] if len(diff) > lines else [])
    return out


def compare(a: Path, b: Path, lines: int = 40) -> int:
    """Print each request whose answer differs between two recordings; 1 when any differs, else 0."""
    ia, ib = load(a), load(b)
    differing = []
    for name in [*ia, *(n for n in ib if n not in ia)]:
        if name not in ib or name not in ia:
            differing.append(name)
            print(f"=== {name}: only in {a if name in ia else b}")
            continue
        found = differences(a, b, ia[name], ib[name], lines)
        if found:
            differing.append(name)
            print(f"=== {name}")
            print("\n".join(found))
    both = len(set(ia) & set(ib))
    print(f"compared {both} requests ({len(ia)} in {a}, {len(ib)} in {b}): {len(differing)} differ")
    families: dict[str, int] = {}
    for name in differing:
        families[name.split("/")[0]] = families.get(name.split("/")[0], 0) + 1
    if families:
        print("differing by family: " + ", ".join(f"{k} {v}" for k, v in families.items()))
    return 1 if differing else 0


def main(argv: list[str] | None = None) -> int:
    """``record DIR`` or ``compare DIR_A DIR_B``; returns the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    commands = parser.add_subparsers(dest="command", required=True)
    rec = commands.add_parser("record", help="send the requests and write their answers to DIR")
    rec.add_argument("dir", type=Path)
    cmp = commands.add_parser("compare", help="compare two recordings request by request")
    cmp.add_argument("a", type=Path)
    cmp.add_argument("b", type=Path)
    cmp.add_argument("--lines", type=int, default=40, help="at most this many lines of diff per request")
    args = parser.parse_args(argv)
    if args.command == "record":
        return record(args.dir)
    return compare(args.a, args.b, args.lines)


if __name__ == "__main__":
    sys.exit(main())
