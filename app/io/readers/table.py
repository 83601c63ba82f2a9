"""Shared pieces of the format readers: the sniffed head of an upload, zip members, numeric columns.

The one CSV stack of :mod:`app.io`: the readers of :mod:`app.io.readers` (and the array readers'
CSV fallback, :mod:`app.io.readers.arrays`) see an upload through :class:`Sniff` (its first bytes as text, or
the member names of a zip), read their numeric columns with :func:`read_columns` (pyarrow's CSV
reader, from a file or from bytes, with the delimiter and the decimal mark: phyphox writes ``1,5``
with ``;`` separators); the sampling rate is decided in :mod:`.timing`.
"""

from __future__ import annotations

import contextlib
import csv
import io
import itertools
import zipfile
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, BinaryIO

import numpy as np

from ..errors import LogFormatError

SNIFF_BYTES = 64 * 1024
ZIP_MAGIC = b"PK\x03\x04"
BINARY_LOG_MAGICS = (b"ULog\x01\x12\x35", b"\xa3\x95\x80")
"""The first bytes of the binary logs read (PX4 ULog's file header; an ArduPilot DataFlash log's first
message, the FMT message, type 0x80, after the 0xA3 0x95 message header)."""
MAX_UNZIPPED_BYTES = 512 << 20
"""A zip member above this size (uncompressed) is refused rather than expanded in memory."""


@dataclass(frozen=True)
class Sniff:
    """What format detection looks at: the head of a text file, the member names of a zip, or the first
    bytes of a binary log (``head``: a flight controller's, recognised by its magic)."""

    name: str
    text: str = ""
    members: tuple[str, ...] | None = None
    lines: list[str] = field(default_factory=list)
    head: bytes = b""

    @property
    def is_zip(self) -> bool:
        return self.members is not None


def sniff(path: Path, name: str) -> Sniff:
    """Read the head of ``path`` (or its zip directory) for format detection."""
    with open(path, "rb") as f:
        head = f.read(SNIFF_BYTES)
    if head.startswith(ZIP_MAGIC):
        try:
            with zipfile.ZipFile(path) as zf:
                members = tuple(i.filename for i in zf.infolist() if not i.is_dir())
        except zipfile.BadZipFile:
            raise LogFormatError(
                f"{name} starts like a zip archive but cannot be opened: upload the "
                "export again (the zip may be cut short)",
                status=415,
            ) from None
        return Sniff(name=name, members=members)
    if head.startswith(BINARY_LOG_MAGICS):
        return Sniff(name=name, head=head[:16])
    text = decode_head(head, name)
    return Sniff(name=name, text=text, lines=text.splitlines()[:200])


def decode_head(head: bytes, name: str) -> str:
    """The head as text; binary or non-UTF-8 files are refused with status 415."""
    if not head.strip():
        raise LogFormatError(f"{name} is empty: upload a CSV with a header row and one sample per line")
    from .kinds import formats_read

    if b"\x00" in head:
        raise LogFormatError(
            f"{name} is not a text file (it holds NUL bytes), and not a format trical reads: upload a CSV log "
            f"with a header row, or a zip export of phyphox or Sensor Logger. trical reads: {formats_read()}",
            status=415,
        )
    try:
        return head.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        if exc.start < len(head) - 4:  # a character cut by the sniff window is fine
            raise LogFormatError(
                f"{name} is not UTF-8 text (byte {exc.start}), and not a format trical reads: upload a CSV log "
                f"with a header row. trical reads: {formats_read()}",
                status=415,
            ) from None
        return head[: exc.start].decode("utf-8-sig")


def find_member(members: Iterable[str] | None, *names: str) -> str | None:
    """The first member whose base name equals one of ``names`` (case-insensitive), in that order."""
    by_base: dict[str, str] = {}
    for m in members or ():
        by_base.setdefault(m.rsplit("/", 1)[-1].lower(), m)
    for n in names:
        if n.lower() in by_base:
            return by_base[n.lower()]
    return None


