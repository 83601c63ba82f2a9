"""Synthetic long recordings for auto-calibration: rest and movement bouts through the errors of
Farago, Maczak and Gingl, IEEE Access.

A recording alternates rest bouts and movement bouts.  A rest bout holds one orientation: with
probability ``posture_fraction`` one of a few posture-like directions (a wrist lying face up or down,
an arm hanging, a forearm on a table...) jittered by a few degrees, otherwise a direction uniform on
the sphere.  A movement bout turns from one direction to another with an oscillating body
acceleration of a few tenths of g on each axis.  The true specific force ``a`` (in g) becomes the
reading ``v = K⁻¹ a − o`` by the 9-parameter model of Farago, Maczak and Gingl, IEEE Access with the
parameters of eq. (17)
(:func:`simulations.triangular.draw_parameters`, :func:`~simulations.triangular.uncalibrate`)
plus white noise.  Optionally some rest bouts are replaced by idle-sleep runs (the first sample
repeated) or NaN gaps.

The recording is written bout by bout into ``out`` (e.g. a ``numpy.lib.format.open_memmap``), so a
week at 100 Hz (60.5 M samples) is generated with bounded memory.  Everything in g.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .triangular import draw_parameters, random_unit_vectors, uncalibrate

POSTURES = np.array(
    [
        [0.0, 0.0, 1.0],  # wrist face up (lying, hand on a table)
        [0.0, 0.0, -1.0],  # face down
        [-1.0, 0.0, 0.0],  # arm hanging
        [-0.5, 0.0, 0.866],  # forearm resting, tilted
        [0.0, 0.94, 0.34],  # on the side
        [0.0, -0.9, 0.44],  # on the other side
    ]
)
"""Posture-like rest directions (unit vectors of the specific force in the sensor frame)."""


@dataclass(frozen=True)
class SimulatedRecording:
    """Truth behind a simulated recording.

    Attributes
    ----------
    p : numpy.ndarray, shape (9,)
        True parameters (Farago, Maczak and Gingl, IEEE Access, eq. (18)); offsets in g.
    n_samples : int
    sampling_rate_hz : float
    rest_bouts : numpy.ndarray, shape (B, 2)
        Start and end (exclusive) of each rest bout, sample indices.
    rest_directions : numpy.ndarray, shape (B, 3)
        True unit specific force of each rest bout.
    idle_bouts, nan_bouts : numpy.ndarray of int
        Indices into ``rest_bouts`` of the bouts replaced by idle sleep or NaN.
    """

    p: np.ndarray
    n_samples: int
    sampling_rate_hz: float
    rest_bouts: np.ndarray
    rest_directions: np.ndarray
    idle_bouts: np.ndarray
    nan_bouts: np.ndarray


def _jitter(rng, d, deg):
    v = d + np.deg2rad(deg) * rng.standard_normal(3)
    return v / np.linalg.norm(v)


def simulate_recording(
    rng: np.random.Generator,
    *,
    duration_s: float,
    sampling_rate_hz: float = 100.0,
    p=None,
    noise_g: float = 0.003,
    posture_fraction: float = 0.8,
    directions=None,
    rest_median_s: float = 90.0,
    move_median_s: float = 60.0,
    idle_fraction: float = 0.0,
    nan_fraction: float = 0.0,
    out=None,
    dtype=np.float32,
) -> tuple[np.ndarray, SimulatedRecording]:
    """Generate a recording of rest and movement bouts (module docstring).

    Parameters
    ----------
    rng : numpy.random.Generator
    duration_s, sampling_rate_hz : float
    p : array_like, shape (9,), optional
        True parameters; drawn by Farago, Maczak and Gingl, IEEE Access, eq. (17) when omitted.
    noise_g : float
        White noise per sample and axis, in g.
    posture_fraction : float
        Share of rest bouts in a posture-like direction.
    directions : array_like, shape (D, 3), optional
        If given, every rest bout takes one of these directions (jittered by 2°), e.g. a single
        direction for a recording at rest in only one orientation.
    rest_median_s, move_median_s : float
        Median bout lengths (log-normal).  ``rest_median_s=0`` gives a recording without rest.
    idle_fraction, nan_fraction : float
        Share of rest bouts replaced by idle sleep (the first sample repeated) or by NaN.
    out : array, shape (N, 3), optional
        Where to write (e.g. a memory map); a new array of ``dtype`` otherwise.

    Returns
    -------
    samples : numpy.ndarray, shape (N, 3)
    truth : SimulatedRecording
    """
    fs = float(sampling_rate_hz)
    n = int(round(duration_s * fs))
    p = draw_parameters(rng) if p is None else np.asarray(p, dtype=float)
    x = np.empty((n, 3), dtype=dtype) if out is None else out
    dirs = None if directions is None else np.asarray(directions, dtype=float).reshape(-1, 3)
    rest_bouts, rest_dirs = [], []
    pos = 0
    current = np.array([0.0, 0.0, 1.0])
    resting = rng.random() < 0.5
    while pos < n:
        if resting and rest_median_s > 0:
            length = int(np.clip(rng.lognormal(np.log(rest_median_s), 1.0), 8.0, 3 * 3600.0) * fs)
            end = min(n, pos + length)
            if dirs is not None:
                d = _jitter(rng, dirs[rng.integers(len(dirs))], 2.0)
            elif rng.random() < posture_fraction:
                d = _jitter(rng, POSTURES[rng.integers(len(POSTURES))], 6.0)
            else:
                d = random_unit_vectors(rng, 1)[0]
            a = np.broadcast_to(d, (end - pos, 3))
            rest_bouts.append((pos, end))
            rest_dirs.append(d)
            current = d
        else:
            length = int(np.clip(rng.lognormal(np.log(move_median_s), 1.0), 3.0, 3600.0) * fs)
            end = min(n, pos + length)
            m = end - pos
            target = random_unit_vectors(rng, 1)[0]
            t = np.arange(m) / fs
            w = np.linspace(0.0, 1.0, m)[:, None]
            a = (1 - w) * current + w * target
            a = a / np.linalg.norm(a, axis=1, keepdims=True)
            amp = rng.uniform(0.15, 0.6, 3)
            freq = rng.uniform(0.5, 3.0, 3)
            phase = rng.uniform(0, 2 * np.pi, 3)
            a = a + amp * np.sin(2 * np.pi * freq * t[:, None] + phase)
            current = target
        v = uncalibrate(p, a) + noise_g * rng.standard_normal((end - pos, 3))
        x[pos:end] = v
        pos = end
        resting = not resting
    bouts = np.array(rest_bouts, dtype=np.int64).reshape(-1, 2)
    nb = len(bouts)
    idle = np.flatnonzero(rng.random(nb) < idle_fraction) if idle_fraction > 0 else np.zeros(0, dtype=int)
    nan = (
        np.setdiff1d(np.flatnonzero(rng.random(nb) < nan_fraction), idle)
        if nan_fraction > 0
        else np.zeros(0, dtype=int)
    )
    for b in idle:
        s, e = bouts[b]
        x[s:e] = x[s]
    for b in nan:
        s, e = bouts[b]
        x[s:e] = np.nan
    return x, SimulatedRecording(
        p=p,
        n_samples=n,
        sampling_rate_hz=fs,
        rest_bouts=bouts,
        rest_directions=np.array(rest_dirs).reshape(-1, 3),
        idle_bouts=idle,
        nan_bouts=nan,
    )
