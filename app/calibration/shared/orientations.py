"""Orientation labels: which device axis points up, away from the Earth.

``+x`` means the x axis points up, so a perfect accelerometer at rest reads ``(+g, 0, 0)``
(readings are specific force, docs/methods.md).
"""

import numpy as np

from .errors import CalibrationError

UP_VECTORS: dict[str, tuple[float, float, float]] = {
    "+x": (1.0, 0.0, 0.0),
    "-x": (-1.0, 0.0, 0.0),
    "+y": (0.0, 1.0, 0.0),
    "-y": (0.0, -1.0, 0.0),
    "+z": (0.0, 0.0, 1.0),
    "-z": (0.0, 0.0, -1.0),
}

CANONICAL_SIX: tuple[str, ...] = ("-x", "+x", "-y", "+y", "-z", "+z")
"""The six canonical orientations in the order of Georgieva et al. (ESGI'95), section 3.3.1."""

POSE_NAMES = {
    "+z": "flat, screen up",
    "-z": "flat, screen down",
    "+y": "upright on its bottom edge (the charging port)",
    "-y": "upside down on its top edge (the earpiece)",
    "+x": "on its left edge as you face the screen, right edge up",
    "-x": "on its right edge as you face the screen, left edge up",
}
"""Each of the six poses in words for a person holding a phone (W3C frame: x right, y up along the
screen, z out of the screen), by what every phone has: the screen, the earpiece at the top edge, the
charging port at the bottom (the side buttons differ between makers); left and right as seen facing
the screen. The pages and the pose advice (:mod:`app.calibration.still.advice`) use them."""

LABEL_MAX_ANGLE_DEG = 20.0
"""A direction is labelled with its nearest axis only when within this angle (docs/rest.md)."""
WITHIN_LABEL_ANGLE = f"within {LABEL_MAX_ANGLE_DEG:g}°"
""":data:`LABEL_MAX_ANGLE_DEG` as the messages say it (``no axis within 20°``)."""


def up_vector(label: str) -> np.ndarray:
    """Unit specific-force vector expected at rest for an orientation label.

    Parameters
    ----------
    label : str
        One of ``+x, -x, +y, -y, +z, -z``.

    Returns
    -------
    numpy.ndarray
        Shape (3,), the reading of a perfect accelerometer in units of g.

    Raises
    ------
    CalibrationError
        If the label is unknown.
    """
    try:
        return np.array(UP_VECTORS[label])
    except (KeyError, TypeError):
        raise CalibrationError(
            f"unknown orientation {label!r}: use one of {', '.join(UP_VECTORS)} (the device axis that points up)"
        ) from None


def nearest_orientation(vector, max_angle_deg: float = LABEL_MAX_ANGLE_DEG) -> str | None:
    """Label of the axis closest to a direction, or None when none is within the angle.

    Parameters
    ----------
    vector : array_like, shape (3,)
        A mean specific-force reading, in any unit.
    max_angle_deg : float
        Largest angle between the direction and the axis that still earns its label.

    Returns
    -------
    str or None
    """
    v = np.asarray(vector, dtype=float)
    norm = float(np.linalg.norm(v))
    if not np.isfinite(norm) or norm == 0.0:
        return None
    axis = int(np.argmax(np.abs(v)))
    cos_angle = abs(v[axis]) / norm
    if cos_angle < np.cos(np.radians(max_angle_deg)):
        return None
    return ("+" if v[axis] > 0 else "-") + "xyz"[axis]
