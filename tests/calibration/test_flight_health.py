"""A compass that does not measure (app/calibration/magnetometer/flight_health.py), tested first on the real
compasses of log171.bin (ArduCopter 3.3, three compasses, tests/data/real/flight/README.md): each measures, and
the same flight's real attitude and firmware field with readings that are zero, stuck at one value or read at a
fifth of their scale are each refused for what they show — never fitted, never judged "better"."""

from __future__ import annotations

import numpy as np
import pytest

from app.calibration.magnetometer import fit_flight_compass
from app.calibration.magnetometer.flight_health import CompassNotMeasuringError, not_measuring
from tests.conftest import DATA

LOG171 = DATA / "real" / "flight" / "log171.bin"


def _flight(instance: int) -> dict:
    """One compass of log171.bin with the field its attitude expects, on the compass's times."""
    from app.geomag import reference_field
    from app.io.flight.compass import read_flight_compass
    from app.workflows.flight_compass import _attitude_on

    log = read_flight_compass(LOG171, mag_instance=instance)
    t = np.asarray(log.time_s, dtype=float)
    c_nb, inside = _attitude_on(t, np.asarray(log.attitude_time_s, float), np.asarray(log.attitude_c_nb, float))
    earth = reference_field(log.utc.date(), log.latitude_deg, log.longitude_deg, log.altitude_m)
    b_ned = np.array([earth.north_ut, earth.east_ut, earth.down_ut])
    return {
        "mag": np.asarray(log.mag_raw_ut)[inside],
        "expected": np.einsum("nji,j->ni", c_nb, b_ned),
        "firmware": np.asarray(log.mag_firmware_ut)[inside],
        "time_s": t[inside],
        "attitude": c_nb,
        "earth": b_ned,
        "stored_ut": log.stored.offsets_ut,
    }


@pytest.fixture(scope="module")
def flights():
    return {k: _flight(k) for k in range(3)}


@pytest.mark.parametrize("instance", [0, 1, 2])
def test_every_real_compass_of_log171_measures(flights, instance):
    f = flights[instance]
    assert not_measuring(f["mag"], f["expected"]) is None


def _refused(f: dict, mag: np.ndarray, firmware: np.ndarray) -> str:
    with pytest.raises(CompassNotMeasuringError) as caught:
        fit_flight_compass(
            mag,
            f["expected"],
            time_s=f["time_s"],
            firmware_field=firmware,
            attitude=f["attitude"],
            earth_ned=f["earth"],
            not_measuring_remedy="set COMPASS_USE2 = 0",
        )
    assert caught.value.code == "compass_not_measuring"
    return str(caught.value)


def test_a_compass_reading_zero_is_refused_before_any_fit(flights):
    # ArduPilot logs the corrected field: a compass reading 0 shows its stored offsets, read back to 0
    f = flights[1]
    zero = np.zeros_like(f["mag"])
    why = _refused(f, zero, np.broadcast_to(f["stored_ut"], zero.shape))
    assert why.startswith("this compass does not measure: the compass reads 0.0 µT for the whole flight")
    assert "58.2 µT" in why and why.endswith("set COMPASS_USE2 = 0")


def test_a_stuck_compass_is_refused_for_not_seeing_the_vehicle_turn(flights):
    f = flights[1]
    stuck = np.broadcast_to(f["mag"][0], f["mag"].shape) + np.random.default_rng(3).normal(0, 0.2, f["mag"].shape)
    why = _refused(f, stuck, stuck)
    assert "does not see the vehicle turn" in why and "turned the Earth's field through 108.5 µT" in why


@pytest.mark.parametrize("scale, words", [(3.0, "turn 3.12 times"), (0.3, "turn 0.31 times")])
def test_a_compass_read_at_a_wrong_scale_turns_by_a_field_far_from_the_earths(flights, scale, words):
    f = flights[0]
    why = _refused(f, f["mag"] * scale, f["firmware"] * scale)
    assert words in why and "the Earth's field of 58.2 µT" in why, why


def test_an_uncalibrated_compass_s_hard_iron_is_no_reason_to_refuse_it(flights):
    # 80 µT of hard iron moves the magnitude far from the Earth's field: that is what the fit corrects
    f = flights[0]
    assert not_measuring(f["mag"] + [80.0, -60.0, 40.0], f["expected"]) is None