def read_member(path: Path, member: str, name: str) -> bytes:
    """The bytes of one zip member, refusing members that would expand beyond a sane size."""
    with zipfile.ZipFile(path) as zf:
        info = zf.getinfo(member)
        if info.file_size > MAX_UNZIPPED_BYTES:
            raise LogFormatError(
                f"{member} in {name} expands to {info.file_size} bytes: export a shorter recording", status=413
            )
        return zf.read(member)


WHITESPACE = " "
"""The delimiter of columns separated by runs of spaces or tabs (``time x y z`` loggers, aligned tables)."""
DELIMITERS = ("\t", ";", ",", WHITESPACE)
"""Separators of a table without a header row, tried in this order: a tab or a semicolon is never
part of a number, a comma may be a decimal mark (``0,5;9,81``), so it is tried after them."""
_TAB_TO_SPACE = bytes.maketrans(b"\t", b" ")


COMMENT_MARKS = ("#", "@")
"""What starts a comment line: ``#``, and ``@`` (HyperIMU's ``@ HyperIMU …`` and ``@ Date:…, Sampling
Rate:50ms`` lines before its header)."""


def is_comment(line: str) -> bool:
    """True for a comment line (:data:`COMMENT_MARKS`)."""
    return line.lstrip().startswith(COMMENT_MARKS)


def split_row(line: str, delimiter: str) -> list[str]:
    if delimiter == WHITESPACE:
        return line.split()
    return [c.strip() for c in next(csv.reader([line], delimiter=delimiter))]


def guess_delimiter(line: str) -> str:
    return max((",", ";", "\t"), key=line.count)


MAX_LISTED_COLUMNS = 20
"""Columns named in a message before "and N more"."""
SKIP = "-"
"""The name of a column to leave out (a list of ``columns``)."""


def listed_columns(names: list[str]) -> str:
    """Column names as a message lists them: quoted, cut at 40 characters, the first 20 and how many more."""
    listed = ", ".join(repr(n[:40]) for n in names[:MAX_LISTED_COLUMNS])
    return listed + (f" and {len(names) - MAX_LISTED_COLUMNS} more" if len(names) > MAX_LISTED_COLUMNS else "")


def columns_not_read(names: list[str], used: Iterable[int], why: str) -> str | None:
    """The note naming a header's columns a reader left (none is dropped in silence), and ``why``; None when it
    read them all. A column named ``-`` was left out by the ``columns`` given, and an empty name (a trailing
    separator) names nothing."""
    left = [n.strip() for c, n in enumerate(names) if c not in set(used) and n.strip() not in ("", SKIP)]
    if not left:
        return None
    return f"{len(left)} column{'s' if len(left) > 1 else ''} not read: {listed_columns(left)} ({why})"


def first_row(lines: list[str]) -> tuple[int, str, list[str]] | None:
    """The 0-based index, delimiter (comma, semicolon or tab) and fields of the first non-blank line."""
    for index, line in enumerate(lines):
        if line.strip():
            delimiter = guess_delimiter(line)
            return index, delimiter, split_row(line, delimiter)
    return None


def guess_decimal(lines: list[str], delimiter: str, first_column: int = 0) -> str:
    """``,`` when the data fields carry a decimal comma (only possible when the separator is not a
    comma), else ``.``; looks at the first 20 non-blank data lines, from column ``first_column``."""
    if delimiter == ",":
        return "."
    data = [ln for ln in lines if ln.strip() and not is_comment(ln)][:20]
    return "," if any("," in f for ln in data for f in split_row(ln, delimiter)[first_column:]) else "."


def is_number(text: str, decimal: str = ".") -> bool:
    """True for a decimal number written with ``decimal`` as its mark (``1.5e-3``, ``-0,25``)."""
    if decimal != ".":
        if "." in text:
            return False
        text = text.replace(decimal, ".")
    try:
        float(text)
    except ValueError:
        return False
    return text.strip().lower() not in ("nan", "inf", "-inf", "+inf", "infinity")


