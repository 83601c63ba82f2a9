"""Match the still segments and moves of a hand-made recording to a protocol's positions and rotations.

People pause, re-place the device and hold it in the hand between the positions of a protocol, so a
recording has more still segments than the protocol has positions.  Each still segment is
identified by its orientation (the sensor axis the accelerometer sees pointing up, within 45°) and
each move between two rests by its integrated rate ∫(ω − b) dt (trapezoidal rule, pre-adjusted
rad/s, bias from the rests):

- a **protocol rotation** when its integral about the protocol's axis is within
  :data:`TURN_TOLERANCE` of the protocol's angle (a quarter turn of cube24 — Särkkä et al., IEEE
  Sensors Journal 17(11) 2017, Fig. 1 — or a full turn of Ferraris' method in either sense) and the
  rest after it has the expected axis up;
- **handling** when the same axis stays up and the move is not that rotation: a pause, a
  re-placement, a short move by hand, a half-hearted turn.  It is not evidence for the
  gyroscope's scale and never enters the gyroscope fit.  Consecutive rests in the same orientation
  are one position; its reading is the *longest* of them (the most samples, so the smallest
  variance of the mean, which Särkkä et al.'s generalised least squares weights by, eq. (13)).
  They are not merged: a re-placement changes the tilt a little, and the mean of two tilts is
  the reading of neither, with a sample covariance inflated by the step between them.  A rotation
  is integrated from the *last* rest before it;
- a still moment with no axis up (held in the hand) is handling too, and the move integrated
  across it.

A recording of an ordered protocol with exactly P rests (P + 1 with the return to position 1) is
taken one rest per position, as recorded: only extra rests are looked at as handling.

cube24 and other ordered protocols are walked in order: a move that is neither the next rotation
nor handling is taken as that rotation anyway, so that the sequence check (Särkkä et al., section
VII-A-1) names it as the first wrong rotation.  Ferraris' protocol (full turns) is matched in any
order: every change of the up axis is a free move into a new position, the first full turn about
each sensor axis is that axis' turn, and the six orientations and three turns must all be there.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..shared.errors import CalibrationError, InsufficientDataError
from ..shared.orientations import nearest_orientation
from .protocols import FERRARIS_SIX, Protocol, explicit_protocol, turn_spec
from .segmentation import Segmentation
from .sequence import FACE_MAX_ANGLE_DEG, normalised_directions

TURN_TOLERANCE = 0.25
"""A move is the protocol's rotation when its integrated angle about the rotation's axis is within
this fraction of the rotation's angle (±22.5° of a quarter turn, ±90° of a full turn): half-way to
the nearest thing it could be confused with (no turn, or a turn and a half), with room for an
uncalibrated gyroscope's scale error and a hand's wobble."""

HANDLING_MAX = 0.5
"""In an ordered protocol a move that keeps the up axis is handling only while its whole integrated
rotation stays below this fraction of the rotation expected (45° for a quarter turn); a larger one
(a quarter turn the wrong way) is a wrong rotation, for the sequence check to name."""


@dataclass(frozen=True)
class Match:
    """The still positions and rotations of a recording, one per protocol position and transition.

    Attributes
    ----------
    segmentation : Segmentation
        ``static``/``still`` one interval per matched position (plus the return to position 1),
        ``rotations`` one per transition, ``handling`` what was left out.
    protocol : Protocol
        The protocol, or for Ferraris' method the order in which the recording made it.
    has_return : bool
        Whether the recording returned to position 1 after the last position (Särkkä et al.
        section II).
    warnings : tuple of str
    """

    segmentation: Segmentation
    protocol: Protocol
    has_return: bool
    warnings: tuple = ()


def _faces(acc, still, gravity: float) -> list:
    """The sensor axis up in each still interval (within 45°), None when none is."""
    means = np.array([acc[a:b].mean(axis=0) for a, b in still])
    return [nearest_orientation(d, FACE_MAX_ANGLE_DEG) for d in normalised_directions(means, gravity)]


def integrated_rate(w, a: int, b: int, bias, fs: float) -> np.ndarray:
    """∫(ω − b) dt over samples a … b − 1 by the trapezoidal rule, rad (sensor frame)."""
    u = w[a:b] - bias
    if len(u) < 2:
        return np.zeros(3)
    return (u.sum(axis=0) - 0.5 * (u[0] + u[-1])) / fs


def _times(a: int, b: int, fs: float) -> str:
    return f"{a / fs:.1f}–{b / fs:.1f} s"


class _Walk:
    """Shared state of a match: the recording's rests, their faces and the handling found."""

    def __init__(self, acc, w, seg: Segmentation, fs: float, gravity: float):
        self.w, self.seg, self.fs = w, seg, fs
        self.faces = _faces(acc, seg.still, gravity)
        self.handling: list[dict] = []

    def move(self, i: int, j: int) -> np.ndarray:
        """Integrated rate from the end of rest i to the start of rest j."""
        return integrated_rate(self.w, self.seg.still[i][1], self.seg.still[j][0], self.seg.gyro_bias, self.fs)

    def length(self, i: int) -> int:
        a, b = self.seg.static[i]
        return b - a

    def best(self, candidates: list[int]) -> int:
        """The longest rest of a position; the others are recorded as handling."""
        keep = max(candidates, key=self.length)
        for i in candidates:
            if i != keep:
                a, b = self.seg.still[i]
                self.handling.append(
                    {
                        "kind": "pause",
                        "start": a,
                        "end": b,
                        "up": self.faces[i],
                        "text": f"the rest at {_times(a, b, self.fs)} ({self.faces[i]} up; a longer "
                        "rest in the same orientation was kept)",
                    }
                )
        return keep

    def handled_move(self, i: int, j: int, angle_deg: float, why: str) -> None:
        a, b = self.seg.still[i][1], self.seg.still[j][0]
        self.handling.append(
            {
                "kind": "move",
                "start": a,
                "end": b,
                "angle_deg": angle_deg,
                "text": f"the move at {_times(a, b, self.fs)} ({angle_deg:.0f}° in all; {why})",
            }
        )

    def tilted(self, j: int) -> None:
        a, b = self.seg.still[j]
        self.handling.append(
            {
                "kind": "tilted",
                "start": a,
                "end": b,
                "up": None,
                "text": f"the still moment at {_times(a, b, self.fs)} (no axis within "
                f"{FACE_MAX_ANGLE_DEG:g}° of up: held in the hand)",
            }
        )

    def result(
        self, positions: list[list[int]], anchors: list[int], protocol: Protocol, ret: list[int] | None
    ) -> Match:
        """The segmentation of the matched positions: each position's longest rest, each rotation
        from the last rest before it to the first after it (padded like Segmentation's)."""
        seg = self.seg
        pad = seg.pad
        groups = positions + ([ret] if ret else [])
        chosen = [self.best(g) for g in groups]
        firsts = [g[0] for g in groups]
        rotations = []
        for k in range(len(groups) - 1):
            a0, b0 = seg.still[anchors[k]]
            a1, b1 = seg.still[firsts[k + 1]]
            rotations.append((max(a0, b0 - pad), min(b1, a1 + pad)))
        self.handling.sort(key=lambda h: h["start"])
        out = replace(
            seg,
            static=tuple(seg.static[i] for i in chosen),
            still=tuple(seg.still[i] for i in chosen),
            rotations=tuple(rotations),
            handling=tuple(self.handling),
            n_still_found=len(seg.still),
        )
        warnings: tuple[str, ...] = ()
        if self.handling:
            warnings = (
                f"treated as handling, not used for the gyroscope: {'; '.join(h['text'] for h in self.handling)}",
            )
        return Match(out, protocol, ret is not None, warnings)


