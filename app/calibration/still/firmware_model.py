"""The flight controllers' offset-and-scale model of an accelerometer, fitted on still readings, and what of a
full correction it cannot hold.

ArduPilot and PX4 correct each axis of the accelerometer by an offset and a scale alone, in the sensor frame:

* ArduPilot, ``libraries/AP_InertialSensor/AP_InertialSensor_Backend.cpp``,
  ``_rotate_and_correct_accel``: ``accel -= _accel_offset`` then ``accel.x *= accel_scale.x`` (y, z alike);
* PX4, ``src/lib/sensor_calibration/Accelerometer.hpp``, ``Accelerometer::Correct``:
  ``(data - _thermal_offset - _offset).emult(_scale)``,

that is ``a = S (m − b)``, ``S = diag(s)``: six parameters. Neither can hold a full correction
``a = M (m − o)``. Keeping ``o`` and the diagonal of ``M`` is not the best of that model: ``M`` also turns the
sensor's axes into the frame the poses define (the table's tilt, the board's mounting), which no diagonal
holds and which a person reads as an error of the firmware's calibration.

The model is fitted here as ArduPilot's own accelerometer calibration fits it: ``libraries/AP_AccelCal/
AccelCalibrator.cpp`` (started with ``ACCEL_CAL_AXIS_ALIGNED_ELLIPSOID`` by ``AP_AccelCal::start``) minimises
``Σ (GRAVITY_MSS − |diag(s) (m_k + offset)|)²`` over the still samples, by Gauss–Newton, and stores
``INS_ACCOFFS = −offset``: a fit of the magnitude, which does not depend on how the board was turned. So
``min over b, s of Σ_k ( |S (m_k − b)| − g )²`` (least squares, Levenberg–Marquardt).

What the model cannot hold of ``M`` is split by the polar decomposition ``M = R P`` (``R`` a rotation, ``P``
symmetric positive definite; Higham, *Functions of Matrices*, SIAM 2008, theorem 8.1): ``R`` turns the
sensor's axes (an axis the correction inverts is first turned back: ``M = R P diag(±1)``), which the firmware's level
calibration takes (ArduPilot ``AHRS_TRIM_X/Y``, PX4
``SENS_BOARD_X_OFF/Y_OFF``); the off-diagonal terms of ``P`` are the axes' non-orthogonality, which neither
firmware holds.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..shared.errors import CalibrationError
from ..shared.norm_metrics import relative_norm_errors
from ..shared.validation import as_vectors

N_PARAMS = 6
"""Three offsets and three scales."""

DIRECTIONS = np.vstack(
    [np.eye(3), -np.eye(3), np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) / np.sqrt(3.0)]
)
"""The 6 axes and the 8 diagonals of a cube: the directions a calibration with too few readings of its own is
fitted on (the readings its full model puts at magnitude g)."""


@dataclass(frozen=True)
class OffsetScaleFit:
    """The firmware model ``a = diag(scale) (m − offset)`` fitted on still readings, beside a full correction.

    Attributes
    ----------
    offset : numpy.ndarray, shape (3,)
        In the readings' unit.
    scale : numpy.ndarray, shape (3,)
    count : int
        Readings fitted.
    from_readings : bool
        True when fitted on the calibration's own still readings; False when it had fewer than six and
        the readings its full model puts at magnitude g in the directions :data:`DIRECTIONS` were used.
    norm_error, norm_error_raw, norm_error_full : numpy.ndarray, shape (count,)
        Relative norm errors ``| |a| − g | / g`` of the readings with this model, raw, and with the full
        correction.
    norm_error_any_direction : float
        The largest relative norm error of this model over every direction, on readings the full correction
        puts at magnitude g (a dense sphere): what it reaches on new orientations if the full model is right.
    rotation_deg : float
        Angle of ``R`` of ``M = R P``, in degrees.
    rotation_axes_deg : numpy.ndarray, shape (3,)
        Its rotation vector in degrees: the turn about x, y and z.
    axis_angles_deg : numpy.ndarray, shape (3,)
        How far the sensor's axes are from 90° apart (xy, xz, yz), in degrees.
    nonorthogonality : float
        ``‖I − D P⁻¹‖₂`` (``D`` the diagonal of ``P``): the largest part of a calibrated reading, relative to
        its magnitude, that the off-diagonal terms of ``P`` make (× g for the reading's unit).
    """

    offset: np.ndarray
    scale: np.ndarray
    count: int
    from_readings: bool
    norm_error: np.ndarray
    norm_error_raw: np.ndarray
    norm_error_full: np.ndarray
    norm_error_any_direction: float
    rotation_deg: float
    rotation_axes_deg: np.ndarray
    axis_angles_deg: np.ndarray
    nonorthogonality: float

    @property
    def dof(self) -> int:
        """Residual degrees of freedom of the fit: 0 for six readings (it fits them exactly)."""
        return max(self.count - N_PARAMS, 0)

    @property
    def improves(self) -> bool:
        """Whether this model's largest norm error on the readings is below their raw one."""
        return bool(self.norm_error.max() < self.norm_error_raw.max())

    def apply(self, readings) -> np.ndarray:
        """``diag(scale) (m − offset)`` of readings (N, 3)."""
        return (as_vectors(readings, "readings") - self.offset) * self.scale


def fit_offset_scale(means, gravity: float, offset0, scale0) -> tuple[np.ndarray, np.ndarray]:
    """Offsets and per-axis scales whose corrected readings have gravity's magnitude.

    Parameters
    ----------
    means : array_like, shape (N, 3)
        Still readings, N ≥ 6, spread over directions.
    gravity : float
        Their true magnitude, in their unit.
    offset0, scale0 : array_like, shape (3,)
        Where the search starts (e.g. a full correction's offset and the diagonal of its ``P``).

    Returns
    -------
    offset, scale : numpy.ndarray, shape (3,)
        Minimising ``Σ ( |diag(scale) (m_k − offset)| − g )²`` (ArduPilot's ``AccelCalibrator`` residual,
        ``AccelCalibrator::calc_residual``, with an axis-aligned ellipsoid).

    Raises
    ------
    CalibrationError
        Fewer than six readings, or a fit that does not converge.
    """
    m = as_vectors(means, "means")
    if len(m) < N_PARAMS:
        raise CalibrationError(f"the offset-and-scale model has {N_PARAMS} parameters: {len(m)} readings cannot fit it")
    g = float(gravity)

    def residual(p):
        return (np.linalg.norm((m - p[:3]) * p[3:], axis=1) - g) / g

    from scipy.optimize import least_squares  # here: scipy.optimize takes ~0.5 s to import, for exports only

    fit = least_squares(
        residual,
        np.r_[np.asarray(offset0, float), np.asarray(scale0, float)],
        method="lm",
        x_scale=np.r_[np.full(3, g), np.ones(3)],
        xtol=1e-14,
        ftol=1e-14,
        gtol=1e-14,
    )
    if not fit.success or not np.all(np.isfinite(fit.x)):
        raise CalibrationError(f"the offset-and-scale fit did not converge: {fit.message}")
    return fit.x[:3].copy(), fit.x[3:].copy()


def _sphere(n: int = 4000) -> np.ndarray:
    """``n`` unit vectors spread evenly over the sphere (a Fibonacci lattice: deterministic)."""
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    phi = np.pi * (1.0 + np.sqrt(5.0)) * i
    r = np.sqrt(1.0 - z * z)
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), z])


