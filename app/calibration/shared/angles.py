"""A calibration's figure as the angle a person levelling or steering thinks in.

An accelerometer's figure is an error of size e (mg: thousandths of g) in the reading of gravity; a
compass's is an error of size e (µT, or counts) in the reading of the Earth's field. Where a level or a
horizon is taken from the accelerometer, and a heading from the compass's horizontal component, that error
turns the measured direction by an angle. The rule here (docs/methods.md, "Figures in degrees"):

**The worst case of a vector error of size e added to a vector of size r turns it by asin(e / r)**
(for e < r; 90° at e ≥ r): the error perpendicular to the true vector and to the line of sight that
turns it most is the one tangent to the circle of radius e around its tip, whose angle is asin(e / r);
an error perpendicular to the vector gives atan(e / r) only, which is smaller, and an error along it none.
So:

- a tilt (a level, a horizon): r = g, the angle asin(e / g);
- a heading: the compass reads the horizontal component H = F cos I of the field F at inclination I
  (positive down), so r = H and the angle is asin(e / H), at the worst, where the error lies in the
  horizontal plane across the field. For a small error it is about 1/cos I times the tilt-like
  asin(e / F): the closer to a pole, the larger (I = 64° in central Europe: 2.3 times).

The figures are worst cases of an error of that size, not the mean of a random one: the figure the verdict
stands on is a norm error | |a| − g | (or | |h| − F |), which bounds below the vector error it comes from,
and the angle says what an error of that size can do to a level or a heading. Decided here, since no
paper states it for a verdict: asin, not the first-order e / r, so that large raw errors are not overstated
as angles beyond 90°.

The place's F and I come from the geomagnetic model (IGRF-14, app.geomag) when the place was given;
else the inclination the calibration measured between the still accelerometer and the field
(:func:`app.calibration.magnetometer.fit.measured_inclination`); else :data:`ASSUMED_INCLINATION_DEG`,
said in the words.
"""

from __future__ import annotations

import math
from collections.abc import Callable

ASSUMED_INCLINATION_DEG = 60.0
"""The inclination assumed where neither the place nor a measured one is known: about that of the
mid-latitudes where most people live (IGRF-14: 64° at 48° N in Europe, 60–70° across the United States,
−50° to −65° in southern Australia; its size is what matters, cos I). It is said wherever it is used."""


def worst_angle_deg(error: float, reference: float) -> float:
    """The largest angle a vector error of size ``error`` turns a vector of size ``reference`` by:
    asin(e / r) in degrees, 90° when e ≥ r.

    Parameters
    ----------
    error : float
        The error's size (≥ 0), in the reference's unit.
    reference : float
        The true vector's size (> 0): g for a tilt, the field's horizontal component H for a heading.

    Returns
    -------
    float
        The angle in degrees, in [0, 90].

    Examples
    --------
    >>> round(worst_angle_deg(32.1, 1000.0), 3)  # 32.1 mg against g
    1.839
    """
    if not reference > 0 or not math.isfinite(reference) or not math.isfinite(error):
        raise ValueError(f"an angle needs a finite error and a positive reference; got {error!r} against {reference!r}")
    ratio = abs(error) / reference
    return 90.0 if ratio >= 1.0 else math.degrees(math.asin(ratio))


def tilt_error_deg(error_mg: float) -> float:
    """The worst tilt error of a level or horizon read from an accelerometer whose reading of gravity is off
    by ``error_mg`` thousandths of g: asin(e / g) (:func:`worst_angle_deg`)."""
    return worst_angle_deg(error_mg, 1000.0)


def horizontal_field(field: float, inclination_deg: float) -> float:
    """H = F cos I: the horizontal component a compass's heading is read from (IGRF's H, app.geomag)."""
    return field * math.cos(math.radians(inclination_deg))


def heading_error_deg(error: float, field: float, inclination_deg: float) -> float:
    """The worst heading error of a compass whose reading of the field F is off by ``error`` (in F's unit),
    at inclination I: asin(e / H) with H = F cos I (:func:`worst_angle_deg`, :func:`horizontal_field`)."""
    return worst_angle_deg(error, horizontal_field(field, inclination_deg))


def compass_inclination(metrics: dict) -> tuple[float, str]:
    """The inclination a compass calibration's heading figure is told at, and where it comes from:
    ``model`` (the place's, IGRF-14), ``measured`` (between the accelerometer at rest and the field, in the
    turn), ``assumed`` (:data:`ASSUMED_INCLINATION_DEG`)."""
    if metrics.get("inclination_deg") is not None:
        return float(metrics["inclination_deg"]), "model"
    if metrics.get("measured_inclination_deg") is not None:
        return float(metrics["measured_inclination_deg"]), "measured"
    return ASSUMED_INCLINATION_DEG, "assumed"


def degrees_text(value: float) -> str:
    """An angle as told: ``1.8°``, ``0.03°``, ``12°``, ``<0.01°`` (the figure's own precision is about two
    digits)."""
    if value >= 10:
        return f"{value:.0f}°"
    if value >= 1:
        return f"{value:.1f}°"
    return f"{value:.2f}°" if value >= 0.005 else "<0.01°"


INCLINATION_WORDS = {
    "model": "the field dips {i:.0f}° at your place",
    "measured": "the field dips {i:.0f}° as measured in the turn",
    "assumed": "assuming the field dips {i:.0f}°: give the place for its own",
}
"""Where a heading figure's inclination comes from, in words (:func:`compass_inclination`)."""


def figure_degrees(before: float | None, after: float | None, unit: str, metrics: dict) -> dict | None:
    """A figure (an error ``before`` and ``after`` in ``unit``) as an angle: a tilt for an accelerometer's
    (``mg``), a heading for a compass's (``µT``, or ``counts`` with its field in counts); None for any other
    (a flight compass's figure is a heading already, in °).

    Returns
    -------
    dict or None
        ``kind`` (``tilt`` or ``heading``), ``before_deg`` (None without a raw figure), ``after_deg``,
        ``inclination_deg`` and ``inclination_source`` (a heading's; None for a tilt), and ``words``:
        ``a level off by 1.8° → 0.03°``, ``a heading off by 2.6° → 0.40° (the field dips 64° at your place)``.
    """
    if after is None:
        return None
    angle: Callable[[float], float]
    if unit == "mg":
        angle, kind, inclination, source = tilt_error_deg, "tilt", None, None
    elif unit in ("µT", "counts") and (metrics or {}).get("field_ut"):
        inclination, source = compass_inclination(metrics)
        field = float(metrics["field_ut"])
        kind = "heading"

        def angle(e: float) -> float:
            return heading_error_deg(e, field, inclination)
    else:
        return None
    before_deg = None if before is None else angle(before)
    after_deg = angle(after)
    told = degrees_text(after_deg) if before_deg is None else f"{degrees_text(before_deg)} → {degrees_text(after_deg)}"
    words = f"a level off by {told}" if kind == "tilt" else f"a heading off by {told}"
    if source is not None and inclination is not None:  # a heading
        words += f" ({INCLINATION_WORDS[source].format(i=abs(inclination))})"
    return {
        "kind": kind,
        "before_deg": before_deg,
        "after_deg": after_deg,
        "inclination_deg": inclination,
        "inclination_source": source,
        "words": words,
    }


__all__ = [
    "ASSUMED_INCLINATION_DEG",
    "compass_inclination",
    "degrees_text",
    "figure_degrees",
    "heading_error_deg",
    "horizontal_field",
    "tilt_error_deg",
    "worst_angle_deg",
]
