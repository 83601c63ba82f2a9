"""Simulated still sensors with known noise terms: white noise N, bias instability B and random walk K.

The three terms as IEEE Std 952-1997, Annex C defines them by their two-sided power spectra of the
rate: white N² (discrete samples of standard deviation N √fs, as Kalibr's ``noise_density``),
flicker B² / (2π f) (shaped in the frequency domain from white noise, without its DC bin) and
random walk K² / (2π f)² (the running sum of steps of standard deviation K / √fs, as Kalibr's
``random_walk``). Their Allan variance is N²/τ + (2 ln 2/π) B² + K² τ / 3.
"""

from __future__ import annotations

import numpy as np


def simulate_still(rng: np.random.Generator, *, n_samples: int, sampling_rate_hz: float, N, B, K, bias=0.0):
    """Samples of a still three-axis sensor, shape (n_samples, 3), with the given terms per axis.

    Parameters
    ----------
    rng : numpy.random.Generator
        Seeded.
    n_samples : int
    sampling_rate_hz : float
    N, B, K : float or array_like of 3
        White-noise density ([u]/√Hz), bias instability ([u]) and random walk ([u]/s/√Hz).
    bias : float or array_like of 3
        Constant offset added.
    """
    fs = float(sampling_rate_hz)
    N, B, K, bias = (np.broadcast_to(np.asarray(v, dtype=float), (3,)) for v in (N, B, K, bias))
    white = rng.standard_normal((n_samples, 3)) * (N * np.sqrt(fs))
    walk = np.cumsum(rng.standard_normal((n_samples, 3)) * (K / np.sqrt(fs)), axis=0)
    spectrum = np.fft.rfft(rng.standard_normal((n_samples, 3)), axis=0)
    f = np.fft.rfftfreq(n_samples, d=1.0 / fs)
    gain = np.zeros_like(f)
    gain[1:] = np.sqrt(fs / (2.0 * np.pi * f[1:]))  # two-sided PSD B² / (2π f) of unit-variance white input
    flicker = np.fft.irfft(spectrum * gain[:, None], n=n_samples, axis=0) * B
    return white + walk + flicker + bias
