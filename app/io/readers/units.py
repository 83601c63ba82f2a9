"""Units decided from the data: the resting magnitude says whether readings are in g, m/s², counts,
µT, gauss or nT, whatever the header or the caller said; chips and ``lsb_per_g`` turn counts into
physical units. The one place where a log's units are settled (:func:`settle_units`), for every
format, before any method sees the arrays.

A still or slowly turned accelerometer reads about 1 g: a median norm of 0.6–1.6 is in g, 6–14 in
m/s², and numbers above 50 are counts of an ADC (LSB) — near 16384, 8192, 4096 or 2048 per g for
the common 16-bit parts, or 1000 for readings in mg (:data:`~app.io.readers.chips.ACC_LSB_PER_G`).
A magnetometer turned through all directions reads the Earth's field, 22–67 µT anywhere on the
Earth (IGRF): 15–100 µT, 0.15–1 gauss or 15 000–100 000 nT; whole numbers outside those are
counts, and so are the whole numbers of a still magnetometer whose unit nothing states (its norm is
not known to be the field: it holds the hard iron).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from ...calibration.shared.gravity import STANDARD_GRAVITY
from ...calibration.shared.headlines import SENSOR_WORDS
from ..errors import LogFormatError
from ..log import ACC_PHYSICAL_UNITS, LogData
from .chips import ACC_LSB_PER_G, ACC_RANGE, GAUSS_UT, GYR_RANGE, Chip
from .gyro_unit import gyro_evidence

LINEAR_FRACTION = 0.25
"""A log whose median norm is below this fraction of g holds no gravity (linear acceleration)."""
COUNTS_TOLERANCE = 0.15
"""Counts resting within this fraction of a common sensitivity are read with it."""
FIELD_RANGES = {"uT": (15.0, 100.0), "gauss": (0.15, 1.0), "nT": (15_000.0, 100_000.0)}
"""The Earth's field (22–67 µT, IGRF) with room for a disturbed room, in each unit a log may use."""


def median_norm(acc: np.ndarray) -> float:
    sub = acc[:200_000]
    return float(np.median(np.linalg.norm(sub, axis=1)))


def _whole(values: np.ndarray) -> bool:
    sub = values[:10_000]
    return bool(np.allclose(sub, np.round(sub)))


def infer_acc_unit(acc: np.ndarray) -> str | None:
    """``g``, ``m/s^2`` or ``raw`` when the median norm leaves no doubt; None otherwise.

    A still or slowly turned device reads about 1 g: a median norm of 0.6–1.6 is in g, 6–14 is in
    m/s², and integer readings above 50 are counts of an ADC (LSB).
    """
    norm = median_norm(acc)
    if 0.6 <= norm <= 1.6:
        return "g"
    if 6.0 <= norm <= 14.0:
        return "m/s^2"
    if norm > 50 and _whole(acc):
        return "raw"
    return None


def common_sensitivity(norm_counts: float) -> float | None:
    """The common accelerometer sensitivity (LSB per g) a resting magnitude in counts sits near, if any."""
    for lsb in ACC_LSB_PER_G:
        if abs(norm_counts / lsb - 1.0) <= COUNTS_TOLERANCE:
            return lsb
    return None


def _sensitivity_hint(lsb: float) -> str:
    chip = {16384.0: "2g", 8192.0: "4g", 4096.0: "8g", 2048.0: "16g"}.get(lsb)
    return f"lsb_per_g={lsb:g}" + (f" or chip=mpu6050-{chip}" if chip else "")


def _sensitivity_words(lsb: float) -> str:
    """Where a common sensitivity comes from, for the messages."""
    if ACC_RANGE[lsb] == "mg":
        return "readings in milli-g (mg), as the BNO055 and the ADXL345 and LIS3DH libraries give them"
    return f"the {ACC_RANGE[lsb]} range of the MPU-6050 family and the ICM-20948"


SHELL_CV = 0.3
"""Readings of a turned magnetometer lie on a shell about the centre of their range: their distances
from it vary by a few per cent to 0.3 of their mean (soft iron, a partial turn, a flat ring). A still
sensor's noise and wander fill a ball instead, whose distances vary by 0.42 of their mean (the
Maxwell distribution of a 3-D Gaussian: std/mean = sqrt(3π/8 − 1) ≈ 0.42)."""


