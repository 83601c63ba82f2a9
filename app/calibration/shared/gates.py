"""Quality gates shared by every fit: small checks that return messages, and their accumulator.

A gate failure is a *reason* (the result's ``ok`` is false); everything else worth telling is a
*warning*.  Every result lists its reasons first among its warnings (:meth:`Gates.fields`).

Each gate takes the message it renders: a ``str.format`` template, or a callable taking the same
keyword fields, so that every method keeps its own wording.  The fields a gate supplies are listed
in its docstring; extra keyword arguments are passed on to the template.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

import numpy as np

from .validation import near_duplicate_pairs, uncovered_directions

Message = str | Callable[..., str]
AXES = "xyz"


def _render(message: Message, **fields) -> str:
    return message(**fields) if callable(message) else message.format(**fields)


def scale_gate(scales, plausible: tuple[float, float] | None, message: Message, **extra) -> list[str]:
    """One message per scale outside the ``plausible`` (lo, hi) range; none when it is None.

    Fields: ``axis`` (x, y, z), ``n`` (1, 2, 3), ``value``, ``lo``, ``hi``.
    """
    if plausible is None:
        return []
    lo, hi = plausible
    return [
        _render(message, axis=AXES[k], n=k + 1, value=s, lo=lo, hi=hi, **extra)
        for k, s in enumerate(scales)
        if not lo <= s <= hi
    ]


def offset_gate(offsets, limit: float | None, message: Message, **extra) -> list[str]:
    """One message per offset above ``limit`` in magnitude; none when ``limit`` is None.

    Fields: ``axis``, ``n``, ``value``, ``limit``.
    """
    if limit is None:
        return []
    return [
        _render(message, axis=AXES[k], n=k + 1, value=o, limit=limit, **extra)
        for k, o in enumerate(offsets)
        if abs(o) > limit
    ]


def residual_gate(errors, limit: float, message: Message, **extra) -> list[str]:
    """The message for the worst of ``errors`` when it exceeds ``limit``.

    Fields: ``index`` (of the worst), ``value``, ``percent`` (100 × value), ``limit``,
    ``gate_percent`` (100 × limit).
    """
    errors = np.asarray(errors)
    worst = int(np.argmax(errors))
    if not errors[worst] > limit:
        return []
    value = errors[worst]
    return [
        _render(message, index=worst, value=value, percent=100 * value, limit=limit, gate_percent=100 * limit, **extra)
    ]


def limit_gate(value, limit: float, message: Message, **extra) -> list[str]:
    """The message when ``value`` exceeds ``limit`` (a condition number, a χ²/dof…).

    Fields: ``value``, ``limit``.
    """
    return [_render(message, value=value, limit=limit, **extra)] if value > limit else []


def deviation_gate(
    named_values: Iterable[tuple[str, float]], centre: float, limit: float, message: Message, **extra
) -> list[str]:
    """One message per named value further than ``limit`` from ``centre``.

    Fields: ``name``, ``value``, ``limit``.
    """
    return [
        _render(message, name=name, value=v, limit=limit, **extra)
        for name, v in named_values
        if abs(v - centre) > limit
    ]


def hemisphere_gate(axis, message: Message, **extra) -> list[str]:
    """The message when all readings lie in one hemisphere around ``axis`` (None: they do not).

    Fields: ``direction`` (the axis printed to two decimals).
    """
    if axis is None:
        return []
    return [_render(message, direction=np.array2string(axis, precision=2), **extra)]


def coverage_gate(vectors, message: Message, *, hemisphere=None, **extra) -> list[str]:
    """The message when some axis direction ±x, ±y, ±z has no reading within 60° of it.

    Skipped when the readings already failed the hemisphere gate (``hemisphere`` not None).
    Fields: ``missing`` (the labels joined by ", ").
    """
    missing = uncovered_directions(vectors)
    if not missing or hemisphere is not None:
        return []
    return [_render(message, missing=", ".join(missing), **extra)]


def near_duplicate_gate(vectors, tolerance: float, message: Message, **extra) -> list[str]:
    """One message per pair of readings closer than ``tolerance`` to each other.

    Fields: ``i`` < ``j`` (0-based), ``pi``, ``pj`` (1-based).
    """
    return [
        _render(message, i=i, j=j, pi=i + 1, pj=j + 1, **extra) for i, j in near_duplicate_pairs(vectors, tolerance)
    ]


def exact_fit_gate(dof: int, message: Message, **extra) -> list[str]:
    """The message when the fit has no residual degrees of freedom."""
    return [_render(message, dof=dof, **extra)] if dof == 0 else []


@dataclass
class Gates:
    """Accumulator of a fit's reasons (gate failures) and warnings, in the order they arise."""

    reasons: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)

    def fail(self, messages: str | Iterable[str]) -> Gates:
        """Add reasons: a message or the list a gate returned."""
        self.reasons.extend([messages] if isinstance(messages, str) else messages)
        return self

    def warn(self, messages: str | Iterable[str]) -> Gates:
        """Add warnings: a message or the list a gate returned."""
        self.warnings.extend([messages] if isinstance(messages, str) else messages)
        return self

    def merge(self, result, *, unique: bool = False) -> Gates:
        """Take over a part's reasons and its warnings that are not reasons.

        With ``unique`` a reason already present is not repeated.
        """
        if unique:
            self.reasons.extend(r for r in result.reasons if r not in self.reasons)
        else:
            self.reasons.extend(result.reasons)
        self.warnings.extend(w for w in result.warnings if w not in result.reasons)
        return self

    def fields(self) -> dict:
        """``warnings`` (reasons first) and ``reasons`` as the tuples every result holds."""
        return {"warnings": tuple(self.reasons + self.warnings), "reasons": tuple(self.reasons)}


def unknown_orientation_gates(
    gates: Gates,
    means,
    gravity: float,
    *,
    condition: float,
    max_condition: float,
    dof: int,
    hemisphere,
    near_fraction: float,
    coverage_hint: str = "",
    positions_hint: str,
) -> None:
    """The gates every fit of still readings of unknown orientation ends with (Georgieva et al., ESGI'95,
    approach 1; Farago, Maczak and Gingl, IEEE Access), in this order: warnings for a poorly conditioned
    design, a direction of the sphere with no position near it and near-duplicate positions, and a reason
    for an exact fit of the 9 parameters. ``coverage_hint`` and ``positions_hint`` end the coverage and
    exact-fit messages with the method's own advice."""
    gates.warn(
        limit_gate(
            condition,
            max_condition,
            "the positions determine the parameters poorly (condition number {value:.3g}): "
            "spread the positions over the whole sphere",
        )
    )
    gates.warn(
        coverage_gate(
            means,
            "poor coverage of the sphere: no position has the {missing} axis within 60° of up; add such positions"
            + coverage_hint,
            hemisphere=hemisphere,
        )
    )
    gates.warn(
        near_duplicate_gate(
            means,
            near_fraction * gravity,
            "readings {i} and {j} (positions {pi} and {pj}, counting from 1) are within 1 % of g "
            "of each other (near-duplicate positions, Georgieva et al. Dataset 3): they weigh one orientation twice",
        )
    )
    gates.fail(
        exact_fit_gate(
            dof,
            "9 positions fit the 9 parameters exactly: there are no residual degrees of freedom, "
            "so no intervals and no check of the fit; " + positions_hint,
        )
    )
