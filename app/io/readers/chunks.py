"""A recording read in chunks of rows, so that what is done with each (a calibration applied, rows written) costs
a chunk of memory whatever the recording's length (a week of wear at 100 Hz is 60.5 M rows).

How the file is read is decided once, as :func:`app.io.readers.read_log` decides it, on its head (its first
:data:`HEAD_LINES` lines for a text log: the format, the columns, the units, the sign); then:

- a generic CSV (``format`` ``csv``) is streamed: pyarrow's incremental reader over the columns
  :func:`app.io.readers.generic_csv.csv_columns` names, each block's rows checked as the whole read checks them
  (rows whose sensors are all empty dropped, a partly empty or non-numeric row refused naming its line), then
  scaled and signed as the head's read decided (counts per g, gauss into µT, iOS's sign: ``LogData.scales`` and
  ``sign``), the time in seconds since the first row;
- a ``.npy`` array is memory-mapped by its reader and taken a slice at a time (an N×4 array's time column is
  turned into seconds whole by the reader: 8 bytes a row);
- a Parquet file is read a batch of rows at a time (pyarrow's ``iter_batches``), its columns and units decided by
  :func:`read_log` on a Parquet file of its first rows;
- every other file (a phone app's export, a flight log, a wearable's binary, a zip, JSON) is read whole by
  :func:`read_log`, then handed on in chunks; :attr:`ChunkedLog.streamed` is False and a note says so.
"""

from __future__ import annotations

import dataclasses
import itertools
import tempfile
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import LogFormatError
from ..log import LogData
from . import parse_columns, read_log
from .arrays import PARQUET_SUFFIXES
from .generic_csv import CSV, csv_columns, map_columns
from .read_options import ReadOptions
from .table import BAD_LINE, _csv_source, first_bad_line
from .timing import time_scale as infer_time_scale

CHUNK_ROWS = 1 << 18
"""Rows per chunk by default: 262 144 (a little under 45 minutes at 100 Hz), about 8 MB per three float64 columns."""

MAX_BLOCK_BYTES = 1 << 20
"""The largest block of a CSV read at a time (its rows are a chunk): pyarrow's streaming reader keeps several
blocks read ahead, so the process's memory grows with the block (a week at 100 Hz: ~140 MB peak with 1 MB blocks,
~270 MB with 4 MB), and no faster beyond it."""

HEAD_LINES = 10_000
"""Lines of a text log its reading is decided on (format, columns, units, sign)."""

SENSORS = ("acc", "gyr", "mag")


@dataclass(frozen=True)
class Chunk:
    """Consecutive rows of a recording: each present sensor's (n, 3) samples in the log's units, the seconds since
    the recording's first sample and the temperature (°C), when it has them."""

    sensors: dict[str, np.ndarray]
    time_s: np.ndarray | None = None
    temperature_c: np.ndarray | None = None

    @property
    def rows(self) -> int:
        return int(next(iter(self.sensors.values())).shape[0])


@dataclass(frozen=True)
class ChunkedLog:
    """A recording to be read in chunks.

    Attributes
    ----------
    log : LogData
        The reader's decisions (format, units, columns, notes), of the file's head when :attr:`streamed` (its
        arrays are the head's), else of the whole file.
    streamed : bool
        Whether the file is read a chunk at a time (False: read whole, then handed on in chunks).
    has_time, has_temperature : bool
        Whether each chunk holds ``time_s`` and ``temperature_c``.
    """

    log: LogData
    streamed: bool
    has_time: bool
    has_temperature: bool
    _chunks: Callable[[], Iterator[Chunk]]

    @property
    def sensors(self) -> list[str]:
        return self.log.channels

    def chunks(self) -> Iterator[Chunk]:
        """The recording's rows, in order, a chunk at a time."""
        return self._chunks()


