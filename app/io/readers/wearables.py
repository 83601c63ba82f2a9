"""Wearable device files (.cwa Axivity, .gt3x ActiGraph, .bin GENEActiv) through actipy — optional.

The decoding is actipy's (``actipy.read_device``; its Java parsers need a Java runtime, which
Debian's ``default-jre-headless`` provides).  It is an optional extra, never a run-time dependency:
``pip install 'trical[wearables]'`` enables it; without it these files are refused with a 415 that
says so.  trical asks actipy for the raw samples only — no low-pass filter, no gravity calibration,
no non-wear flags and no resampling — so that the auto-calibration of Farago et al. sees what the device
recorded, in g.  Compressed files (``.gz``, ``.zip``) are decompressed by actipy.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import LogFormatError
from ..log import LogData
from .timing import with_timing

WEARABLE_SUFFIXES = (".cwa", ".gt3x", ".bin")
BIN_MAGICS = (b"Device Identity", b"MDTC")
"""The first bytes of the .bin files actipy reads (its readers: a GENEActiv .bin's text header ``Device Identity``,
a Matrix .bin's ``MDTC`` signature); .bin is also ArduPilot's DataFlash log
(:data:`app.io.readers.table.BINARY_LOG_MAGICS`), and the name of many a binary of no format trical reads."""


def refuse_unknown_binary(path: Path, name: str) -> None:
    """Refuse a ``.bin`` file whose first bytes are none of the .bin formats trical reads (a binary of no known
    format), listing the formats trical reads (:data:`app.io.readers.kinds.FILE_KINDS`)."""
    from .kinds import formats_read

    suffixes = [s.lower() for s in Path(path).suffixes]
    if suffixes and suffixes[-1] in (".gz", ".zip"):
        return  # compressed: actipy decompresses it, and says what it finds
    suffix = suffixes[-1] if suffixes else ""
    with open(path, "rb") as f:
        head = f.read(16)
    if suffix == ".bin" and not head.startswith(BIN_MAGICS):
        raise LogFormatError(
            f"{name} is not a format trical reads: its first bytes ({head[:8].hex(' ')}) are none of the .bin "
            "formats (an ArduPilot DataFlash log, a GENEActiv or Matrix wearable's recording). trical reads: "
            f"{formats_read()}",
            status=415,
        )


def is_wearable(path: Path) -> bool:
    """True for ``.cwa``, ``.gt3x``, ``.bin`` (optionally ``.gz``/``.zip`` compressed)."""
    suffixes = [s.lower() for s in Path(path).suffixes]
    if suffixes and suffixes[-1] in (".gz", ".zip"):
        suffixes = suffixes[:-1]
    return bool(suffixes) and suffixes[-1] in WEARABLE_SUFFIXES


def read_wearable_log(
    path: Path, *, sampling_rate_hz: float | None = None, units: dict[str, str] | None = None, name: str = "the file"
) -> LogData:
    """Read a wearable device file with actipy into samples in g.

    Raises
    ------
    LogFormatError
        actipy is not installed (415, with the command that enables it), or it cannot read the file.
    """
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(2, "No such file", str(path))
    refuse_unknown_binary(path, name)
    try:
        import actipy
    except ImportError:
        raise LogFormatError(
            f"{name} is a wearable device file ({''.join(path.suffixes)}); reading it needs the optional "
            "actipy package and a Java runtime: pip install 'trical[wearables]' (and apt-get install "
            "default-jre-headless), or export the samples to .npy, Parquet or CSV",
            status=415,
        ) from None
    if (units or {}).get("acc") not in (None, "g"):
        raise LogFormatError(f"{name}: wearable files are read in g; leave the unit out or give g")
    try:
        data, info = actipy.read_device(
            str(path), lowpass_hz=None, calibrate_gravity=False, detect_nonwear=False, resample_hz=None, verbose=False
        )
    except Exception as exc:  # actipy raises many kinds of errors on a bad file
        raise LogFormatError(f"{name} could not be read as a wearable device file: {exc}", status=415) from None
    acc = data[["x", "y", "z"]].to_numpy(dtype=np.float32)
    rate = float(info.get("SampleRate") or 0) or None  # the device's stated rate; the caller's wins
    time_s = np.asarray((data.index - data.index[0]).total_seconds(), dtype=float) if len(data) else None
    return with_timing(
        LogData(
            acc=acc,
            gyr=None,
            mag=None,
            time_s=time_s,
            sampling_rate_hz=rate,
            units={"acc": "g"},
            format=f"wearable:{info.get('Device', path.suffix.lstrip('.'))}",
            columns=["x", "y", "z"],
        ),
        sampling_rate_hz,
        name,
    )
