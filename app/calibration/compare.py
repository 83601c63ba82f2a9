"""Two calibrations of one device, parameter by parameter: which differences are real, and what they do.

Every correction is ``f = M (m − o)`` (:mod:`app.calibration.shared.correction`), whatever model made it, so two
calibrations are compared through their corrections and nothing else (a calibration read from a firmware's
parameter file is compared like a fitted one). The matrix is split by its polar decomposition
``M = R S`` (R a rotation, S symmetric positive definite: Higham, *Functions of Matrices*, SIAM 2008, section 8.1):

- the **scales** are S's diagonal, their difference told as a relative change in ppm, ``S_B,ii / S_A,ii − 1``;
- the **cross-axis terms** are S's off-diagonal, each told as the angle ``asin(S_ij / √(S_ii S_jj))`` by which it
  skews axes i and j towards each other (an accelerometer's non-orthogonality, a compass's soft iron);
- the **orientation** is the angle of the rotation ``R_B R_Aᵀ``, ``acos((tr − 1) / 2)``: readings of magnitude
  alone (still poses, a turn) do not see it, so a model fitted on them fixes it by its convention (a lower
  triangular K, a symmetric M), and two models of different conventions differ by it without the device having
  changed;
- the **offsets** are o in the readings' unit, told in the calibrated unit as ``diag(S_A) (o_B − o_A)`` (mg of g for
  an accelerometer, µT for a compass: its hard iron; °/s for a gyroscope).

Each difference's 95 % interval combines the two results' own (``uncertainty``, read through
:func:`correction_half_widths`) in quadrature, the two sessions being independent; a difference is **real** when
its interval excludes zero (``|Δ| > half-width``). Where neither result has an interval the difference has none,
and whether it is real is not told (None).

The effect at the place's field is the largest difference the two corrections make to a vector of the reference's
size, ``max |f_B(m) − f_A(m)|`` over the readings m that A corrects to a vector of size r (g for an accelerometer,
F for a compass), told as the worst tilt ``asin(e / g)`` or heading ``asin(e / H)``, H = F cos I
(:mod:`app.calibration.shared.angles`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .shared.angles import ASSUMED_INCLINATION_DEG, heading_error_deg, tilt_error_deg
from .shared.correction import AffineCorrection
from .shared.errors import CalibrationError
from .shared.gravity import STANDARD_GRAVITY
from .shared.result import CalibrationResult

AXES = ("x", "y", "z")
PAIRS = ((0, 1), (0, 2), (1, 2))

GROUPS = {
    "acc": {"offsets": "offsets", "scales": "scales", "cross": "cross-axis terms", "orientation": "orientation"},
    "gyr": {"offsets": "biases", "scales": "scales", "cross": "cross-axis terms", "orientation": "orientation"},
    "mag": {"offsets": "hard iron", "scales": "soft iron", "cross": "soft iron", "orientation": "orientation"},
}
"""What each group of parameters is called for each sensor: a compass's offsets are its hard iron, its scales and
cross terms its soft iron."""

RAD_S_TO_DEG_S = 180.0 / math.pi


@dataclass(frozen=True)
class Difference:
    """One parameter's difference B − A: its ``group`` (``offsets``, ``scales``, ``cross``, ``orientation``), its
    ``axis`` (``x``, ``xy``…, empty for the orientation), ``value`` and 95 % ``half_width`` (None without one) in
    ``unit`` (``mg``, ``µT``, ``°/s``, ``counts``, ``ppm``, ``°``); an offset's also ``in_input_unit``, o_B − o_A in
    the readings' own ``input_unit`` (counts, m/s², g…)."""

    sensor: str
    group: str
    axis: str
    value: float
    half_width: float | None
    unit: str
    in_input_unit: float | None = None
    input_unit: str | None = None

    @property
    def real(self) -> bool | None:
        """True when the interval excludes zero; None without an interval."""
        return None if self.half_width is None else abs(self.value) > self.half_width

    @property
    def words(self) -> str:
        """The group as said of this sensor (``hard iron``, ``offsets``…)."""
        return GROUPS.get(self.sensor, GROUPS["acc"])[self.group]

    def to_dict(self) -> dict:
        return {
            "sensor": self.sensor,
            "group": self.group,
            "parameter": self.words,
            "axis": self.axis,
            "difference": self.value,
            "half_width": self.half_width,
            "unit": self.unit,
            "real": self.real,
            "difference_in_input_unit": self.in_input_unit,
            "input_unit": self.input_unit,
        }