def numeric_layout(lines: list[str]) -> tuple[str, str, int] | None:
    """The delimiter, decimal mark and column count of a table without a header row, or None.

    ``lines`` are the first lines of the file; ``#`` comments and blank lines are skipped. The first
    data line decides whether there is a header row: None unless it splits into two or more numbers.
    Of the :data:`DELIMITERS` that split it so, the first that gives the same count on the next lines
    (up to 20) wins (else the first: the reader then names the line that differs); the decimal mark
    is a comma when the separator is not one and the numbers carry commas.
    """
    data = [ln for ln in lines if ln.strip() and not is_comment(ln)][:20]
    if not data:
        return None
    found = []
    for delimiter in DELIMITERS:
        fields = split_row(data[0], delimiter)
        marks = [d for d in ((".", ",") if delimiter != "," else (".",)) if all(is_number(f, d) for f in fields)]
        if len(fields) < 2 or not marks:
            continue
        rows = [split_row(ln, delimiter) for ln in data]
        commas = "." not in marks or any("," in f for r in rows for f in r)
        layout = (delimiter, "," if "," in marks and commas else ".", len(fields))
        if all(len(r) == len(fields) for r in rows):
            return layout
        found.append(layout)
    return found[0] if found else None


class _SingleSpaced(io.RawIOBase):
    """A text file whose runs of blanks become one space, with none at a line's ends: what pyarrow's
    one-character delimiter needs to read whitespace-separated columns. Read in blocks, never whole."""

    def __init__(self, source: BinaryIO, block_size: int = 1 << 22):
        self._source = source
        self._block_size = block_size
        self._pending = b""
        self._out = memoryview(b"")
        self._eof = False

    def readable(self) -> bool:
        return True

    def _fill(self) -> None:
        chunk = self._source.read(self._block_size)
        if not chunk:
            self._eof = True
            text, self._pending = self._pending, b""
        else:
            text = self._pending + chunk
            cut = text.rfind(b"\n") + 1  # whole lines only: a run of blanks is never split
            text, self._pending = text[:cut], text[cut:]
        text = text.translate(_TAB_TO_SPACE)
        while b"  " in text:  # bytes.replace is C: a few passes beat one regex by far
            text = text.replace(b"    ", b" ").replace(b"  ", b" ")
        text = text.replace(b"\n ", b"\n").replace(b" \n", b"\n").replace(b" \r", b"\r")
        if text.startswith(b" "):  # the chunk starts at a line's start
            text = text[1:]
        if self._eof and text.endswith(b" "):
            text = text[:-1]
        self._out = memoryview(text)

    def readinto(self, buffer: Any) -> int:
        while not self._out and not self._eof:
            self._fill()
        n = min(len(buffer), len(self._out))
        buffer[:n] = self._out[:n]
        self._out = self._out[n:]
        return n

    def close(self) -> None:
        self._source.close()
        super().close()


def _csv_source(data: bytes | Path, delimiter: str) -> io.BufferedReader | contextlib.nullcontext[io.BytesIO | str]:
    """What pyarrow reads: the bytes, the file's path (its own reader), or the single-spaced stream."""
    if delimiter == WHITESPACE:
        return io.BufferedReader(_SingleSpaced(io.BytesIO(data) if isinstance(data, bytes) else open(data, "rb")))
    return contextlib.nullcontext(io.BytesIO(data) if isinstance(data, bytes) else str(data))


