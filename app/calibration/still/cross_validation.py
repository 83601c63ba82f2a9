"""What a calibration will do on orientations it has not seen: the cross-validated norm error.

The in-sample error of a fit flatters it: with as many readings as parameters it is zero whatever
the calibration does elsewhere.  Each reading is calibrated here by the fit made *without* it
(leave-one-out; K-fold above :data:`LEAVE_ONE_OUT_MAX` readings), and its norm error
| |a_i| − g | / g is what a person gets on a new orientation.
"""

from __future__ import annotations

import numpy as np

from ..shared.errors import CalibrationError

LEAVE_ONE_OUT_MAX = 50
"""Up to this many readings every one is left out in turn; above, K-fold with :data:`K_FOLDS`."""

K_FOLDS = 10


def _folds(n: int) -> tuple[list[np.ndarray], str]:
    if n <= LEAVE_ONE_OUT_MAX:
        return [np.array([i]) for i in range(n)], "leave-one-out"
    order = np.random.default_rng(0).permutation(n)  # fixed: the same readings give the same figure
    return [np.sort(f) for f in np.array_split(order, K_FOLDS)], f"{K_FOLDS}-fold"


def cross_validated_error(refit, means, gravity: float) -> dict:
    """Mean and largest norm error of each reading calibrated by the fit made without it.

    Parameters
    ----------
    refit : callable
        ``refit(indices)`` → a result with ``apply`` fitted on the readings at ``indices`` only.
    means : array_like, shape (N, 3)
        The still readings the calibration was fitted on.
    gravity : float
        Their reference magnitude.

    Returns
    -------
    dict
        ``cv_error_mg`` and ``cv_error_max_mg`` (thousandths of the reference magnitude) and
        ``cv_scheme`` (``leave-one-out`` or ``10-fold``); when a fit without some readings is not
        determined, both figures are None and ``cv_note`` says how to get them.
    """
    m = np.asarray(means, dtype=float).reshape(-1, 3)
    folds, scheme = _folds(len(m))
    errors = np.empty(len(m))
    everything = np.arange(len(m))
    for held in folds:
        kept = np.setdiff1d(everything, held)
        try:
            fit = refit(kept)
        except CalibrationError:
            return {
                "cv_error_mg": None,
                "cv_error_max_mg": None,
                "cv_scheme": scheme,
                "cv_note": (
                    f"no figure for new orientations: without some of the {len(m)} readings the model "
                    "is not determined; add poses in other directions to get one"
                ),
            }
        errors[held] = np.abs(np.linalg.norm(fit.apply(m[held]), axis=1) - gravity) / gravity
    return {
        "cv_error_mg": float(1000.0 * errors.mean()),
        "cv_error_max_mg": float(1000.0 * errors.max()),
        "cv_scheme": scheme,
    }


SIX_POSITION_NOTE = (
    "no figure for new orientations: the six-position solution fits its six readings "
    "exactly (no redundancy); add poses (method orientations, or a magnitude model) to get one"
)
"""Why ``six_position`` has no cross-validated error."""
