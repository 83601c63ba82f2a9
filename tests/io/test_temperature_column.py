"""A CSV's sensor temperature: a ``temp_c`` column (or temp, temperature, T (°C)) read into LogData.temperature_c,
never taken for the time column; named with ``columns`` in a table without a header row, or mapped."""

from __future__ import annotations

import numpy as np
import pytest

from app.io.readers import read_log
from app.io.readers.read_options import ReadOptions

ROWS = [
    (0.00, 0.1, 0.2, 9.8, 21.5),
    (0.01, 0.1, 0.2, 9.8, 21.52),
    (0.02, 0.1, 0.2, 9.81, 21.55),
    (0.03, 0.11, 0.2, 9.8, 21.6),
]


def _write(tmp_path, header: str | None, rows=ROWS):
    path = tmp_path / "log.csv"
    lines = ([header] if header else []) + [",".join(f"{v:g}" for v in r) for r in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("name", ["temp_c", "temp", "Temperature", "T (°C)", "temperature (degC)", "temp [C]"])
def test_temperature_headers_are_recognised(tmp_path, name):
    log = read_log(_write(tmp_path, f"time_s,acc_x,acc_y,acc_z,{name}"))
    np.testing.assert_allclose(log.temperature_c, [r[4] for r in ROWS])
    assert log.time_s is not None and log.time_s[-1] == pytest.approx(0.03)


def test_a_log_without_temperature_has_none(tmp_path):
    log = read_log(_write(tmp_path, "time_s,acc_x,acc_y,acc_z", [r[:4] for r in ROWS]))
    assert log.temperature_c is None


def test_columns_name_or_map_the_temperature(tmp_path):
    path = _write(tmp_path, None)
    log = read_log(path, ReadOptions(columns="t,acc_x,acc_y,acc_z,temp_c", sampling_rate_hz=100))
    np.testing.assert_allclose(log.temperature_c, [r[4] for r in ROWS])
    path = _write(tmp_path, "time_s,acc_x,acc_y,acc_z,board")
    log = read_log(path, ReadOptions(columns="temp_c:board"))
    np.testing.assert_allclose(log.temperature_c, [r[4] for r in ROWS])
