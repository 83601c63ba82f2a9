"""Calibration protocols: the static positions of a recording and the rotations between them.

A protocol lists P positions, each with the attitude of the sensor in the calibration frame
(Särkkä et al. (IEEE Sensors J. 2017), section III-C: position 1 *is* the calibration frame), and the P − 1
transitions between them.  A transition is a known rotation (a right-hand rotation by an angle
about an axis fixed in the calibration frame, Särkkä et al. Fig. 1) or *free* (None): the device was moved
but the rotation is not used for the gyroscope.

- ``cube24``: docs/methods.md, the 24 positions of Särkkä et al. Fig. 1.
- ``ferraris``: six static positions and one 360° rotation about each sensor axis (the protocol of
  the imucal library), with free moves between the positions.  Recorded by hand, its rests and
  turns are matched by orientation and integrated angle (:mod:`.matching`), or taken from an
  annotated section list (:mod:`.sections`).
- :func:`explicit_protocol`: any list of positions and rotations.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from ..shared.errors import CalibrationError
from ..shared.orientations import UP_VECTORS, nearest_orientation, up_vector
from . import quaternion as quat

CUBE24_ROTATIONS: tuple[str, ...] = (
    "z+",
    "z+",
    "z+",
    "x+",
    "z+",
    "z+",
    "z+",
    "x+",
    "z+",
    "z+",
    "z+",
    "x-",
    "z+",
    "z+",
    "z+",
    "x-",
    "z+",
    "z+",
    "z+",
    "x+",
    "z+",
    "z+",
    "z+",
)
"""The 23 body rotations of cube24 in the calibration frame (docs/methods.md)."""

CUBE24_UPS: tuple[str, ...] = ("+z",) * 4 + ("-x",) * 4 + ("-y",) * 4 + ("-z",) * 4 + ("+x",) * 4 + ("+y",) * 4
"""The sensor axis that points up in each of the 24 positions on a level plane (docs/methods.md)."""

_AXES = {"x": np.array([1.0, 0.0, 0.0]), "y": np.array([0.0, 1.0, 0.0]), "z": np.array([0.0, 0.0, 1.0])}
_ROTATION_RE = re.compile(r"^\s*([xyz])\s*([+-])\s*(\d+(?:\.\d*)?)?\s*$")


@dataclass(frozen=True)
class Rotation:
    """A known net rotation between two positions.

    Attributes
    ----------
    axis : numpy.ndarray, shape (3,)
        Unit axis in the calibration frame (fixed in space: the plane's normal or the jig edge).
    angle_deg : float
        Right-hand rotation angle; 90 for a cube turn, 360 for a full turn.
    label : str
        Human name, e.g. ``z+`` or ``x+360``.
    """

    axis: np.ndarray
    angle_deg: float
    label: str

    def quaternion(self) -> np.ndarray:
        """Net rotation as a quaternion on the branch of its angle (360° → −1)."""
        return quat.from_axis_angle(self.axis, np.radians(self.angle_deg))

    def matrix(self) -> np.ndarray:
        """Net rotation as a matrix in the calibration frame."""
        return quat.to_matrix(self.quaternion())


def parse_rotation(spec) -> Rotation | None:
    """A rotation from ``"z+"``, ``"x-"``, ``"y+360"``, a dict ``{"axis", "angle_deg"}`` or None.

    Raises
    ------
    CalibrationError
        On an unreadable specification.
    """
    if spec is None or (isinstance(spec, str) and spec.strip().lower() in ("free", "none", "")):
        return None
    if isinstance(spec, Rotation):
        return spec
    if isinstance(spec, str):
        m = _ROTATION_RE.match(spec.lower())
        if not m:
            raise CalibrationError(
                f"unknown rotation {spec!r}: write an axis of the calibration frame and a sign, "
                "optionally an angle in degrees (z+, x-, y+360), or 'free' for a move that is not used"
            )
        axis, sign, angle = m.groups()
        deg = float(angle) if angle else 90.0
        return Rotation(_AXES[axis], deg if sign == "+" else -deg, spec.strip())
    if isinstance(spec, dict):
        try:
            axis = np.asarray(spec["axis"], dtype=float).reshape(3)
            deg = float(spec.get("angle_deg", 90.0))
        except (KeyError, TypeError, ValueError):
            raise CalibrationError(
                f"rotation {spec!r} needs 'axis' (3 numbers, calibration frame) and 'angle_deg'"
            ) from None
        norm = np.linalg.norm(axis)
        if not np.isfinite(norm) or norm == 0 or not np.isfinite(deg):
            raise CalibrationError(f"rotation {spec!r}: the axis must be a non-zero finite vector")
        return Rotation(axis / norm, deg, spec.get("label", f"{np.round(axis / norm, 3).tolist()} {deg:g}°"))
    raise CalibrationError(f"unknown rotation {spec!r}")


@dataclass(frozen=True)
class Protocol:
    """Positions and transitions of a calibration recording.

    Attributes
    ----------
    name : str
    attitudes : numpy.ndarray, shape (P, 3, 3)
        R_p, sensor → calibration frame, in each position; ``C_c^s(t_p) = R_pᵀ`` of Särkkä et al. eq. (6).
    quaternions : numpy.ndarray, shape (P, 4)
        The same attitudes as quaternions, on the branch reached by the rotations (Särkkä et al. section
        III-B, footnote 2): after a 360° turn the quaternion is the negative of the one before.
    rotations : tuple of Rotation or None
        P − 1 transitions; None marks a free move.
    ups : tuple of str
        The sensor axis that points up in each position when the plane is level.
    heading_known : bool
        True when every attitude is known about the vertical too (a jig), so that the direction
        of the reference field (α, β of Särkkä et al. eq. (8)) can be estimated.
    reading_positions : tuple of int or None
        0-based positions whose still readings enter the accelerometer and magnetometer fits and
        the gyroscope bias; None for all.  An annotated Ferraris section list names six rests, and
        its turns' end points only anchor the turns.
    """

    name: str
    attitudes: np.ndarray
    quaternions: np.ndarray
    rotations: tuple
    ups: tuple
    heading_known: bool
    reading_positions: tuple | None = None

    @property
    def n_positions(self) -> int:
        """Number of static positions P."""
        return len(self.attitudes)

    def describe_rotation(self, k: int) -> str:
        """``rotation 4 (x+, from position 4 into position 5)`` for 0-based transition k."""
        rot = self.rotations[k]
        label = "free move" if rot is None else rot.label
        return f"rotation {k + 1} ({label}, from position {k + 1} into position {k + 2})"

    def to_dict(self) -> dict:
        """Plain form: name, ups, rotations (label, axis, angle) and the attitudes."""
        return {
            "name": self.name,
            "ups": list(self.ups),
            "rotations": [
                None if r is None else {"label": r.label, "axis": r.axis.tolist(), "angle_deg": r.angle_deg}
                for r in self.rotations
            ],
            "attitudes": self.attitudes.tolist(),
            "heading_known": self.heading_known,
            "reading_positions": None if self.reading_positions is None else list(self.reading_positions),
        }

    def uses_reading(self, k: int) -> bool:
        """Whether position k (0-based) is a reading of the field sensors and of the gyroscope's bias."""
        return self.reading_positions is None or k in self.reading_positions

    @property
    def full_turns(self) -> bool:
        """True when every known rotation is a full turn (ferraris): matched by angle, in any order."""
        known = [r for r in self.rotations if r is not None]
        return bool(known) and all(abs(r.angle_deg) >= 360.0 for r in known)


def attitude_for_up(label: str, *, first: bool = False) -> np.ndarray:
    """The attitude given to a position with ``label`` up: the identity for position 1 with +z up
    (position 1 is the calibration frame, Särkkä et al. section III-C), else a representative."""
    return np.eye(3) if first and label == "+z" else _attitude_for_up(label)


def _attitude_for_up(label: str) -> np.ndarray:
    """A representative attitude R with the sensor axis ``label`` pointing up (Rᵀ e_z = up)."""
    u = up_vector(label)
    # Third row of R is the up axis in sensor coordinates; complete a right-handed basis.
    helper = np.array([1.0, 0.0, 0.0]) if abs(u[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    r1 = np.cross(helper, u)
    r1 /= np.linalg.norm(r1)
    r0 = np.cross(r1, u)
    return np.vstack([r0, r1, u])


def _up_label(R: np.ndarray) -> str:
    """The sensor axis pointing up for attitude R (the axis along Rᵀ e_z)."""
    return nearest_orientation(R.T @ np.array([0.0, 0.0, 1.0]), max_angle_deg=45.0) or "tilted"


def explicit_protocol(rotations, *, ups=None, name: str = "explicit", first_up: str = "+z") -> Protocol:
    """A protocol from a list of rotations (and, after free moves, the up axis of each position).

    Parameters
    ----------
    rotations : sequence
        P − 1 transitions: ``"z+"``, ``"x-90"``, ``"y+360"``, ``{"axis": [..], "angle_deg": ..}``
        (axes in the calibration frame), or ``"free"``/None for a move that is not a known rotation.
    ups : sequence of str, optional
        Up axis of each of the P positions.  Required where a free move makes it unknown; where
        given after a known rotation it must agree with the chained attitude.
    name : str
    first_up : str
        Up axis of position 1 when ``ups`` is not given; position 1 defines the calibration
        frame (Särkkä et al. section III-C), so only +z (R = I) keeps the sensor and calibration frames equal.

    Returns
    -------
    Protocol

    Raises
    ------
    CalibrationError
        Unreadable rotations, missing or contradictory up axes.
    """
    rots = [parse_rotation(r) for r in rotations]
    n = len(rots) + 1
    if ups is not None and len(ups) != n:
        raise CalibrationError(
            f"{len(rots)} rotations join {n} positions, but {len(ups)} up axes were given: give one per position"
        )
    if ups is not None:
        for lab in ups:
            if lab is not None:
                up_vector(lab)
    first = ups[0] if ups is not None and ups[0] is not None else first_up
    R = [attitude_for_up(first, first=True)]
    q = [quat.from_matrix(R[0])]
    heading_known = True
    for k, rot in enumerate(rots):
        if rot is None:
            heading_known = False
            lab = None if ups is None else ups[k + 1]
            if lab is None:
                raise CalibrationError(
                    f"position {k + 2} follows a free move: give its up axis in `ups` (one of {', '.join(UP_VECTORS)})"
                )
            R.append(_attitude_for_up(lab))
            q.append(quat.from_matrix(R[-1]))
        else:
            # Särkkä et al. Fig. 1: a rotation about an axis fixed in the calibration frame, R ← Rot R.
            dq = rot.quaternion()
            q.append(quat.multiply(dq, q[-1]))
            R.append(quat.to_matrix(q[-1]))
            if ups is not None and ups[k + 1] is not None and _up_label(R[-1]) != ups[k + 1]:
                raise CalibrationError(
                    f"rotation {k + 1} ({rot.label}) leads into position {k + 2} with {_up_label(R[-1])} up, "
                    f"but the protocol says {ups[k + 1]}: correct the rotation or the up axis"
                )
    attitudes = np.array(R)
    return Protocol(
        name=name,
        attitudes=attitudes,
        quaternions=np.array(q),
        rotations=tuple(rots),
        ups=tuple(_up_label(r) for r in attitudes),
        heading_known=heading_known,
    )


def cube24() -> Protocol:
    """The 24-position cube protocol of docs/methods.md (Särkkä et al. Fig. 1)."""
    return explicit_protocol(CUBE24_ROTATIONS, ups=CUBE24_UPS, name="cube24")


FERRARIS_SIX: tuple[str, ...] = ("+x", "-x", "+y", "-y", "+z", "-z")
"""The six static positions of imucal's ``x_p, x_a, y_p, y_a, z_p, z_a`` (x_p: +x up, reads +g)."""

FERRARIS_TURN_DEG = -360.0
"""imucal's turn: clockwise seen from above, so the gyroscope reads negative about the up axis.
Recordings may turn either way; the sense is taken from the data."""


def turn_spec(up: str, axis: int, angle_deg: float, *, first: bool = False) -> dict:
    """A full turn about the sensor axis ``axis`` (0, 1, 2) in a position with ``up`` up, as a
    rotation of the calibration frame for :func:`explicit_protocol`."""
    R = attitude_for_up(up, first=first)
    sense = "+" if angle_deg > 0 else "-"
    return {
        "axis": R[:, axis].tolist(),
        "angle_deg": float(angle_deg),
        "label": f"{'xyz'[axis]}{sense}{abs(angle_deg):g}",
    }


def ferraris() -> Protocol:
    """Six static positions, then one 360° turn about each sensor axis (imucal's protocol).

    Positions +x, −x, +y, −y, +z, −z joined by free moves (imucal's ``x_p, x_a, y_p, y_a, z_p,
    z_a``); then, as imucal's documentation has it, each turn about the sensor axis that points up
    (``x_rot`` in the x_p position, ``y_rot`` in y_p, ``z_rot`` in z_p), clockwise seen from
    above, from a rest to a rest in the same place: 12 still positions.  This is the order the
    simulation records; a recording is matched in any order (:mod:`.matching`).  The headings are
    unknown, so the field direction is not estimated (α = β = 0) and the magnetometer cannot be
    calibrated with this protocol.
    """
    rotations: list = [None] * 5
    ups = list(FERRARIS_SIX)
    for k, up in enumerate(("+x", "+y", "+z")):
        rotations += [None, turn_spec(up, k, FERRARIS_TURN_DEG)]
        ups += [up, up]
    return explicit_protocol(rotations, ups=ups, name="ferraris")


PROTOCOLS = {"cube24": cube24, "ferraris": ferraris}


def get_protocol(protocol) -> Protocol:
    """A :class:`Protocol` from a name (``cube24``, ``ferraris``), a Protocol, or a dict
    ``{"rotations": [...], "ups": [...]}`` for :func:`explicit_protocol`.

    Raises
    ------
    CalibrationError
        Unknown name or unreadable specification.
    """
    if isinstance(protocol, Protocol):
        return protocol
    if isinstance(protocol, str):
        try:
            return PROTOCOLS[protocol]()
        except KeyError:
            raise CalibrationError(
                f"unknown protocol {protocol!r}: use one of {', '.join(PROTOCOLS)} or an explicit "
                "list of positions and rotations"
            ) from None
    if isinstance(protocol, dict) and "rotations" in protocol:
        return explicit_protocol(protocol["rotations"], ups=protocol.get("ups"), name=protocol.get("name", "explicit"))
    raise CalibrationError("protocol must be 'cube24', 'ferraris' or {'rotations': [...], 'ups': [...]}")
