"""What a MEMS sensor can read: the physical limits every result is checked against, in one place.

A figure outside them is not a sensor's but a mistake in how its readings were read — the unit, the
columns, the chip — and a result holding one is not ok (:meth:`~app.calibration.shared.result.CalibrationResult.
plausibility`, which every result runs when it is made). Each result says which figures it holds
(``physical_figures``); this module says what is plausible and, when a figure is not, the likely
cause and what to give.

The limits (docs/methods.md, "Plausible figures"):

- a scale (the diagonal of a correction ``M`` between readings and the same unit) within 0.5–2: a
  MEMS part's sensitivity error is a few percent (MPU-6050 Product Specification rev. 3.4, sections
  6.1–6.2: ±3 % initial tolerance); a factor of 2 is a wrong range or unit;
- an accelerometer's offset within 1 g: the MPU-6050's zero-g offset is ±50–80 mg (section 6.2),
  the largest of the common parts under 0.15 g;
- a gyroscope's bias within 30 °/s: the MPU-6050's zero-rate output is ±20 °/s (section 6.1), the
  largest of the common parts;
- a magnetometer's field within 15–100 µT: the Earth's field is 22–67 µT at the surface (the World
  Magnetic Model 2020 technical report, NOAA/BGS, figure of total intensity F), with room for a
  local anomaly;
- a noise density within a factor of :data:`NOISE_FACTOR` of the datasheets of the quietest and the
  noisiest common part (:data:`NOISE_DENSITY`).

The datasheet scales of the parts trical reads counts of (``app/io/readers/chips.py``) live at the
edge, where the counts are read; these limits are the core's, so that the core imports nothing of
``app.io`` and a result read back from the store is judged by the same numbers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .gravity import STANDARD_GRAVITY
from .headlines import SENSOR_WORDS

SCALE_RANGE = (0.5, 2.0)
"""A correction's scale (diagonal of ``M``, readings to the same unit) outside it is a wrong unit or range."""

ACC_OFFSET_MAX_G = 1.0
"""The largest plausible accelerometer offset, in g (the MPU-6050's zero-g offset: ±80 mg)."""


@dataclass(frozen=True)
class GyroPart:
    """A gyroscope's datasheet figures at 25 °C: its initial zero-rate offset tolerance (what a still
    gyroscope reads before calibration) and its rate noise spectral density."""

    name: str
    zero_rate_dps: float
    noise_dps_rthz: float


GYR_PARTS = (
    GyroPart("MPU-6050", 20.0, 0.005),  # InvenSense MPU-6000/MPU-6050 Product Specification rev. 3.4, section 6.1
    GyroPart("MPU-6500", 5.0, 0.01),  # InvenSense MPU-6500 Product Specification, section 3.1
    GyroPart("MPU-9250", 5.0, 0.01),  # InvenSense MPU-9250 Product Specification, section 3.1
    GyroPart("ICM-20948", 5.0, 0.015),  # TDK ICM-20948 datasheet DS-000189, table 1
    GyroPart("ICM-42688-P", 0.5, 0.0028),  # TDK ICM-42688-P datasheet DS-000347, table 1
    GyroPart("BMI160", 3.0, 0.007),  # Bosch BMI160 datasheet BST-BMI160-DS000, table 2
    GyroPart("LSM6DS3", 10.0, 0.007),  # ST LSM6DS3 datasheet DocID026899, table 3
)
"""The MEMS gyroscopes of boards and phones whose figures bound what a gyroscope can read: the bias gate
here, and the gyroscope's unit read from its data at the edge (``app/io/readers/gyro_unit.py``)."""

GYRO_BIAS_MAX_DPS = 1.5 * max(p.zero_rate_dps for p in GYR_PARTS)
"""The largest plausible gyroscope bias, in °/s: the widest datasheet tolerance (the MPU-6050's ±20 °/s)
with half again for temperature and soldering stress (30 °/s)."""

FIELD_RANGE_UT = (15.0, 100.0)
"""The Earth's field at the surface is 22–67 µT (World Magnetic Model 2020); outside 15–100 µT the
readings are not in µT."""

