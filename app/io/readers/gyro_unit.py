"""The gyroscope's unit from its own data, as the accelerometer's is from its resting magnitude.

A still gyroscope reads its offset and its noise, whatever its unit; what a MEMS gyroscope can read
bounds both (:data:`~app.calibration.shared.plausible.GYR_PARTS`): an offset beyond 30 °/s, a white rate noise
outside 0.0014–0.45 °/s/√Hz is no MEMS part's. So a still offset of 4.5 read as rad/s (258 °/s) is
impossible, and a phone's noise of 0.001 rad/s per sample read as °/s is far below any part's.

Turned between rests, the gyroscope's integral is the turn that gravity's direction shows: the
accelerometer's mean direction in one rest, carried by the integrated rate to the next rest, lands
on the next rest's direction only with the right scale (rad/s, °/s, or counts at 131, 65.5, 32.8
or 16.4 LSB per °/s). The body-frame increments exp(ω Δt) are composed into the turn R between the
rests, and gravity's direction then reads g₂ = Rᵀ g₁ (Titterton & Weston, *Strapdown Inertial
Navigation Technology*, 2nd ed., IET 2004, eq. 3.31, the body-rate update of the attitude).
"""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np

from ...calibration.shared.plausible import GYR_PARTS, GYRO_BIAS_MAX_DPS
from .chips import GYR_LSB_PER_DPS, GYR_RANGE

DEG = math.pi / 180.0
GYR_NOISE_RANGE_DPS_RTHZ = (
    min(p.noise_dps_rthz for p in GYR_PARTS) / 2.0,
    max(p.noise_dps_rthz for p in GYR_PARTS) * 30.0,
)
"""A still gyroscope's white rate noise, °/s/√Hz, read at τ = 0.1 s (below any filter's corner): from half
the quietest part's datasheet figure to thirty times the noisiest's (a worn board, a simulation's
generous noise; a real MPU-6050 reads 0.009). Only halved below: rad/s and °/s differ by 57, and a
phone's rad/s noise read as °/s (below 0.0002) must stay outside; where a part's °/s noise read as
rad/s stays inside (0.16–0.45), the offset or a turn decides, or the unit is asked for."""
TURN_MIN_DEG = 20.0
"""Gravity's direction must turn this much between two rests for their move to weigh the scales."""
MOVE_MAX_S = 30.0
"""A move longer than this is not integrated (the offset's drift would weigh in)."""
TURN_TOLERANCE_DEG = 10.0
"""The right scale lands within this (or a quarter of the turn) of the next rest's direction."""
FIRM_FACTOR = 3.0
"""An offset this many times beyond what a MEMS gyroscope reads rules a unit out even at a rest the
accelerometer does not confirm (4.5 read as rad/s: 258 °/s, 8.6 times the limit)."""
WINDOW_S = 0.5
"""Without rests, the turn of gravity's direction is read over windows of this length of motion: the
accelerometer's direction (smoothed over :data:`SMOOTH_S`, centred, so that a hand's linear acceleration
weighs less) at a window's two ends, against the gyroscope's integral across it."""
SMOOTH_S = 0.3
WINDOW_TURN_MIN_DEG = 10.0
"""A window weighs the scales when gravity's direction turns this much across it (and no more than 90°)."""
MIN_WINDOWS = 5
"""Windows needed for the windows' median to decide a unit."""
MAX_WINDOWS = 400
"""At most this many windows are integrated (evenly chosen over a long recording)."""
NO_RATE_WORDS = "; without the sampling rate neither its noise at rest nor its turns can be read"
"""What the evidence says it lacks in a recording without times or a rate (:attr:`GyroEvidence.needs_rate`)."""
MIN_REST_S = 1.0
"""The shortest rest whose offset and noise are read (a second: fifty half-second blocks' worth of a
detector that cuts every knock)."""
NOISE_TAU_S = 0.1
"""The averaging time at which the white rate noise is read."""
MIN_DISTINCT = 10
"""The noise is read only from an axis showing at least this many distinct values at rest."""


