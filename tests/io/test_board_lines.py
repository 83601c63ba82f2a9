"""The lines boards print, read live (app/io/board/lines.py): real board recordings of tests/data/real
replayed as the bytes a serial port delivers, in chunks, with boot text and every line end."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from app.calibration import STANDARD_GRAVITY
from app.io.board.formats import MOTIONCAL_RAW, RATE_MIN_S, RATE_STEPS, RATE_WINDOW_S
from app.io.board.lines import BoardLineReader, LogWriter, StreamRate, board_rate, numbers_format, read_lines, to_log
from app.io.errors import LogFormatError
from app.io.readers import read_log

REAL = Path(__file__).parents[1] / "data" / "real"
POSE = REAL / "mpu6050_pose_files" / "x_axis_pos.csv"  # Arduino, ms timestamps, m/s² under a "(g)" header
ESP32 = REAL / "mpu6050_esp32_pose_files" / "imu_data_negZ.csv"  # ESP32, µs timestamps, counts, CRLF
STILL = REAL / "mpu6050_session2_still_30s.csv"  # UNO, counts, no time column, two comment lines
COMPASS = REAL / "magnetometer" / "tomisuarez2_qmc5883l_turn_every10.csv"  # QMC5883L counts
BOOT = ["", "ets Jun  8 2016 00:22:57", "rst:0x1 (POWERON_RESET),boot:0x13", "MPU6050 Found!"]


def data_lines(path: Path) -> list[str]:
    return [ln for ln in path.read_text().splitlines() if ln.strip() and not ln.startswith("#")]


def play(text: str, *, chunk: int, fmt: str = "auto", rate_hz: float = 100.0, burst: int = 1):
    """Feed ``text`` in chunks of ``chunk`` bytes; the lines arrive at ``rate_hz`` in bursts of ``burst``."""
    reader = BoardLineReader(fmt)
    data = text.encode()
    out = []
    lines_before = 0
    for i in range(0, len(data), chunk):
        piece = data[i : i + chunk]
        # the arrival of a line: the burst its number falls in
        arrival = (lines_before // burst) * burst / rate_hz
        out += reader.feed(piece, arrival_s=arrival)
        lines_before += piece.count(b"\n") + piece.count(b"\r") - piece.count(b"\r\n")
    out += reader.finish(arrival_s=lines_before / rate_hz)
    return out, reader


@pytest.mark.parametrize("end", ["\n", "\r\n", "\r"])
@pytest.mark.parametrize("chunk", [1, 7, 64, 4096])
def test_arduino_csv_with_boot_text_in_any_chunks_and_line_ends(end, chunk):
    lines = data_lines(POSE)
    out, reader = play(end.join(BOOT + lines) + end, chunk=chunk)
    assert reader.format.name == "csv" and reader.format.sensors == ("acc", "gyr")
    assert len(out) == len(lines) - 1 == 200
    assert reader.skipped == 3 and reader.last_unreadable == "MPU6050 Found!"
    first = [float(v) for v in lines[1].split(",")]
    assert out[0].board_time == first[0] and out[0].values["acc"] == tuple(first[1:4])
    assert out[0].values["gyr"] == tuple(first[5:8])


def test_the_same_lines_as_an_uploaded_log():
    """The board's lines give the arrays, units and rate the same file gives uploaded."""
    out, reader = play("\n".join(data_lines(POSE)) + "\n", chunk=50, burst=8)
    live = to_log(out, reader.format)
    uploaded = read_log(POSE)
    np.testing.assert_array_equal(live.acc, uploaded.acc)
    np.testing.assert_array_equal(live.gyr, uploaded.gyr)
    assert live.units == uploaded.units == {"acc": "m/s^2", "gyr": "rad/s"}
    assert live.sampling_rate_hz == pytest.approx(uploaded.sampling_rate_hz, rel=1e-12)
    assert live.sampling_rate_hz == pytest.approx(62.8157, abs=1e-4)  # the board's millis(), not the arrivals
    assert any("header said g" in w for w in live.warnings)  # the unit checked at rest, as for an upload


