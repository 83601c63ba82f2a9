"""Several files uploaded together, each asked which column is which on its own (issue 42, the column card for
several files): a refusal names the file it asks about (``file``), and ``columns`` takes one entry per file,
``NAME=COLUMNS;NAME=COLUMNS`` (app.io.readers.columns_of_file). Real data: a still MPU-6050's gyroscope in counts
without a header row (tests/data/real/corpus/mpu6050_still_gyro_counts_headerless), whose columns read as a
gyroscope or a magnetometer, split in two files as two rests of one board."""

from __future__ import annotations

from tests.real_corpus import CORPUS

STILL = CORPUS / "mpu6050_still_gyro_counts_headerless" / "imu_static_test_cols456.csv"


def _two_files() -> list[tuple[str, tuple[str, bytes, str]]]:
    lines = STILL.read_text().splitlines()
    half = len(lines) // 2
    return [
        ("file", ("rest_1.csv", ("\n".join(lines[:half]) + "\n").encode(), "text/csv")),
        ("file", ("rest_2.csv", ("\n".join(lines[half:]) + "\n").encode(), "text/csv")),
    ]


def test_each_of_several_files_is_asked_its_columns_and_read_with_its_own(client):
    form = {"sampling_rate_hz": "100"}
    r = client.post("/api/v1/recordings", files=_two_files(), data=form)
    assert r.status_code == 422 and r.json()["code"] == "columns_ambiguous", r.text
    first = r.json()
    assert first["file"] == "rest_1.csv" and [c["columns"] for c in first["candidates"]] == [
        "gyr_x,gyr_y,gyr_z",
        "mag_x,mag_y,mag_z",
    ], first
    # The first file answered: the second is asked about next.
    r = client.post("/api/v1/recordings", files=_two_files(), data={**form, "columns": "rest_1.csv=gyr_x,gyr_y,gyr_z"})
    assert r.status_code == 422 and r.json()["file"] == "rest_2.csv", r.text
    # Both answered: one recording of the gyroscope in counts, in two parts.
    both = "rest_1.csv=gyr_x,gyr_y,gyr_z;rest_2.csv=gyr_x,gyr_y,gyr_z"
    r = client.post("/api/v1/recordings", files=_two_files(), data={**form, "columns": both})
    assert r.status_code == 201, r.text
    rec = r.json()
    assert rec["channels"] == ["gyr"] and [p["filename"] for p in rec["parts"]] == ["rest_1.csv", "rest_2.csv"]
    assert rec["n_samples"] == 3000


def test_an_entry_that_names_no_file_is_refused_saying_how_to_write_it(client):
    r = client.post(
        "/api/v1/recordings", files=_two_files(), data={"sampling_rate_hz": "100", "columns": "rest_1.csv=;x"}
    )
    assert r.status_code == 422 and "is not NAME=COLUMNS" in r.json()["detail"], r.text