@dataclass(frozen=True)
class SensorComparison:
    """One sensor's differences and their effect: ``effect`` (the largest vector difference at the reference's
    size, in ``effect_unit``) and ``effect_deg`` (as a tilt or a heading, ``effect_kind``; None without a field)."""

    sensor: str
    differences: tuple[Difference, ...]
    effect: float
    effect_unit: str
    effect_deg: float | None
    effect_kind: str | None
    reference: float

    def real(self) -> tuple[Difference, ...]:
        """The differences whose interval excludes zero."""
        return tuple(d for d in self.differences if d.real)

    def drifted(self, *, without: tuple[str, ...] = ()) -> tuple[str, ...]:
        """The groups (in words, once each, in order) with a real difference, leaving out groups ``without``."""
        out: list[str] = []
        for d in self.real():
            if d.group not in without and d.words not in out:
                out.append(d.words)
        return tuple(out)

    def to_dict(self) -> dict:
        return {
            "sensor": self.sensor,
            "differences": [d.to_dict() for d in self.differences],
            "effect": self.effect,
            "effect_unit": self.effect_unit,
            "effect_deg": self.effect_deg,
            "effect_kind": self.effect_kind,
            "reference": self.reference,
            "real": [d.words + (f" {d.axis}" if d.axis else "") for d in self.real()],
        }


def polar(M: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``M = R S``: the rotation R and the symmetric positive-definite S = (MᵀM)^½ (Higham 2008, section 8.1).

    Raises
    ------
    CalibrationError
        When M is singular or reflects (det M ≤ 0): no correction of a sensor does.
    """
    M = np.asarray(M, dtype=float)
    if not np.all(np.isfinite(M)) or np.linalg.det(M) <= 0:
        raise CalibrationError("a correction matrix M must be finite with a positive determinant")
    U, s, Vt = np.linalg.svd(M)
    S = Vt.T @ np.diag(s) @ Vt
    return U @ Vt, S


def rotation_angle_deg(R: np.ndarray) -> float:
    """The angle of a rotation, acos((tr R − 1) / 2), in degrees."""
    return math.degrees(math.acos(float(np.clip((np.trace(R) - 1.0) / 2.0, -1.0, 1.0))))


def _pairs(model, interval, path: tuple[str, ...], out: list) -> None:
    """Each (path, value, half-width) of a model's arrays of 3 or 3 × 3 numbers beside its uncertainty's."""
    if isinstance(model, dict):
        for key, value in model.items():
            _pairs(value, interval.get(key) if isinstance(interval, dict) else None, (*path, str(key)), out)
        return
    try:
        value = np.asarray(model, dtype=float)
        hw = None if interval is None else np.asarray(interval, dtype=float)
    except (TypeError, ValueError):
        return
    if value.shape in ((3,), (3, 3)) and np.all(np.isfinite(value)):
        out.append(
            (path, value, hw if hw is not None and hw.shape == value.shape and np.all(np.isfinite(hw)) else None)
        )


def _matches(value: np.ndarray, target: np.ndarray) -> bool:
    return bool(np.allclose(value, target, rtol=1e-6, atol=1e-9 * max(1.0, float(np.max(np.abs(target))))))


def correction_half_widths(result: CalibrationResult) -> dict[str, tuple[np.ndarray | None, np.ndarray | None]]:
    """The 95 % half-widths of each sensor's correction ``M`` and ``o``, read from the result's ``uncertainty``.

    A result's intervals are of its model's parameters (``X``, ``y``; ``K``, ``o``; ``M``, ``b``; a cube's ``S``,
    ``b`` per sensor), not of its correction's; they are mapped here by value, so that any result is read the same
    way: the parameter equal to ``o`` or ``−o`` gives o's half-widths, the one equal to ``M`` gives M's, and the one
    equal to ``M⁻¹`` (X, S) gives M's to first order, ``|M| h |M|`` (δ(X⁻¹) = −X⁻¹ δX X⁻¹, each entry bounded by
    the triangle inequality). A result whose parameters map to neither has None there.

    Returns
    -------
    dict
        Sensor → ``(half_widths of M or None, half_widths of o or None)``.
    """
    try:
        uncertainty = result.uncertainty() or {}
        model = result.model_dict()
    except (NotImplementedError, KeyError, TypeError, ValueError):
        return dict.fromkeys(result.corrected_sensors(), (None, None))
    found: list = []
    _pairs(model, uncertainty, (), found)
    out: dict[str, tuple[np.ndarray | None, np.ndarray | None]] = {}
    for sensor, c in result.corrections().items():
        mine = [p for p in found if sensor in p[0]] or [p for p in found if not set(p[0]) & set(GROUPS)]
        hw_M = hw_o = None
        inverse = np.linalg.inv(c.M)
        for _, value, hw in mine:
            if hw is None:
                continue
            if value.shape == (3,) and hw_o is None and (_matches(value, c.o) or _matches(value, -c.o)):
                hw_o = hw
            elif value.shape == (3, 3) and hw_M is None:
                if _matches(value, c.M):
                    hw_M = hw
                elif _matches(value, inverse):
                    hw_M = np.abs(c.M) @ hw @ np.abs(c.M)
        out[sensor] = (hw_M, hw_o)
    return out


def calibrated_unit(c: AffineCorrection, gravity: float | None = None) -> tuple[str, float]:
    """The unit an offset difference is told in and the factor from the calibrated unit to it: mg of g for an
    accelerometer (1000 / g, g the result's own reference where given), µT or counts for a compass, °/s for a
    gyroscope."""
    unit = c.output_unit or ""
    if c.sensor == "acc":
        return "mg", 1000.0 / acc_reference(c, gravity)
    if c.sensor == "gyr":
        return "°/s", RAD_S_TO_DEG_S if unit in ("rad/s", "") else 1.0
    return ("µT", 1.0) if unit in ("µT", "uT", "ut") else ("counts", 1.0)


def acc_reference(c: AffineCorrection, gravity: float | None = None) -> float:
    """Gravity in an accelerometer's calibrated unit: the result's own reference where given, else 1 g or
    9.80665 m/s² by the unit."""
    if gravity is not None and gravity > 0:
        return float(gravity)
    return 1.0 if c.output_unit == "g" else STANDARD_GRAVITY


def reference_size(c: AffineCorrection, field_ut: float | None, gravity: float | None = None) -> float | None:
    """The size of the true vector in the calibrated unit: g for an accelerometer, F for a compass (None
    without a field), none for a gyroscope (no tilt or heading is told for it)."""
    if c.sensor == "acc":
        return acc_reference(c, gravity)
    if c.sensor == "mag":
        return field_ut
    return None


def _quadrature(*parts: np.ndarray | None) -> np.ndarray | None:
    given = [np.asarray(p, dtype=float) for p in parts if p is not None]
    return None if not given else np.sqrt(sum(p * p for p in given))


def _fibonacci_sphere(n: int = 600) -> np.ndarray:
    """``n`` directions spread evenly over the sphere (Fibonacci's lattice), for the largest difference."""
    k = np.arange(n) + 0.5
    z = 1.0 - 2.0 * k / n
    phi = math.pi * (1.0 + math.sqrt(5.0)) * k
    r = np.sqrt(1.0 - z * z)
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), z])