NOISE_FACTOR = 10.0
"""How far a noise density may lie outside the datasheets' range before it is no MEMS part's."""

QUANTISATION_RMS = 1.0 / math.sqrt(12.0)
"""The RMS of the rounding to whole counts, in counts."""

DEG = math.pi / 180.0
MICRO_G = 1e-6 * STANDARD_GRAVITY

NOISE_DENSITY = {
    # Rate noise spectral density: the quietest and the noisiest of GYR_PARTS (ICM-42688-P 0.0028,
    # ICM-20948 0.015 °/s/√Hz).
    "gyr": (
        min(p.noise_dps_rthz for p in GYR_PARTS) * DEG,
        max(p.noise_dps_rthz for p in GYR_PARTS) * DEG,
        "rad/s/√Hz",
    ),
    # Noise power spectral density: Analog Devices ADXL355 datasheet: 22.5 µg/√Hz; ICM-42688-P table 2:
    # 70; ICM-20948 table 2: 230; MPU-6050 section 6.2: 400 µg/√Hz.
    "acc": (22.5 * MICRO_G, 400.0 * MICRO_G, "m/s²/√Hz"),
    # From the RMS noise at the output bandwidth: MEMSIC MMC5983MA, 0.4 mG over 800 Hz ≈ 0.0014 µT/√Hz;
    # Honeywell HMC5883L, 2 mG at 75 Hz (37.5 Hz bandwidth) ≈ 0.033; ST LIS3MDL, 3.2 mG at 80 Hz ≈ 0.051.
    "mag": (0.0014, 0.051, "uT/√Hz"),
}
"""The quietest and noisiest common MEMS part of each sensor, in SI (rad/s, m/s², µT per √Hz)."""

TO_SI = {"rad/s": 1.0, "deg/s": DEG, "m/s^2": 1.0, "g": STANDARD_GRAVITY, "uT": 1.0, "nT": 1e-3, "gauss": 100.0}
"""The units a result's figures can be in, to SI (rad/s, m/s², µT); ``raw`` (counts) has no scale."""

UNIT_WORDS = {"rad/s": "rad/s", "deg/s": "°/s", "m/s^2": "m/s²", "g": "g", "uT": "µT", "nT": "nT", "gauss": "gauss"}
"""Each unit of :data:`TO_SI` as a person reads it: the one list of these words (app/words.py adds counts)."""
OPTION = {"acc": "acc_unit", "gyr": "gyr_unit", "mag": "mag_unit"}
"""The upload's option that gives each sensor's unit (docs/rest.md)."""
ALTERNATIVES = {"acc": ("m/s^2", "g"), "gyr": ("rad/s", "deg/s"), "mag": ("uT", "nT", "gauss")}
"""The units a sensor's readings may have been in."""


@dataclass(frozen=True)
class PhysicalFigure:
    """One figure of a result to judge: its ``sensor`` (acc, gyr, mag), ``kind`` (``scale``, ``offset``,
    ``bias``, ``noise_density``, ``field``), ``values`` (per axis, or one) and the ``unit`` of the readings
    it came from (``raw``: counts, judged only as a scale between counts and as a noise density, which
    needs the ``sampling_rate_hz``); ``stated``: the unit is the format's own (a flight controller's log), so
    an implausible figure is no misread unit."""

    sensor: str
    kind: str
    values: tuple
    unit: str
    sampling_rate_hz: float | None = None
    stated: bool = False


