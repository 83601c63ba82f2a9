"""An annotated Ferraris section list instead of detected rests and turns.

imucal (the mad-lab-fau package for Ferraris' calibration) stores the regions a person marked in
its interactive plot as ``{"x_p": {"start": 540, "end": 1271}, "x_a": …, "y_p", "y_a", "z_p",
"z_a", "x_rot", "y_rot", "z_rot"}``: sample indices of the recording, ``end`` exclusive (imucal
slices ``data.iloc[start:end]``).  ``x_p`` is a rest with +x up (x reads +g), ``x_a`` with −x up;
``x_rot`` a full turn about the sensor's x axis (imucal's documentation: in the x_p position,
clockwise seen from above).

The six rests are taken as they were marked (no trimming) and are the only readings of the
accelerometer fit and of the gyroscope bias, as in Ferraris' method; each turn is integrated over
its whole region, and its first and last samples anchor it (the sense of the turn is taken from
the data).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..shared.errors import CalibrationError
from ..shared.orientations import nearest_orientation
from .matching import integrated_rate
from .protocols import FERRARIS_SIX, Protocol, explicit_protocol, turn_spec
from .segmentation import Segmentation
from .sequence import FACE_MAX_ANGLE_DEG, normalised_directions

REST_KEYS = ("x_p", "x_a", "y_p", "y_a", "z_p", "z_a")
TURN_KEYS = ("x_rot", "y_rot", "z_rot")
SECTION_KEYS = REST_KEYS + TURN_KEYS
"""imucal's ``FerrarisCalibration.FERRARIS_SECTIONS``."""

ANCHOR_S = 0.1
"""Seconds at each end of a turn's region that stand for the rest it starts and ends in."""

_FIX = (
    f'give each of {", ".join(SECTION_KEYS)} as {{"start": first sample, "end": sample after the last}} '
    "(imucal's section list)"
)


def _index(value, where: str) -> int:
    if (
        isinstance(value, bool)
        or not isinstance(value, (int, float, np.integer, np.floating))
        or not np.isfinite(value)
        or float(value) != int(value)
    ):
        raise CalibrationError(f"sections.{where} must be a whole sample index; got {value!r}: {_FIX}")
    return int(value)


def validated_sections(sections, n_samples: int) -> dict[str, tuple[int, int]]:
    """The nine regions as ``{key: (start, end)}``, checked against the recording.

    Raises
    ------
    CalibrationError
        A missing or unknown key, a region that is not ``{start, end}``, is empty or reversed, or
        reaches past the recording (the message names the key and the recording's range).
    """
    if not isinstance(sections, dict):
        raise CalibrationError(f"sections must be an object keyed by section name: {_FIX}")
    unknown = [k for k in sections if k not in SECTION_KEYS]
    if unknown:
        raise CalibrationError(f"sections has unknown key(s) {', '.join(map(repr, unknown))}: {_FIX}")
    missing = [k for k in SECTION_KEYS if k not in sections]
    if missing:
        raise CalibrationError(f"sections lacks {', '.join(missing)}: {_FIX}")
    out = {}
    for key in SECTION_KEYS:
        region = sections[key]
        if not isinstance(region, dict) or set(region) != {"start", "end"}:
            raise CalibrationError(f'sections.{key} must be {{"start": …, "end": …}}; got {region!r}')
        a, b = _index(region["start"], f"{key}.start"), _index(region["end"], f"{key}.end")
        if not 0 <= a < b:
            raise CalibrationError(
                f"sections.{key} runs from {a} to {b}: start must be at least 0 and before end (end is exclusive)"
            )
        if b > n_samples:
            raise CalibrationError(
                f"sections.{key} ends at sample {b}, but the recording has {n_samples} samples (0–{n_samples - 1}): "
                "check that the section list belongs to this recording and counts samples, not seconds"
            )
        if b - a < 2:
            raise CalibrationError(f"sections.{key} holds {b - a} sample: mark at least two")
        out[key] = (a, b)
    return out


def from_sections(sections, acc, w, *, sampling_rate_hz: float, gravity: float) -> tuple[Segmentation, Protocol]:
    """The segmentation and protocol of an annotated Ferraris recording.

    Parameters
    ----------
    sections : dict
        imucal's section list (module docstring).
    acc, w : numpy.ndarray, shape (N, 3)
        Raw accelerometer samples and pre-adjusted gyroscope rates (rad/s).
    sampling_rate_hz, gravity : float

    Returns
    -------
    (Segmentation, Protocol)
        Twelve positions — the six rests, then each turn's start and end — and the protocol joining
        them (free moves, and a full turn about x, y and z).

    Raises
    ------
    CalibrationError
        Invalid regions (:func:`validated_sections`), or a rest whose up axis is not its label's.
    """
    fs = float(sampling_rate_hz)
    regions = validated_sections(sections, len(acc))
    rests = [regions[k] for k in REST_KEYS]
    dirs = normalised_directions(np.array([acc[a:b].mean(axis=0) for a, b in rests]), gravity)
    for key, label, d in zip(REST_KEYS, FERRARIS_SIX, dirs):
        seen = nearest_orientation(d, FACE_MAX_ANGLE_DEG)
        if seen != label:
            raise CalibrationError(
                f"sections.{key} should be a rest with {label} up, but the accelerometer reads "
                f"{seen or 'no axis'} up there: check the labels ({key[0]}_p is +{key[0]} up, reading +g; "
                f"{key[0]}_a is −{key[0]} up)"
            )
    bias = np.vstack([w[a:b] for a, b in rests]).mean(axis=0)
    n_anchor = max(1, int(round(ANCHOR_S * fs)))
    static = list(rests)
    rotations: list = [None] * 5
    ups = list(FERRARIS_SIX)
    intervals = [(rests[k][1], max(rests[k][1], rests[k + 1][0])) for k in range(5)]
    prev_end = rests[-1][1]
    for axis, key in enumerate(TURN_KEYS):
        a, b = regions[key]
        n = max(1, min(n_anchor, (b - a) // 2))
        up = _turn_up(acc, (a, b), rests, gravity, axis)
        angle = 360.0 if integrated_rate(w, a, b, bias, fs)[axis] >= 0 else -360.0
        static += [(a, a + n), (b - n, b)]
        ups += [up, up]
        rotations += [None, turn_spec(up, axis, angle)]
        intervals += [(prev_end, max(prev_end, a)), (a, b)]
        prev_end = b
    proto = explicit_protocol(rotations, ups=ups, name="ferraris")
    proto = replace(proto, reading_positions=tuple(range(6)))
    seg = Segmentation(
        static=tuple(static),
        still=tuple(static),
        rotations=tuple(intervals),
        gyro_bias=bias,
        threshold=None,
        source="sections",
    )
    return seg, proto


def _turn_up(acc, region, rests, gravity: float, axis: int) -> str:
    """The up axis over a turn's region (a turn about the vertical keeps it), normalised as the
    rests are; the turn's own axis (imucal's x_rot in the x_p position) when no axis is up."""
    a, b = region
    means = np.array([acc[s:e].mean(axis=0) for s, e in rests] + [acc[a:b].mean(axis=0)])
    return nearest_orientation(normalised_directions(means, gravity)[-1], FACE_MAX_ANGLE_DEG) or f"+{'xyz'[axis]}"
