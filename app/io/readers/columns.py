"""Which column is which, from the data, for a table whose columns are not named for a sensor.

A time column rises at every line; a temperature column is one number that stays within a few
degrees; the rest are sensors, three columns each (x, y, z), told apart by what they read:

- an accelerometer rests at about 1 g: a norm of 0.8–1.2 (g), 8–12 (m/s²) or near a common
  sensitivity in counts (:data:`~app.io.readers.chips.ACC_LSB_PER_G`), and its direction turns from
  rest to rest while its norm stays;
- a gyroscope rests near zero — an offset a MEMS part can have (within 30 °/s, or its counts at
  131 LSB per °/s, :data:`~app.calibration.shared.plausible.GYRO_BIAS_MAX_DPS`) — and comes back to the same
  offset at every rest, however far it swung between;
- a magnetometer reads the Earth's field, 22–67 µT (0.22–0.67 gauss, or counts), a near-constant
  norm around its hard iron while its direction turns.

The file's name breaks a tie (``gyro``, ``accel``, ``mag``, ``compass``, ``hmc``, ``qmc``, ``ak``…).
Where the data and the name leave more than one reading, :class:`ColumnsAmbiguous` names each with
the ``columns`` value that reads the file so.
"""

from __future__ import annotations

import itertools
import re
from collections.abc import Iterable
from typing import Any

import numpy as np

from ...calibration.shared.headlines import SENSOR_WORDS
from ...calibration.shared.plausible import GYRO_BIAS_MAX_DPS
from ..errors import LogFormatError
from .chips import ACC_LSB_PER_G, CHIPS, GYR_LSB_PER_DPS
from .table import SKIP
from .units import turn_field

SENSORS = ("acc", "gyr", "mag")
NAME_WORDS = {
    "gyr": re.compile(r"gyr|gyro|gyroscope|angular|rotation[ _-]?rate|rate[ _-]?gyro"),
    "acc": re.compile(r"acc|accel|accelerometer|acceleration|adxl|lis3dh"),
    "mag": re.compile(r"mag|magn|magnetometer|compass|hmc|qmc|ak89|ak09|lis3mdl|mmc5|bmm"),
}
"""Words of a file's name that say which sensor it holds."""
ACC_REST = {"g": (0.8, 1.2), "m/s^2": (8.0, 12.0)}
"""An accelerometer at rest reads 1 g within a bad part's scale and offset errors."""
FIELD_REST = {"uT": (20.0, 70.0), "gauss": (0.2, 0.7), "nT": (20_000.0, 70_000.0)}
"""The Earth's field, 22–67 µT anywhere (IGRF), as a still magnetometer reads it."""
_MAG_SCALES = [c.scale for c in CHIPS.values() if c.sensor == "mag"]  # µT per count
MAG_COUNTS = (FIELD_REST["uT"][0] / max(_MAG_SCALES), FIELD_REST["uT"][1] / min(_MAG_SCALES))
"""The Earth's field in the counts of the magnetometers of the chips table (0.6 µT/LSB to 16384 LSB/gauss)."""
COUNTS_TOLERANCE = 0.15
MAX_CANDIDATES = 6
PREVIEW_LINES = 8


