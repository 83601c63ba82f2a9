"""The cores this process may run on: what the core's threads and the CLI's processes are counted from."""

from __future__ import annotations

import os


def usable_cores(at_most: int | None = None) -> int:
    """The cores this process may run on: its CPU affinity where the system tells it (Linux: a container's or a
    ``taskset``'s share, not the machine's), else the machine's count.

    Parameters
    ----------
    at_most : int, optional
        A cap (the work stops gaining past a few cores).

    Returns
    -------
    int
        At least 1.
    """
    try:
        usable = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        usable = os.cpu_count() or 1
    return max(1, usable if at_most is None else min(at_most, usable))
