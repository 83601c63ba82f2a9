"""Writers of sample tables, fed a chunk of rows at a time (memory: one chunk, whatever the length).

The columns are named with their units, in the spelling trical's readers take from a header
(:mod:`app.io.readers.generic_csv`): ``time (s)``, ``acc_x (m/s^2)`` … ``gyr_x (rad/s)`` … ``mag_x (uT)`` …,
``temp_c``; a file written here reads back with the same units.

- CSV: comment lines (``# …``) say what was done (which sensors were corrected, which passed through), then the
  header row, then the numbers in the shortest form that reads back to the same float64 (pyarrow's writer).
- Parquet: the same column names; each field's metadata holds ``unit`` and ``corrected`` (``true``/``false``), the
  schema's metadata ``trical`` the comment lines as JSON.
- ``.npy``: a one-dimensional array of a structured dtype whose field names are the column names (so carry the
  units), float64 each; written as the rows come, its header's shape filled in at the end (no sidecar file).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import IO

import numpy as np

from ..errors import LogFormatError

FORMATS = ("csv", "parquet", "npy")
"""The formats samples are written in, by the output file's suffix unless named."""

SUFFIXES = {".csv": "csv", ".txt": "csv", ".parquet": "parquet", ".pq": "parquet", ".npy": "npy"}

MEDIA_TYPES = {"csv": "text/csv", "parquet": "application/vnd.apache.parquet", "npy": "application/octet-stream"}


@dataclass(frozen=True)
class Column:
    """One output column: its name (with its unit), its unit, the sensor it belongs to (``time``,
    ``temperature``, ``acc``, ``gyr``, ``mag``) and whether a calibration corrected it."""

    name: str
    unit: str
    sensor: str
    corrected: bool = False


def sensor_columns(sensor: str, unit: str, corrected: bool) -> list[Column]:
    """The x, y and z columns of a sensor in ``unit``: ``acc_x (m/s^2)``, …"""
    return [Column(f"{sensor}_{a} ({unit})", unit, sensor, corrected) for a in "xyz"]


TIME_COLUMN = Column("time (s)", "s", "time")
TEMPERATURE_COLUMN = Column("temp_c", "degC", "temperature")


def output_format(path: Path | str | None, fmt: str | None) -> str:
    """The format to write: ``fmt`` when given, else the output file's suffix.

    Raises
    ------
    LogFormatError
        A format that is not one of :data:`FORMATS`, or no format and a suffix that names none.
    """
    if fmt:
        if fmt not in FORMATS:
            raise LogFormatError(f"unknown output format {fmt!r}: give `output_format` as one of {', '.join(FORMATS)}")
        return fmt
    suffix = Path(path or "").suffix.lower()
    if suffix not in SUFFIXES:
        raise LogFormatError(
            f"the output's suffix {suffix or '(none)'!r} names no format: end its name in .csv, .parquet or .npy, "
            f"or give `output_format` (one of {', '.join(FORMATS)})"
        )
    return SUFFIXES[suffix]


class SampleWriter:
    """Write rows, a chunk at a time: :meth:`write` each chunk's columns (a list of 1-D arrays, in the order of
    ``columns``), then :meth:`close`."""

    def __init__(self, out: IO[bytes], columns: list[Column], comments: list[str]):
        self.out = out
        self.columns = columns
        self.comments = comments
        self.rows = 0

    def write(self, values: list[np.ndarray]) -> None:  # pragma: no cover - every writer defines it
        raise NotImplementedError

    def close(self) -> None:
        """Finish the file (the writer's footer or header)."""


class CsvWriter(SampleWriter):
    def __init__(self, out: IO[bytes], columns: list[Column], comments: list[str]):
        super().__init__(out, columns, comments)
        head = "".join(f"# {c}\n" for c in comments) + ",".join(c.name for c in columns) + "\n"
        out.write(head.encode("utf-8"))

    def write(self, values: list[np.ndarray]) -> None:
        import pyarrow as pa
        import pyarrow.csv as pacsv

        table = pa.table({f"c{i}": v for i, v in enumerate(values)})
        pacsv.write_csv(table, self.out, write_options=pacsv.WriteOptions(include_header=False))
        self.rows += len(values[0])


class ParquetWriter(SampleWriter):
    def __init__(self, out: IO[bytes], columns: list[Column], comments: list[str]):
        import pyarrow as pa
        import pyarrow.parquet as pq

        super().__init__(out, columns, comments)
        fields = [
            pa.field(c.name, pa.float64(), metadata={"unit": c.unit, "corrected": str(c.corrected).lower()})
            for c in columns
        ]
        self.schema = pa.schema(fields, metadata={"trical": json.dumps(comments)})
        self.writer = pq.ParquetWriter(out, self.schema)

    def write(self, values: list[np.ndarray]) -> None:
        import pyarrow as pa

        self.writer.write_table(pa.Table.from_arrays([pa.array(v) for v in values], schema=self.schema))
        self.rows += len(values[0])

    def close(self) -> None:
        self.writer.close()


NPY_HEADER_BYTES = 4096
"""Room kept for a ``.npy`` file's header (a multiple of 64, as numpy aligns it): written first with no rows, filled
in with the count at the end."""


class NpyWriter(SampleWriter):
    def __init__(self, out: IO[bytes], columns: list[Column], comments: list[str]):
        super().__init__(out, columns, comments)
        self.dtype = np.dtype([(c.name, "<f8") for c in columns])
        self.start = out.tell()
        out.write(self._header(0))

    def _header(self, rows: int) -> bytes:
        """NumPy's format 1.0 header (magic, version, length, the dict padded with spaces to a fixed size)."""
        text = repr({"descr": np.lib.format.dtype_to_descr(self.dtype), "fortran_order": False, "shape": (rows,)})
        room = NPY_HEADER_BYTES - 10
        if len(text) + 1 > room:
            raise LogFormatError("too many columns for a .npy header: write csv or parquet")
        body = (text + " " * (room - len(text) - 1) + "\n").encode("latin1")
        return b"\x93NUMPY\x01\x00" + len(body).to_bytes(2, "little") + body

    def write(self, values: list[np.ndarray]) -> None:
        rows = np.empty(len(values[0]), dtype=self.dtype)
        for c, v in zip(self.columns, values):
            rows[c.name] = v
        self.out.write(rows.tobytes())
        self.rows += len(rows)

    def close(self) -> None:
        end = self.out.tell()
        self.out.seek(self.start)
        self.out.write(self._header(self.rows))
        self.out.seek(end)


WRITERS: dict[str, type[SampleWriter]] = {"csv": CsvWriter, "parquet": ParquetWriter, "npy": NpyWriter}


def open_writer(out: IO[bytes], fmt: str, columns: list[Column], comments: list[str]) -> SampleWriter:
    """A writer of ``fmt`` (one of :data:`FORMATS`) on a binary file open for writing (seekable for ``.npy``)."""
    return WRITERS[output_format(None, fmt)](out, columns, comments)