def test_esp32_crlf_counts_in_microseconds():
    out, reader = play(ESP32.read_bytes().decode(), chunk=33, rate_hz=50.0, burst=10)
    log = to_log(out, reader.format)
    uploaded = read_log(ESP32)
    np.testing.assert_allclose(log.acc, uploaded.acc, rtol=0, atol=0)
    assert log.units["acc"] == "g" and any("16384" in w for w in log.warnings)
    assert log.sampling_rate_hz == pytest.approx(uploaded.sampling_rate_hz, rel=1e-12)
    assert 170 < log.sampling_rate_hz < 180  # every fifth row of ≈ 875 Hz: the board's clock, not 50 Hz of arrivals


def test_bursts_of_arrival_do_not_change_the_rate():
    """Lines without a time column: the span of the arrivals gives the rate, bursts of 10 do not move it."""
    lines = data_lines(STILL)[1:]  # bare numbers: the header dropped
    out, reader = play("\n".join(lines) + "\n", chunk=64, rate_hz=100.0, burst=10)
    assert reader.format == numbers_format(3) and len(out) == 3000 and reader.skipped == 0
    timing = board_rate(out, reader.format)
    arrivals = np.array([r.arrival_s for r in out])
    assert np.median(np.diff(arrivals)) == 0.0  # a burst's lines arrive together
    assert timing.sampling_rate_hz == pytest.approx(100.0, rel=0.005)
    log = to_log(out, reader.format)
    assert log.units == {"acc": "g"} and np.median(np.linalg.norm(log.acc, axis=1)) == pytest.approx(0.912, abs=0.01)


def test_bare_numbers_with_a_leading_time_and_six_columns():
    lines = data_lines(POSE)[1:]
    six = [",".join(ln.split(",")[:4] + ln.split(",")[5:]) for ln in lines]  # time, acc, gyr: 7 columns
    out, reader = read_lines(BOOT + six)
    assert reader.format.name == "numbers" and reader.format.time_col == 0
    assert reader.format.sensors == ("acc", "gyr") and len(out) == 200
    assert reader.skipped == 3
    log = to_log(out, reader.format)
    assert log.sampling_rate_hz == pytest.approx(62.8157, abs=1e-4)
    assert any("ms" in n for n in log.notes)


def test_compass_csv_is_counts():
    out, reader = read_lines(data_lines(COMPASS))
    log = to_log(out, reader.format)
    assert reader.format.sensors == ("mag",) and log.units == {"mag": "raw"}
    assert log.mag.shape == (2275, 3)


def _raw_lines(acc_ms2, gyr_dps, mag_ut):
    a = np.round(np.asarray(acc_ms2) / STANDARD_GRAVITY / MOTIONCAL_RAW["acc_g_per_count"]).astype(int)
    g = np.round(np.asarray(gyr_dps) / MOTIONCAL_RAW["gyr_dps_per_count"]).astype(int)
    m = np.round(np.asarray(mag_ut) / MOTIONCAL_RAW["mag_ut_per_count"]).astype(int)
    return [f"Raw:{','.join(str(v) for v in [*ai, *gi, *mi])}" for ai, gi, mi in zip(a, g, m)]


def test_motioncal_raw_and_uni_lines():
    """The real board's accelerometer printed as MotionCal's Raw: counts and as Uni: values (gyroscope
    and magnetometer columns: the board's gyroscope and a fixed field), as Adafruit's sketches print them."""
    rows = np.array([[float(v) for v in ln.split(",")] for ln in data_lines(POSE)[1:]])
    acc, gyr = rows[:, 1:4], rows[:, 5:8]  # gyroscope in rad/s
    mag = np.tile([20.0, -5.0, 40.0], (len(rows), 1))
    raw = _raw_lines(acc, np.degrees(gyr), mag)
    out, reader = read_lines(["Adafruit AHRS - IMU Calibration!", "Calibration filesys test", *raw, "Cal1:0,0,0"])
    assert reader.format.name == "raw" and len(out) == 200 and reader.skipped == 3
    assert reader.last_unreadable == "Cal1:0,0,0"
    log = to_log(out, reader.format)
    assert log.units == {"acc": "m/s^2", "gyr": "deg/s", "mag": "uT"} and not log.warnings
    step = MOTIONCAL_RAW["acc_g_per_count"] * STANDARD_GRAVITY
    assert np.abs(log.acc - acc).max() <= step / 2 + 1e-12
    np.testing.assert_allclose(log.mag, mag, atol=1e-12)
    uni = [f"Uni:{','.join(f'{v:.4f}' for v in [*a, *g, *m])}" for a, g, m in zip(acc, gyr, mag)]
    out, reader = read_lines(uni)
    assert reader.format.name == "uni" and reader.skipped == 0
    log = to_log(out, reader.format)
    np.testing.assert_allclose(log.acc, acc, atol=5e-5)
    assert log.units == {"acc": "m/s^2", "gyr": "rad/s", "mag": "uT"}