def _walk_ordered(walk: _Walk, proto: Protocol) -> Match:
    """cube24 and explicit protocols: the rests in the protocol's order, pauses and moves by hand between."""
    P = proto.n_positions
    faces = walk.faces
    n = len(faces)
    start = next((i for i in range(n) if faces[i] is not None), None)
    # One rest per position, as recorded: when the count already fits (P, or P + 1 with the return),
    # without a face to go by (raw units seen in one orientation only), and after a wrong rotation
    # (the attitudes are unknown from there).
    lost = start is None or n in (P, P + 1)
    start = start or 0
    for i in range(start):
        walk.tilted(i)
    positions, anchors = [[start]], [start]
    ret: list[int] | None = None
    for j in range(start + 1, n):
        p = len(positions) - 1
        if lost:
            if p + 1 < P:
                positions.append([j])
            elif ret is None:
                ret = [j]
            else:
                break
            anchors.append(j)
            continue
        if faces[j] is None:
            walk.tilted(j)
            continue
        v = np.degrees(walk.move(anchors[-1], j))
        here = proto.ups[p] if ret is None else proto.ups[0]
        if p + 1 < P and ret is None:
            rot = proto.rotations[p]
            about = float(v @ (proto.attitudes[p].T @ rot.axis)) if rot is not None else 0.0
            turned = rot is not None and abs(about - rot.angle_deg) <= TURN_TOLERANCE * abs(rot.angle_deg)
            expected = proto.ups[p + 1]
            if turned and faces[j] == expected:
                positions.append([j])
                anchors.append(j)
                continue
            limit = HANDLING_MAX * (90.0 if rot is None else abs(rot.angle_deg))
            if faces[j] == here and (rot is None or np.linalg.norm(v) < limit):
                walk.handled_move(anchors[-1], j, float(np.linalg.norm(v)), f"{here} stayed up")
                positions[-1].append(j)
                anchors[-1] = j
                continue
            positions.append([j])  # the protocol's rotation, whatever was made: the sequence check judges it
            anchors.append(j)
            lost = True
            continue
        if faces[j] == here and np.linalg.norm(v) < HANDLING_MAX * 90.0:
            walk.handled_move(anchors[-1], j, float(np.linalg.norm(v)), f"{here} stayed up")
            (positions[-1] if ret is None else ret).append(j)
            anchors[-1] = j
        elif ret is None:
            ret = [j]  # the return to position 1 (Särkkä et al. section II)
            anchors.append(j)
        else:
            walk.handled_move(anchors[-1], j, float(np.linalg.norm(v)), "after the return to position 1")
    if len(positions) < P:
        raise CalibrationError(
            f"found {len(positions)} still positions in the recording, but protocol {proto.name} has {P} "
            f"({P + 1} with the return to position 1; {len(walk.handling)} moves or rests were handling): "
            "check the protocol, or hold the device still for at least a second in each position"
        )
    return walk.result(positions, anchors, proto, ret)


