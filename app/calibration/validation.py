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
        raise CalibrationError(
            f"{name} must have shape N×3 (one [x, y, z] per row); got shape {tuple(arr.shape)}"
        )
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


def check_gravity(gravity: float) -> float:
    """Return the reference magnitude as a float, or raise when it is not positive and finite."""
    try:
        g = float(gravity)
    except (TypeError, ValueError):
        raise CalibrationError(f"gravity must be a number; got {gravity!r}") from None
    if not (math.isfinite(g) and g > 0.0):
        raise CalibrationError(f"gravity must be a positive finite number; got {gravity!r}")
    return g


def near_duplicate_pairs(vectors: np.ndarray, tolerance: float) -> list[tuple[int, int]]:
    """Index pairs (i < j) of rows closer to each other than ``tolerance`` (000, Dataset 3)."""
    d = np.linalg.norm(vectors[:, None, :] - vectors[None, :, :], axis=-1)
    i, j = np.nonzero(np.triu(d < tolerance, k=1))
    return list(zip(i.tolist(), j.tolist()))
