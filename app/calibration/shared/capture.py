"""One still capture of the guided wizard: is it still, in which pose, at what rate?

The wizard sends the raw samples of each pose (not only their mean), so the server checks what
the page saw: the device was still, an axis pointed up (within 20°, docs/rest.md), the
magnitude was that of gravity, and the rate follows from the event timestamps.  The mean then
enters the six-position solution (Georgieva et al. (ESGI'95), section 3.3.1) as one reading m̄.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import CalibrationError, InsufficientDataError, NotStillError
from .orientations import LABEL_MAX_ANGLE_DEG, nearest_orientation
from .validation import as_vectors

STILL_MAX_STD_G = 0.03
"""Largest per-axis standard deviation of a still capture, as a fraction of g (0.29 m/s²).

A phone resting on a table shows 0.01–0.05 m/s² (browser rounding to 0.1 m/s² adds up to 0.03);
a hand holding it, 0.1–0.3; a slide or a tap, more."""

STILL_MAX_DRIFT_G = 0.02
"""Largest change of the mean between the capture's two halves, as a fraction of g: a slow
slide or roll keeps a small spread yet moves the mean."""

MAGNITUDE_TOLERANCE = 0.15
"""The mean's magnitude must lie within ±15 % of g: a looser gate would pass a device that
accelerates, a tighter one would refuse the badly calibrated sensors the wizard is for."""

MIN_SAMPLES = 10


def median_interval_ms(t_ms: np.ndarray) -> float:
    """The median of the positive intervals between non-decreasing event timestamps, in ms.

    Browser events arrive unevenly (and some share a timestamp), so the median interval, not a
    nominal ``interval``, gives the rate.
    """
    steps = np.diff(t_ms)
    positive = steps[steps > 0]
    if len(positive) == 0:
        raise CalibrationError("all timestamps are equal: send each event's own timeStamp")
    return float(np.median(positive))


def on_uniform_grid(t_ms: np.ndarray, *signals: np.ndarray) -> tuple[list[np.ndarray], float]:
    """Signals (N×3) interpolated linearly onto a grid at the median event interval from the first
    timestamp to the last, and that interval in ms."""
    h = median_interval_ms(t_ms)
    grid = np.arange(t_ms[0], t_ms[-1] + 0.5 * h, h)
    return [np.column_stack([np.interp(grid, t_ms, x[:, k]) for k in range(x.shape[1])]) for x in signals], h


@dataclass(frozen=True)
class StillCapture:
    """A checked still capture.

    Attributes
    ----------
    position : str
        The recognised pose: the device axis that points up (``+x`` … ``-z``).
    mean, std : numpy.ndarray, shape (3,)
        Mean and standard deviation of the samples, in their unit.
    count : int
        Number of samples.
    sampling_rate_hz : float
        From the median interval between event timestamps.
    duration_s : float
        From the first to the last timestamp.
    """

    position: str
    mean: np.ndarray
    std: np.ndarray
    count: int
    sampling_rate_hz: float
    duration_s: float

    def to_dict(self) -> dict:
        return {
            "position": self.position,
            "mean": self.mean.tolist(),
            "std": self.std.tolist(),
            "count": self.count,
            "sampling_rate_hz": self.sampling_rate_hz,
            "duration_s": self.duration_s,
        }


def check_still_capture(
    acc, t_ms, *, gravity: float, expected: str | None = None, max_angle_deg: float = LABEL_MAX_ANGLE_DEG
) -> StillCapture:
    """Check one capture of the wizard and summarise it.

    Parameters
    ----------
    acc : array_like, shape (N, 3)
        Specific force samples (W3C sign: at rest the up axis reads +g), in the unit of ``gravity``.
    t_ms : array_like, shape (N,)
        Event timestamps in milliseconds, non-decreasing (``DeviceMotionEvent.timeStamp``).
    gravity : float
        Reference magnitude in the samples' unit (9.80665 for m/s², 1 for g).
    expected : str, optional
        The pose the caller says it is; refused when the data show another.
    max_angle_deg : float
        Largest angle between the mean direction and the axis that names the pose.

    Returns
    -------
    StillCapture

    Raises
    ------
    CalibrationError
        With a message a person can act on: too few samples, timestamps out of order, not still,
        not near a pose, a magnitude that is not gravity's, or a pose other than ``expected``.
    """
    a = as_vectors(acc, "acc")
    t = np.asarray(t_ms, dtype=float).reshape(-1)
    if len(a) < MIN_SAMPLES:
        raise InsufficientDataError(f"a capture needs at least {MIN_SAMPLES} samples; got {len(a)}")
    if len(t) != len(a):
        raise CalibrationError(f"t_ms has {len(t)} timestamps for {len(a)} samples: give one per sample")
    if not np.all(np.isfinite(t)):
        raise CalibrationError("t_ms holds a value that is not a finite number")
    steps = np.diff(t)
    if np.any(steps < 0):
        raise CalibrationError(
            f"t_ms goes back in time at sample {int(np.argmax(steps < 0)) + 1}: "
            "send the event timestamps in the order they arrived"
        )
    duration_s = float(t[-1] - t[0]) / 1000.0
    rate = 1000.0 / median_interval_ms(t)

    mean = a.mean(axis=0)
    std = a.std(axis=0, ddof=1)
    limit = STILL_MAX_STD_G * gravity
    if np.any(std > limit):
        axis = "xyz"[int(np.argmax(std))]
        raise NotStillError(
            f"the device moved during the capture (spread {std.max():.3g} on {axis}, at most {limit:.3g} "
            "allowed): rest it on a steady surface and keep your hands off until the capture ends"
        )
    half = len(a) // 2
    drift = float(np.linalg.norm(a[half:].mean(axis=0) - a[:half].mean(axis=0)))
    if drift > STILL_MAX_DRIFT_G * gravity:
        raise NotStillError(
            f"the device slid or tilted during the capture (its mean moved by {drift:.3g}): "
            "rest it on a steady surface and capture again"
        )
    magnitude = float(np.linalg.norm(mean))
    if abs(magnitude - gravity) > MAGNITUDE_TOLERANCE * gravity:
        raise CalibrationError(
            f"the reading's magnitude is {magnitude:.4g}, not gravity's {gravity:.6g} (±15 %): the samples "
            "must include gravity (accelerationIncludingGravity) in the declared unit"
        )
    position = nearest_orientation(mean, max_angle_deg)
    if position is None:
        raise CalibrationError(
            f"no axis points up within {max_angle_deg:g}° (the reading is {np.round(mean, 3).tolist()}): "
            "lay the device flat on a face or stand it straight on an edge"
        )
    if expected is not None and expected != position:
        raise CalibrationError(
            f"the device is in the {position} pose, not {expected}: turn it so that "
            f"{expected} points up, or capture {position}"
        )
    return StillCapture(
        position=position, mean=mean, std=std, count=len(a), sampling_rate_hz=rate, duration_s=duration_s
    )


class PoseTooCloseError(CalibrationError):
    """A free-pose capture that points within the minimum angle of one already taken."""

    code = "pose_too_close"


def check_new_direction(mean, previous, *, min_angle_deg: float) -> None:
    """Refuse a still reading whose direction is within ``min_angle_deg`` of an earlier one.

    A magnitude model learns from orientations, not from repeats: two poses a few degrees apart
    weigh one orientation twice (near duplicates, Georgieva et al. Dataset 3).

    Parameters
    ----------
    mean : array_like, shape (3,)
        The new capture's mean reading.
    previous : array_like, shape (N, 3)
        The mean readings already taken (N may be 0).
    min_angle_deg : float

    Raises
    ------
    PoseTooCloseError
        Naming the nearest earlier pose (counting from 1) and the angle to it.
    """
    prev = np.asarray(previous, dtype=float).reshape(-1, 3)
    if len(prev) == 0:
        return
    u = np.asarray(mean, dtype=float) / np.linalg.norm(mean)
    cos = (prev / np.linalg.norm(prev, axis=1, keepdims=True)) @ u
    nearest = int(np.argmax(cos))
    angle = float(np.degrees(np.arccos(np.clip(cos[nearest], -1.0, 1.0))))
    if angle < min_angle_deg:
        raise PoseTooCloseError(
            f"this pose is only {angle:.0f}° from pose {nearest + 1}, already captured: turn the device "
            f"at least {min_angle_deg:g}° further (another face or edge up, or tilted) and let it rest again"
        )
