"""The sampling rate of a time column (app/io/readers/timing.py): units, bursts of a serial host, gaps."""

from __future__ import annotations

import numpy as np
import pytest

from app.io.errors import LogFormatError
from app.io.readers import read_log
from app.io.readers.timing import JITTER_MAX, decide_timing, time_scale
from simulations.serial import host_arrival_times

FS = 100.0


def test_bursts_of_a_serial_host_give_the_sensor_s_rate_and_a_jitter_note():
    t = host_arrival_times(np.random.default_rng(5), n_samples=30_000, sampling_rate_hz=FS)
    steps = np.diff(t)
    assert 1.5e-3 < np.median(steps) < 3e-3 and steps.max() > 0.05  # as a USB serial host sees them
    timing = decide_timing(t)
    assert timing.sampling_rate_hz == pytest.approx(FS, rel=2e-3)
    assert timing.source == "time column" and timing.gaps == ()
    assert timing.jitter > 1.0 > JITTER_MAX
    note = " ".join(timing.notes)
    assert f"{100 * timing.jitter:.0f} % of the interval" in note and "from the span" in note
    assert f"not {1 / np.median(steps[steps > 0]):.4g} Hz from the median step" in note
    # Stamped in whole milliseconds, the bursts are still bursts.
    whole_ms = decide_timing(np.round(t, 3))
    assert whole_ms.jitter > 1.0 and whole_ms.sampling_rate_hz == pytest.approx(FS, rel=2e-3)


def test_a_sensor_clock_has_no_jitter_note():
    t = np.arange(5_000) / 250.0 + np.random.default_rng(1).normal(scale=1e-5, size=5_000)
    timing = decide_timing(t)
    assert timing.sampling_rate_hz == pytest.approx(250.0, rel=1e-5)
    assert timing.jitter < 0.01 and timing.notes == () and timing.gaps == ()


@pytest.mark.parametrize(
    "values, unit, rate",
    [
        (np.arange(1_000) * 0.01, "s", 100.0),
        (np.arange(1_000) * 10.0, "ms", 100.0),  # millis()
        (np.arange(1_000) * 1.0, "ms", 1000.0),  # 1, 2, 3: milliseconds at 1 kHz, not seconds at 1 Hz
        (np.arange(1_000) * 1000.0, "µs", 1000.0),  # micros() at 1 kHz, not milliseconds at 1 Hz
        (np.round(np.arange(1_000) * 2500.0 + 123_456_789), "µs", 400.0),
        (np.arange(1_000) * 5e6, "ns", 200.0),
    ],
)
def test_the_unit_of_a_time_column_from_its_step(values, unit, rate):
    scale, name = time_scale(values)
    assert name == unit
    assert decide_timing((values - values[0]) * scale).sampling_rate_hz == pytest.approx(rate)


def test_whole_milliseconds_at_400_hz_are_400_hz_not_the_median_step():
    # millis() at 400 Hz: steps of 2 and 3 ms; one over the median step would say 500 or 333 Hz.
    t = np.floor(np.arange(4_000) * 2.5) * 1e-3
    timing = decide_timing(t)
    assert timing.sampling_rate_hz == pytest.approx(400.0, rel=1e-3)
    # Their 20 % scatter is the rounding to whole milliseconds, not a host's bursts: no note.
    assert timing.jitter == pytest.approx(np.sqrt(0.25 - 1 / 6) / 2.5, rel=0.01) and timing.notes == ()


def test_a_gap_is_found_with_its_place_and_length_and_the_rate_leaves_it_out():
    t = np.delete(np.arange(20_000) / FS, np.arange(8_000, 8_150))  # 1.5 s lost
    timing = decide_timing(t)
    assert timing.sampling_rate_hz == pytest.approx(FS, rel=1e-9)
    [gap] = timing.gaps
    assert gap.index == 8_000 and gap.t_s == pytest.approx(79.99) and gap.missing_s == pytest.approx(1.5)
    assert any("1 gap in the time column" in n and "1.5 s" in n for n in timing.notes)


def test_a_gap_among_bursts_is_found_and_bursts_are_not_gaps():
    rng = np.random.default_rng(6)
    t = host_arrival_times(rng, n_samples=30_000, sampling_rate_hz=FS, lost=[(12_000, 12_300), (20_000, 20_060)])
    timing = decide_timing(t)
    assert timing.sampling_rate_hz == pytest.approx(FS, rel=3e-3)
    assert [g.index for g in timing.gaps] == [12_000, 19_700]
    assert [g.missing_s for g in timing.gaps] == pytest.approx([3.0, 0.6], abs=0.08)