def test_a_chosen_format_skips_what_is_not_it():
    lines = data_lines(POSE)
    out, reader = read_lines(lines, "numbers")  # the header is not a reading of bare numbers
    assert reader.format is None
    assert len(out) == 0 and reader.skipped == len(lines)  # 8 columns are no bare-number layout
    out, reader = read_lines(lines, "raw")
    assert out == [] and reader.skipped == len(lines) and reader.last_unreadable == lines[-1]
    with pytest.raises(LogFormatError, match="use one of auto, raw, uni, csv, numbers"):
        BoardLineReader("motioncal")


def test_a_sensor_printed_as_zeros_is_left_out():
    """An MPU-6050 has no magnetometer: its Uni: lines print zeros there (static/sketches/mpu6050_uni)."""
    lines = [f"Uni:{a:.4f},0.1000,9.8000,0.01000,-0.00200,0.00300,0,0,0" for a in np.linspace(-0.1, 0.1, 30)]
    out, reader = read_lines(lines)
    assert reader.format.sensors == ("acc", "gyr") and set(out[0].values) == {"acc", "gyr"}
    assert to_log(out, reader.format).mag is None


def test_nothing_but_boot_text():
    out, reader = read_lines(BOOT * 10)
    assert out == [] and reader.format is None and reader.skipped == 30
    with pytest.raises(LogFormatError, match="check the baud rate"):
        to_log(out, numbers_format(3))


def test_log_written_as_received_reads_back_with_the_board_rate(tmp_path):
    lines = data_lines(ESP32)
    out, reader = read_lines(lines)
    path = tmp_path / "board.csv"
    writer = LogWriter(path, reader.format)
    writer.write(out[:100])
    writer.write(out[100:])
    writer.close()
    back = read_log(path)
    live = to_log(out, reader.format)
    np.testing.assert_array_equal(back.acc, live.acc)
    assert back.sampling_rate_hz == pytest.approx(live.sampling_rate_hz, rel=1e-12)
    with open(path) as f:
        header = next(csv.reader(f))
    assert header[0] == "timestamp_us" and header[1] == "acc_x"
    # lines without a time column: the arrival times in seconds
    out, reader = read_lines(
        _raw_lines([[0, 0, 9.8]] * 50, [[1, 2, 3]] * 50, [[30, 0, 20]] * 50), arrivals=np.arange(50) / 100.0
    )
    writer = LogWriter(tmp_path / "raw.csv", reader.format)
    writer.write(out)
    writer.close()
    back = read_log(tmp_path / "raw.csv")
    assert back.units == {"acc": "m/s^2", "gyr": "deg/s", "mag": "uT"}
    assert back.sampling_rate_hz == pytest.approx(100.0, rel=1e-6)


@pytest.mark.parametrize("burst_s", [1.0, 2.0])
def test_live_rate_counted_over_bursts_of_arrival(burst_s):
    """A board at 62.5 Hz whose lines arrive in bursts of 1 s and 2 s (each split in two reads 0.1 s apart,
    the host's delay varying by 50 ms): the rate is counted, never read from a burst's arrival."""
    rng = np.random.default_rng(4)
    rate, lines = StreamRate(), 0
    decided_at = None
    for k in range(10):
        t = k * burst_s + rng.uniform(0, 0.05)
        made = round(62.5 * (k + 1) * burst_s)
        first = (made - lines) // 2
        rate.arrive(first, t)
        rate.arrive(made - lines - first, t + 0.1)
        lines = made
        if decided_at is None and rate.rate_hz is not None:
            decided_at = t
    assert decided_at == pytest.approx(3 * burst_s, abs=0.2)  # the ends of the first and third bursts
    assert rate.rate_hz == pytest.approx(62.5, rel=0.01)
    # steady arrivals, every 16 ms: decided after a second
    steady = StreamRate()
    for k in range(100):
        steady.arrive(1, k * 0.016)
    assert steady.rate_hz == pytest.approx(62.5, rel=1e-6) and steady.span_s >= 1.0


