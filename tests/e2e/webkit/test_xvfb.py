"""Xvfb's start, which once hung the suite: Xvfb writes its display number and the newline in two
writes to the -displayfd pipe; a fixture that read once and closed the pipe between the two made
Xvfb's second write fail, Xvfb exit, and the WebDriver session wait for a browser for ever."""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import time

import pytest

from tests.e2e.webkit.conftest import XVFB, start_driver
from tests.processes import ProcessFailed, check_alive, read_line, start_xvfb, stop

STARTS = 25
BUSY = "import time\nend = time.monotonic() + 120\nwhile time.monotonic() < end: pass\n"


def test_a_line_written_in_two_parts_is_read_to_its_newline():
    read, write = os.pipe()

    def writer():
        os.write(write, b"17")
        time.sleep(0.3)  # the first read returns before this
        os.write(write, b"\n")

    thread = threading.Thread(target=writer)
    thread.start()
    try:
        assert read_line(read, timeout_s=5) == b"17\n"
    finally:
        thread.join(timeout=5)
        os.close(read)
        os.close(write)


def test_read_line_stops_at_end_of_file_and_at_its_time_bound():
    read, write = os.pipe()
    os.write(write, b"3")
    os.close(write)
    assert read_line(read, timeout_s=5) == b"3"  # the writer closed the pipe: no newline will come
    os.close(read)
    read, write = os.pipe()
    t0 = time.monotonic()
    assert read_line(read, timeout_s=0.3) == b""  # nothing written: back after the bound, not never
    assert 0.25 < time.monotonic() - t0 < 5
    os.close(read)
    os.close(write)


@pytest.fixture
def busy_cores():
    """Two busy loops, one per core of a two-core machine, ended after the test (or after 120 s)."""
    loops = [subprocess.Popen([sys.executable, "-c", BUSY]) for _ in range(2)]
    yield
    for loop in loops:
        stop(loop, timeout_s=5)


def test_xvfb_starts_many_times_in_a_row_under_load(busy_cores):
    """Each start gives a display number and leaves Xvfb running (the race lost it, now and then, on a
    loaded machine)."""
    displays = []
    for _ in range(STARTS):
        process, display, log = start_xvfb(XVFB, timeout_s=20)
        try:
            time.sleep(0.05)  # Xvfb's failing second write came right after the first
            check_alive("Xvfb", process, log, "after it wrote its display number")
            displays.append(display)
        finally:
            stop(process)
    assert len(displays) == STARTS and all(d[1:].isdigit() for d in displays)


def test_an_xvfb_that_cannot_start_fails_with_its_own_words(tmp_path):
    """An Xvfb that exits before it writes a display number (here: an option it does not know): a failure
    that says so and quotes Xvfb, at once rather than after the time bound."""
    fake = tmp_path / "Xvfb"
    fake.write_text(f'#!/bin/sh\nexec {XVFB} "$@" -no-such-option\n')
    fake.chmod(0o755)
    t0 = time.monotonic()
    with pytest.raises(ProcessFailed) as info:
        start_xvfb(str(fake), timeout_s=20)
    message = str(info.value)
    assert time.monotonic() - t0 < 10
    assert message.startswith("Xvfb wrote no display number") and "-no-such-option" in message, message


def test_a_browser_that_never_answers_fails_the_session_start_in_time(xvfb_display, tmp_path):
    """A MiniBrowser that starts but never answers WebKitWebDriver (as one without a display does):
    the session's start fails within its bound, naming WebKitWebDriver, instead of waiting for ever."""
    silent = tmp_path / "MiniBrowser"
    silent.write_text("#!/bin/sh\nexec sleep 30\n")
    silent.chmod(0o755)
    t0 = time.monotonic()
    with pytest.raises(ProcessFailed) as info:
        start_driver(xvfb_display, browser=silent, timeout_s=5)
    assert time.monotonic() - t0 < 30
    assert str(info.value).startswith("WebKitWebDriver started no MiniBrowser session within 5 s"), str(info.value)
