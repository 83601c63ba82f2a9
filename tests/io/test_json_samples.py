"""JSON arrays of samples and the Betaflight configurator's compass-tumble export (issue 31, point 4)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from app.io.errors import LogFormatError
from app.io.readers import read_log
from app.io.readers.read_options import ReadOptions
from tests.conftest import DATA

BETAFLIGHT = (
    DATA / "real" / "corpus" / "betaflight_mag_characterization_model" / "characterization_model_2026-06-26.json"
)


def write(tmp_path, name, data) -> object:
    path = tmp_path / name
    path.write_text(json.dumps(data))
    return path


def test_objects_nested_by_sensor_are_flattened_to_the_canonical_columns(tmp_path):
    rng = np.random.default_rng(4)
    acc = np.array([0.1, -0.2, 9.8]) + 0.01 * rng.standard_normal((300, 3))
    samples = [
        {"t_ms": 10 * i, "acc": dict(zip("xyz", a)), "mag": {"x": 20.5, "y": -5.25, "z": 40.125}, "label": "rest"}
        for i, a in enumerate(acc.tolist())
    ]
    log = read_log(write(tmp_path, "imu.json", {"device": "board", "samples": samples}), name="imu.json")
    assert log.channels == ["acc", "mag"] and log.units == {"acc": "m/s^2", "mag": "uT"}
    assert log.sampling_rate_hz == 100.0 and log.n_samples == 300
    assert log.notes[0] == (
        "read as JSON: the array 'samples', 300 samples, keys t_ms, acc_x, acc_y, acc_z, mag_x, "
        "mag_y, mag_z (label not numbers: left out)"
    )
    assert log.acc == pytest.approx(acc, abs=1e-12)


def test_lists_of_numbers_are_a_table_without_a_header_row(tmp_path):
    rows = [[i * 0.01, 0.0, 0.0, 1.0] for i in range(200)]
    log = read_log(write(tmp_path, "rows.json", rows), name="rows.json")
    assert log.channels == ["acc"] and log.units == {"acc": "g"} and log.sampling_rate_hz == 100.0


@pytest.mark.parametrize(
    "data, message",
    [
        ([{"t": 0, "x": 1, "y": 2, "z": 3}, {"t": 1, "x": 1, "y": 2}], "sample 1 of the top-level array lacks 'z'"),
        (
            [{"t": 0, "x": 1, "y": 2, "z": 3}, {"t": 1, "x": "abc", "y": 2, "z": 3}],
            "sample 1 of the top-level array holds \"abc\" in 'x'",
        ),
        ([[0, 1, 2, 3], [1, 1, 2]], "sample 1 of the top-level array is [1, 1, 2], not 4 numbers"),
        ({"acc": [[0, 1, 2]] * 3, "gyr": [[0, 1, 2]] * 3}, "a JSON object holding several arrays ('acc', 'gyr')"),
        ({"name": "quad"}, "is a JSON object (keys 'name') holding no array of samples"),
        ([1, 2, 3], "holds int values, not samples"),
    ],
)
def test_what_is_not_an_array_of_samples_is_refused_naming_what_it_holds(tmp_path, data, message):
    with pytest.raises(LogFormatError) as err:
        read_log(write(tmp_path, "bad.json", data), name="bad.json")
    assert message in str(err.value)


def test_a_json_file_cut_short_is_named_by_line_and_column(tmp_path):
    path = tmp_path / "cut.json"
    path.write_text('[{"t": 0, "x": 1, "y": 2, "z": 3},\n {"t": 1, "x": 1')
    with pytest.raises(LogFormatError, match=r"cut.json starts like JSON but is not JSON: line 2, column"):
        read_log(path, name="cut.json")


def test_the_betaflight_export_is_refused_whatever_format_is_asked(tmp_path):
    for fmt in ("auto", "betaflight_mag", "json"):
        with pytest.raises(
            LogFormatError, match="Betaflight configurator's magnetometer characterization model"
        ) as err:
            read_log(BETAFLIGHT, ReadOptions(format=fmt), name=BETAFLIGHT.name)
        assert err.value.status == 422
