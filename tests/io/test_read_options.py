"""The readers' interface: each reader of app.io.readers.READERS takes the options it reads as keyword-only
parameters and nothing else, the table says which, and read_log decides the format once, then calls one reader.

A misspelled option is a programming mistake and fails loudly (TypeError), wherever it is planted: in a
ReadOptions, in a call of a reader, or in the table. An option the user gives that the format has no use for is
answered as before (tests/api/test_remedies.py, tests/test_cli_errors.py).
"""

from __future__ import annotations

import json
import sys
import zipfile

import pytest

from app.io.errors import LogFormatError
from app.io.readers import FLIGHT_FORMATS, READER_OPTIONS, READERS, Reader, read_log, reader_options, tagged_lines
from app.io.readers.read_options import ReadOptions
from app.io.readers.table import sniff
from tests.conftest import DATA

CSV = DATA / "formats" / "generic_g.csv"
POSES = sorted((DATA / "real" / "mpu6050_pose_files").iterdir())


def test_read_options_refuses_a_misspelled_option():
    with pytest.raises(TypeError, match="sampling_rate"):
        ReadOptions(sampling_rate=100.0)  # sampling_rate_hz, misspelled on purpose
    with pytest.raises(TypeError, match="lsb_per_gee"):
        ReadOptions.from_stored({"format": "csv", "lsb_per_gee": 16384})


@pytest.mark.parametrize("fmt", list(READERS))
def test_every_reader_refuses_an_option_it_does_not_declare(fmt):
    """No reader swallows unknown options (no ``**kwargs``): ``unit`` for ``units`` fails before anything is read."""
    with pytest.raises(TypeError, match="unexpected keyword argument 'unit'"):
        READERS[fmt].read(CSV, sniff(CSV, CSV.name), name=CSV.name, unit={"acc": "g"})


def test_a_table_entry_and_its_reader_must_agree():
    """The table is checked against the readers' signatures when it is built: an option misspelled in it, one its
    reader declares but the table leaves out, or a reader with a catch-all, is a TypeError."""
    read = tagged_lines.read
    with pytest.raises(TypeError, match=r"declares \['units'\].*honours \['unit'\].*unit not among"):
        Reader("text", tagged_lines.detect, read, ("unit",))
    with pytest.raises(TypeError, match=r"declares \['units'\], but the table says it honours \[\]"):
        Reader("text", tagged_lines.detect, read)

    def swallowing(path, s, *, units=None, name="the file", **_):
        return read(path, s, units=units, name=name)

    with pytest.raises(TypeError, match=r"and \*\*_"):
        Reader("text", tagged_lines.detect, swallowing, ("units",))


def test_the_table_names_what_each_family_reads():
    assert set(reader_options(ReadOptions(), None)) == set(READER_OPTIONS)
    for fmt, reader in READERS.items():
        assert set(reader.honours) <= set(READER_OPTIONS), fmt
        flight = {"instance", "mag_instance", "clock"} & set(reader.honours)
        assert bool(flight) == (fmt in FLIGHT_FORMATS) == (reader.family == "flight"), fmt
        if reader.family == "json":  # its samples become a table, read as a CSV with the options
            assert reader.honours == (), fmt


def _entries_of_read_log(read):
    """How many times ``read_log`` is entered while ``read()`` runs."""
    entered = []

    def profile(frame, event, arg):
        if event == "call" and frame.f_code is read_log.__code__:
            entered.append(frame)

    sys.setprofile(profile)
    try:
        log = read()
    finally:
        sys.setprofile(None)
    return log, len(entered)


def test_read_log_reads_a_zip_of_json_files_without_calling_itself(tmp_path):
    """A zip of log files, each JSON samples: every member's format is decided and read by its one reader, the
    JSON's samples as the table they make — read_log is entered once."""
    upload = tmp_path / "poses.zip"
    with zipfile.ZipFile(upload, "w") as zf:
        for path in POSES:
            lines = path.read_text().splitlines()
            header = lines[0].split(",")
            rows = [dict(zip(header, map(float, line.split(",")))) for line in lines[1:]]
            zf.writestr(path.stem + ".json", json.dumps({"device": "MPU-6050", "samples": rows}))
    log, entered = _entries_of_read_log(lambda: read_log(upload, ReadOptions(), name=upload.name))
    assert entered == 1
    assert [p.filename for p in log.parts] == [p.stem + ".json" for p in POSES]
    assert log.format == "csv" and log.units["acc"] == "m/s^2"
    assert log.parts[0].notes[0].startswith("read as JSON: the array 'samples', 200 samples, keys Timestamp")


def test_a_zip_inside_a_zip_under_another_name_is_refused(tmp_path):
    """A member that is itself a zip of log files is refused as one named .zip is (app.io.readers.parts), not read as a
    recording inside the recording."""
    inner = tmp_path / "inner.zip"
    with zipfile.ZipFile(inner, "w") as zf:
        for path in POSES[:3]:
            zf.write(path, path.name)
    upload = tmp_path / "poses.zip"
    with zipfile.ZipFile(upload, "w") as zf:
        zf.write(inner, "first.csv")
        for path in POSES[3:]:
            zf.write(path, path.name)
    with pytest.raises(LogFormatError, match=r"first\.csv is a zip inside a recording of several files"):
        read_log(upload, ReadOptions(), name=upload.name)


def test_a_json_files_table_is_read_as_text_whatever_its_first_key(tmp_path):
    """The table a JSON file's samples make is read as a CSV: a first key that starts as JSON does (``[t]``) does
    not make it JSON again."""
    path = tmp_path / "samples.json"
    path.write_text(json.dumps([{"[t]": i / 100, "acc_x": 0.01, "acc_y": 0.02, "acc_z": 1.0} for i in range(300)]))
    log = read_log(path, ReadOptions(), name=path.name)
    assert log.format == "csv" and log.acc.shape == (300, 3) and log.units["acc"] == "g"
    assert log.notes[0] == "read as JSON: the top-level array, 300 samples, keys [t], acc_x, acc_y, acc_z"