def test_the_caller_s_rate_wins_with_a_note_when_the_time_column_disagrees():
    t = np.arange(3_000) / 98.0
    timing = decide_timing(t, 100.0)
    assert timing.sampling_rate_hz == 100.0 and timing.source == "sampling_rate_hz"
    assert any("the given rate 100 Hz is used; the time column's span says 98 Hz" in n for n in timing.notes)
    with pytest.raises(LogFormatError, match="sampling_rate_hz must be a positive number"):
        decide_timing(t, -1.0)


def test_no_time_column_no_rate():
    timing = decide_timing(None)
    assert timing.sampling_rate_hz is None and timing.source == "none"
    assert "noise, cube and autocal methods ask for one" in timing.notes[0]


def test_a_time_column_that_goes_back_uses_the_median_step_and_says_so():
    t = np.concatenate([np.arange(1_000) * 0.01, 5.0 + np.arange(1_000) * 0.01])
    timing = decide_timing(t)
    assert timing.sampling_rate_hz == pytest.approx(100.0)
    assert any("goes back 1 time(s), first after sample 1000" in n for n in timing.notes)
    with pytest.raises(LogFormatError, match="does not increase from its first row to its last"):
        decide_timing(np.arange(10.0)[::-1])


def test_a_csv_of_host_stamps_in_ms_reads_at_the_sensor_s_rate(tmp_path):
    t = host_arrival_times(np.random.default_rng(7), n_samples=6_000, sampling_rate_hz=FS)
    gyr = np.random.default_rng(8).normal(scale=0.05, size=(6_000, 3))
    path = tmp_path / "serial.csv"
    np.savetxt(
        path,
        np.column_stack([np.round(t * 1e3 + 31_000, 3), gyr]),
        delimiter=",",
        comments="",
        header="t,gyr_x,gyr_y,gyr_z",
        fmt="%.6g",
    )
    log = read_log(path)
    assert log.sampling_rate_hz == pytest.approx(FS, rel=3e-3) and log.timing.source == "time column"
    assert any("time column 't' read in ms" in n for n in log.notes)
    assert any("irregular" in n for n in log.notes)


@pytest.mark.parametrize(
    "steps",
    [
        0.005 + np.random.default_rng(1).integers(-11, 12, size=2_160_000) * 1e-13,  # a clock's steps, a few values
        np.full(100_001, 0.01),  # all equal, odd count
        np.diff(host_arrival_times(np.random.default_rng(2), n_samples=200_000, sampling_rate_hz=FS)),  # bursts
        np.random.default_rng(3).integers(0, 3, size=300_000) * 1e-3,  # whole milliseconds, zeros among them
        np.concatenate([np.full(150_000, 1.0), np.full(150_000, 2.0)]),  # the two middle values differ
        np.sort(np.random.default_rng(4).exponential(size=250_000)),  # sorted
        np.where(np.arange(300_000) == 7, np.nan, 0.01),  # a NaN: numpy's median is NaN
        np.where(np.arange(300_000) % 1000 == 0, np.inf, 0.01),
        np.random.default_rng(5).normal(size=1_000),  # short: numpy's median itself
    ],
)
def test_the_exact_median_is_numpy_s_to_the_last_bit(steps):
    from app.io.readers.timing import exact_median

    expected, got = float(np.median(steps)), exact_median(steps)
    assert got == expected or (np.isnan(got) and np.isnan(expected))
    assert np.signbit(got) == np.signbit(expected)


@pytest.mark.parametrize(
    "case", ["px4_sample_gyro_ringing_after_landing", "hyperimu_lsm6ds3_phone_still", "hmc5883l_esp32_still_counts"]
)
def test_the_exact_median_of_real_clocks_steps_is_numpy_s(case):
    """A PX4 flight controller's microsecond stamps, a phone app's irregular milliseconds, an ESP32's serial log
    (tests/data/real/corpus): their time columns' steps, repeated past the length from which exact_median
    narrows a band (8 × MEDIAN_SAMPLE) and as they are, give numpy's median to the last bit."""
    from app.io.readers.read_options import ReadOptions
    from app.io.readers.timing import MEDIAN_SAMPLE, exact_median
    from tests import real_corpus

    found = next(c for c in real_corpus.cases() if c.name == case)
    log = read_log(found.files[0], ReadOptions(columns=found.form.get("columns")), name=found.files[0].name)
    steps = np.diff(log.time_s)
    long = np.tile(steps, 8 * MEDIAN_SAMPLE // len(steps) + 1)
    for values in (steps, long, long[:-1]):
        assert exact_median(values) == float(np.median(values))