def _limits(fig: PhysicalFigure) -> tuple[float, float] | None:
    """The plausible (lo, hi) of a figure's magnitude in SI (counts for ``raw``), or None when it has none."""
    if fig.unit == "raw":
        if fig.kind == "noise_density" and fig.sampling_rate_hz:
            # Whole counts carry at least the quantisation noise of one count, 1/√12 count RMS (Widrow and
            # Kollár, Quantization Noise, Cambridge 2008, eq. (5.11)), white over the Nyquist band fs/2.
            return QUANTISATION_RMS / math.sqrt(fig.sampling_rate_hz / 2.0) / NOISE_FACTOR, math.inf
        return SCALE_RANGE if fig.kind == "scale" else None
    if fig.kind == "scale":
        return SCALE_RANGE
    if fig.kind == "offset" and fig.sensor == "acc":
        return 0.0, ACC_OFFSET_MAX_G * STANDARD_GRAVITY
    if fig.kind == "bias" and fig.sensor == "gyr":
        return 0.0, GYRO_BIAS_MAX_DPS * DEG
    if fig.kind == "field" and fig.sensor == "mag":
        return FIELD_RANGE_UT
    if fig.kind == "noise_density" and fig.sensor in NOISE_DENSITY:
        lo, hi, _ = NOISE_DENSITY[fig.sensor]
        return lo / NOISE_FACTOR, hi * NOISE_FACTOR
    return None


def _shown(value_si: float, fig: PhysicalFigure) -> str:
    """A figure in the words a person reads it in (°/s, mg, µT, °/s/√Hz, µg/√Hz, counts)."""
    if fig.kind == "scale" or not math.isfinite(value_si):
        return f"{value_si:.3g}"
    per = "/√Hz" if fig.kind == "noise_density" else ""
    if fig.unit == "raw":
        return f"{value_si:.3g} counts{per}"
    if fig.sensor == "gyr":
        return f"{value_si / DEG:.3g} °/s{per}"
    if fig.sensor == "acc":
        return f"{value_si / STANDARD_GRAVITY * 1000:.3g} mg{per}"
    return f"{value_si:.3g} µT{per}"


def _plausible(value_si: float, limits: tuple[float, float], fig: PhysicalFigure) -> bool:
    lo, hi = limits
    return lo <= abs(value_si) <= hi


def _si(fig: PhysicalFigure, unit: str) -> list[float]:
    """The figure's values in SI had its readings been in ``unit`` (a scale has no unit)."""
    if fig.kind == "scale" or unit == "raw":
        return [float(v) for v in fig.values]
    return [float(v) * TO_SI[unit] for v in fig.values]


def _farthest(values: list[float], limits: tuple[float, float]) -> float:
    """The value farthest outside ``limits``: by ratio from their geometric centre, or the largest
    magnitude for a limit from zero."""
    lo, hi = limits
    if lo <= 0:
        return max(values, key=abs)
    if hi == math.inf:
        return min(values, key=abs)
    centre = math.sqrt(lo * hi)
    return max(values, key=lambda v: abs(math.log(max(abs(v), 1e-300) / centre)))


def _misread_as(fig: PhysicalFigure, limits) -> list[str]:
    """The units the readings were likely in: those that, had they been read in another of the sensor's
    units instead, make every value plausible (a result's unit may be the one its readings were
    converted into, so every pair of the sensor's units is tried)."""
    units = ALTERNATIVES.get(fig.sensor, ())
    fits = []
    for actual in units:
        for given in units:
            factor = TO_SI[actual] / TO_SI[given]
            if (
                given != actual
                and actual not in fits
                and all(_plausible(v * factor, limits, fig) for v in _si(fig, fig.unit))
            ):
                fits.append(actual)
    return fits


