"""Recordings made of several files: one file per pose, as makers log their boards.

A maker who calibrates a board over a serial port usually saves one file per pose
(``x_axis_pos.csv``, ``x_axis_neg.csv``, …). trical reads such a set — several files, or a zip of
them — as **one recording in parts**: every file is read by the same reader with the same options
(:func:`app.io.readers.read_log`), and the parts are joined end to end, each keeping its name and
its sample range (:class:`Part`), so that every still reading can say which file it came from.

A file's name may name its pose (:func:`pose_from_name`): ``x_axis_pos``, ``xpos``, ``+x``,
``x_up``, ``posZ`` name the axis that points up; ``x_axis_neg``, ``xminus``, ``z_down``, ``-z`` its
opposite. The name is only checked against the data (the caller compares it with the still
readings); the data always decide the label.
"""

from __future__ import annotations

import dataclasses
import re
import tempfile
import zipfile
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path, PurePosixPath
from typing import TYPE_CHECKING

import numpy as np

from ..errors import LogFormatError
from ..log import LogData
from .kinds import TEXT_SUFFIXES

if TYPE_CHECKING:  # for the annotations only: read_parts imports the module where it reads
    from .sensor_files import ReadFile

MAX_PARTS = 200
"""More files than this in one recording are refused: a calibration needs a few poses, not thousands."""


@dataclass(frozen=True)
class Part:
    """One file of a recording in parts: its name and its samples ``start:end`` in the joined log."""

    filename: str
    start: int
    end: int
    sampling_rate_hz: float | None
    notes: tuple[str, ...] = ()

    @property
    def n_samples(self) -> int:
        return self.end - self.start


# -- the pose a file's name gives ---------------------------------------------------------------

_UP = ("positive", "pos", "plus", "up")
_DOWN = ("negative", "neg", "minus", "down")
_WORD = "|".join(_UP + _DOWN)
_END = r"(?=_|\d|$)"
_AXIS_FIRST = re.compile(rf"(?:^|_)(?P<axis>[xyz])_?(?:axis_?)?(?P<dir>{_WORD}){_END}")
_AXIS_LETTER = re.compile(rf"(?:^|_)(?P<axis>[xyz])_(?P<dir>[pnma]){_END}")  # imucal's x_p / x_a, x_n, x_m
_DIR_FIRST = re.compile(rf"(?:^|_)(?P<dir>{_WORD})_?(?P<axis>[xyz])(?:_?axis)?{_END}")
_SIGNED = re.compile(r"(?:^|(?<=[^a-z0-9]))(?P<sign>[+-])(?P<axis>[xyz])(?![a-z])")


def pose_from_name(filename: str) -> str | None:
    """The up axis a file's name gives (``+x`` … ``-z``), or None when it names none, or several.

    ``x_axis_pos``, ``xpos``, ``x_plus``, ``x_up``, ``posX``, ``+x`` give ``+x`` (the x axis points
    up, away from the Earth: it reads +g); ``x_axis_neg``, ``xminus``, ``x_down``, ``negX``, ``-x``
    and imucal's ``x_a`` give ``-x``.

    Parameters
    ----------
    filename : str
        The file's name, with or without folders and suffix.

    Returns
    -------
    str or None
    """
    stem = PurePosixPath(str(filename).replace("\\", "/")).name.lower()
    for suffix in (".gz", *TEXT_SUFFIXES):
        stem = stem.removesuffix(suffix)
    found = set()
    for match in _SIGNED.finditer(stem):
        found.add(f"{match['sign']}{match['axis']}")
    words = re.sub(r"[^a-z0-9]+", "_", stem)
    for pattern in (_AXIS_FIRST, _AXIS_LETTER, _DIR_FIRST):
        for match in pattern.finditer(words):
            direction = match["dir"]
            sign = "+" if direction in _UP or direction == "p" else "-"
            found.add(f"{sign}{match['axis']}")
    return found.pop() if len(found) == 1 else None


# -- reading and joining the parts ----------------------------------------------------------------

LOG_SUFFIXES = ("", *TEXT_SUFFIXES, ".npy", ".parquet", ".pq")
"""Members of a zip of pose files that are read; anything else (a photo, a README) is left out with a note."""

SKIPPED_MEMBERS = ("__macosx/", ".ds_store", "thumbs.db", "desktop.ini")
"""Members a zip made on a Mac or Windows carries besides the files put in it."""


def log_members(members: Iterable[str]) -> list[str]:
    """The members of a zip that are files put in it (not folders, not a system's own files), in its order."""
    kept = []
    for m in members:
        low = m.lower()
        base = low.rsplit("/", 1)[-1]
        if m.endswith("/") or any(s in low for s in SKIPPED_MEMBERS) or base.startswith("._") or not base:
            continue
        kept.append(m)
    return kept


def refuse_repeated_names(names: Sequence[str]) -> None:
    """Refuse two files of one name in one recording: each file's name is what its readings are called by."""
    twice = sorted({n for n in names if list(names).count(n) > 1})
    if twice:
        raise LogFormatError(
            f"{', '.join(twice)} is given more than once: give each pose's file once, each with its own name"
        )


