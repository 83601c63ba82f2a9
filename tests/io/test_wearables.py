"""Wearable device files through the optional actipy (app/io/readers/wearables.py)."""

from __future__ import annotations

import sys
import types

import numpy as np
import pytest

from app.io.errors import LogFormatError
from app.io.readers.arrays import read_array_log as read_log
from app.io.readers.wearables import is_wearable


def test_suffixes():
    assert is_wearable("a.cwa") and is_wearable("b.GT3X") and is_wearable("c.bin") and is_wearable("d.cwa.gz")
    assert not is_wearable("e.csv") and not is_wearable("f.npy")


def test_without_actipy_the_file_is_refused_with_the_way_to_enable_it(tmp_path, monkeypatch):
    f = tmp_path / "rec.cwa"
    f.write_bytes(b"\x00" * 100)
    monkeypatch.setitem(sys.modules, "actipy", None)  # import actipy → ImportError
    with pytest.raises(LogFormatError, match=r"pip install 'trical\[wearables\]'") as err:
        read_log(f)
    assert err.value.status == 415


def test_samples_come_raw_from_actipy(tmp_path, monkeypatch):
    import pandas as pd  # the test extras install actipy, and pandas with it

    calls = {}

    def read_device(path, **kw):
        calls.update(kw)
        idx = pd.date_range("2026-01-01", periods=1000, freq="10ms")
        df = pd.DataFrame(
            {"x": np.zeros(1000), "y": np.zeros(1000), "z": np.ones(1000), "temperature": 20.0}, index=idx
        )
        return df, {"SampleRate": 100.0, "Device": "Axivity"}

    monkeypatch.setitem(sys.modules, "actipy", types.SimpleNamespace(read_device=read_device))
    f = tmp_path / "rec.cwa"
    f.write_bytes(b"\x00")
    log = read_log(f)
    assert calls == dict(
        lowpass_hz=None, calibrate_gravity=False, detect_nonwear=False, resample_hz=None, verbose=False
    )
    assert log.acc.shape == (1000, 3) and log.units == {"acc": "g"} and log.sampling_rate_hz == 100.0
    assert log.format == "wearable:Axivity" and log.time_s[-1] == pytest.approx(9.99)


def test_an_unreadable_device_file_is_a_415(tmp_path):
    import shutil

    import actipy  # noqa: F401  the test extras install it; `make test` installs Java (system-deps)

    assert shutil.which("java"), "actipy's readers need a Java runtime: apt-get install default-jre-headless"
    f = tmp_path / "broken.cwa"
    f.write_bytes(np.random.default_rng(0).bytes(2000))
    with pytest.raises(LogFormatError, match="could not be read as a wearable") as err:
        read_log(f)
    assert err.value.status == 415
