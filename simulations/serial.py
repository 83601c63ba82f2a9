"""Timestamps of a sensor logged over a serial port, as the host stamps the lines on arrival.

A board prints one line per sample at its sensor's rate; the USB bridge (or CDC stack) hands the
host whatever has queued up when it is polled, so lines arrive in bursts: a long wait, then a few
lines close together.  Each sample arrives at the first poll after it was made; the lines of one
poll are read ``line_s`` apart.  With polls 1–70 ms apart and lines 1–3 ms apart, a 100 Hz
sensor's steps range from about 1 to 70 ms with a median near 2 ms and a mean of 10 ms — what a
host sees of a USB serial stream.
"""

from __future__ import annotations

import numpy as np


def host_arrival_times(
    rng: np.random.Generator,
    *,
    n_samples: int,
    sampling_rate_hz: float,
    poll_s=(0.001, 0.070),
    line_s=(0.001, 0.003),
    lost=(),
) -> np.ndarray:
    """Arrival times (seconds) of ``n_samples`` samples made at ``sampling_rate_hz``.

    Parameters
    ----------
    rng : numpy.random.Generator
        Seeded.
    n_samples : int
    sampling_rate_hz : float
        The sensor's rate.
    poll_s, line_s : tuple of float
        Ranges (uniform) of the time between two polls of the host, and between two lines read in one poll.
    lost : sequence of (int, int)
        Sample ranges ``[a, b)`` that never arrive (a full buffer): they are left out of the result.

    Returns
    -------
    numpy.ndarray
        Non-decreasing arrival times of the samples that arrive (``n_samples`` less the lost ones).
    """
    made = np.arange(n_samples) / float(sampling_rate_hz)
    polls = np.cumsum(rng.uniform(*poll_s, size=int(made[-1] / poll_s[0]) + 2))
    polls = polls[polls >= made[0]]
    poll_of = np.searchsorted(polls, made)  # the first poll at or after each sample is made
    first = np.searchsorted(poll_of, poll_of)  # the first sample of the same poll
    rank = np.arange(n_samples) - first  # the line's place in its burst
    spacing = rng.uniform(*line_s, size=n_samples)
    arrival = polls[poll_of] + rank * spacing
    arrival = np.maximum.accumulate(arrival)  # lines are read in order
    keep = np.ones(n_samples, dtype=bool)
    for a, b in lost:
        keep[a:b] = False
    return arrival[keep]