def _shell_spread(sub: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> float:
    """The std/mean of the readings' distances from the centre of their 1–99 % range."""
    d = np.linalg.norm(sub - (lo + hi) / 2.0, axis=1)
    mean = float(d.mean())
    return float(d.std() / mean) if mean > 0 else np.inf


def field_magnitude(mag: np.ndarray) -> float:
    """The field a magnetometer reads: half the 1–99 % range per axis when it turned through all
    directions (free of the hard-iron offset), else the median norm."""
    turn = turn_field(mag)
    return median_norm(np.asarray(mag[:200_000], dtype=float)) if turn is None else turn


def turn_field(mag: np.ndarray) -> float | None:
    """Half the 1–99 % range per axis (the field, free of the hard iron) when the magnetometer turned
    through all directions; None when it did not (a still sensor: its norm is all there is)."""
    sub = np.asarray(mag[:200_000], dtype=float)
    lo, hi = np.percentile(sub, [1.0, 99.0], axis=0)
    half = (hi - lo) / 2.0
    norm = median_norm(sub)
    # Turned: every axis spans a like range, far beyond a still sensor's noise (a few thousandths of
    # its norm), even under a hard iron many times the field (an MMC5983MA's mid-scale zero: 4 %);
    # and the readings lie on a shell, not in a ball: a still sensor's noise and slow wander can span
    # 2.5 % of its norm (a BNO055 at 954 counts: ±25), but they fill the ball (SHELL_CV).
    if half.min() > 0.3 * half.max() and half.mean() > 0.025 * norm and _shell_spread(sub, lo, hi) < SHELL_CV:
        return float(half.mean())
    return None


def infer_mag_unit(mag: np.ndarray) -> str | None:
    """``uT``, ``gauss``, ``nT`` or ``raw`` (counts) from the field the readings show; None when no
    unit fits (:data:`FIELD_RANGES`)."""
    field = field_magnitude(mag)
    whole = _whole(mag)
    for unit in ("uT", "gauss", "nT"):
        low, high = FIELD_RANGES[unit]
        if low <= field <= high and not (whole and unit != "uT"):
            return unit
    if whole and field > 1.0:
        return "raw"
    return None


@dataclasses.dataclass(frozen=True)
class Claim:
    """What was said of a sensor's unit, and who said it (for the messages)."""

    unit: str | None
    by: str | None

    def words(self) -> str:
        return f"{self.by} said {self.unit}"


def _claim(sensor: str, given: dict[str, str], stated: dict[str, str], stated_by: str) -> Claim:
    if given.get(sensor):
        return Claim(given[sensor], f"{sensor}_unit")
    if stated.get(sensor):
        return Claim(stated[sensor], stated_by)
    return Claim(None, None)


def settle_units(
    log: LogData,
    *,
    given: dict[str, str] | None = None,
    stated: dict[str, str] | None = None,
    lsb_per_g: float | None = None,
    lsb_source: str = "lsb_per_g",
    chips: dict[str, Chip] | None = None,
    stated_by: str = "the header",
    check_mag: bool = True,
    name: str = "the file",
) -> LogData:
    """Each sensor's unit as its data show it, counts turned into physical units where a scale is known.

    Parameters
    ----------
    log : LogData
        As a reader made it: ``units`` what the caller, the header or the format said (or a default).
    given : dict, optional
        The caller's units per sensor (``acc_unit`` …); ``gauss`` for a magnetometer in gauss.
    stated : dict, optional
        The units the file's header (or its format) names per sensor; ``stated_by`` says which, for
        the messages.
    lsb_per_g : float, optional
        Counts per g of the accelerometer (the caller's, or a comment of the file: ``lsb_source``).
    chips : dict, optional
        :class:`~app.io.readers.chips.Chip` per sensor (:func:`~app.io.readers.chips.parse_chips`).
    check_mag : bool
        Whether the magnetometer's unit is checked against its field (a phone format that states µT
        keeps it: a phone's hard iron can exceed the Earth's field on a still recording).
    name : str
        How to call the file in messages.

    Returns
    -------
    LogData
        Arrays in ``g``, ``m/s^2``, ``deg/s``, ``rad/s``, ``uT``, ``nT`` or ``raw`` (counts whose scale
        is unknown); a note for every conversion, and in ``warnings`` every decision against what the
        caller or the header said (naming both) and every sensor left in counts.

    Raises
    ------
    LogFormatError
        A scale given for readings that are not counts, a scale that makes the accelerometer rest far
        from 1 g, a unit given twice (a chip and a unit), an accelerometer that rests at a magnitude
        no unit explains.
    """
    given, stated, chips = dict(given or {}), dict(stated or {}), dict(chips or {})
    notes: list[str] = []
    warns: list[str] = []
    questions: list[dict[str, Any]] = []
    units = dict(log.units)
    arrays: dict[str, Any] = {}
    for sensor, chip in chips.items():
        if getattr(log, sensor) is None:
            notes.append(f"chip {chip.name} is for the {SENSOR_WORDS[sensor]}, which the file does not have: not used")
    if log.acc is not None:
        arrays["acc"], units["acc"] = _settle_acc(
            log.acc,
            units.get("acc"),
            _claim("acc", given, stated, stated_by),
            lsb_per_g,
            lsb_source,
            chips.get("acc"),
            notes,
            warns,
            name,
        )
    if log.gyr is not None:
        arrays["gyr"], units["gyr"] = _settle_gyr(
            log.gyr,
            units.get("gyr"),
            _claim("gyr", given, stated, stated_by),
            chips.get("gyr"),
            notes,
            warns,
            questions,
            acc=arrays.get("acc", log.acc),
            fs=log.sampling_rate_hz,
            time_s=log.time_s,
        )
    if log.mag is not None:
        arrays["mag"], units["mag"] = _settle_mag(
            log.mag,
            units.get("mag"),
            _claim("mag", given, stated, stated_by),
            chips.get("mag"),
            check_mag,
            notes,
            warns,
        )
    scales = {
        sensor: scale
        for sensor in arrays
        if (
            scale := _scale(
                getattr(log, sensor),
                arrays[sensor],
                sensor,
                chips.get(sensor),
                given_by=lsb_source if sensor == "acc" and lsb_per_g is not None else None,
            )
        )
    }
    return dataclasses.replace(
        log,
        **arrays,
        units=units,
        notes=tuple(log.notes) + tuple(notes),
        warnings=tuple(log.warnings) + tuple(warns),
        questions=tuple(log.questions) + tuple(questions),
        scales=scales,
    )


def _scale(
    before: np.ndarray, after: np.ndarray, sensor: str, chip: Chip | None, given_by: str | None = None
) -> dict[str, Any] | None:
    """How the file's numbers became the sensor's unit (:attr:`app.io.log.LogData.scales`), or None where they
    were in it: the factor of the largest reading, a magnetometer's as µT per number (× 0.15, × 100), the
    others' as numbers per unit (÷ 16384 counts per g, ÷ 131 per °/s), with the part, the option that gave it
    (``given_by``) or the data that showed it."""
    head = np.asarray(before[:1000], dtype=float)
    if head.size == 0 or after is before:
        return None
    i = np.unravel_index(int(np.argmax(np.abs(head))), head.shape)
    if head[i] == 0:
        return None
    k = float(f"{float(np.asarray(after[:1000], dtype=float)[i] / head[i]):.12g}")
    if abs(k - 1.0) < 1e-9:
        return None
    source = f"the {chip.label}" if chip is not None else None
    if sensor == "mag":
        gauss = chip is None and abs(k - GAUSS_UT) < 1e-9
        words = source or ("100 µT per gauss" if gauss else f"{k:g} µT per count, as the data showed")
        return {"op": "*", "value": k, "words": words, "read_in": "gauss" if gauss else "counts"}
    per, value = {"acc": "g", "gyr": "°/s"}[sensor], float(f"{1.0 / k:.12g}")
    said = f"{value:g} counts per {per}, " + (f"as {given_by} gave it" if given_by else "as the data showed")
    return {"op": "/", "value": value, "words": source or said, "read_in": "counts"}


def _refuse_scale_and_unit(sensor: str, claim: Claim, scale: str) -> None:
    if claim.by == f"{sensor}_unit" and claim.unit != "raw":
        raise LogFormatError(
            f"{scale} converts counts of the {SENSOR_WORDS[sensor]}, but {sensor}_unit says its "
            f"readings are in {claim.unit}: give one of them ({sensor}_unit=raw with the scale, "
            f"or the unit alone)"
        )


def _settle_acc(
    acc: np.ndarray,
    unit: str | None,
    claim: Claim,
    lsb_per_g: float | None,
    lsb_source: str,
    chip: Chip | None,
    notes: list[str],
    warns: list[str],
    name: str,
) -> tuple[np.ndarray, str | None]:
    norm = median_norm(acc) if len(acc) else 0.0
    inferred = infer_acc_unit(acc) if len(acc) else None
    if chip is not None and lsb_per_g is not None and abs(lsb_per_g * chip.scale - 1.0) > 1e-9:
        raise LogFormatError(
            f"chip {chip.name} ({1 / chip.scale:g} LSB/g) and lsb_per_g={lsb_per_g:g} disagree: give one of them"
        )
    if chip is not None or lsb_per_g is not None:
        return _acc_by_scale(acc, norm, inferred, claim, lsb_per_g, lsb_source, chip, notes)
    if inferred in ACC_PHYSICAL_UNITS:
        if claim.unit is not None and claim.unit != inferred:
            warns.append(
                f"{claim.words()} for the accelerometer, but its readings rest at a median norm of "
                f"{norm:.3g}, about 1 g in {inferred}: calibrated in {inferred}"
            )
        elif claim.unit is None:
            notes.append(f"accelerometer unit {inferred} inferred from the data (median norm {norm:.3g})")
        return acc, inferred
    if norm > 50:  # counts of an ADC
        return _acc_counts(acc, norm, claim, warns)
    if (1.6 < norm < 6.0 or 14.0 < norm <= 50) and claim.unit in (None, "raw"):
        warns.append(
            f"the accelerometer rests at a median norm of {norm:.3g}, neither about 1 (g) nor about 9.8 "
            "(m/s²): it is calibrated in the readings' own unit (an analogue sensor's volts, or counts), "
            "and its figures are labelled counts; give acc_unit, or lsb_per_g / chip for counts"
        )
        return acc, "raw"
    if 1.6 < norm < 6.0 or 14.0 < norm <= 50:
        raise LogFormatError(
            f"the accelerometer of {name} rests at a median norm of {norm:.3g}"
            + (f" ({claim.words()})" if claim.unit else "")
            + ", which is neither about 1 (g) nor about 9.8 (m/s²) nor counts of a 16-bit sensor: check that "
            "acc_x, acc_y, acc_z are the accelerometer's columns, and give acc_unit (g, m/s^2), or lsb_per_g / "
            "chip for counts"
        )
    if claim.unit is None and unit not in ("g", "m/s^2", "raw"):
        unit = "m/s^2"
    if claim.unit is None and norm >= LINEAR_FRACTION:
        notes.append(
            "accelerometer unit not named and not evident from the data: m/s² assumed (give acc_unit to change it)"
        )
    return acc, unit


def _acc_by_scale(
    acc: np.ndarray,
    norm: float,
    inferred: str | None,
    claim: Claim,
    lsb_per_g: float | None,
    lsb_source: str,
    chip: Chip | None,
    notes: list[str],
) -> tuple[np.ndarray, str | None]:
    """Accelerometer counts divided by the counts per g a chip or ``lsb_per_g`` gives, into g; refused when the
    readings are not counts, or rest far from 1 g with that scale."""
    if lsb_per_g is not None:
        lsb = lsb_per_g
    else:
        assert chip is not None, "the counts per g of a chip where lsb_per_g is not given"
        lsb = 1.0 / chip.scale
    what = f"chip {chip.name}" if chip is not None else f"{lsb_source}={lsb:g}"
    if not (np.isfinite(lsb) and lsb > 0):
        raise LogFormatError(f"lsb_per_g must be a positive number (e.g. 16384 for ±2 g on 16 bits); got {lsb}")
    _refuse_scale_and_unit("acc", claim, what)
    if inferred in ACC_PHYSICAL_UNITS:
        raise LogFormatError(
            f"{what} converts counts (LSB) into g, but the accelerometer's readings are "
            f"already in {inferred} (they rest at a median norm of {norm:.3g}): leave "
            f"{what.split('=')[0]} "
            "out"
        )
    in_g = norm / lsb
    if not 0.6 <= in_g <= 1.6:
        fit = common_sensitivity(norm)
        raise LogFormatError(
            f"with {what} the accelerometer rests at {in_g:.3g} g, not about 1 g: "
            + (
                f"its counts rest at {norm:.0f}, which fits {fit:g} LSB/g ({ACC_RANGE[fit]}): give "
                f"{_sensitivity_hint(fit)}"
                if fit
                else f"its counts rest at {norm:.0f}; give the sensitivity of the range the sensor was set to "
                "(its datasheet's LSB per g)"
            )
        )
    notes.append(f"accelerometer counts divided by {lsb:g} LSB per g ({what}) into g")
    return acc / lsb, "g"


def _acc_counts(acc: np.ndarray, norm: float, claim: Claim, warns: list[str]) -> tuple[np.ndarray, str | None]:
    """Accelerometer readings that are counts of an ADC (median norm over 50) with no scale given: divided
    into g by the common sensitivity they fit, else left in counts; a warning says which."""
    if claim.by == "acc_unit" and claim.unit == "raw":
        warns.append(
            "the accelerometer's readings are counts (acc_unit=raw): its figures are in counts; give "
            "chip or lsb_per_g to calibrate in g"
        )
        return acc, "raw"
    fit = common_sensitivity(norm)
    said = f" ({claim.words()})" if claim.unit not in (None, "raw") else ""
    if fit is not None:
        warns.append(
            f"the accelerometer's readings are counts{said}: they rest at a median norm of {norm:.0f}, "
            f"about {fit:g} LSB per g ({_sensitivity_words(fit)}), so they were divided by {fit:g} into "
            "g; give chip or lsb_per_g for another scale, or acc_unit=raw to calibrate in counts"
        )
        return acc / fit, "g"
    warns.append(
        f"the accelerometer's readings are counts{said} resting at a median norm of {norm:.0f}, near "
        f"none of the common sensitivities ({', '.join(f'{v:g}' for v in ACC_LSB_PER_G)} LSB per g): "
        "calibrated in counts, "
        "and its figures are in counts; give lsb_per_g (or chip) to calibrate in g"
    )
    return acc, "raw"


def _settle_gyr(
    gyr: np.ndarray,
    unit: str | None,
    claim: Claim,
    chip: Chip | None,
    notes: list[str],
    warns: list[str],
    questions: list[dict[str, Any]],
    *,
    acc: np.ndarray | None = None,
    fs: float | None = None,
    time_s: np.ndarray | None = None,
) -> tuple[np.ndarray, str | None]:
    if chip is not None:
        _refuse_scale_and_unit("gyr", claim, f"chip {chip.name}")
        notes.append(f"gyroscope counts times {chip.scale:.6g} °/s per count (chip {chip.name}) into deg/s")
        return gyr * chip.scale, "deg/s"
    if len(gyr) == 0 or not np.any(gyr != 0):
        return gyr, unit
    whole = _whole(gyr)
    peak = float(np.max(np.abs(gyr[:200_000])))
    # Whole numbers are counts (beyond 35 rad/s, 2000 °/s, no rate sensor reads in rad/s): their scale, and
    # else the unit, from what a MEMS gyroscope reads at rest and from the turns between rests (.gyro_unit).
    if whole and claim.unit in ("deg/s", "rad/s") and not (claim.unit == "rad/s" and peak > 35.0):
        whole = False  # a logger printing whole degrees per second, as its header says
    ev = gyro_evidence(gyr, whole=whole, acc=acc, fs=fs, time_s=time_s)
    if whole:
        if claim.unit not in (None, "raw"):
            warns.append(
                f"{claim.words()} for the gyroscope, but its readings are whole numbers up to {peak:.0f}: "
                "read as counts"
            )
        if ev.unit is not None:
            lsb = float(ev.unit[4:])
            if claim.unit == "raw" and claim.by == "gyr_unit":
                warns.append(
                    f"the gyroscope's readings are counts (gyr_unit=raw): its figures are in counts; "
                    f"{ev.words}: give chip=mpu6050-{GYR_RANGE[lsb][1:-4]}dps to have them in °/s"
                )
                return gyr, "raw"
            warns.append(
                f"the gyroscope's readings are counts: {ev.words}, so they were divided by {lsb:g} into "
                "deg/s; give chip for another scale, or gyr_unit=raw to calibrate in counts"
            )
            return gyr / lsb, "deg/s"
        warns.append(
            "the gyroscope's readings are counts: its figures are in counts; give chip (e.g. "
            "mpu6050-250dps) or gyr_unit to have them in °/s"
        )
        return gyr, "raw"
    if ev.unit is not None and claim.unit is not None and claim.unit != ev.unit and not ev.firm:
        notes.append(
            f"{claim.words()} for the gyroscope; its quietest stretch would rather say {ev.unit} "
            f"({ev.words}), but no accelerometer confirms that it was still: read as {claim.unit}"
        )
        return gyr, claim.unit
    if ev.unit is not None:
        if claim.unit is not None and claim.unit != ev.unit:
            warns.append(f"{claim.words()} for the gyroscope, but {ev.words}: read as {ev.unit}")
        elif claim.unit is None:
            notes.append(f"gyroscope unit {ev.unit} inferred from the data: {ev.words}")
        return gyr, ev.unit
    if claim.unit is not None:
        return gyr, claim.unit
    remedy = (
        "give sampling_rate_hz, from which its data may show the unit, or gyr_unit (rad/s or deg/s)"
        if ev.needs_rate
        else "give gyr_unit (rad/s or deg/s)"
    )
    question = (
        f"the gyroscope's unit is not evident from its data ({ev.words}): its figures were read as "
        f"{unit}, which may be wrong by a factor of 57; {remedy}"
    )
    warns.append(question)
    questions.append({"sensor": "gyr", "detail": question})
    return gyr, unit


def _settle_mag(
    mag: np.ndarray, unit: str | None, claim: Claim, chip: Chip | None, check: bool, notes: list[str], warns: list[str]
) -> tuple[np.ndarray, str | None]:
    if chip is not None:
        _refuse_scale_and_unit("mag", claim, f"chip {chip.name}")
        out = mag * chip.scale
        field = field_magnitude(out)
        low, high = FIELD_RANGES["uT"]
        notes.append(f"magnetometer counts times {chip.scale:.6g} µT per count (chip {chip.name}) into µT")
        if not low <= field <= high:
            warns.append(
                f"with chip {chip.name} the magnetometer shows a field of {field:.1f} µT, outside the "
                f"Earth's {low:g}–{high:g} µT: check the chip's range (or a magnet near the sensor)"
            )
        return out, "uT"
    if unit == "gauss" and not check:
        return mag * GAUSS_UT, "uT"
    if not check or len(mag) == 0:
        return mag, unit
    inferred = infer_mag_unit(mag)
    field = field_magnitude(mag)
    if inferred == "uT" and claim.unit is None and _whole(mag) and turn_field(mag) is None:
        # Said by no one, whole numbers are µT only when a turn shows the field's radius: the norm of a
        # still sensor's counts can fall in 15–100 too (an AK8963 at 14 bits, 0.6 µT per count, reads 80
        # for 48 µT), and it holds the hard iron besides.
        inferred = "raw"
    said = claim.unit is not None and claim.unit != inferred
    if inferred is None:
        if unit == "gauss":
            return mag * GAUSS_UT, "uT"
        if claim.unit in ("uT", "nT") or claim.unit is None:
            warns.append(
                f"the magnetometer's readings show a field of {field:.4g}"
                + (f" ({claim.words()})" if claim.unit else "")
                + ", which fits no unit (µT 15–100, gauss 0.15–1, nT 15000–100000): its figures are left "
                "in the readings' own unit, labelled counts; give mag_unit, or chip for a known part"
            )
            return mag, "raw"
        return mag, unit
    if said:
        warns.append(
            f"{claim.words()} for the magnetometer, but its readings show a field of {field:.4g}, "
            + ("which is counts" if inferred == "raw" else f"the Earth's field in {inferred}")
            + f": read as {'counts' if inferred == 'raw' else inferred}"
        )
    if inferred == "raw":
        warns.append(
            f"the magnetometer's readings are counts (a field of {field:.0f} counts): its figures are "
            "in counts; give chip (e.g. ak8963-16bit, qmc5883l-2g, hmc5883l-1090) or mag_unit to have "
            "them in µT"
        )
        return mag, "raw"
    if inferred == "gauss":
        notes.append("magnetometer readings in gauss multiplied by 100 into µT")
        return mag * GAUSS_UT, "uT"
    return mag, inferred


def refuse_linear_acceleration(acc: np.ndarray, unit: str, name: str, hint: str = "") -> None:
    """Refuse a log whose readings hold no gravity (a linear-acceleration / user-acceleration export)."""
    if unit not in ACC_PHYSICAL_UNITS or len(acc) == 0:
        return
    g = 1.0 if unit == "g" else STANDARD_GRAVITY
    norm = median_norm(acc)
    if norm < LINEAR_FRACTION * g:
        if unit == "m/s^2" and 0.6 <= norm <= 1.6:
            raise LogFormatError(
                f"the readings of {name} have a median norm of {norm:.3g}, about 1 g, but their unit is m/s^2: "
                "if they are in g, give acc_unit=g (or name the unit in the header, e.g. acc_x (g))"
            )
        raise LogFormatError(
            f"{name} holds linear acceleration (gravity removed): its median norm is {norm:.3g} {unit}, "
            f"not about {g:g} {unit}. Calibration needs the raw accelerometer including gravity"
            + (f": {hint}" if hint else ": export 'acceleration including gravity' instead")
        )