def candidates(whole: bool) -> dict[str, float]:
    """Each unit the readings can be in, with its factor to rad/s (``raw@131`` … for counts)."""
    if whole:
        return {f"raw@{lsb:g}": DEG / lsb for lsb in GYR_LSB_PER_DPS}
    return {"rad/s": 1.0, "deg/s": DEG}


def unit_words(key: str) -> str:
    """``raw@131`` → ``counts at 131 LSB per °/s (±250 °/s)``; units as they are."""
    if key.startswith("raw@"):
        lsb = float(key[4:])
        return f"counts at {lsb:g} LSB per °/s ({GYR_RANGE[lsb]})"
    return key


@dataclasses.dataclass(frozen=True)
class GyroEvidence:
    """What the data say of the gyroscope's unit: ``unit`` the one they leave (None when they leave
    several or none), ``words`` why, for messages."""

    unit: str | None
    words: str
    offset: float
    turn_errors: dict[str, float]
    moves: int
    firm: bool = True
    """Whether the evidence may overrule a unit the header or the caller stated: the turns between rests,
    or an offset read at a rest the accelerometer confirms (or beyond :data:`FIRM_FACTOR` times what a part
    reads). A rest found on the gyroscope alone may be a steady turn, and a hand never quite still reads a
    noise no MEMS part has: such evidence decides only where nothing states the unit."""
    needs_rate: bool = False
    """Whether a rate (or times) would let the data show the unit: without one neither the noise at rest nor the
    turns are read (the question asks for the rate first)."""
    by_turns: bool = False
    """Whether gravity's turns decided (between rests, or over windows of motion): the accelerometer beside the
    gyroscope confirms the unit, whatever a rest's offset or noise would say."""


