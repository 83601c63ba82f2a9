"""Array logs: NumPy ``.npy`` (N×3, or N×4 with time first) and Parquet files.

``.npy`` files are memory-mapped, never loaded: ``LogData.acc`` is a view of the map (float32 stays
float32), so a week at 100 Hz (60.5 M samples, 726 MB as float32) costs no memory until a chunk of
it is read.  An N×4 array holds the time in its first column (seconds, or milliseconds … nanoseconds
inferred from the step, as for CSV logs).

Parquet files are read with pyarrow; the columns are recognised by the same names as CSV headers
(:mod:`app.io.readers.generic_csv`: ``acc_x``/``ax``/``x``…, an optional time column ``time``/``time_s``/
``timestamp``…).  A timestamp column of Arrow type ``timestamp`` is converted to seconds.

:func:`read_array_log` picks the reader from the file name (``.npy``, ``.parquet``/``.pq``, the wearable
formats ``.cwa``/``.gt3x``/``.bin`` through the optional actipy (:mod:`app.io.readers.wearables`), else CSV).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from app.calibration.shared.headlines import SENSOR_WORDS

from ..errors import LogFormatError
from ..log import UNITS, LogData
from .generic_csv import map_columns, read_csv_log
from .timing import time_scale as infer_time_scale
from .timing import with_timing

NPY_SUFFIXES = (".npy",)
PARQUET_SUFFIXES = (".parquet", ".pq")
CSV_SUFFIXES = (".csv", ".txt", ".tsv")
SUFFIXES = NPY_SUFFIXES + PARQUET_SUFFIXES + CSV_SUFFIXES + (".cwa", ".gt3x", ".bin")


def _unit(units: dict[str, str] | None) -> str:
    unit = (units or {}).get("acc") or UNITS["acc"][0]
    if unit not in UNITS["acc"]:
        raise LogFormatError(f"acc unit {unit!r} is not one of {', '.join(UNITS['acc'])}")
    return unit


def read_npy_log(
    path: Path, *, sampling_rate_hz: float | None = None, units: dict[str, str] | None = None, name: str = "the file"
) -> LogData:
    """Memory-map a ``.npy`` array of samples (N×3 ``x, y, z`` or N×4 ``time, x, y, z``).

    Parameters
    ----------
    path : pathlib.Path
    sampling_rate_hz : float, optional
        Required for N×3 arrays; overrides the rate an N×4 array's time column gives.
    units : dict, optional
        ``{"acc": "g"}``; ``m/s^2`` by default, as for CSV logs.
    name : str
        How to call the file in messages.

    Raises
    ------
    LogFormatError
        Not a ``.npy`` file (415), not a numeric N×3/N×4 array, no rows, no sampling rate.
    """
    path = Path(path)
    with open(path, "rb") as f:
        magic = f.read(6)
    if magic != b"\x93NUMPY":
        raise LogFormatError(
            f"{name} is not a readable .npy array (it does not start with NumPy's magic string): save the "
            "samples with numpy.save as an N×3 (x, y, z) or N×4 (time, x, y, z) float array",
            status=415,
        )
    try:
        arr = np.load(path, mmap_mode="r", allow_pickle=False)
    except FileNotFoundError:
        raise
    except (ValueError, OSError, EOFError) as exc:
        raise LogFormatError(
            f"{name} is not a readable .npy array ({exc}): save the samples with numpy.save as an "
            "N×3 (x, y, z) or N×4 (time, x, y, z) float array",
            status=415,
        ) from None
    if not isinstance(arr, np.ndarray):
        raise LogFormatError(
            f"{name} holds several arrays (.npz?): save one N×3 or N×4 array with numpy.save", status=415
        )
    if arr.ndim != 2 or arr.shape[1] not in (3, 4):
        held = (
            f"{arr.size} numbers in a single row"
            if arr.ndim <= 1
            else f"rows of {arr.shape[1]} numbers"
            if arr.ndim == 2
            else f"a {arr.ndim}-dimensional block of numbers"
        )
        raise LogFormatError(
            f"{name} holds {held}: save one row per sample with 3 numbers (x, y, z) or 4 (time, x, y, z), "
            "e.g. numpy.save(path, samples) with samples of 3 or 4 columns"
        )
    if arr.dtype.kind not in "fiu":
        raise LogFormatError(f"{name} holds {arr.dtype} values: expected numbers (float32 or float64)")
    if arr.shape[0] == 0:
        raise LogFormatError(f"{name} holds no samples")
    time = None
    acc = arr
    if arr.shape[1] == 4:
        time = np.asarray(arr[:, 0], dtype=float)
        acc = arr[:, 1:4]
    time_s = None
    if time is not None and len(time) >= 2:
        time_s = time - time[0]  # scaled in place: one array the length of the column, not two
        scale = infer_time_scale(time)[0]
        if scale != 1.0:
            time_s *= scale
    return with_timing(
        LogData(
            acc=acc,
            gyr=None,
            mag=None,
            time_s=time_s,
            sampling_rate_hz=None,
            units={"acc": _unit(units)},
            format="npy",
            columns=["time", "x", "y", "z"][4 - arr.shape[1] :],
        ),
        sampling_rate_hz,
        name,
    )


def read_parquet_log(
    path: Path, *, sampling_rate_hz: float | None = None, units: dict[str, str] | None = None, name: str = "the file"
) -> LogData:
    """Read a Parquet table of samples (columns named as in CSV logs).

    Raises
    ------
    LogFormatError
        Not a Parquet file (415), no accelerometer columns, non-numeric or missing values, no rate.
    """
    import pyarrow as pa
    import pyarrow.parquet as pq

    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(2, "No such file", str(path))
    try:
        pf = pq.ParquetFile(path)
    except (pa.ArrowInvalid, OSError) as exc:
        raise LogFormatError(f"{name} is not a readable Parquet file ({exc})", status=415) from None
    names = list(pf.schema_arrow.names)
    channels, time_col, time_scale, header_units = map_columns(names)
    cols = [names[channels["acc"][a]] for a in "xyz"] if "acc" in channels else []
    # Gyroscope and magnetometer columns beside it (or alone), when all three axes are there (noise, cube).
    others = {
        s: [names[channels[s][a]] for a in "xyz"] for s in ("gyr", "mag") if set(channels.get(s, {})) >= set("xyz")
    }
    wanted = (
        cols + [c for group in others.values() for c in group] + ([names[time_col]] if time_col is not None else [])
    )
    try:
        table = pf.read(columns=wanted)
    except (pa.ArrowInvalid, OSError) as exc:
        raise LogFormatError(f"{name}: the columns cannot be read ({exc})") from None
    if table.num_rows == 0:
        raise LogFormatError(f"{name} has no rows")

    def numbers(group: list[str], what: str) -> np.ndarray:
        try:
            return np.column_stack([table.column(c).to_numpy(zero_copy_only=False).astype(float) for c in group])
        except (ValueError, TypeError, pa.ArrowInvalid):
            raise LogFormatError(f"{name}: the {what} columns {group} must hold numbers") from None

    acc = numbers(cols, SENSOR_WORDS["acc"]) if cols else None
    extra = {s: numbers(group, SENSOR_WORDS[s]) for s, group in others.items()}
    time = None
    if time_col is not None:
        col = table.column(names[time_col])
        if pa.types.is_timestamp(col.type):
            ns = col.cast(pa.timestamp("ns")).to_numpy(zero_copy_only=False).astype("datetime64[ns]").astype(np.int64)
            time, time_scale = (ns - ns[0]).astype(float), 1e-9  # relative first: float64 of epoch ns loses µs
        else:
            time = col.to_numpy(zero_copy_only=False).astype(float)
    unit = (units or {}).get("acc") or header_units.get("acc") or UNITS["acc"][0]
    sensor_units = {"acc": _unit({"acc": unit})} if acc is not None else {}
    for s in extra:
        sensor_units[s] = (units or {}).get(s) or header_units.get(s) or UNITS[s][0]
        if sensor_units[s] not in UNITS[s]:
            raise LogFormatError(f"{s} unit {sensor_units[s]!r} is not one of {', '.join(UNITS[s])}")
    return with_timing(
        LogData(
            acc=acc,
            gyr=extra.get("gyr"),
            mag=extra.get("mag"),
            time_s=None
            if time is None or len(time) < 2
            else (time - time[0]) * (time_scale or infer_time_scale(time)[0]),
            sampling_rate_hz=None,
            units=sensor_units,
            format="parquet",
            columns=names,
        ),
        sampling_rate_hz,
        name,
    )


def is_array_file(path: Path) -> bool:
    """True for the binary sample files this module reads (``.npy``, Parquet, wearable formats)."""
    from .wearables import is_wearable

    return Path(path).suffix.lower() in NPY_SUFFIXES + PARQUET_SUFFIXES or is_wearable(path)


def read_array_log(
    path: Path, *, sampling_rate_hz: float | None = None, units: dict[str, str] | None = None, name: str | None = None
) -> LogData:
    """Read a binary sample file, chosen by the file name's suffix (CSV when none matches)."""
    path = Path(path)
    name = name or str(path)
    suffix = path.suffix.lower()
    if suffix in NPY_SUFFIXES:
        return read_npy_log(path, sampling_rate_hz=sampling_rate_hz, units=units, name=name)
    if suffix in PARQUET_SUFFIXES:
        return read_parquet_log(path, sampling_rate_hz=sampling_rate_hz, units=units, name=name)
    from .wearables import is_wearable, read_wearable_log

    if is_wearable(path):
        return read_wearable_log(path, sampling_rate_hz=sampling_rate_hz, units=units, name=name)
    return read_csv_log(path, sampling_rate_hz=sampling_rate_hz, units=units, name=name)