def held_reader(hold_s: float, at_s: float = 0.5, hz: float = 100.0, until_s: float = 20.0):
    """Arrivals of a steady board at ``hz`` read every 16 ms whose reader was held for ``hold_s`` once at
    ``at_s`` (a page's thread busy drawing as the board connected): (readings, arrival) pairs."""
    t, n, out = 0.0, 0, []
    while t < until_s:
        t += hold_s if at_s <= t < at_s + 0.016 else 0.016
        n_new = round(hz * t) - n
        n += n_new
        out.append((n_new, t))
    return out


@pytest.mark.parametrize("hold_s", [0.4, 3.0])
def test_a_reader_held_once_is_not_waited_out(hold_s):
    """A reader held once in the first second (for 0.4 s, or 3 s): the arrivals after the pause decide the
    rate once they span what the window needs (a second, or twice the pause) and their halves agree, or the
    pause leaves the 8 s window. The rule once waited for that whatever the pause (the page showed no rate,
    its board's readings held back, for 8–15 s on a loaded host), and before that for ever."""
    rate, decided_at = StreamRate(), None
    for n_new, t in held_reader(hold_s):
        rate.arrive(n_new, t)
        if decided_at is None and rate.rate_hz is not None:
            decided_at = t
    # (the pause has left the window once the arrival before it has: 0.5 s + the window)
    assert decided_at == pytest.approx(
        min(0.5 + hold_s + max(RATE_MIN_S, RATE_STEPS * hold_s), 0.5 + RATE_WINDOW_S), abs=0.1
    )
    assert rate.rate_hz == pytest.approx(100, rel=0.01)


def test_a_host_hiccuping_now_and_then_decides_the_rate_right():
    """A board at 62.5 Hz read every 16 ms (±3 ms) by a host that hiccups for 50–500 ms about every 5 s,
    200 seeded runs: every rate decided within the window and a second, each within 2 % (a chunk's readings
    over a second's span); most within 2.2 s."""
    decided, errors = [], []
    for seed in range(200):
        rng = np.random.default_rng(seed)
        rate, t, due = StreamRate(), 0.0, 0.0
        while rate.rate_hz is None and t < 30:
            step = 0.016 + abs(rng.normal(0, 0.003)) + (rng.uniform(0.05, 0.5) if rng.random() < 0.003 else 0.0)
            t, due = t + step, due + 62.5 * step
            rate.arrive(int(due), t)
            due -= int(due)
        decided.append(t)
        errors.append(abs(rate.rate_hz / 62.5 - 1))
    assert max(decided) <= RATE_WINDOW_S + 1.0 and np.percentile(decided, 95) <= 2.2
    assert max(errors) < 0.02


def test_a_burst_read_late_by_a_loaded_reader_does_not_decide_the_rate():
    """Bursts of 1 s from a board at 100 Hz, the third read 0.15 s late (a loaded host: once seen as
    "rate 93.38 Hz"): the halves of the span disagree, and the rate is decided a burst later (a burst's end
    is known when the next one arrives), right."""
    rate = StreamRate()
    for k in range(6):
        rate.arrive(100, k + (0.15 if k == 2 else 0.0))
        if rate.rate_hz is not None:
            break
    assert k == 4 and rate.rate_hz == pytest.approx(100, rel=1e-9)


def test_a_board_time_column_wins_over_bursts():
    """Lines with the board's time column: its times decide the rate (the rule of uploads), however the
    lines arrived."""
    lines = [f"{4 * i},0.01,0.02,0.98" for i in range(500)]  # millis() at 250 Hz
    arrivals = np.repeat(np.arange(5) * 0.4, 100)  # 100 lines at once every 0.4 s
    out, reader = read_lines(lines, arrivals=arrivals)
    assert reader.format.time_col == 0
    assert board_rate(out, reader.format).sampling_rate_hz == pytest.approx(250.0, rel=1e-9)