def _mul(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Hamilton products of quaternions (w, x, y, z), broadcast over leading axes."""
    w1, x1, y1, z1 = np.moveaxis(p, -1, 0)
    w2, x2, y2, z2 = np.moveaxis(q, -1, 0)
    return np.stack(
        [
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ],
        axis=-1,
    )


def compose(rotvecs: np.ndarray) -> np.ndarray:
    """The product exp(r₁) exp(r₂) … exp(r_N) of body-frame increments, shape (…, N, 3) → (…, 4),
    by pairwise products in order (log₂ N vectorised steps)."""
    angle = np.linalg.norm(rotvecs, axis=-1, keepdims=True)
    axis = np.divide(rotvecs, angle, out=np.zeros_like(rotvecs), where=angle > 0)
    q = np.concatenate([np.cos(angle / 2), axis * np.sin(angle / 2)], axis=-1)
    while q.shape[-2] > 1:
        if q.shape[-2] % 2:
            pad = np.zeros(q.shape[:-2] + (1, 4))
            pad[..., 0] = 1.0
            q = np.concatenate([q, pad], axis=-2)
        q = _mul(q[..., 0::2, :], q[..., 1::2, :])
    return q[..., 0, :]


def rotate_back(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Rᵀ v for the rotations R of quaternions ``q`` (…, 4)."""
    conj = q * np.array([1.0, -1.0, -1.0, -1.0])
    vq = np.concatenate([np.zeros(v.shape[:-1] + (1,)), v], axis=-1)
    return _mul(_mul(conj, vq), q)[..., 1:]


def _angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    a = a / np.linalg.norm(a, axis=-1, keepdims=True)
    b = b / np.linalg.norm(b, axis=-1, keepdims=True)
    angle: np.ndarray = np.degrees(np.arccos(np.clip(np.sum(a * b, axis=-1), -1.0, 1.0)))
    return angle


def turn_errors(
    gyr: np.ndarray, ref: np.ndarray, runs: list[tuple[int, int]], dt: np.ndarray, scales: dict[str, float]
) -> tuple[dict[str, float], int]:
    """The median angle (degrees) by which each scale's integral misses the next rest's direction of
    ``ref`` (gravity), over the moves between consecutive rests that turn it by 20° or more."""
    errs: dict[str, list[float]] = {k: [] for k in scales}
    factors = np.array(list(scales.values()))
    for (a1, b1), (a2, b2) in itertools.pairwise(runs):
        g1, g2 = ref[a1:b1].mean(axis=0), ref[a2:b2].mean(axis=0)
        if _angle(g1, g2) < TURN_MIN_DEG or float(np.sum(dt[b1:a2])) > MOVE_MAX_S:
            continue
        bias = (gyr[a1:b1].sum(axis=0) + gyr[a2:b2].sum(axis=0)) / ((b1 - a1) + (b2 - a2))
        lo, hi = (a1 + b1) // 2, (a2 + b2) // 2
        steps = (gyr[lo:hi] - bias) * dt[lo:hi, None]
        q = compose(factors[:, None, None] * steps[None])
        predicted = rotate_back(q, np.broadcast_to(g1, (len(factors), 3)))
        for key, e in zip(scales, _angle(predicted, g2[None])):
            errs[key].append(float(e))
    moves = len(next(iter(errs.values()))) if errs else 0
    return {k: float(np.median(v)) for k, v in errs.items() if v}, moves


def window_turn_errors(
    gyr: np.ndarray, ref: np.ndarray, dt: np.ndarray, fs: float, scales: dict[str, float]
) -> tuple[dict[str, float], int, float]:
    """The median angle (degrees) by which each scale's integral over a half-second window of motion misses
    the turn of gravity's direction across it, the number of windows that turn it by 10°–90°, and their
    median turn. No rest is needed: a phone turned in the hand the whole time shows its scale so (the
    accelerometer smoothed over 0.3 s, its direction at the window's ends, g₂ = Rᵀ g₁ as between rests;
    the offset, unknown without a rest, is a MEMS part's few tenths of a degree per second at most)."""
    k = max(1, int(round(SMOOTH_S * fs)))
    m = max(2, int(round(WINDOW_S * fs)))
    if len(ref) < m + 2 * k + 1:
        return {}, 0, 0.0
    kernel = np.ones(k) / k
    smooth = np.column_stack([np.convolve(ref[:, i], kernel, mode="same") for i in range(3)])
    starts = np.arange(k, len(ref) - m - k, m)
    turn = _angle(smooth[starts], smooth[starts + m])
    weighs = (turn >= WINDOW_TURN_MIN_DEG) & (turn <= 90.0)
    starts, turn = starts[weighs], turn[weighs]
    if len(starts) > MAX_WINDOWS:
        pick = np.linspace(0, len(starts) - 1, MAX_WINDOWS).astype(int)
        starts, turn = starts[pick], turn[pick]
    if len(starts) == 0:
        return {}, 0, 0.0
    rows = starts[:, None] + np.arange(m)[None]
    steps = gyr[rows] * dt[rows][..., None]
    factors = np.array(list(scales.values()))
    q = compose(factors[:, None, None, None] * steps[None])
    predicted = rotate_back(q, np.broadcast_to(smooth[starts], (len(factors), len(starts), 3)))
    errors = _angle(predicted, smooth[starts + m][None])
    return {key: float(np.median(e)) for key, e in zip(scales, errors)}, len(starts), float(np.median(turn))


def _decided(errors: dict[str, float], plausible: dict[str, bool] | None = None) -> tuple[str, float, str] | None:
    """The scale whose integral lands within 10° of gravity's turns while every other misses by twice that and
    10° more (and the offset rules it out no more), with its error and the others' words; else None."""
    if not errors:
        return None
    ranked = sorted(errors, key=lambda k: errors[k])
    best, e1 = ranked[0], errors[ranked[0]]
    e2 = errors[ranked[1]] if len(ranked) > 1 else math.inf
    if e1 <= TURN_TOLERANCE_DEG and e2 >= 2.0 * e1 + TURN_TOLERANCE_DEG and (plausible or {}).get(best, True):
        return best, e1, ", ".join(f"{unit_words(k)} {errors[k]:.0f}°" for k in ranked[1:])
    return None


def _by_windows(
    gyr: np.ndarray, ref: np.ndarray | None, dt: np.ndarray | None, fs: float | None, scales: dict[str, float]
) -> GyroEvidence | None:
    """The evidence of half-second windows of motion (:func:`window_turn_errors`), or None where they decide
    nothing: too few windows, or a right scale that does not land within a third of the turn."""
    if ref is None or len(ref) != len(gyr) or dt is None:
        return None
    fs = fs or 1.0 / float(np.median(dt))
    errors, windows, turn = window_turn_errors(np.asarray(gyr, float), np.asarray(ref, float), dt, fs, scales)
    found = _decided(errors) if windows >= MIN_WINDOWS else None
    if found is None or found[1] > turn / 3.0:
        return None
    best, e1, others = found
    return GyroEvidence(
        best,
        f"its integral over {windows} half-second windows of motion lands within {e1:.1f}° of the turn of "
        f"gravity's direction ({turn:.0f}° in the median window) in {unit_words(best)} (off by {others})",
        math.nan,
        errors,
        windows,
        by_turns=True,
    )


def _steps_s(n: int, fs: float | None, time_s: np.ndarray | None) -> np.ndarray | None:
    """Each sample's time step in seconds: from the times where there are, else from the rate, else None."""
    if time_s is not None and len(time_s) > 2:
        return np.diff(time_s, append=time_s[-1] + (time_s[-1] - time_s[-2]))
    return np.full(n, 1.0 / fs) if fs else None


def rest_figures(gyr: np.ndarray, run: tuple[int, int], fs: float | None) -> tuple[np.ndarray, float | None]:
    """The offset (median at rest) and, when the readings are fine enough, the white rate noise density
    in the readings' unit per √Hz: the Allan deviation at τ = 0.1 s times √τ (IEEE Std 952-1997, annex
    C: σ(τ) = N/√τ), free of a low-pass filter's narrowing of the band above 5 Hz."""
    still = np.asarray(gyr[run[0] : min(run[1], run[0] + 200_000)], dtype=float)  # plenty for an offset and a noise
    offset = np.median(still, axis=0)
    if fs is None:
        return offset, None
    m = max(1, int(round(NOISE_TAU_S * fs)))
    blocks = len(still) // m
    if blocks < 20 or sum(len(np.unique(still[:, ax])) >= MIN_DISTINCT for ax in range(3)) < 3:
        return offset, None
    means = still[: blocks * m].reshape(blocks, m, 3).mean(axis=1)
    adev = np.sqrt(0.5 * np.mean(np.diff(means, axis=0) ** 2, axis=0))
    return offset, float(np.median(adev)) * math.sqrt(m / fs)


def gyro_evidence(
    gyr: np.ndarray, *, whole: bool, acc: np.ndarray | None, fs: float | None, time_s: np.ndarray | None
) -> GyroEvidence:
    """What the gyroscope's data say of its unit: at rest its offset and noise against what a MEMS
    gyroscope can read, turned its integral against gravity's turn between rests.

    Parameters
    ----------
    gyr : numpy.ndarray, shape (N, 3)
        The readings as the file holds them.
    whole : bool
        Whole numbers: counts (their scale is what is sought), else rad/s or °/s.
    acc : numpy.ndarray, shape (N, 3), optional
        The accelerometer of the same recording (any unit: its direction is read).
    fs : float, optional
        The sampling rate (Hz); without it (and ``time_s``) only the offset is read.
    time_s : numpy.ndarray, optional
        Seconds of each sample.

    Returns
    -------
    GyroEvidence
    """
    from ...calibration.noise.still_part import still_runs  # here: the core's detector, as the noise method's

    scales = candidates(whole)
    ref = acc if acc is not None and len(acc) == len(gyr) else None
    runs = still_runs(ref if ref is not None else gyr, fs or 100.0) if len(gyr) >= 20 else [(0, len(gyr))]
    least = max(10, int(round(MIN_REST_S * (fs or 100.0))))
    runs = [r for r in runs if r[1] - r[0] >= least]
    dt = _steps_s(len(gyr), fs, time_s)
    if not runs:  # never still for a second: neither an offset nor a noise to read, nor turns between rests
        windows = _by_windows(gyr, ref, dt, fs, scales)
        if windows is not None:
            return windows
        return GyroEvidence(
            None,
            f"it never rests for {MIN_REST_S:g} s, so neither its offset nor its noise shows its unit",
            math.nan,
            {},
            0,
            False,
        )
    longest = max(runs, key=lambda r: r[1] - r[0])
    offset, noise = rest_figures(gyr, longest, fs)
    off = float(np.linalg.norm(offset))
    lo_noise, hi_noise = GYR_NOISE_RANGE_DPS_RTHZ
    plausible, said, by_offset = {}, {}, {}
    for key, k in scales.items():
        off_dps = off * k / DEG
        ok = by_offset[key] = off_dps <= GYRO_BIAS_MAX_DPS
        words = f"a still offset of {off:.3g} is {off_dps:.3g} °/s in {unit_words(key)}"
        if noise is not None and not whole:
            n_dps = noise * k / DEG
            if not lo_noise <= n_dps <= hi_noise:
                if ok:  # the offset, where it rules the unit out, is named first
                    words = f"a still noise of {noise:.2g} per √Hz is {n_dps:.2g} °/s/√Hz in {unit_words(key)}"
                ok = False
        plausible[key], said[key] = ok, words
    errors: dict[str, float] = {}
    moves = 0
    if ref is not None and len(runs) >= 2 and dt is not None:
        errors, moves = turn_errors(np.asarray(gyr, float), np.asarray(ref, float), runs, dt, scales)
    found = _decided(errors, plausible)
    if found is not None:
        best, e1, others = found
        return GyroEvidence(
            best,
            f"its integral over {moves} turn{'s' if moves > 1 else ''} between rests "
            f"lands within {e1:.1f}° of gravity's direction in {unit_words(best)} "
            f"(off by {others})",
            off,
            errors,
            moves,
            by_turns=True,
        )
    windows = _by_windows(gyr, ref, dt, fs, scales)
    # a hand's tremor at a "rest" is no sensor's noise (the windows' evidence always names a unit)
    if windows is not None and windows.unit is not None and by_offset[windows.unit]:
        return dataclasses.replace(windows, offset=off)
    left = [k for k, ok in plausible.items() if ok]
    if len(left) == 1 and not whole:
        gone = next(k for k in scales if k not in left)
        by_offset_alone = sum(by_offset.values()) == 1
        far = off * scales[gone] / DEG > FIRM_FACTOR * GYRO_BIAS_MAX_DPS
        firm = by_offset_alone and (ref is not None or far)
        return GyroEvidence(
            left[0],
            f"{said[gone]}, beyond what a MEMS gyroscope reads (an offset within "
            f"{GYRO_BIAS_MAX_DPS:g} °/s, a noise within {lo_noise:g}–{hi_noise:g} °/s/√Hz)",
            off,
            errors,
            moves,
            firm,
        )
    return GyroEvidence(
        None,
        f"a still offset of {off:.3g}"
        + (f" and a noise of {noise:.2g} per √Hz" if noise else "")
        + " fit "
        + " and ".join(unit_words(k) for k in left or scales)
        + (
            NO_RATE_WORDS
            if dt is None
            else ", and no turn between rests shows its scale"
            if not errors
            else ", and its turns between rests do not single out one scale"
        ),
        off,
        errors,
        moves,
        needs_rate=dt is None,
    )
