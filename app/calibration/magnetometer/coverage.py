"""How much of the sphere of directions a magnetometer recording covers: the faces of an icosahedron.

A compass calibration fits an ellipsoid to the readings; where a part of the sphere of field
directions (in the device frame) has no reading, the ellipsoid is free to bulge there, and the
soft iron across it is undetermined.  MotionCal draws the readings on a sphere split into regions
and calls the calibration good once most regions hold a reading; trical does the same with the 20
faces of a regular icosahedron, which split the sphere into equal parts of 41.8° across, small
enough that a turn missing one of them shows, large enough that a slow turn by hand fills them.

Each face is named by the device directions its centre lies closest to: the eight faces around the
diagonals of the device's octants are named by three signs (``+x+y+z``), the twelve others by the
axis they lean on first and the axis they lean towards (``+z+y``: mostly +z, tilted towards +y).
The page (``/wizard?protocol=compass``) reads the same faces from the HTML the server renders.

A turn kept flat (a compass turned round on a table) puts its readings on a ring in one plane, whatever
the centre: :func:`thickness` measures that from the readings alone, before any fit.
"""

from __future__ import annotations

import numpy as np

_PHI = (1.0 + 5.0**0.5) / 2.0

ICOSAHEDRON_VERTICES = np.array(
    [(s1, s2 * _PHI, 0.0) for s1 in (-1, 1) for s2 in (-1, 1)]
    + [(0.0, s1, s2 * _PHI) for s1 in (-1, 1) for s2 in (-1, 1)]
    + [(s2 * _PHI, 0.0, s1) for s1 in (-1, 1) for s2 in (-1, 1)]
) / np.sqrt(1.0 + _PHI**2)
"""The 12 unit vertices of a regular icosahedron: the cyclic permutations of (±1, ±φ, 0)."""


def _faces(vertices: np.ndarray) -> np.ndarray:
    """The 20 triangles of the icosahedron: the vertex triples whose three edges are all the
    shortest edge length (each vertex has five neighbours at the same distance)."""
    d = np.linalg.norm(vertices[:, None] - vertices[None], axis=2)
    edge = d[d > 1e-9].min()
    near = np.abs(d - edge) < 1e-9
    n = len(vertices)
    faces = [
        (i, j, k)
        for i in range(n)
        for j in range(i + 1, n)
        for k in range(j + 1, n)
        if near[i, j] and near[j, k] and near[i, k]
    ]
    return np.array(faces, dtype=int)


ICOSAHEDRON_FACES = _faces(ICOSAHEDRON_VERTICES)
"""Indices into :data:`ICOSAHEDRON_VERTICES` of the 20 faces."""

_centres = ICOSAHEDRON_VERTICES[ICOSAHEDRON_FACES].mean(axis=1)
FACE_CENTRES = _centres / np.linalg.norm(_centres, axis=1, keepdims=True)
"""Unit centres of the 20 faces: the eight (±1, ±1, ±1)/√3 and twelve (0, ±φ⁻¹, ±φ)/√3 cyclic."""

MIN_SAMPLES_PER_FACE = 1
"""A face counts as covered from one reading in it: a slow turn at 10 Hz puts several in each."""


def _sign(value: float, axis: str) -> str:
    return ("+" if value > 0 else "-") + axis


def face_name(centre) -> str:
    """The name of the face whose centre is ``centre``: ``+x+y+z`` for an octant's diagonal,
    ``+z+y`` (mostly +z, towards +y) for the others."""
    c = np.asarray(centre, dtype=float)
    order = np.argsort(-np.abs(c))
    if np.abs(c[order[2]]) > 0.3:  # a diagonal: all three components equal in size
        return "".join(_sign(c[k], "xyz"[k]) for k in range(3))
    return "".join(_sign(c[k], "xyz"[k]) for k in order[:2])


FACE_NAMES = tuple(face_name(c) for c in FACE_CENTRES)
"""The 20 face names, in the order of :data:`FACE_CENTRES`."""


def face_of(vectors) -> np.ndarray:
    """Index of the face each direction falls in (the face whose centre is nearest).

    Parameters
    ----------
    vectors : array_like, shape (N, 3)
        Directions of any length; rows of zeros fall in face 0.

    Returns
    -------
    numpy.ndarray of int, shape (N,)
    """
    v = np.asarray(vectors, dtype=float).reshape(-1, 3)
    return np.argmax(v @ FACE_CENTRES.T, axis=1)


def face_counts(vectors) -> np.ndarray:
    """How many of ``vectors`` fall in each of the 20 faces."""
    return np.bincount(face_of(vectors), minlength=len(FACE_CENTRES))


def coverage(vectors, min_samples: int = MIN_SAMPLES_PER_FACE) -> tuple[float, list[str]]:
    """Share of the sphere of directions the readings cover, and the faces they miss.

    Parameters
    ----------
    vectors : array_like, shape (N, 3)
        Field directions in the device frame, centred on the hard iron (``m − b`` or the
        calibrated ``h``); their length does not matter.
    min_samples : int
        Readings a face needs to count as covered.

    Returns
    -------
    share : float
        Covered faces over 20, in [0, 1].
    missing : list of str
        Names of the faces not covered (:data:`FACE_NAMES`), in their order.
    """
    covered = face_counts(vectors) >= min_samples
    return float(covered.mean()), [FACE_NAMES[k] for k in np.flatnonzero(~covered)]


def thickness(readings) -> float:
    """How far the readings leave their best plane: the third singular value of the readings about
    their mean over the first (the principal axes of the cloud).

    0 for a ring in one plane (a device turned round flat), about 0.4 for a hemisphere and 0.65–1 for
    a turn through all directions; it needs no centre, so no fit.

    Parameters
    ----------
    readings : array_like, shape (N, 3)

    Returns
    -------
    float
        In [0, 1]; 0 when the readings do not change.
    """
    m = np.asarray(readings, dtype=float).reshape(-1, 3)
    s = np.linalg.svd(m - m.mean(axis=0), compute_uv=False)
    return float(s[2] / s[0]) if s[0] > 0.0 else 0.0