SPHERE = _fibonacci_sphere()


def compare_corrections(
    a: AffineCorrection,
    b: AffineCorrection,
    *,
    half_a: tuple[np.ndarray | None, np.ndarray | None] = (None, None),
    half_b: tuple[np.ndarray | None, np.ndarray | None] = (None, None),
    field_ut: float | None = None,
    inclination_deg: float | None = None,
    gravity: float | None = None,
) -> SensorComparison:
    """The differences B − A of one sensor's two corrections, with their intervals and their effect.

    Parameters
    ----------
    a, b : AffineCorrection
        The same sensor's corrections ``f = M (m − o)``, of readings in the same unit.
    half_a, half_b : (M's half-widths or None, o's half-widths or None)
        Each correction's 95 % half-widths (:func:`correction_half_widths`).
    field_ut : float, optional
        The place's field F (a compass's reference); without it no heading is told.
    inclination_deg : float, optional
        The place's inclination I (:data:`~app.calibration.shared.angles.ASSUMED_INCLINATION_DEG` without it).
    gravity : float, optional
        Gravity in the accelerometer's calibrated unit (A's reference); 1 g or 9.80665 m/s² by the unit without it.

    Returns
    -------
    SensorComparison
    """
    if a.sensor != b.sensor:
        raise CalibrationError(f"cannot compare a {a.sensor} correction with a {b.sensor} one")
    unit, factor = calibrated_unit(a, gravity)
    R_a, S_a = polar(a.M)
    R_b, S_b = polar(b.M)
    hw_M = _quadrature(half_a[0], half_b[0])
    hw_o = _quadrature(half_a[1], half_b[1])
    scale_a, scale_b = np.diag(S_a), np.diag(S_b)
    diffs: list[Difference] = []
    # Offsets in the calibrated unit: diag(S_A) (o_B − o_A); each half-width through the same scale.
    offset = scale_a * (b.o - a.o) * factor
    for i, axis in enumerate(AXES):
        hw = None if hw_o is None else float(abs(scale_a[i]) * hw_o[i] * factor)
        raw = float(b.o[i] - a.o[i])
        diffs.append(Difference(a.sensor, "offsets", axis, float(offset[i]), hw, unit, raw, a.input_unit))
    # Scales: S_B,ii / S_A,ii − 1 in ppm; M's diagonal half-widths taken for S's (relative to each scale).
    for i, axis in enumerate(AXES):
        rel = None if hw_M is None else float(1e6 * hw_M[i, i] / scale_a[i])
        diffs.append(Difference(a.sensor, "scales", axis, float(1e6 * (scale_b[i] / scale_a[i] - 1.0)), rel, "ppm"))
    # Cross-axis terms: asin(S_ij / √(S_ii S_jj)) in degrees; M's off-diagonal half-widths taken for S's.
    for i, j in PAIRS:

        def skew(S: np.ndarray, i: int = i, j: int = j) -> float:
            return math.degrees(math.asin(float(np.clip(S[i, j] / math.sqrt(S[i, i] * S[j, j]), -1.0, 1.0))))

        hw = None
        if hw_M is not None:
            hw = math.degrees(float(max(hw_M[i, j], hw_M[j, i])) / math.sqrt(scale_a[i] * scale_a[j]))
        diffs.append(Difference(a.sensor, "cross", AXES[i] + AXES[j], skew(S_b) - skew(S_a), hw, "°"))
    diffs.append(Difference(a.sensor, "orientation", "", rotation_angle_deg(R_b @ R_a.T), None, "°"))
    reference = reference_size(a, field_ut, gravity)
    size = 1.0 if reference is None else reference
    # The largest |f_B(m) − f_A(m)| over the readings A corrects to size r: m = o_A + M_A⁻¹ (r u).
    m = a.o + (size * SPHERE) @ np.linalg.inv(a.M).T
    effect = float(np.max(np.linalg.norm(b.apply(m) - a.apply(m), axis=1)))
    effect_deg: float | None = None
    kind: str | None = None
    if a.sensor == "acc" and reference is not None:
        effect_deg, kind = tilt_error_deg(effect * factor), "tilt"
    elif a.sensor == "mag" and reference is not None:
        inc = ASSUMED_INCLINATION_DEG if inclination_deg is None else inclination_deg
        effect_deg, kind = heading_error_deg(effect, reference, inc), "heading"
    return SensorComparison(
        a.sensor,
        tuple(diffs),
        effect * factor,
        unit,
        effect_deg,
        kind,
        size,
    )