def example_columns(n: int, name: str = "") -> str:
    """A ``columns`` value for a table of ``n`` columns, as a person would name them: a time first where the count
    leaves one over, then the sensor the file's name says (``gyro.txt``) and the others, accelerometer first
    (``-`` for any column left)."""
    named = [s for s in SENSORS if NAME_WORDS[s].search(name.lower())]
    order = named + [s for s in SENSORS if s not in named]
    time = ["t"] if n % 3 else []
    triples = [f"{s}_{axis}" for s in order for axis in "xyz"][: 3 * ((n - len(time)) // 3)]
    names = time + triples
    return ",".join(names + [SKIP] * (n - len(names)))


class ColumnsAmbiguous(LogFormatError):
    """The data leave two or more readings of the columns open: each candidate's words and the
    ``columns`` value that reads the file so, with the file's first lines."""

    code = "columns_ambiguous"

    def __init__(self, message: str, candidates: list[dict[str, Any]], preview: list[str], file: str | None = None):
        super().__init__(message)
        self.candidates = candidates
        self.preview = preview
        self.file = file
        """The file whose columns are asked about: one of several uploaded together answers for its own
        (``columns`` as ``NAME=…;NAME=…``, :func:`app.io.readers.columns_of_file`)."""


def _whole(x: np.ndarray) -> bool:
    sub = x[:10_000]
    return bool(np.allclose(sub, np.round(sub)))


MAX_TIME_STEPS_BACK = 3
"""A time column may step back this many times (or once per thousand rows, if more): a clock adjusted while
logging, files joined. :mod:`.timing` names the steps and takes the rate from the median step."""


def is_time(col: np.ndarray) -> bool:
    """A column that rises at (nearly) every line from its first row to its last: a time or a sample counter,
    which may step back a few times (:data:`MAX_TIME_STEPS_BACK`)."""
    if len(col) < 3:
        return False
    d = np.diff(col)
    back = int(np.count_nonzero(d < 0))
    return bool(back <= max(MAX_TIME_STEPS_BACK, len(d) // 1000) and col[-1] > col[0] and np.mean(d > 0) > 0.9)


def is_temperature(col: np.ndarray) -> bool:
    """A die temperature, 5–85 °C, that moves by at most 15 degrees over the file, by small steps."""
    lo, mid, hi = np.percentile(col, [1, 50, 99])
    if not (5.0 <= mid <= 85.0 and hi - lo <= 15.0):
        return False
    steps = np.abs(np.diff(col))
    return bool(len(steps) == 0 or np.percentile(steps, 99) <= max(0.5, 0.2 * (hi - lo)))


def _rests(x: np.ndarray) -> tuple[list[np.ndarray], float]:
    """The means of the quiet blocks (spread within 3× the quietest tenth's) of a triple, in order, and
    that quietest tenth's spread (the noise floor)."""
    n = len(x)
    w = max(5, min(50, n // 20))
    blocks = n // w
    if blocks < 2:
        return [x.mean(axis=0)], float(x.std(axis=0).sum())
    b = x[: blocks * w].reshape(blocks, w, 3)
    spread = b.std(axis=1).sum(axis=1)
    floor = float(np.percentile(spread, 10))
    quiet = spread <= 3.0 * floor + 1e-12
    return list(b.mean(axis=1)[quiet]), floor


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    c = np.dot(a, b) / (np.linalg.norm(a) * np.linalg.norm(b) + 1e-300)
    return float(np.degrees(np.arccos(np.clip(c, -1.0, 1.0))))


def _near(value: float, ranges: Iterable[tuple[float, float]]) -> bool:
    return any(lo <= value <= hi for lo, hi in ranges)


def _counts_near(value: float, scales: Iterable[float]) -> bool:
    return any(abs(value / s - 1.0) <= COUNTS_TOLERANCE for s in scales)


def triple_sensors(x: np.ndarray) -> set[str]:
    """The sensors three columns can be, from what they read at rest and how they move."""
    x = np.asarray(x, dtype=float)
    x = x[:: max(1, len(x) // 400_000)]  # a long log: every k-th line tells the same
    whole = _whole(x)
    found, noise = _rests(x)
    rests = np.array(found)
    center = np.median(rests, axis=0)
    rest_norms = np.linalg.norm(rests, axis=1)
    rest_norm = float(np.median(rest_norms))
    picked = rests[:: max(1, len(rests) // 40)]
    turned = max(_angle(r, q) for r in picked for q in picked)  # how far the rests' direction turns
    rest_spread = float(np.max(np.linalg.norm(rests - center, axis=1)))  # how far the rests lie apart
    excursion = float(np.percentile(np.linalg.norm(x - center, axis=1), 99))  # how far it swings from its rest
    norms = np.linalg.norm(x, axis=1)
    moved = excursion > max(20.0 * noise, 0.05 * rest_norm)
    one_rest = rest_spread <= 0.2 * rest_norm + 10.0 * noise  # the same reading at every rest
    out: set[str] = set()
    sphere = _sphere(x, rests) if moved else None
    if sphere is not None:
        # Turned through many directions on a sphere: an accelerometer's is centred near zero with a radius of
        # 1 g; a magnetometer's is the Earth's field around its hard iron. A gyroscope's swings pass its rest.
        c, r = sphere
        if (_near(r, ACC_REST.values()) or (whole and _counts_near(r, ACC_LSB_PER_G))) and c < 0.2 * r:
            out.add("acc")
        if (_near(r, FIELD_REST.values()) or (whole and MAG_COUNTS[0] <= r <= MAG_COUNTS[1])) and not (
            whole and "acc" in out
        ):
            out.add("mag")
        return out
    # Accelerometer: about 1 g at rest, in every rest (its direction turns from rest to rest).
    if (
        (_near(rest_norm, ACC_REST.values()) or (whole and _counts_near(rest_norm, ACC_LSB_PER_G)))
        and float(np.max(rest_norms)) <= 1.3 * float(np.min(rest_norms))
        and (not moved or turned > 20.0 or np.percentile(norms, 90) < 1.6 * rest_norm)
    ):
        out.add("acc")
    # Magnetometer: the Earth's field (the sphere's radius when turned, free of the hard iron).
    field = rest_norm
    on_shell = True
    if moved:
        # Turned: the field is the half-range of a shell of readings about the hard iron (.units.turn_field);
        # readings that swing through a ball (a gyroscope turned every way) hold no field.
        turned_field = turn_field(x)
        on_shell = turned_field is not None
        if turned_field is not None:
            field = turned_field
    fits_field = on_shell and (_near(field, FIELD_REST.values()) or (whole and MAG_COUNTS[0] <= field <= MAG_COUNTS[1]))
    if fits_field and not (whole and "acc" in out) and (not moved or not one_rest):
        out.add("mag")
    # Gyroscope: an offset a MEMS part can have, the same at every rest, swinging only between rests.
    offset_max = GYRO_BIAS_MAX_DPS * (max(GYR_LSB_PER_DPS) if whole else 1.0)
    if float(np.linalg.norm(center)) <= offset_max and one_rest:
        out.add("gyr")
        if moved and excursion > 3.0 * rest_norm:
            out -= {"acc", "mag"}  # far swings that come back to one rest: a rate, not a direction
    if "acc" in out and not moved and noise < 0.02 * rest_norm and not _near(rest_norm, FIELD_REST.values()):
        out.discard("gyr")  # resting at 1 g with the small spread of an accelerometer
    return out


def _sphere(x: np.ndarray, rests: np.ndarray) -> tuple[float, float] | None:
    """The norm of the centre and the radius of the sphere the readings lie on, when they turned through
    directions wide enough to fix it, lie on it within 30 % (a soft iron: a QMC5883L reads 16 %), and rest
    on it too (a gyroscope's rest is the centre of its swings); None otherwise."""
    sub = x[:: max(1, len(x) // 5000)]
    a = np.column_stack([2.0 * sub, np.ones(len(sub))])
    sol, *_ = np.linalg.lstsq(a, np.sum(sub**2, axis=1), rcond=None)
    c, k = sol[:3], sol[3]
    r2 = k + float(c @ c)
    if r2 <= 0:
        return None
    r = float(np.sqrt(r2))
    d = sub - c
    dist = np.linalg.norm(d, axis=1)
    u = d / np.maximum(dist, 1e-300)[:, None]
    lo, hi = np.percentile(sub, [1, 99], axis=0)
    # Around the centre on every side (not a cap of a huge sphere through one cluster of readings).
    wide = float(np.linalg.norm(u.mean(axis=0))) < 0.7 and r <= 1.5 * float(np.max(hi - lo)) / 2.0
    if not wide or float(np.std(dist - r)) > 0.3 * r or np.any(np.abs(np.linalg.norm(rests - c, axis=1) - r) > 0.3 * r):
        return None
    return float(np.linalg.norm(c)), r


def name_sensor(name: str) -> str | None:
    """The sensor the file's name says (``gyro.csv`` → ``gyr``), if exactly one."""
    stem = re.sub(r"\.[A-Za-z0-9]+$", "", name.lower())
    said = [s for s, pattern in NAME_WORDS.items() if pattern.search(stem)]
    return said[0] if len(said) == 1 else None


def _layouts(values: np.ndarray) -> list[tuple[int | None, int | None, list[int]]]:
    """Ways to split the columns into (time, temperature, the sensors' first columns)."""
    width = values.shape[1]
    out = []
    for time_col in [None] + [c for c in (0, width - 1) if is_time(values[:, c])]:
        rest = [c for c in range(width) if c != time_col]
        extra = len(rest) % 3
        temps: list[int | None] = [None] if extra == 0 else []
        if extra == 1:
            temps = [c for c in (rest[0], rest[-1]) if is_temperature(values[:, c])]
        for temp_col in temps:
            sensors = [c for c in rest if c != temp_col]
            if 3 <= len(sensors) <= 9:
                out.append((time_col, temp_col, sensors[0::3]))
    return sorted(out, key=lambda lay: (lay[0] is None, lay[1] is not None))


def _readings(
    width: int, time_col: int | None, temp_col: int | None, firsts: list[int], kinds: list[set[str]]
) -> list[tuple[list[str], str]]:
    """Every reading of a layout's columns in which each triple is one of the sensors it can be, none twice:
    the names, one per column, and the sensors in words."""
    out = []
    for assign in itertools.product(*[sorted(k, key=SENSORS.index) for k in kinds]):
        if len(set(assign)) != len(assign):
            continue
        names = [SKIP] * width
        if time_col is not None:
            names[time_col] = "time"
        if temp_col is not None:
            names[temp_col] = "temp_c"
        for first, sensor in zip(firsts, assign):
            names[first : first + 3] = [f"{sensor}_{a}" for a in "xyz"]
        out.append((names, ", ".join(SENSOR_WORDS[s] for s in assign)))
    return out


def guess_columns(
    values: np.ndarray, name: str, lines: list[str], header: list[str] | None = None
) -> tuple[list[str], str]:
    """One name per column (as the ``columns`` field takes them) and the words saying why.

    Parameters
    ----------
    values : numpy.ndarray, shape (N, W)
        Every column of the table.
    name : str
        The file's name (its words break a tie).
    lines : list of str
        The table's first lines, for the question.
    header : list of str, optional
        A header row that names no sensor (for the messages).

    Raises
    ------
    ColumnsAmbiguous
        The data (and the name) leave two or more readings.
    LogFormatError
        No reading fits.
    """
    said = name_sensor(name)
    readings: list[tuple[list[str], str]] = []
    guesses: list[tuple[list[str], str]] = []
    for time_col, temp_col, firsts in _layouts(values):
        kinds = [triple_sensors(values[:, c : c + 3]) for c in firsts]
        if said is not None and len(firsts) == 1 and not kinds[0]:
            kinds = [{said}]
        readings = _readings(values.shape[1], time_col, temp_col, firsts, kinds)
        if readings:
            break  # the first layout (with a time column, without a temperature) that fits any reading
        if not guesses and sum(not k for k in kinds) == 1 and len(firsts) > 1:
            # One triple the data name nothing for beside triples they name: the sensors left over are a
            # guess by elimination, which is asked, never taken (a gyroscope turned every way reads neither
            # a rest nor a shell).
            left = set(SENSORS) - set().union(*kinds)
            guesses = _readings(values.shape[1], time_col, temp_col, firsts, [k or left for k in kinds])
    by_name = False
    if said is not None and len(readings) > 1:
        named = [r for r in readings if f"{said}_x" in r[0]]
        by_name = bool(named)
        readings = named or readings
    if len(readings) == 1:
        names, words = readings[0]
        return names, f"read from the data as {words}" + (f" (and the file's name, {name})" if by_name else "")
    what = f"the header row of {name} names no sensor ({', '.join(header)})," if header else f"{name} has no header row"
    if not readings and guesses:
        candidates = [{"sensors": words, "columns": ",".join(names)} for names, words in guesses[:MAX_CANDIDATES]]
        raise ColumnsAmbiguous(
            f"{what}; its columns read as "
            + "; or ".join(f"{c['sensors']} (columns={c['columns']})" for c in candidates)
            + " only by elimination (one set of three reads as no sensor on its own): say which, with `columns`",
            candidates,
            lines[:PREVIEW_LINES],
            name,
        )
    if not readings:
        raise LogFormatError(
            f"{what} and its {values.shape[1]} columns read as no accelerometer, gyroscope or "
            "magnetometer (three columns each, with a time and a temperature column or not): name them, one per "
            f"column in order, with `columns`, e.g. columns={example_columns(values.shape[1], name)} (- skips "
            "a column)"
        )
    shown = readings[:MAX_CANDIDATES]
    candidates = [{"sensors": words, "columns": ",".join(names)} for names, words in shown]
    raise ColumnsAmbiguous(
        f"{what} and its columns can be read more than one way: "
        + "; ".join(f"{c['sensors']} (columns={c['columns']})" for c in candidates)
        + ": say which, with `columns`",
        candidates,
        lines[:PREVIEW_LINES],
        name,
    )