def _cause(fig: PhysicalFigure, limits) -> str:
    """The likely cause of an implausible figure and what to give."""
    option, word = OPTION.get(fig.sensor, "the unit"), SENSOR_WORDS.get(fig.sensor, fig.sensor)
    if fig.stated:  # the log's own unit: the readings, not their unit, are not those of a sensor at rest
        return (
            f"the log states the {word}'s unit, so the readings are not those of {'an' if word[0] in 'aeiou' else 'a'} "
            f"{word} at rest: a vehicle's "
            "vibration, a touch or a turn reads as noise — record it resting on a table, motors off, untouched"
        )
    if fig.unit == "raw" and fig.kind == "noise_density":
        return (
            f"these readings are not counts (whole numbers): give {option} the unit they are in "
            f"({' or '.join(ALTERNATIVES.get(fig.sensor, ()))})"
        )
    # A unit it was not read in: "give m/s²" for readings read in m/s² would send the person round in a circle.
    fits = [u for u in _misread_as(fig, limits) if u != fig.unit] if fig.kind != "scale" else []
    if fits:
        return (
            f"the readings fit a MEMS {word} in {' or '.join(UNIT_WORDS[u] for u in fits)}, not in the unit "
            f"they were read in: give {option} {fits[0]}"
        )
    if fig.kind == "scale":
        return (
            f"the {word}'s readings are not in the unit they were read in (a range or unit a factor of 2 "
            f"or more off): give {option} (or its chip, for counts), and check that the columns are the "
            f"{word}'s"
        )
    moved = (
        " — or the device was not still: a noise is read from a recording at rest, on a table, untouched"
        if fig.kind == "noise_density"
        else ""
    )
    return (
        f"check that the columns are the {word}'s (not another sensor's), that {option} is its unit, and "
        f"for counts the chip and its range{moved}"
    )


MARK = "which no MEMS part reads"
"""The words every reason of this gate holds, by which a result made again drops the reasons of its
earlier making before judging its figures again."""


def is_plausibility_reason(reason: str) -> bool:
    """Whether a reason is this gate's (:data:`MARK`)."""
    return MARK in reason


def implausible(figures) -> list[str]:
    """One reason per figure no MEMS part can have, naming the likely cause and what to give.

    Parameters
    ----------
    figures : iterable of PhysicalFigure
        A result's figures (counts, ``raw``, are judged only as scales between counts).

    Returns
    -------
    list of str
        Empty when every figure is plausible.
    """
    out = []
    for fig in figures:
        limits = _limits(fig)
        if limits is None or (fig.unit not in TO_SI and fig.unit != "raw" and fig.kind != "scale"):
            continue
        bad = [v for v in _si(fig, fig.unit) if math.isfinite(v) and not _plausible(v, limits, fig)]
        if not bad:
            continue
        worst = _farthest(bad, limits)
        lo, hi = limits
        span = (
            f"at least {_shown(lo, fig)}"
            if hi == math.inf
            else f"{_shown(lo, fig)}–{_shown(hi, fig)}"
            if lo > 0
            else f"at most {_shown(hi, fig)}"
        )
        what = {
            "scale": "scale",
            "offset": "offset",
            "bias": "bias",
            "field": "field",
            "noise_density": "noise density",
        }[fig.kind]
        out.append(
            f"the {SENSOR_WORDS.get(fig.sensor, fig.sensor)}'s {what} is {_shown(worst, fig)}, {MARK} "
            f"(plausible: {span}): {_cause(fig, limits)}"
        )
    return out


def correction_figures(sensor: str, M, o, input_unit: str | None, output_unit: str | None) -> list[PhysicalFigure]:
    """The figures of a correction ``f = M (m − o)``: its scale (the diagonal of M) where it maps readings
    to the same unit, and its offset ``o`` (the accelerometer's offset, the gyroscope's bias; a compass's
    hard iron has no limit of its own) in the readings' unit."""
    out = []
    if input_unit is not None and input_unit == output_unit:
        out.append(
            PhysicalFigure(sensor, "scale", tuple(float(v) for v in np.diag(np.asarray(M, dtype=float))), input_unit)
        )
    kind = {"acc": "offset", "gyr": "bias"}.get(sensor)
    if kind is not None and input_unit in TO_SI:
        out.append(PhysicalFigure(sensor, kind, tuple(float(v) for v in np.asarray(o, dtype=float)), input_unit))
    return out


__all__ = [
    "ACC_OFFSET_MAX_G",
    "FIELD_RANGE_UT",
    "GYRO_BIAS_MAX_DPS",
    "NOISE_DENSITY",
    "NOISE_FACTOR",
    "SCALE_RANGE",
    "PhysicalFigure",
    "correction_figures",
    "implausible",
    "is_plausibility_reason",
]
