"""Reading the same upload again with other options (the start page's *Read again with these units*)
supersedes the earlier calibration of that recording and method: the list shows one row per recording and
method with how many it superseded, those earlier ones are listed on asking, and every one still reads by id."""

from __future__ import annotations

from tests.api.test_pose_files import six, upload_files


def calibrate(client, rec: dict, method: str = "auto") -> dict:
    r = client.post("/api/v1/calibrations", json={"method": method, "recording_id": rec["id"]})
    assert r.status_code == 201, r.text
    return r.json()


def uploaded(client, files, **form) -> dict:
    r = upload_files(client, files, **form)
    assert r.status_code == 201, r.text
    return r.json()


def test_reading_the_same_pose_files_again_supersedes_and_keeps_the_earlier_ones(client):
    """The MPU-6050's six real pose files (tests/data/real/README.md), read three times with other options."""
    files = six(rows=120)
    first = uploaded(client, files)
    a = calibrate(client, first)
    again = uploaded(client, files, acc_unit="m/s^2")  # the same files, the unit said
    assert again["content_sha256"] == first["content_sha256"] and again["id"] != first["id"]
    b = calibrate(client, again)
    c = calibrate(client, uploaded(client, files, acc_unit="m/s^2", sampling_rate_hz=62.5))
    other = calibrate(client, uploaded(client, six(rows=100)))  # other readings: a recording of its own
    assert a["method"] == b["method"] == c["method"] and "superseded_by" not in c

    items = client.get("/api/v1/calibrations").json()["items"]
    assert [x["id"] for x in items] == [other["id"], c["id"]]  # one row per recording and method
    assert items[1]["earlier"] == 2 and "earlier" not in items[0]
    earlier = client.get("/api/v1/calibrations", params={"superseded_by": c["id"]}).json()["items"]
    assert [x["id"] for x in earlier] == [b["id"], a["id"]] and {x["superseded_by"] for x in earlier} == {c["id"]}
    for old in (a, b):  # nothing acknowledged is lost: each reads, exports and applies by id
        got = client.get(f"/api/v1/calibrations/{old['id']}").json()
        assert got["superseded_by"] == c["id"] and got["model"] == old["model"]
        assert client.get(f"/api/v1/calibrations/{old['id']}/export", params={"format": "c"}).status_code == 200
    assert client.get(f"/api/v1/calibrations/{c['id']}").json()["earlier"] == 2

    # Another method on the same upload is a row of its own, and supersedes nothing.
    orient = calibrate(client, first, method="orientations")
    assert orient["method"] != c["method"]
    items = client.get("/api/v1/calibrations").json()["items"]
    assert [x["id"] for x in items] == [orient["id"], other["id"], c["id"]] and items[2]["earlier"] == 2


def test_each_compass_of_a_flight_log_keeps_its_own_calibration(client):
    """The real ArduCopter log171.bin (tests/data/real/flight/README.md): its compass 1 calibrated after compass 0 is
    another compass, not a later reading of the first — both stay listed, each naming its compass (external,
    internal: COMPASS_EXTERNAL, COMPASS_EXTERN2) — and compass 0 calibrated again supersedes compass 0 only."""
    from tests.conftest import DATA

    log = DATA / "real" / "flight" / "log171.bin"
    rec = client.post("/api/v1/recordings", files={"file": (log.name, log.read_bytes(), "application/octet-stream")})
    assert rec.status_code == 201, rec.text

    def compass(instance: int, **extra) -> dict:
        r = client.post(
            "/api/v1/calibrations",
            json={"method": "compass_flight", "recording_id": rec.json()["id"], "mag_instance": instance, **extra},
        )
        assert r.status_code == 201, r.text
        return r.json()

    zero, one = compass(0), compass(1)
    assert (zero["flight"]["instance"], zero["flight"]["external"]) == (0, True)
    assert (one["flight"]["instance"], one["flight"]["external"]) == (1, False)
    items = client.get("/api/v1/calibrations").json()["items"]
    assert [x["id"] for x in items] == [one["id"], zero["id"]] and not any("earlier" in x for x in items)
    again = compass(0, window="all")
    items = client.get("/api/v1/calibrations").json()["items"]
    assert [x["id"] for x in items] == [again["id"], one["id"]] and items[0]["earlier"] == 1
