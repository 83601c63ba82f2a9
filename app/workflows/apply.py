"""A stored calibration applied to a whole recording, a chunk at a time: each sensor the calibration corrects and
the file holds is calibrated by the result's own ``apply`` (``f = M (m − o)``), the other columns pass through,
and the rows are written as CSV, Parquet or ``.npy`` (app.io.writers.samples) with each column's unit in its name.

Memory is a chunk's (app.io.readers.chunks), whatever the recording's length, where the file is read in chunks (a
generic CSV, a ``.npy`` array, Parquet); other formats are read whole first, and the answer's notes say so."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any

import numpy as np

from app.calibration import CalibrationError
from app.calibration.shared.headlines import SENSOR_WORDS
from app.io.log import TO_SI
from app.io.readers.chunks import CHUNK_ROWS, HEAD_LINES, ChunkedLog, read_in_chunks
from app.io.readers.read_options import ReadOptions
from app.io.writers.samples import TEMPERATURE_COLUMN, TIME_COLUMN, Column, open_writer, sensor_columns


@dataclass(frozen=True)
class SensorStep:
    """What is done to one sensor's columns: calibrated (``factor`` first brings the file's unit to the
    calibration's), or passed through in the file's unit."""

    sensor: str
    file_unit: str
    corrected: bool
    factor: float = 1.0
    output_unit: str | None = None

    @property
    def unit(self) -> str:
        return (self.output_unit or self.file_unit) if self.corrected else self.file_unit


@dataclass(frozen=True)
class Applied:
    """What :func:`apply_to_file` wrote: the rows, the columns (names with units), the sensors corrected and
    passed through, whether the file was read in chunks, and the reader's and the apply's notes."""

    rows: int
    format: str
    columns: tuple[Column, ...]
    corrected: tuple[str, ...]
    passed: tuple[str, ...]
    streamed: bool
    notes: tuple[str, ...]

    def body(self) -> dict[str, Any]:
        return {
            "rows": self.rows,
            "format": self.format,
            "columns": [{"name": c.name, "unit": c.unit, "corrected": c.corrected} for c in self.columns],
            "corrected": list(self.corrected),
            "passed_through": list(self.passed),
            "streamed": self.streamed,
            "notes": list(self.notes),
        }


def sensor_steps(result: Any, units: dict[str, str], sensors: list[str], name: str) -> list[SensorStep]:
    """Each sensor of the file, calibrated where the result has its correction (the file's unit converted to the
    calibration's where both are physical), else passed through.

    Raises
    ------
    CalibrationError
        The result corrects nothing (its own ``apply`` says why), none of the file's sensors (naming both), or a
        file's unit that is not the calibration's and cannot become it (counts against a physical unit).
    """
    corrections = result.corrections()
    if not corrections:  # a noise characterisation, a temperature calibration: its own apply says why not
        result.apply(np.zeros((1, 3)))
    if not set(corrections) & set(sensors):
        have = ", ".join(SENSOR_WORDS[s] for s in corrections) or "no sensor (it corrects nothing)"
        held = ", ".join(SENSOR_WORDS[s] for s in sensors)
        raise CalibrationError(
            f"the calibration corrects {have}, and {name} holds {held}: apply it to a recording of the sensor it "
            "calibrates"
        )
    steps = []
    for s in sensors:
        c = corrections.get(s)
        if c is None:
            steps.append(SensorStep(s, units[s], corrected=False))
            continue
        have, want = units[s], c.input_unit or units[s]
        if have == want:
            factor = 1.0
        elif "raw" not in (have, want) and have in TO_SI[s] and want in TO_SI[s]:
            factor = TO_SI[s][have] / TO_SI[s][want]
        else:
            raise CalibrationError(
                f"the calibration's {SENSOR_WORDS[s]} model takes {_unit(want)}, and {name} gives its "
                f"{SENSOR_WORDS[s]} in {_unit(have)}, which cannot be converted: {_remedy(s, have, want)}"
            )
        steps.append(SensorStep(s, have, corrected=True, factor=factor, output_unit=c.output_unit))
    return steps


def _remedy(sensor: str, have: str, want: str) -> str:
    """How to read a recording in the calibration's unit: counts given their scale, or read as counts."""
    if have == "raw":
        scale = "chip or lsb_per_g" if sensor == "acc" else "chip"
        return (
            f"give the counts' scale ({scale}) so that they are read in {want}, or apply a calibration fitted in counts"
        )
    return f"read the recording in counts ({sensor}_unit=raw), or apply a calibration fitted in {have}"


def _unit(unit: str) -> str:
    return "counts (raw)" if unit == "raw" else unit


def output_columns(chunked: ChunkedLog, steps: list[SensorStep]) -> list[Column]:
    """The columns written: the time (seconds since the first sample) when the file has one, each sensor's x, y, z
    in its output unit, the temperature when the file has one."""
    columns = [TIME_COLUMN] if chunked.has_time else []
    for step in steps:
        columns += sensor_columns(step.sensor, step.unit, step.corrected)
    return columns + ([TEMPERATURE_COLUMN] if chunked.has_temperature else [])


def comments(body: dict[str, Any], steps: list[SensorStep], name: str) -> list[str]:
    """The lines that head a written file: the calibration, what was corrected, what passed through."""
    lines = [
        f"calibrated by trical with calibration {body.get('id') or '(unstored)'} ({body.get('method')}) from {name}"
    ]
    for st in steps:
        if st.corrected:
            how = f"corrected, {_unit(st.file_unit)} -> {_unit(st.unit)}"
            if st.factor != 1.0:
                how += f" (read in {_unit(st.file_unit)}, times {st.factor:.12g} into the calibration's unit first)"
        else:
            word = SENSOR_WORDS[st.sensor]
            how = f"passed through unchanged, {_unit(st.file_unit)}: the calibration has no {word} model"
        lines.append(f"{st.sensor}: {how}")
    return lines


def apply_to_file(
    body: dict[str, Any],
    path: str | Path,
    out: IO[bytes],
    *,
    fmt: str,
    options: ReadOptions = ReadOptions(),
    name: str | None = None,
    chunk_rows: int = CHUNK_ROWS,
    head_lines: int = HEAD_LINES,
) -> Applied:
    """Apply a stored calibration to every row of a recording and write the rows to ``out``.

    Parameters
    ----------
    body : dict
        A stored calibration's body (rebuilt by :func:`app.calibration.registry.from_dict`).
    path : str or pathlib.Path
        The recording: any log :func:`app.io.readers.read_log` reads; a generic CSV, ``.npy`` and Parquet are
        read in chunks.
    out : binary file
        Where to write (seekable for ``npy``).
    fmt : str
        ``csv``, ``parquet`` or ``npy`` (:data:`app.io.writers.samples.FORMATS`).
    options : ReadOptions
        How to read the recording.
    name : str, optional
        How to call the file in messages (default its file name).
    chunk_rows, head_lines : int
        Rows per chunk; lines of a text log its reading is decided on (:func:`app.io.readers.chunks.read_in_chunks`).

    Returns
    -------
    Applied

    Raises
    ------
    CalibrationError
        A calibration that corrects none of the file's sensors, a unit that cannot become the calibration's.
    LogFormatError
        A file that cannot be read (as :func:`app.io.readers.read_log`), an unknown format.
    """
    from app.calibration import registry  # from_dict imports every model

    path = Path(path)
    name = name or path.name
    try:
        result = registry.from_dict(body)
    except (KeyError, TypeError, ValueError) as exc:
        raise CalibrationError(
            f"the calibration cannot be read back as a result ({type(exc).__name__}: {exc}): give a calibration as "
            "trical stored it (its id, or its JSON body as the API gives it)"
        ) from None
    chunked = read_in_chunks(path, options, name=name, chunk_rows=chunk_rows, head_lines=head_lines)
    steps = sensor_steps(result, chunked.log.units, chunked.sensors, name)
    columns = output_columns(chunked, steps)
    writer = open_writer(out, fmt, columns, comments(body, steps, name))
    for chunk in chunked.chunks():
        values: list[np.ndarray] = [chunk.time_s] if chunked.has_time and chunk.time_s is not None else []
        for step in steps:
            m = chunk.sensors[step.sensor]
            if step.corrected:
                m = result.apply(m * step.factor if step.factor != 1.0 else m, step.sensor)
            values += [np.ascontiguousarray(m[:, k]) for k in range(3)]
        if chunked.has_temperature and chunk.temperature_c is not None:
            values.append(chunk.temperature_c)
        writer.write(values)
    writer.close()
    return Applied(
        rows=writer.rows,
        format=fmt,
        columns=tuple(columns),
        corrected=tuple(s.sensor for s in steps if s.corrected),
        passed=tuple(s.sensor for s in steps if not s.corrected),
        streamed=chunked.streamed,
        notes=tuple(chunked.log.warnings) + tuple(chunked.log.notes),
    )