def _walk_full_turns(walk: _Walk, proto: Protocol) -> Match:
    """Ferraris' protocol: rests in any order, a full turn about each sensor axis between two of them."""
    angle = max(abs(r.angle_deg) for r in proto.rotations if r is not None)
    faces = walk.faces
    positions: list[list[int]] = []
    anchors: list[int] = []
    transitions: list = []
    turned: dict[int, tuple] = {}
    for j, face in enumerate(faces):
        if face is None:
            walk.tilted(j)
            continue
        if not positions:
            positions.append([j])
            anchors.append(j)
            continue
        here = faces[anchors[-1]]
        v = np.degrees(walk.move(anchors[-1], j))
        k = int(np.argmax(np.abs(v)))
        full = abs(abs(v[k]) - angle) <= TURN_TOLERANCE * angle
        if face == here and full and k not in turned:
            turned[k] = (len(transitions), float(np.sign(v[k]) * angle))
            transitions.append(k)
            positions.append([j])
        elif face == here:
            why = (
                f"a second full turn about {'xyz'[k]}: the first is used"
                if full
                else f"{here} stayed up, not a full turn"
            )
            walk.handled_move(anchors[-1], j, float(np.linalg.norm(v)), why)
            positions[-1].append(j)
            anchors[-1] = j
            continue
        else:
            transitions.append(None)  # a free move into another orientation
            positions.append([j])
        anchors.append(j)
    ups = [faces[g[0]] for g in positions]
    missing = [u for u in FERRARIS_SIX if u not in ups]
    if missing:
        raise InsufficientDataError(
            f"no still position with {', '.join(missing)} up was found ({len(positions)} positions: "
            f"{', '.join(ups)}): protocol {proto.name} needs the device at rest with each axis up and down "
            "(imucal's x_p, x_a, y_p, y_a, z_p, z_a), or give the annotated sections"
        )
    absent = [a for a in range(3) if a not in turned]
    if absent:
        raise InsufficientDataError(
            f"no full turn about {', '.join('xyz'[a] for a in absent)} was found: protocol {proto.name} needs one "
            f"{angle:g}° turn about each sensor axis, from a rest to a rest in the same orientation "
            "(imucal's x_rot, y_rot, z_rot), or give the annotated sections"
        )
    rotations: list[dict | None] = []
    for k, t in enumerate(transitions):
        if t is None:
            rotations.append(None)
        else:
            rotations.append(turn_spec(ups[k], t, turned[t][1], first=k == 0))
    built = explicit_protocol(rotations, ups=ups, name=proto.name)
    return walk.result(positions, anchors, built, None)


def match_protocol(acc, w, seg: Segmentation, proto: Protocol, *, sampling_rate_hz: float, gravity: float) -> Match:
    """Match a recording's still segments and moves to a protocol (module docstring).

    Parameters
    ----------
    acc : numpy.ndarray, shape (N, 3)
        Raw accelerometer samples (any unit).
    w : numpy.ndarray, shape (N, 3)
        Pre-adjusted gyroscope rates, rad/s.
    seg : Segmentation
        Every still segment of the recording (:func:`.segmentation.segment_recording`).
    proto : Protocol
    sampling_rate_hz : float
    gravity : float
        Reference magnitude in the accelerometer's unit (to tell physical units from raw ones).

    Returns
    -------
    Match

    Raises
    ------
    CalibrationError
        Fewer positions than the protocol has.
    InsufficientDataError
        Ferraris' method without one of its six orientations or three turns.
    """
    walk = _Walk(acc, w, seg, float(sampling_rate_hz), gravity)
    if proto.full_turns and not proto.heading_known:
        return _walk_full_turns(walk, proto)
    return _walk_ordered(walk, proto)
