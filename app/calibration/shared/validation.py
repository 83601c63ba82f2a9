"""Checks shared by every method: shapes, finiteness, reference magnitudes."""

import math

import numpy as np

from .errors import CalibrationError, InsufficientDataError


def as_vectors(values, name: str, *, min_rows: int = 1) -> np.ndarray:
    """Return ``values`` as a finite float array of shape (N, 3), or raise.

    Parameters
    ----------
    values : array_like
        N triaxial vectors.
    name : str
        What the values are, for the message (``"means"``, ``"samples"``...).
    min_rows : int
        Fewest rows the caller can work with.

    Raises
    ------
    CalibrationError
        Wrong shape or a NaN/infinite value (the message names the first bad row).
    InsufficientDataError
        Fewer than ``min_rows`` rows.
    """
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise CalibrationError(f"{name} must be a list of [x, y, z] numbers") from None
    if arr.ndim == 1 and arr.shape[0] == 3:
        arr = arr[np.newaxis, :]
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise CalibrationError(f"{name} must have shape N×3 (one [x, y, z] per row); got shape {tuple(arr.shape)}")
    bad = ~np.isfinite(arr).all(axis=1)
    if bad.any():
        row = int(np.flatnonzero(bad)[0])
        raise CalibrationError(
            f"{name} row {row} is {arr[row].tolist()}: NaN or infinite values cannot be calibrated; "
            "drop or re-measure that reading"
        )
    if arr.shape[0] < min_rows:
        raise InsufficientDataError(f"{name} has {arr.shape[0]} rows; at least {min_rows} are needed")
    return arr


def as_samples(raw) -> np.ndarray:
    """``raw`` as a float array of shape (3,) or (N, 3), the shapes every ``apply`` takes, or raise.

    Raises
    ------
    CalibrationError
        Any other shape.
    """
    m = np.asarray(raw, dtype=float)
    if m.shape[-1:] != (3,) or m.ndim > 2:
        raise CalibrationError(f"samples must have shape N×3; got shape {tuple(m.shape)}")
    return m


MIN_GRAVITY = 1e-6
"""Below this a reference magnitude is no unit of acceleration anyone reads (1 µg in g): refused
rather than divided by."""


def check_gravity(gravity: float) -> float:
    """Return the reference magnitude as a float, or raise when it is not positive and finite."""
    try:
        g = float(gravity)
    except (TypeError, ValueError):
        raise CalibrationError(f"gravity must be a number; got {gravity!r}") from None
    if not (math.isfinite(g) and g >= MIN_GRAVITY):
        raise CalibrationError(
            f"gravity must be a finite number of at least {MIN_GRAVITY:g} (the readings' unit); got {gravity!r}"
        )
    return g


def near_duplicate_pairs(vectors: np.ndarray, tolerance: float) -> list[tuple[int, int]]:
    """Index pairs (i < j) of rows closer to each other than ``tolerance`` (Georgieva et al., Dataset 3)."""
    d = np.linalg.norm(vectors[:, None, :] - vectors[None, :, :], axis=-1)
    i, j = np.nonzero(np.triu(d < tolerance, k=1))
    return list(zip(i.tolist(), j.tolist()))


SPHERE_COVERAGE_COS = 0.5
"""A direction ±axis counts as covered when some reading is within 60° of it."""


def sphere_directions(vectors: np.ndarray) -> np.ndarray:
    """Unit directions of readings (rows), zero rows left at zero."""
    n = np.linalg.norm(vectors, axis=1, keepdims=True)
    return np.divide(vectors, n, out=np.zeros_like(vectors, dtype=float), where=n > 0)


def one_hemisphere_axis(vectors: np.ndarray) -> np.ndarray | None:
    """A unit axis w with every reading strictly on its side (d·w > 0), or None.

    Solved as the linear programme ``max t`` subject to ``dᵢ·w ≥ t``, ``|w|∞ ≤ 1``: all readings
    lie in one open hemisphere exactly when the optimum t is positive.  A fit of a sphere or an
    ellipsoid to such readings cannot separate the offset from the scale along w.
    """
    from scipy.optimize import linprog  # here, not at the top: scipy.optimize takes ~0.5 s to import

    d = sphere_directions(np.asarray(vectors, dtype=float))
    n = len(d)
    res = linprog(
        c=np.array([0.0, 0.0, 0.0, -1.0]),
        A_ub=np.hstack([-d, np.ones((n, 1))]),
        b_ub=np.zeros(n),
        bounds=[(-1.0, 1.0)] * 3 + [(None, 1.0)],
        method="highs",
    )
    if not res.success or res.x is None or res.x[3] <= 1e-6:
        return None
    w = res.x[:3]
    return w / np.linalg.norm(w)


def uncovered_directions(vectors: np.ndarray, cos_min: float = SPHERE_COVERAGE_COS) -> list[str]:
    """Labels ``±x, ±y, ±z`` of the axis directions no reading comes within ``acos(cos_min)`` of."""
    d = sphere_directions(np.asarray(vectors, dtype=float))
    missing = []
    for k, ax in enumerate("xyz"):
        if not (d[:, k] >= cos_min).any():
            missing.append("+" + ax)
        if not (d[:, k] <= -cos_min).any():
            missing.append("-" + ax)
    return missing


def check_sphere_points(means, gravity: float, *, min_points: int, method: str, n_params: int) -> np.ndarray:
    """Gate still readings of unknown orientation before an ellipsoid-type fit.

    Parameters
    ----------
    means : array_like, shape (N, 3)
        Averaged still readings, in the unit of ``gravity``.
    gravity : float
        Reference magnitude (already checked).
    min_points : int
        Fewest distinct positions the model needs (its number of parameters).
    method, n_params
        For the messages.

    Returns
    -------
    numpy.ndarray, shape (N, 3)

    Raises
    ------
    CalibrationError
        Wrong shape, NaN or infinite values.
    InsufficientDataError
        Fewer than ``min_points`` readings, or fewer than ``min_points`` distinct positions
        (readings within 1 % of g of each other count once), e.g. all positions identical.
    """
    m = as_vectors(means, "means")
    if len(m) < min_points:
        raise InsufficientDataError(
            f"{len(m)} positions cannot determine the {n_params} parameters of the {method} model: "
            f"hold the device still in at least {min_points} different positions (about 20 spread over "
            "the sphere are recommended, Georgieva et al. section 2.2)"
        )
    # Count distinct positions: greedy clustering at 1 % of g.
    tol = 0.01 * gravity
    reps: list[np.ndarray] = []
    for v in m:
        if not any(np.linalg.norm(v - r) < tol for r in reps):
            reps.append(v)
    if len(reps) < min_points:
        raise InsufficientDataError(
            f"the {len(m)} positions hold only {len(reps)} distinct orientations (readings within "
            f"1 % of g of each other count once); the {method} model needs at least {min_points}: "
            "turn the device to new orientations between captures"
        )
    return m