def read_parts(sources: list[tuple[str, Path]], read: ReadFile, *, name: str, columns_given: bool = False) -> LogData:
    """Read every file of a recording in parts with ``read`` and join them end to end — or, when the files
    are one per sensor (:mod:`app.io.readers.sensor_files`), merge them onto one clock.

    Parameters
    ----------
    sources : list of (str, pathlib.Path)
        Each file's name (as the person gave it) and where it is, in the recording's order.
    read : callable
        ``read(path, name, columns=None)`` → :class:`LogData`: the one reader, with the upload's options
        (``columns``, when given, replaces the upload's for that file).
    name : str
        How to call the whole recording in messages.
    columns_given : bool
        The upload named the columns: files of one sensor each keep them as they are.

    Returns
    -------
    LogData
        The samples of every file, one after the other, with ``parts`` naming each file's range.

    Raises
    ------
    LogFormatError
        No file, too many, a name given twice, a zip inside, or files whose sensors, units or signs
        differ (the message names the two files and what to give).
    """
    if not sources:
        raise LogFormatError(f"{name} holds no file to read: put the pose files (CSV) in it")
    if len(sources) > MAX_PARTS:
        raise LogFormatError(
            f"{name} holds {len(sources)} files; at most {MAX_PARTS} are read as one recording: "
            "give the files of one calibration only"
        )
    refuse_repeated_names([n for n, _ in sources])
    for part_name, _ in sources:
        if part_name.lower().endswith(".zip"):
            raise LogFormatError(
                f"{part_name} is a zip inside a recording of several files: give the files "
                "themselves, or one zip of them"
            )
    from .sensor_files import first_time, merge_sensor_logs, read_as_named, read_sensor_files, sensor_from_name

    merged = read_sensor_files(sources, read, name=name, columns_given=columns_given)
    if merged is not None:  # named one per sensor
        return merged
    logs = [  # a file named for one sensor reads its unnamed x, y, z as that sensor's
        (part_name, read_as_named(read, path, part_name, sensor_from_name(part_name), columns_given))
        for part_name, path in sources
    ]
    held = [s for _, log in logs for s in log.channels]
    if len(logs) > 1 and len(held) == len(set(held)):
        # Not named so, but the files hold different sensors (one each, or x-io's Inertial.csv beside its
        # Magnetometer.csv): one recording, each sensor from its file, merged onto one clock.
        return merge_sensor_logs(
            [
                (part_name, sensor, log, first_time(path, log, part_name))
                for (part_name, log), (_, path) in zip(logs, sources)
                for sensor in log.channels
            ],
            name=name,
        )
    return join_parts(logs)


def join_parts(logs: list[tuple[str, LogData]]) -> LogData:
    """Join logs read from the files of one recording end to end (see :func:`read_parts`)."""
    first_name, first = logs[0]
    for part_name, log in logs[1:]:
        if log.channels != first.channels:
            raise LogFormatError(
                f"{part_name} holds {', '.join(log.channels)} but {first_name} holds {', '.join(first.channels)}: "
                "every file of one calibration needs the same sensors — log the same columns for every pose"
            )
        for sensor in first.channels:
            if log.units[sensor] != first.units[sensor]:
                raise LogFormatError(
                    f"{part_name} reads the {sensor} in {log.units[sensor]} but {first_name} in "
                    f"{first.units[sensor]}: give the unit ({sensor}_unit) so "
                    "that every file is read in the same one"
                )
        if log.sign != first.sign:
            raise LogFormatError(
                f"{part_name} and {first_name} come in opposite signs (one was negated as an iOS Core Motion "
                "log): give sign=1 or sign=-1 for all of them"
            )
    parts, start, notes = [], 0, []
    for part_name, log in logs:
        n = log.n_samples
        parts.append(
            Part(
                filename=part_name,
                start=start,
                end=start + n,
                sampling_rate_hz=log.sampling_rate_hz,
                notes=tuple(log.notes),
            )
        )
        start += n
        for note in log.notes:
            if note not in notes:
                notes.append(note)
    if any(log.format != first.format for _, log in logs):
        notes.append("the files came in different formats: " + ", ".join(f"{n} {log.format}" for n, log in logs))
    # Time runs on across the files: each starts one of its intervals after the previous one ends.
    time_s = None
    if all(log.time_s is not None for _, log in logs):
        pieces, offset = [], 0.0
        for _, log in logs:
            t = np.asarray(log.time_s, dtype=float)
            pieces.append(t - t[0] + offset)
            offset = pieces[-1][-1] + (1.0 / log.sampling_rate_hz if log.sampling_rate_hz else 0.0)
        time_s = np.concatenate(pieces)
    total = sum(p.n_samples for p in parts)
    # The rate of the whole: the parts' own, weighted by their samples; none when a part has none (pose
    # files without a time column: still poses need no rate).
    rate = (
        sum(p.n_samples * (p.sampling_rate_hz or 0.0) for p in parts) / total
        if all(p.sampling_rate_hz for p in parts)
        else None
    )
    # Each file's gaps, at their place in the whole; its jitter the largest of the files'.
    timing = first.timing
    if timing is not None:
        gaps = tuple(
            dataclasses.replace(g, index=g.index + p.start) for p, (_, log) in zip(parts, logs) for g in log.gaps
        )
        jitters = [log.timing.jitter for _, log in logs if log.timing is not None and log.timing.jitter is not None]
        timing = dataclasses.replace(timing, sampling_rate_hz=rate, gaps=gaps, jitter=max(jitters) if jitters else None)

    def stacked(sensor: str) -> np.ndarray | None:
        if getattr(first, sensor) is None:
            return None
        return np.concatenate([np.asarray(getattr(log, sensor), dtype=float) for _, log in logs])

    return dataclasses.replace(
        first,
        acc=stacked("acc"),
        gyr=stacked("gyr"),
        mag=stacked("mag"),
        time_s=time_s,
        sampling_rate_hz=None if rate is None else float(rate),
        notes=tuple(notes),
        parts=tuple(parts),
        timing=timing,
    )