@dataclass(frozen=True)
class Comparison:
    """Two calibrations compared, sensor by sensor (the sensors both correct); ``missing`` names the sensors
    only one of them corrects."""

    sensors: tuple[SensorComparison, ...]
    missing: tuple[str, ...]

    def to_dict(self) -> dict:
        return {"sensors": [s.to_dict() for s in self.sensors], "missing": list(self.missing)}


def compare(
    a: CalibrationResult,
    b: CalibrationResult,
    *,
    field_ut: float | None = None,
    inclination_deg: float | None = None,
) -> Comparison:
    """Compare two calibrations of a device through their corrections (module docstring).

    Parameters
    ----------
    a, b : CalibrationResult
        Any two results with corrections (``b − a`` is told); their readings' units must agree.
    field_ut, inclination_deg : float, optional
        The place's field and inclination, for a compass's heading; a compass result's own ``field_ut`` metric
        is taken when none is given.

    Returns
    -------
    Comparison

    Raises
    ------
    CalibrationError
        When the two have no sensor in common, or a sensor's readings are in different units.
    """
    ca, cb = a.corrections(), b.corrections()
    common = [s for s in ca if s in cb]
    if not common:
        raise CalibrationError(
            f"the two calibrations correct no sensor in common (one corrects {', '.join(ca) or 'nothing'}, the "
            f"other {', '.join(cb) or 'nothing'}): compare two calibrations of the same sensor"
        )
    ha, hb = correction_half_widths(a), correction_half_widths(b)
    field = field_ut
    if field is None:
        own = (a.metrics or {}).get("field_ut") if isinstance(a.metrics, dict) else None
        field = float(own) if isinstance(own, (int, float)) else None
    gravity = a.gravity if a.unit != "raw" and isinstance(a.gravity, (int, float)) else None
    out = []
    for sensor in common:
        if (ca[sensor].input_unit or "") != (cb[sensor].input_unit or ""):
            raise CalibrationError(
                f"the two {sensor} corrections take readings in different units ({ca[sensor].input_unit} and "
                f"{cb[sensor].input_unit}): compare calibrations of readings in the same unit"
            )
        out.append(
            compare_corrections(
                ca[sensor],
                cb[sensor],
                half_a=ha.get(sensor, (None, None)),
                half_b=hb.get(sensor, (None, None)),
                field_ut=field,
                inclination_deg=inclination_deg,
                gravity=gravity,
            )
        )
    missing = tuple(s for s in (*ca, *cb) if s not in common)
    return Comparison(tuple(out), tuple(dict.fromkeys(missing)))


__all__ = [
    "Comparison",
    "Difference",
    "SensorComparison",
    "compare",
    "compare_corrections",
    "correction_half_widths",
    "polar",
]