def _worst_direction(error) -> float:
    """The largest of ``error`` (unit vectors (N, 3) → (N,)) over the sphere: the best of an even lattice, each
    of its five best points then climbed to its local maximum (Nelder–Mead on the direction)."""
    grid = _sphere()
    values = error(grid)
    best = float(values.max())
    from scipy.optimize import minimize  # here, as least_squares above

    def negative(u: np.ndarray) -> float:
        return -error((u / np.linalg.norm(u))[None, :])[0]

    for start in grid[np.argsort(values)[-5:]]:
        found = minimize(
            negative,
            start,
            method="Nelder-Mead",
            options={"xatol": 1e-10, "fatol": 1e-14, "maxiter": 2000},
        )
        best = max(best, -float(found.fun))
    return best


def offset_scale_fit(M, o, gravity: float, means=None) -> OffsetScaleFit:
    """The firmware's offset-and-scale model fitted beside a full correction ``a = M (m − o)``.

    Parameters
    ----------
    M : array_like, shape (3, 3)
    o : array_like, shape (3,)
        The full correction, readings in their unit.
    gravity : float
        Gravity's magnitude in the calibrated unit (the readings' when they are physical).
    means : array_like, shape (N, 3), optional
        The still readings the full correction was fitted on. With fewer than six (or none), the model is
        fitted on the readings the full correction puts at magnitude g along :data:`DIRECTIONS`.

    Returns
    -------
    OffsetScaleFit
    """
    M = np.asarray(M, dtype=float)
    o = np.asarray(o, dtype=float)
    g = float(gravity)
    X = np.linalg.inv(M)
    given = None if means is None else np.asarray(means, dtype=float).reshape(-1, 3)
    from_readings = given is not None and len(given) >= N_PARAMS
    readings = given if given is not None and from_readings else DIRECTIONS * g @ X.T + o
    # An axis the correction inverts (a negative diagonal term) keeps its sign in the scale: the magnitude does
    # not see it. M = R P diag(sign), P symmetric positive definite.
    sign = np.where(np.diag(M) < 0, -1.0, 1.0)
    from scipy.linalg import polar  # here, as least_squares below: scipy.linalg and scipy.spatial take ~0.3 s
    from scipy.spatial.transform import Rotation  # to import, which every command that lists the exports paid

    R, P = polar(M * sign)
    if np.linalg.det(R) < 0:
        raise CalibrationError("the correction mirrors the axes (a left-handed frame): no offsets and scales hold it")
    offset, scale = fit_offset_scale(readings, g, o, np.diag(P))
    scale = np.abs(scale) * sign

    def fit_apply(m):
        return (m - offset) * scale

    Xs = np.linalg.inv(M * sign)
    rows = Xs / np.linalg.norm(Xs, axis=1, keepdims=True)  # the sensor's axes, in the calibrated frame
    cos = np.clip([rows[0] @ rows[1], rows[0] @ rows[2], rows[1] @ rows[2]], -1.0, 1.0)
    rotvec = Rotation.from_matrix(R).as_rotvec()
    return OffsetScaleFit(
        offset=offset,
        scale=scale,
        count=int(len(readings)),
        from_readings=bool(from_readings),
        norm_error=relative_norm_errors(fit_apply(readings), g),
        norm_error_raw=relative_norm_errors(readings, g),
        norm_error_full=relative_norm_errors((readings - o) @ M.T, g),
        norm_error_any_direction=_worst_direction(lambda u: relative_norm_errors(fit_apply(g * u @ X.T + o), g)),
        rotation_deg=float(np.degrees(np.linalg.norm(rotvec))),
        rotation_axes_deg=np.degrees(rotvec),
        axis_angles_deg=np.degrees(np.arccos(cos)) - 90.0,
        nonorthogonality=float(np.linalg.norm(np.eye(3) - np.diag(np.diag(P)) @ np.linalg.inv(P), 2)),
    )