def read_parts_zip(
    path: Path, members: Iterable[str], read: ReadFile, *, name: str, columns_given: bool = False
) -> LogData:
    """Read a zip of pose files (not a phyphox or Sensor Logger export) as one recording in parts.

    Each member is read by ``read(path, member name)`` in the zip's order; the parts are named by
    the members' names without their folders.
    """
    from .table import MAX_UNZIPPED_BYTES, read_member

    files = log_members(members)
    nested = [m for m in files if m.lower().endswith(".zip")]
    if nested:
        raise LogFormatError(
            f"{', '.join(nested)} is a zip inside a recording of several files ({name}): give the "
            "files themselves, or one zip of them"
        )
    kept = [m for m in files if PurePosixPath(m).suffix.lower() in LOG_SUFFIXES]
    left = [m for m in files if m not in kept]
    if not kept:
        listed = ", ".join(files[:12]) or "nothing"
        raise LogFormatError(
            f"{name} is a zip holding {listed}: trical reads phyphox exports (Raw Data.csv), Sensor Logger "
            "exports (Metadata.csv with TotalAcceleration.csv or AccelerometerUncalibrated.csv) and zips of log "
            "files (CSV, text or JSON; one per pose, or one per sensor); upload the CSV itself otherwise",
            status=415,
        )
    with zipfile.ZipFile(path) as zf:
        total = sum(zf.getinfo(m).file_size for m in kept)
    if total > MAX_UNZIPPED_BYTES:
        raise LogFormatError(
            f"the files in {name} expand to {total} bytes together, more than "
            f"{MAX_UNZIPPED_BYTES >> 20} MiB: give the files of one calibration only",
            status=413,
        )
    with tempfile.TemporaryDirectory(prefix="trical-parts-") as tmp:
        sources = []
        for i, member in enumerate(kept):
            base = member.rsplit("/", 1)[-1]
            target = Path(tmp) / f"{i:04d}{Path(base).suffix.lower()}"
            target.write_bytes(read_member(path, member, name))
            sources.append((base, target))
        log = read_parts(sources, read, name=name, columns_given=columns_given)
    if left:
        note = f"{name}: {', '.join(left)} left out (not a log file)"
        log = dataclasses.replace(log, notes=tuple(log.notes) + (note,))
    return log


def part_log(log: LogData, index: int) -> LogData:
    """One file of a recording in parts, as a log of its own (its samples, its rate, its notes)."""
    part = log.parts[index]

    def cut(a: np.ndarray | None) -> np.ndarray | None:
        return None if a is None else a[part.start : part.end]

    time_s = None if log.time_s is None else log.time_s[part.start : part.end] - log.time_s[part.start]
    timing = log.timing
    if timing is not None:  # the file's own gaps, counted from its first sample
        gaps = tuple(
            dataclasses.replace(g, index=g.index - part.start) for g in log.gaps if part.start < g.index < part.end
        )
        timing = dataclasses.replace(timing, sampling_rate_hz=part.sampling_rate_hz, gaps=gaps)
    return dataclasses.replace(
        log,
        acc=cut(log.acc),
        gyr=cut(log.gyr),
        mag=cut(log.mag),
        time_s=time_s,
        sampling_rate_hz=part.sampling_rate_hz,
        notes=part.notes,
        parts=(),
        timing=timing,
    )


def content_digest(path: Path) -> str:
    """The SHA-256 (hex) of what was uploaded: of a zip, its members' names and contents in order (a zip
    of the same pose files made again differs only in its members' times), else the file's bytes. Two
    uploads of the same file or files have the same digest, whatever options they are read with."""
    import hashlib

    digest = hashlib.sha256()
    if zipfile.is_zipfile(path):
        with zipfile.ZipFile(path) as zf:
            for info in zf.infolist():
                digest.update(info.filename.encode() + b"\0" + str(info.file_size).encode() + b"\0")
                with zf.open(info) as member:
                    for chunk in iter(lambda: member.read(1 << 20), b""):
                        digest.update(chunk)
    else:
        with open(path, "rb") as f:
            for chunk in iter(lambda: f.read(1 << 20), b""):
                digest.update(chunk)
    return digest.hexdigest()
