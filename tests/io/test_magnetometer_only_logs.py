"""Logs of the magnetometer alone, in every format that carries one, read for the compass; and the
accelerometer methods refuse them by name."""

from __future__ import annotations

import io
import zipfile

import numpy as np
import pytest

from app.io.errors import LogFormatError
from app.io.readers import read_log
from app.io.readers.read_options import ReadOptions
from app.workflows.recordings import describe_log
from simulations.magnetometer import simulate_session

N = 200
RATE = 20.0
MAG, _, _ = simulate_session(41, n=N)
T = np.arange(N) / RATE


def _csv(header: str, rows) -> str:
    return header + "\n" + "\n".join(",".join(f"{v:.6f}" for v in row) for row in rows) + "\n"


def _sensor_logger_csv() -> str:
    ns = (1_700_000_000_000_000_000 + T * 1e9).astype(np.int64)
    lines = ["time,seconds_elapsed,z,y,x"] + [
        f"{n},{s:.6f},{v[2]:.6f},{v[1]:.6f},{v[0]:.6f}" for n, s, v in zip(ns, T, MAG)
    ]
    return "\n".join(lines) + "\n"


def _gnss_logger() -> str:
    header = [
        "# Header Description:",
        "# UncalMag,utcTimeMillis,elapsedRealtimeNanos,UncalMagXMicroT,UncalMagYMicroT,"
        "UncalMagZMicroT,BiasXMicroT,BiasYMicroT,BiasZMicroT,CalibrationAccuracy",
    ]
    ns = (5_000_000_000 + T * 1e9).astype(np.int64)
    lines = [
        f"UncalMag,{1_700_000_000_000 + int(s * 1000)},{n},{v[0]:.6f},{v[1]:.6f},{v[2]:.6f},10.0,20.0,30.0,3"
        for n, s, v in zip(ns, T, MAG)
    ]
    return "\n".join(header + lines) + "\n"


def _zip(**members) -> bytes:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        for name, text in members.items():
            z.writestr(name, text)
    return buf.getvalue()


CASES = {
    "generic CSV": ("turn.csv", _csv("time_s,mag_x (uT),mag_y (uT),mag_z (uT)", np.column_stack([T, MAG])), {}, "csv"),
    "headerless with columns": (
        "turn.csv",
        _csv("", np.column_stack([T, MAG])).lstrip("\n"),
        {"columns": "t,mag_x,mag_y,mag_z"},
        "csv",
    ),
    "Sensor Logger CSV": ("MagnetometerUncalibrated.csv", _sensor_logger_csv(), {}, "sensor_logger"),
    "Sensor Logger zip": (
        "turn.zip",
        _zip(
            **{
                "Metadata.csv": "platform,standardisation\nandroid,true\n",
                "MagnetometerUncalibrated.csv": _sensor_logger_csv(),
            }
        ),
        {},
        "sensor_logger",
    ),
    "phyphox": (
        "Raw Data.csv",
        _csv(
            '"Time (s)","Magnetic field x (µT)","Magnetic field y (µT)","Magnetic field z (µT)"',
            np.column_stack([T, MAG]),
        ),
        {},
        "phyphox",
    ),
    "GnssLogger UncalMag": ("gnss_log.txt", _gnss_logger(), {}, "gnss_logger"),
}


@pytest.mark.parametrize("case", CASES, ids=list(CASES))
def test_a_magnetometer_alone_is_read(tmp_path, case):
    filename, content, options, fmt = CASES[case]
    path = tmp_path / filename
    path.write_bytes(content if isinstance(content, bytes) else content.encode())
    log = read_log(path, ReadOptions(format="auto", sampling_rate_hz=None, units={}, **options), name=filename)
    assert log.format == fmt and log.channels == ["mag"] and log.acc is None
    assert log.units == {"mag": "uT"} and log.n_samples == N
    assert log.sampling_rate_hz == pytest.approx(RATE, rel=1e-3)
    np.testing.assert_allclose(log.mag, MAG, atol=1e-5)
    meta = describe_log(log)
    assert meta["segments"] == [] and meta["channels"] == ["mag"] and meta["quantization_step"] is None


def test_a_file_without_any_sensor_triple_says_what_it_wants(tmp_path):
    path = tmp_path / "x.csv"
    path.write_text("time_s,temperature,pressure\n0,20,1000\n0.1,20,1000\n")
    with pytest.raises(LogFormatError, match="mag_x, mag_y, mag_z"):
        read_log(path, ReadOptions(format="auto", sampling_rate_hz=None, units={}), name="x.csv")
