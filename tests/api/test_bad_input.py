"""Bad input gets a 4xx whose message names the problem; nothing stored is lost; never a 500."""

from __future__ import annotations

import pytest

from tests.api.test_calibrations import CANONICAL, six_request
from tests.conftest import seed_table


def post_raw(client, text):
    return client.post("/api/v1/calibrations", content=text, headers={"Content-Type": "application/json"})


def readings(rows, labels=CANONICAL):
    return {"method": "six_position", "readings": [{"up": u, "mean": m} for u, m in zip(labels, rows)]}


GOOD = seed_table(1)[:6].tolist()


@pytest.mark.parametrize(
    "payload, status, fragment",
    [
        (readings([[1.0, 2.0]] + GOOD[1:]), 422, "readings[0].mean"),
        (readings(GOOD[:5]), 422, "exactly 6 readings"),
        (readings(GOOD, CANONICAL[:5] + ["+w"]), 422, "readings[5].up"),
        (readings(GOOD, CANONICAL[:5] + ["-z"]), 422, "-z is given more than once and +z is missing"),
        (
            {
                "method": "orientations",
                "readings": [{"up": u, "mean": m} for u, m in zip(["+x", "-x", "+y", "-y"], GOOD[:4])],
            },
            422,
            "condition (22)",
        ),
        ({"method": "orientations", "readings": [{"up": "+x", "mean": GOOD[0]}]}, 422, "at least 4"),
        ({"method": "magic", "readings": []}, 422, "magic"),
        ({"readings": GOOD}, 422, "the field `method` is required: one of auto, six_position"),
        ({"method": "six_position"}, 422, "either `readings` or `recording_id`"),
        ({"method": "six_position", "recording_id": "rec_nope"}, 404, "no recording with id 'rec_nope'"),
        ({**readings(GOOD), "gravity": -1}, 422, "gravity"),
        # Found by the schema fuzzer: a subnormal gravity overflowed the magnitude models' division.
        (
            {"method": "auto", "gravity": 5e-324, "means": [[0.0, 0.0, 1.0]] * 9},
            422,
            "gravity: Input should be greater than or equal to 0.1",
        ),
        ({**readings(GOOD), "unit": "furlong"}, 422, "unit"),
        ({**readings(GOOD), "unexpected": 1}, 422, "unexpected"),
    ],
)
def test_bad_calibration_requests(client, payload, status, fragment):
    r = client.post("/api/v1/calibrations", json=payload)
    assert r.status_code == status, r.text
    assert fragment in r.json()["detail"]


@pytest.mark.parametrize(
    "text, fragment",
    [
        ('{"method": "six_position", "readings": [{"up": "-x", "mean": [NaN, 0, 0]}]}', "finite"),
        ('{"method": "six_position", "readings": [{"up": "-x", "mean": [Infinity, 0, 0]}]}', "finite"),
        ('{"method": "six_position", "readings": [', "not valid JSON"),
        ("", "JSON body"),
    ],
)
def test_non_finite_and_broken_json(client, text, fragment):
    r = post_raw(client, text)
    assert r.status_code == 422, r.text
    assert fragment in r.json()["detail"]


def test_nothing_stored_is_lost_and_no_500(client):
    good = client.post("/api/v1/calibrations", json=six_request(seed_table(1), CANONICAL))
    assert good.status_code == 201
    for bad in ('{"method": 1}', "[]", '"text"', '{"method": "six_position", "readings": "x"}', "null"):
        r = post_raw(client, bad)
        assert 400 <= r.status_code < 500, (bad, r.status_code, r.text)
    assert client.get(f"/api/v1/calibrations/{good.json()['id']}").status_code == 200
    assert len(client.get("/api/v1/calibrations").json()["items"]) == 1


def test_unknown_ids_and_formats(client):
    assert client.get("/api/v1/calibrations/cal_missing").status_code == 404
    cal = client.post("/api/v1/calibrations", json=six_request(seed_table(1), CANONICAL)).json()
    r = client.get(f"/api/v1/calibrations/{cal['id']}/export", params={"format": "docx"})
    assert r.status_code == 422 and "unknown export format 'docx'" in r.json()["detail"]
    r = client.post(f"/api/v1/calibrations/{cal['id']}/apply", json={"samples": [[1, 2]]})
    assert r.status_code == 422 and "samples[0]" in r.json()["detail"]
