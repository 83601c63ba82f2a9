"""A seeded simulated flight (simulations.flight_compass.simulate_flight) written as both
firmwares' logs (tests.flight_logs), for the compass-from-a-flight tests over HTTP, the CLI and the bench.

The simulator's dict holds the flight (time, attitude, raw compass in the frame L, current, throttle, place
and date) and its truth ``h = M (Q m_L − b − k p)``; the log writers want, beside it, what each firmware
stored (``stored``) and the field of the place. They are added here, the simulator's meaning untouched:

- the Earth's field of the simulation is the geomagnetic model's at the flight's place and date (what the
  workflow expects there), not the simulator's default;
- each firmware stored a stale calibration: offsets off the truth by a few µT, no soft iron, no motor term,
  and orientation 0 (None) while the compass is mounted at ``orientation`` — so the flight must find it.
  ArduPilot's COMPASS_OFS is added to the field, PX4's CAL_MAGn_xOFF subtracted (FirmwareCompassCal).

The writers log the IMU beside the compass, as every real flight log does.
"""

from __future__ import annotations

import datetime
from pathlib import Path

import numpy as np

from tests.flight_logs import ardupilot_flight_messages, dataflash_bytes, px4_flight_topics, ulog_bytes


def earth_field_at(flight_place: dict | None = None) -> np.ndarray:
    """The geomagnetic model's field in north-east-down (µT) where and when :func:`simulate_flight` flies."""
    from app.geomag import reference_field

    place = flight_place or {
        "lat": 47.4,
        "lon": 8.5,
        "alt_m": 430.0,
        "utc": datetime.datetime(2025, 6, 1, 10, 0, tzinfo=datetime.UTC),
    }
    e = reference_field(place["utc"].date(), place["lat"], place["lon"], place["alt_m"])
    return np.array([e.north_ut, e.east_ut, e.down_ut])


def seeded_flight(seed: int, *, orientation: int = 2, stale_ut: float = 5.0, **kw) -> dict:
    """:func:`simulate_flight` under the model's field, with each firmware's stale stored calibration."""
    from simulations.flight_compass import simulate_flight

    flight = simulate_flight(seed, orientation=orientation, earth_ned=earth_field_at(), **kw)
    stale = flight["truth"]["b"] + np.random.default_rng(seed + 7_000).normal(0.0, stale_ut, 3)
    common = {"matrix": np.eye(3), "motor": np.zeros(3), "motor_kind": None, "orientation": 0}
    flight["stored"] = {"ardupilot": {"offsets_ut": -stale, **common}, "px4": {"offsets_ut": stale, **common}}
    return flight


def write_flight_compass_logs(
    directory, flight: dict, *, gps: bool = True, imu: bool = True, stem: str = "flight"
) -> tuple[Path, Path]:
    """``flight`` (:func:`seeded_flight`) as an ArduPilot DataFlash log and a PX4 ULog with their IMU:
    ``(bin_path, ulg_path)``. ``gps=False`` leaves the GPS out (no place, no date in the log); ``imu=False``
    the IMU (a minimal log: attitude, compass, GPS, power)."""
    directory = Path(directory)
    messages = ardupilot_flight_messages(flight)
    topics, params, info = px4_flight_topics(flight)
    if not gps:
        messages = [m for m in messages if m["name"] != "GPS"]
        topics = [t for t in topics if t["name"] != "vehicle_gps_position"]
    if not imu:
        messages = [m for m in messages if m["name"] not in ("IMU", "ACC", "GYR")]
        topics = [t for t in topics if t["name"] not in ("sensor_accel", "sensor_gyro", "sensor_combined")]
    bin_path, ulg_path = directory / f"{stem}.bin", directory / f"{stem}.ulg"
    bin_path.write_bytes(dataflash_bytes(messages))
    ulg_path.write_bytes(ulog_bytes(topics, params=params, info=info))
    return bin_path, ulg_path