def read_columns(
    data: bytes | Path,
    *,
    skip_lines: int,
    n_columns: int,
    columns: list[int],
    delimiter: str,
    decimal: str = ".",
    name: str = "the file",
    column_names: list[str] | None = None,
    first_line: int | None = None,
    integer_columns: tuple[int, ...] = (),
    drop_empty: tuple[int, ...] = (),
    notes: list[str] | None = None,
) -> list[np.ndarray]:
    """Numeric columns of a delimited table, as float arrays.

    Parameters
    ----------
    data : bytes or pathlib.Path
        The table's text, or the file holding it (read by pyarrow in blocks, never whole); the first
        ``skip_lines`` lines (header, comments) are skipped.
    n_columns : int
        Columns per row (the header's count).
    columns : list of int
        Which columns to return, in that order.
    delimiter, decimal : str
        Field separator (:data:`WHITESPACE` for runs of spaces or tabs) and decimal mark.
    name : str
        How to call the file in messages.
    column_names : list of str, optional
        The header's names, for messages.
    first_line : int, optional
        1-based line number of the first data line in the uploaded file (default ``skip_lines + 1``).
    integer_columns : tuple of int
        Columns read as int64 (epoch nanoseconds, beyond float64's 2⁵³).
    drop_empty : tuple of int
        The sensors' columns: a row where all of them are empty is dropped (a log interleaving packets
        of two rates leaves the other packet's fields empty), with a line in ``notes``; a row where
        only some are empty is refused.
    notes : list of str, optional
        Where the note of dropped rows goes.

    Raises
    ------
    LogFormatError
        A non-numeric value (naming its line and column), a partly empty row, or no data rows.
    """
    # pyarrow (~0.16 s to import) is loaded by the first table read: a command given a .npy never pays for it.
    import pyarrow as pa
    import pyarrow.csv as pacsv

    names = [f"c{i}" for i in range(n_columns)]
    first_line = first_line or skip_lines + 1
    try:
        with _csv_source(data, delimiter) as source:
            table = pacsv.read_csv(
                source,
                read_options=pacsv.ReadOptions(skip_rows=skip_lines, column_names=names, block_size=1 << 22),
                parse_options=pacsv.ParseOptions(delimiter=delimiter, ignore_empty_lines=True),
                convert_options=pacsv.ConvertOptions(
                    include_columns=[names[c] for c in columns],
                    column_types={names[c]: pa.int64() if c in integer_columns else pa.float64() for c in columns},
                    null_values=["", "nan", "NaN", "NA"],
                    strings_can_be_null=False,
                    decimal_point=decimal,
                ),
            )
    except (pa.ArrowInvalid, pa.ArrowTypeError, UnicodeDecodeError):
        detail = first_bad_line(data, skip_lines, delimiter, decimal, columns, column_names or names, first_line)
        raise LogFormatError(f"{name}: {detail}: every used column must hold numbers", code=BAD_LINE) from None
    if table.num_rows == 0:
        raise LogFormatError(f"{name} has a header (line {first_line - 1}) but no data rows: add the samples below it")
    empty = np.zeros(table.num_rows, dtype=bool)
    if drop_empty:
        empty = np.logical_and.reduce(
            [table.column(names[c]).is_null().to_numpy(zero_copy_only=False) for c in drop_empty]
        )
    out: list[np.ndarray] = []
    for c in columns:
        chunked = table.column(names[c])
        if chunked.null_count and (chunked.is_null().to_numpy(zero_copy_only=False) & ~empty).any():
            row = int(np.flatnonzero(chunked.is_null().to_numpy(zero_copy_only=False) & ~empty)[0])
            raise LogFormatError(
                f"{name}: data row {row + 1} (line {first_line + row} if the file has no blank "
                f"lines) has an empty value in column {(column_names or names)[c]!r}: fill or "
                "remove that line",
                code=BAD_LINE,
            )
        arr = chunked.to_numpy(zero_copy_only=False)
        arr = arr if c in integer_columns else arr.astype(float, copy=False)
        out.append(arr[~empty] if empty.any() else arr)
    # The table's blocks are numpy's now; Arrow's allocator keeps freed pages for reuse, which would
    # hold a second copy of a large log for the rest of the process (a night at 200 Hz: 0.6 GB).
    del table, chunked, arr
    pa.default_memory_pool().release_unused()
    if empty.any():
        if empty.all():
            labels = ", ".join(repr((column_names or names)[c]) for c in drop_empty)
            raise LogFormatError(f"{name}: every data row leaves {labels} empty: those columns hold no readings")
        if notes is not None:
            notes.append(
                f"{name}: {int(empty.sum())} of {len(empty)} rows leave the sensors' columns empty (another "
                "packet type's rows, as logs interleaving packets of two rates write them): skipped"
            )
    for c, arr in zip(columns, out):
        bad = ~np.isfinite(arr)
        if bad.any():
            row = int(np.flatnonzero(bad)[0])
            label = (column_names or names)[c]
            raise LogFormatError(
                f"{name}: data row {row + 1} (line {first_line + row} if the file has no blank lines) has an "
                f"empty or non-finite value in column {label!r}: fill or remove that line",
                code=BAD_LINE,
            )
    return out