def read_in_chunks(
    path: Path,
    options: ReadOptions = ReadOptions(),
    *,
    name: str = "the file",
    chunk_rows: int = CHUNK_ROWS,
    head_lines: int = HEAD_LINES,
) -> ChunkedLog:
    """A recording read in chunks of about ``chunk_rows`` rows, its units, columns and sign those
    :func:`app.io.readers.read_log` decides.

    Parameters
    ----------
    path : pathlib.Path
    options : ReadOptions
        How to read it, as for :func:`app.io.readers.read_log`.
    name : str
        How to call the file in messages.
    chunk_rows : int
        Rows per chunk at most (a CSV's chunks are pyarrow's blocks, sized to about this many rows and at most
        :data:`MAX_BLOCK_BYTES`).
    head_lines : int
        Lines of a text log its reading is decided on; a file no longer than that is read whole.

    Raises
    ------
    LogFormatError
        What :func:`read_log` refuses; a line of a streamed CSV that is not numbers in a used column, or is partly
        empty, when its chunk is reached (naming its line).
    """
    path = Path(path)
    chunk_rows = max(1, int(chunk_rows))
    if path.suffix.lower() in PARQUET_SUFFIXES:
        return _streamed_parquet(path, options, name, chunk_rows, head_lines)
    if path.suffix.lower() == ".npy" or not _is_text(path):
        return _whole(read_log(path, options, name=name), chunk_rows, streamed=path.suffix.lower() == ".npy")
    head, lines = _read_head(path, options, name, head_lines)
    if lines < head_lines:  # the head is the whole file
        return _whole(read_log(path, options, name=name), chunk_rows, streamed=False, small=True)
    columns = parse_columns(options.columns) if options.columns else None
    if head.format != CSV or head.parts or head.flight is not None or not _linear(head.scales):
        return _whole(read_log(path, options, name=name), chunk_rows, streamed=False)
    return _streamed_csv(path, head, options, columns, name, chunk_rows)


def _linear(scales: dict[str, dict[str, Any]] | None) -> bool:
    """Whether the reader's scaling of the numbers (counts, gauss) is a factor that each chunk can take."""
    return all(s.get("op") in ("*", "/") for s in (scales or {}).values())


def _is_text(path: Path) -> bool:
    """A text log (a CSV and its kin) whose first lines read as the whole would, not a zip, an array, a flight log,
    a wearable's binary or JSON (whose head is not JSON)."""
    with open(path, "rb") as f:
        start = f.read(4096)
    first = start.lstrip(b"\xef\xbb\xbf \t\r\n")[:1]
    return b"\x00" not in start and not start.startswith(b"PK") and first not in (b"[", b"{")


def _read_head(path: Path, options: ReadOptions, name: str, head_lines: int) -> tuple[LogData, int]:
    """The log its first ``head_lines`` lines make, read by :func:`read_log` (its decisions are the file's), and
    how many lines that head holds."""
    with tempfile.TemporaryDirectory(prefix="trical-head-") as tmp:
        head = Path(tmp) / path.name
        with open(path, "rb") as src, open(head, "wb") as out:
            lines = 0
            for line in itertools.islice(src, head_lines):
                out.write(line)
                lines += 1
        return read_log(head, options, name=name), lines


def _whole(log: LogData, chunk_rows: int, *, streamed: bool, small: bool = False) -> ChunkedLog:
    """A log read whole (a ``.npy`` memory-mapped), handed on in slices of ``chunk_rows``."""
    notes = log.notes
    if not streamed and not small:
        notes += (f"read whole: {log.format} files are not read in chunks (a generic CSV, Parquet and .npy are)",)
    n = log.n_samples

    def chunks() -> Iterator[Chunk]:
        for s in range(0, n, chunk_rows):
            e = min(n, s + chunk_rows)
            yield Chunk(
                {k: np.asarray(getattr(log, k)[s:e], dtype=float) for k in log.channels},
                None if log.time_s is None else np.asarray(log.time_s[s:e], dtype=float),
                None if log.temperature_c is None else np.asarray(log.temperature_c[s:e], dtype=float),
            )

    return ChunkedLog(
        _replace_notes(log, notes), streamed, log.time_s is not None, log.temperature_c is not None, chunks
    )


def _replace_notes(log: LogData, notes: tuple[str, ...]) -> LogData:
    return dataclasses.replace(log, notes=notes)


