"""Seeded simulation of a raw accelerometer log of a device rested in several orientations.

The device rests in a sequence of orientations; between two rests a hand turns it (a smooth,
slerp-like turn of 1–3 s with hand tremor and a little linear acceleration of the hand).  The sensor
has a true affine error of Georgieva et al., ESGI'95, Approach 2, ``m = X a + y`` (Georgieva et al.,
ESGI'95, section 3.2),
white noise, and optionally a slow offset drift (temperature), short bumps (knocks on the table) and
quantisation to a step (browsers round to 0.1 m/s²).  Everything is returned as arrays: the core
never touches files.

All magnitudes are in the unit of ``gravity`` (m/s² by default); the defaults are typical of a
phone in m/s² and are scaled by ``gravity / 9.80665`` so that the same call works in g.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from app.calibration.shared.errors import CalibrationError
from app.calibration.shared.gravity import STANDARD_GRAVITY
from app.calibration.shared.orientations import CANONICAL_SIX, UP_VECTORS, nearest_orientation
from app.calibration.shared.validation import check_gravity


@dataclass(frozen=True)
class SimulatedLog:
    """A simulated raw log and its ground truth.

    Attributes
    ----------
    samples : numpy.ndarray
        Shape (N, 3), raw readings ``m = X a + y (+ drift + noise)``, quantised if asked.
    sampling_rate_hz : float
    gravity : float
        Magnitude of the true specific force at rest, in the unit of ``samples``.
    X, y : numpy.ndarray
        The true affine error (Georgieva et al., ESGI'95, Approach 2), shapes (3, 3) and (3,).
    segments : tuple of (int, int, str or None)
        True rests as ``(start, end, up)``, sample indices with ``end`` exclusive; ``up`` is the
        label of the rest's direction (None for a direction more than 20° from every axis).
    directions : numpy.ndarray
        Shape (len(segments), 3), the true unit specific-force direction of each rest.
    bumps : tuple of (int, int)
        Sample ranges of the knocks, each inside a rest.
    drift : numpy.ndarray
        Shape (3,), the offset drift reached at the end of the log.
    """

    samples: np.ndarray
    sampling_rate_hz: float
    gravity: float
    X: np.ndarray
    y: np.ndarray
    segments: tuple
    directions: np.ndarray
    bumps: tuple = ()
    drift: np.ndarray | None = None

    def to_dict(self) -> dict:
        """Ground truth as plain JSON (the samples are left out)."""
        return {
            "sampling_rate_hz": self.sampling_rate_hz,
            "n_samples": int(len(self.samples)),
            "gravity": self.gravity,
            "model": {"type": "affine", "X": self.X.tolist(), "y": self.y.tolist()},
            "segments": [
                {"start": s, "end": e, "up": up, "direction": d.tolist()}
                for (s, e, up), d in zip(self.segments, self.directions)
            ],
            "bumps": [{"start": s, "end": e} for s, e in self.bumps],
            "drift": None if self.drift is None else self.drift.tolist(),
        }


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    n = np.linalg.norm(v)
    if v.shape != (3,) or not np.isfinite(n) or n == 0:
        raise CalibrationError(f"an orientation must be a label or a non-zero [x, y, z] vector; got {v!r}")
    return v / n


def _direction(o) -> np.ndarray:
    if isinstance(o, str):
        if o not in UP_VECTORS:
            raise CalibrationError(f"unknown orientation {o!r}: use one of {', '.join(UP_VECTORS)}")
        return np.array(UP_VECTORS[o])
    return _unit(o)


def _per_item(value, n: int, rng: np.random.Generator, name: str) -> np.ndarray:
    """A duration per item: a ``(low, high)`` tuple drawn uniformly, or a list of n values."""
    if isinstance(value, tuple) and len(value) == 2:
        return rng.uniform(float(value[0]), float(value[1]), size=n)
    arr = np.asarray(value, dtype=float)
    if arr.shape == (n,) and np.all(arr >= 0):
        return arr
    raise CalibrationError(f"{name} must be a (low, high) tuple in seconds or a list of {n} non-negative durations")


def _tilt(u: np.ndarray, rng: np.random.Generator, max_deg: float) -> np.ndarray:
    """Tilt a unit vector by a random angle up to ``max_deg`` in a random direction."""
    if max_deg <= 0:
        return u
    perp = np.cross(u, rng.normal(size=3))
    perp /= np.linalg.norm(perp)
    ang = np.radians(rng.uniform(0, max_deg))
    return u * np.cos(ang) + perp * np.sin(ang)


def _turn(p: np.ndarray, q: np.ndarray, n: int, profile: str, rng: np.random.Generator) -> np.ndarray:
    """Directions of n samples turning p into q about their common normal (exclusive of p, inclusive of q)."""
    cos_t = float(np.clip(p @ q, -1.0, 1.0))
    theta = np.arccos(cos_t)
    k = np.cross(p, q)
    if np.linalg.norm(k) < 1e-9:  # opposite (or equal) directions: turn about a random perpendicular
        k = np.cross(p, rng.normal(size=3))
    k /= np.linalg.norm(k)
    u = np.arange(1, n + 1) / n
    s = 0.5 * (1.0 - np.cos(np.pi * u)) if profile == "smooth" else u
    phi = theta * s
    kp = np.cross(k, p)
    return np.outer(np.cos(phi), p) + np.outer(np.sin(phi), kp)  # Rodrigues with k ⟂ p


def _tremor(n: int, fs: float, rng: np.random.Generator) -> np.ndarray:
    """Band-limited (4–10 Hz) unit-RMS random signal per axis, shape (n, 3)."""
    t = np.arange(n) / fs
    out = np.zeros((n, 3))
    for _ in range(3):
        f = rng.uniform(4.0, 10.0, size=3)
        ph = rng.uniform(0, 2 * np.pi, size=3)
        out += np.sin(2 * np.pi * t[:, None] * f + ph)
    return out / np.sqrt(1.5)


def simulate_static_log(
    rng: np.random.Generator,
    *,
    orientations=None,
    repeats: int = 0,
    sampling_rate_hz: float = 100.0,
    gravity: float = STANDARD_GRAVITY,
    rest_s=(5.0, 8.0),
    turn_s=(1.0, 3.0),
    turn_profile="smooth",
    X=None,
    y=None,
    noise_std: float = 0.02,
    drift: float = 0.0,
    n_bumps: int = 0,
    bump_amplitude: float = 3.0,
    bump_s: float = 0.12,
    quantisation_step: float | None = None,
    tremor_deg: float = 1.0,
    hand_acc: float = 0.5,
    tilt_deg: float = 0.0,
) -> SimulatedLog:
    """Simulate a raw log of a device resting in a sequence of orientations.

    The log starts with the hand placing the device (a turn from a random direction into the
    first orientation) and ends with it picking the device up, so every rest has two transition
    edges.

    Parameters
    ----------
    rng : numpy.random.Generator
        The only source of randomness (seeded by the caller).
    orientations : sequence of str or [x, y, z], optional
        Rest directions (labels such as ``+x`` or unit specific-force vectors).  Default: the six
        canonical orientations in an order shuffled by ``rng``.
    repeats : int
        Extra rests in randomly chosen canonical orientations (never the same as the one before),
        appended to ``orientations``.
    sampling_rate_hz : float
    gravity : float
        Magnitude of the specific force at rest; sets the unit (9.80665 for m/s², 1 for g).
    rest_s, turn_s : (float, float) tuple or list of float
        Rest and turn durations in seconds: a uniform range as a tuple, or a list with one value
        per rest (turn).  There
        are ``len(orientations) + 1`` turns.  A rest of 0 s makes the device pass through the
        direction without stopping (when the adjacent turns are ``constant``).
    turn_profile : {"smooth", "constant"} or sequence of them
        ``smooth``: a cosine ease, the angle's rate rising from and falling back to zero (a hand
        turn); ``constant``: a constant rate (a slow sweep).  One value or one per turn.
    X, y : array_like, optional
        True affine error ``m = X a + y`` (Georgieva et al., ESGI'95, Approach 2); default drawn from
        ``rng``: diagonal
        1 ± 2 %, cross terms ± 1 %, offsets ± 0.1 m/s² (standard deviations).
    noise_std : float
        White noise per axis (data unit before quantisation).
    drift : float
        Size of a slow offset drift reached at the end of the log, in a random direction, with a
        warm-up profile ``1 − exp(−t / τ)``, τ a third of the log.
    n_bumps : int
        Knocks, each in the middle part of a randomly chosen rest: a damped 15 Hz oscillation of
        ``bump_amplitude`` lasting ``bump_s``; the device does not move.
    quantisation_step : float, optional
        Round the readings to this step (0.1 m/s² like browsers).
    tremor_deg : float
        RMS hand tremor during turns, degrees, vanishing at the ends of each turn.
    hand_acc : float
        Peak linear acceleration of the hand during turns (data unit).
    tilt_deg : float
        Largest random tilt of each rest away from its nominal direction (0: exact).

    Returns
    -------
    SimulatedLog

    Raises
    ------
    CalibrationError
        Unknown labels, zero vectors, non-positive rate, or inconsistent duration lists.
    """
    g = check_gravity(gravity)
    fs = float(sampling_rate_hz)
    if not (np.isfinite(fs) and fs > 0):
        raise CalibrationError(f"sampling_rate_hz must be positive; got {sampling_rate_hz!r}")
    unit = g / STANDARD_GRAVITY  # scales the m/s² defaults to the unit of gravity

    if orientations is None:
        orientations = [CANONICAL_SIX[i] for i in rng.permutation(6)]
    orientations = list(orientations)
    for _ in range(int(repeats)):
        prev = orientations[-1] if orientations else None
        choices = [o for o in CANONICAL_SIX if o != prev]
        orientations.append(choices[int(rng.integers(len(choices)))])
    if not orientations:
        raise CalibrationError("give at least one orientation")
    dirs = np.array([_tilt(_direction(o), rng, tilt_deg) for o in orientations])
    n_rest = len(dirs)
    rests = _per_item(rest_s, n_rest, rng, "rest_s")
    turns = _per_item(turn_s, n_rest + 1, rng, "turn_s")
    profiles = [turn_profile] * (n_rest + 1) if isinstance(turn_profile, str) else list(turn_profile)
    if len(profiles) != n_rest + 1 or any(p not in ("smooth", "constant") for p in profiles):
        raise CalibrationError(f"turn_profile must be 'smooth', 'constant' or one of them per turn ({n_rest + 1})")

    if X is None:
        X = np.eye(3) + np.diag(rng.normal(0, 0.02, 3)) + (1 - np.eye(3)) * rng.normal(0, 0.01, (3, 3))
    if y is None:
        y = rng.normal(0, 0.1, 3) * unit
    X = np.asarray(X, dtype=float).reshape(3, 3)
    y = np.asarray(y, dtype=float).reshape(3)

    start_dir = _unit(rng.normal(size=3))
    end_dir = _unit(rng.normal(size=3))
    waypoints = [start_dir, *dirs, end_dir]

    parts_dir: list[np.ndarray] = []
    parts_acc: list[np.ndarray] = []
    segments = []
    pos = 0
    # The first sample: the device in the hand at its start direction.
    parts_dir.append(start_dir[None, :])
    parts_acc.append(np.zeros((1, 3)))
    pos = 1
    for i in range(n_rest + 1):
        n = max(2, int(round(turns[i] * fs)))
        d = _turn(waypoints[i], waypoints[i + 1], n, profiles[i], rng)
        env = np.sin(np.pi * np.arange(1, n + 1) / n)  # tremor and hand motion vanish at the ends
        if tremor_deg > 0:
            trem = np.radians(tremor_deg) * env[:, None] * _tremor(n, fs, rng)
            trem -= (trem * d).sum(axis=1, keepdims=True) * d  # keep it a rotation (⟂ direction)
            d = d + trem
            d /= np.linalg.norm(d, axis=1, keepdims=True)
        acc = np.zeros((n, 3))
        if hand_acc > 0:
            # the hand moves out and back: one period of a sine under the envelope
            acc = (
                (hand_acc * unit)
                * (np.sin(2 * np.pi * np.arange(1, n + 1) / n) * env)[:, None]
                * _unit(rng.normal(size=3))
            )
        parts_dir.append(d)
        parts_acc.append(acc)
        pos += n
        if i < n_rest:
            m = int(round(rests[i] * fs))
            parts_dir.append(np.repeat(dirs[i][None, :], m, axis=0))
            parts_acc.append(np.zeros((m, 3)))
            u = orientations[i] if isinstance(orientations[i], str) else nearest_orientation(dirs[i])
            if m > 0:
                segments.append((pos, pos + m, u))
            pos += m
    # A short tail in the hand after the pick-up.
    tail = int(round(0.5 * fs))
    parts_dir.append(np.repeat(end_dir[None, :], tail, axis=0))
    parts_acc.append(np.zeros((tail, 3)))

    f = g * np.concatenate(parts_dir) + np.concatenate(parts_acc)  # true specific force
    N = len(f)
    t = np.arange(N) / fs

    bumps = []
    long_rests = [k for k, (s, e, _) in enumerate(segments) if e - s >= int(3.0 * fs)]
    for _ in range(int(n_bumps)):
        if not long_rests:
            break
        s, e, _ = segments[long_rests[int(rng.integers(len(long_rests)))]]
        nb = max(2, int(round(bump_s * fs)))
        b0 = int(rng.integers(s + int(0.4 * (e - s)), s + int(0.6 * (e - s)) - nb))
        tb = np.arange(nb) / fs
        shape = np.exp(-tb / (bump_s / 3)) * np.sin(2 * np.pi * 15.0 * tb + rng.uniform(0, 2 * np.pi))
        f[b0 : b0 + nb] += (bump_amplitude * unit) * shape[:, None] * _unit(rng.normal(size=3))
        bumps.append((b0, b0 + nb))

    m = f @ X.T + y
    drift_vec = np.zeros(3)
    if drift:
        drift_vec = drift * _unit(rng.normal(size=3))
        tau = max(t[-1], 1.0) / 3.0
        prof = (1 - np.exp(-t / tau)) / (1 - np.exp(-max(t[-1], 1.0) / tau))
        m += prof[:, None] * drift_vec
    if noise_std > 0:
        m += rng.normal(0, noise_std * unit, size=m.shape)
    if quantisation_step:
        m = np.round(m / quantisation_step) * quantisation_step
    return SimulatedLog(
        samples=m,
        sampling_rate_hz=fs,
        gravity=g,
        X=X,
        y=y,
        segments=tuple(segments),
        directions=dirs,
        bumps=tuple(sorted(bumps)),
        drift=drift_vec,
    )