BAD_LINE = "bad_line"
"""The code of a refusal naming a line that is not numbers (its line, its column and its text)."""


def _text_lines(data: bytes | Path) -> Iterator[str]:
    if isinstance(data, bytes):
        yield from data.decode("utf-8-sig", errors="replace").splitlines()
        return
    with open(data, encoding="utf-8-sig", errors="replace", newline="") as f:
        for line in f:
            yield line.rstrip("\r\n")


def first_bad_line(
    data: bytes | Path,
    skip_lines: int,
    delimiter: str,
    decimal: str,
    columns: list[int],
    names: list[str],
    first_line: int,
) -> str:
    """Describe the first data line whose used columns are not all numbers (slow path, errors only)."""
    try:
        return _scan_for_bad_line(data, skip_lines, delimiter, decimal, columns, names, first_line)
    except csv.Error as exc:
        return (
            f"a line after the header could not be read as delimited text ({exc}; lines are limited to "
            f"{csv.field_size_limit()} characters per field)"
        )


def _scan_for_bad_line(
    data: bytes | Path,
    skip_lines: int,
    delimiter: str,
    decimal: str,
    columns: list[int],
    names: list[str],
    first_line: int,
) -> str:
    for offset, line in enumerate(itertools.islice(_text_lines(data), skip_lines, None)):
        number = first_line + offset
        if not line.strip() or is_comment(line):
            continue
        row = split_row(line, delimiter)
        if len(row) < len(names):
            return f"line {number} has {len(row)} columns but the header names {len(names)}"
        for c in columns:
            value = row[c]
            try:
                float(value.replace(decimal, ".") if decimal != "." else value)
            except ValueError:
                return f"line {number}, column {names[c]!r}: {value[:40]!r} is not a number"
    return "a line could not be read as numbers"


def text_block_cell(
    text: str, delimiter: str, skip_lines: int, names: list[str], records: int = 20
) -> tuple[int, str, str] | None:
    """The first cell of a table's data rows that holds a block of text over several lines (a quoted
    cell with line breaks, as a logger writing message objects with ``csv.writer`` makes): its 1-based
    line, its column's name and its first line of text; None when the first ``records`` rows hold none.

    ``text`` is the head of the file, ``skip_lines`` the lines before the data (header, comments).
    """
    if delimiter == WHITESPACE or '"' not in text:
        return None
    reader = csv.reader(text.splitlines(keepends=True)[skip_lines:], delimiter=delimiter)
    try:
        for _ in range(records):
            line = skip_lines + reader.line_num + 1
            for column, cell in enumerate(next(reader)):
                if "\n" in cell or "\r" in cell:
                    label = names[column] if column < len(names) else f"column {column + 1}"
                    return line, label, cell.strip().splitlines()[0]
    except (StopIteration, csv.Error):
        pass
    return None


def resample_to(time_s: np.ndarray, other_time_s: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Values of another stream (gyroscope, magnetometer) linearly interpolated at ``time_s``."""
    order = np.argsort(other_time_s, kind="stable")
    t, v = other_time_s[order], values[order]
    return np.column_stack([np.interp(time_s, t, v[:, k]) for k in range(v.shape[1])])