def _streamed_csv(
    path: Path,
    head: LogData,
    options: ReadOptions,
    columns: dict[str, str] | list[str] | None,
    name: str,
    chunk_rows: int,
) -> ChunkedLog:
    """A generic CSV read a block at a time by pyarrow, its columns as the whole read takes them."""
    table = csv_columns(
        path,
        name,
        column_map=columns if isinstance(columns, dict) else None,
        column_names=columns if isinstance(columns, list) else None,
    )
    layout = table.layout
    sensors = {s: [table.channels[s][a] for a in "xyz"] for s in SENSORS if s in table.channels}
    if sorted(sensors) != sorted(head.channels):  # the reader kept other sensors than the columns name: read whole
        return _whole(read_log(path, options, name=name), chunk_rows, streamed=False)
    time_col = table.time_col if head.time_s is not None else None
    stated_scale = table.time_scale
    # The reader's scaling (counts into g, gauss into µT) and sign (iOS), as it applied them to the whole file.
    factors = {s: (str(v["op"]), float(v["value"])) for s, v in (head.scales or {}).items() if s in sensors}
    if head.sign != 1 and "acc" in sensors:
        op, k = factors.get("acc", ("*", 1.0))
        factors["acc"] = (op, k * head.sign)
    used = [c for group in sensors.values() for c in group]
    wanted = used + [c for c in (time_col, table.temp_col) if c is not None]
    head_bytes = sum(len(line) + 1 for line in table.text.splitlines()[: layout.skip_lines + 200])
    per_line = max(8, head_bytes // max(1, min(200 + layout.skip_lines, len(table.text.splitlines()))))
    # pyarrow's reader reads several blocks ahead: memory grows with the block, not with the file.
    block = min(MAX_BLOCK_BYTES, max(4096, per_line * chunk_rows))

    def chunks() -> Iterator[Chunk]:
        import pyarrow as pa
        import pyarrow.csv as pacsv

        names = [f"c{i}" for i in range(len(layout.names))]
        done = 0
        t0: float | None = None
        time_scale = stated_scale
        with _csv_source(path, layout.delimiter) as source:
            try:
                reader = pacsv.open_csv(
                    source,
                    read_options=pacsv.ReadOptions(skip_rows=layout.skip_lines, column_names=names, block_size=block),
                    parse_options=pacsv.ParseOptions(delimiter=layout.delimiter, ignore_empty_lines=True),
                    convert_options=pacsv.ConvertOptions(
                        include_columns=[names[c] for c in wanted],
                        column_types={names[c]: pa.float64() for c in wanted},
                        null_values=["", "nan", "NaN", "NA"],
                        strings_can_be_null=False,
                        decimal_point=layout.decimal,
                    ),
                )
                for batch in reader:
                    values = {c: batch.column(names[c]) for c in wanted}
                    chunk = _checked(values, used, sensors, layout.names, name, layout.skip_lines + 1 + done)
                    done += batch.num_rows
                    if chunk is None:
                        continue
                    for s, (op, k) in factors.items():
                        chunk[0][s] = chunk[0][s] / k if op == "/" else chunk[0][s] * k
                    time_s = None
                    if time_col is not None:
                        t = np.asarray(values[time_col].to_numpy(zero_copy_only=False), dtype=float)[chunk[1]]
                        if t0 is None:  # the first rows: where the seconds start, and their unit when unnamed
                            t0 = float(t[0])
                            time_scale = time_scale or infer_time_scale(t)[0]
                        time_s = (t - t0) * float(time_scale or 1.0)
                    temp = None
                    if table.temp_col is not None:
                        temp = np.asarray(values[table.temp_col].to_numpy(zero_copy_only=False), dtype=float)[chunk[1]]
                    yield Chunk(chunk[0], time_s, temp)
            except (pa.ArrowInvalid, pa.ArrowTypeError, UnicodeDecodeError):
                detail = first_bad_line(
                    path,
                    layout.skip_lines,
                    layout.delimiter,
                    layout.decimal,
                    wanted,
                    layout.names,
                    layout.skip_lines + 1,
                )
                raise LogFormatError(f"{name}: {detail}: every used column must hold numbers", code=BAD_LINE) from None

    notes = head.notes + (f"read in chunks of about {max(1, block // per_line)} rows ({block // 1024} kB)",)
    return ChunkedLog(
        _replace_notes(head, notes),
        True,
        time_col is not None,
        table.temp_col is not None and head.temperature_c is not None,
        chunks,
    )


def _checked(
    values: dict[int, Any],
    used: list[int],
    sensors: dict[str, list[int]],
    labels: list[str],
    name: str,
    first_line: int,
) -> tuple[dict[str, np.ndarray], np.ndarray] | None:
    """A block's sensors as float arrays, rows whose sensors are all empty dropped (as the whole read drops them),
    and which rows were kept; None when none is. A partly empty or non-finite row is refused naming its line."""
    nulls = {c: values[c].is_null().to_numpy(zero_copy_only=False) for c in used}
    empty = np.logical_and.reduce([nulls[c] for c in used])
    keep = ~empty
    arrays: dict[int, np.ndarray] = {}
    for c in used:
        arr = np.asarray(values[c].to_numpy(zero_copy_only=False), dtype=float)
        bad = (nulls[c] & keep) | (~np.isfinite(arr) & keep)
        if bad.any():
            row = int(np.flatnonzero(bad)[0])
            raise LogFormatError(
                f"{name}: line {first_line + row} (if the file has no blank lines) has an empty or non-finite value "
                f"in column {labels[c]!r}: fill or remove that line",
                code=BAD_LINE,
            )
        arrays[c] = arr[keep] if empty.any() else arr
    if not keep.any():
        return None
    return {s: np.column_stack([arrays[c] for c in group]) for s, group in sensors.items()}, keep


def _streamed_parquet(path: Path, options: ReadOptions, name: str, chunk_rows: int, head_lines: int) -> ChunkedLog:
    """A Parquet table read a batch of rows at a time; what :func:`read_log` decides (units, sign, the time column)
    decided on a file of its first ``head_lines`` rows."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    try:
        pf = pq.ParquetFile(path)
    except (pa.ArrowInvalid, OSError):
        return _whole(read_log(path, options, name=name), chunk_rows, streamed=False)  # its refusal, read_log's
    if pf.metadata.num_rows <= head_lines:
        return _whole(read_log(path, options, name=name), chunk_rows, streamed=False, small=True)
    with tempfile.TemporaryDirectory(prefix="trical-head-") as tmp:
        first = Path(tmp) / path.name
        pq.write_table(pa.Table.from_batches([next(pf.iter_batches(batch_size=head_lines))]), first)
        head = read_log(first, options, name=name)
    names = list(pf.schema_arrow.names)
    channels, time_col, time_scale, _ = map_columns(names)
    sensors = {s: [names[channels[s][a]] for a in "xyz"] for s in head.channels}
    time_name = names[time_col] if time_col is not None and head.time_s is not None else None
    wanted = [c for group in sensors.values() for c in group] + ([time_name] if time_name else [])

    def chunks() -> Iterator[Chunk]:
        t0: float | None = None
        scale = time_scale
        for batch in pf.iter_batches(batch_size=chunk_rows, columns=wanted):
            arrays = {
                s: head.sign * np.column_stack([np.asarray(batch.column(c), dtype=float) for c in group])
                if s == "acc"
                else np.column_stack([np.asarray(batch.column(c), dtype=float) for c in group])
                for s, group in sensors.items()
            }
            time_s = None
            if time_name is not None:
                col = batch.column(time_name)
                if pa.types.is_timestamp(col.type):  # as the reader: nanoseconds relative to the first, then seconds
                    t = np.asarray(col.cast(pa.timestamp("ns")).to_numpy(zero_copy_only=False)).astype(np.int64)
                    t0 = float(t[0]) if t0 is None else t0
                    time_s = (t - np.int64(t0)).astype(float) * 1e-9
                else:
                    tf = np.asarray(col, dtype=float)
                    if t0 is None:
                        t0 = float(tf[0])
                        scale = scale or infer_time_scale(tf)[0]
                    time_s = (tf - t0) * float(scale or 1.0)
            yield Chunk(arrays, time_s, None)

    notes = head.notes + (f"read in chunks of {chunk_rows} rows",)
    return ChunkedLog(_replace_notes(head, notes), True, time_name is not None, False, chunks)
