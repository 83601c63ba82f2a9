"""The rules of the guided capture flows: how long a pose is captured, when a device is still, how far a free
pose must point from the others and how many the free flow fits from — shared by the server's sessions
(app.guided.sessions), the pages' tables (app.web.tables) and the terminal's capture (app.cli.board), so that
what the page or the terminal captures the server accepts; with the capture machine's own thresholds
(:func:`capture_thresholds`).
"""

from __future__ import annotations

from dataclasses import dataclass

from app.calibration.shared.orientations import LABEL_MAX_ANGLE_DEG
from app.calibration.still.advice import MIN_SEPARATION_DEG


@dataclass(frozen=True)
class WizardProtocol:
    """A capture protocol by name, and what the wizard's pages show of it (app/web/pages.py; the template
    branches on the flags, never on a protocol's name). Its strategy, what it asks next and how it is solved,
    is the class of app.guided.protocols whose ``name`` it is."""

    name: str
    words: str
    """The protocol in words, on the pages' list of choices."""
    session: bool = False
    """A guided session runs it (the page's wizard, ``POST /api/v1/sessions``)."""
    phone: bool = True
    """A phone's motion events can do it (the noise page records a board)."""
    template: str = "wizard.html"
    flow: str = ""
    """The page's flow module (static/js/<flow>.js, and its view's render hooks in <flow>_view.js)."""
    has_turns: bool = False
    """Positions in a fixed order, a turn between each that the gyroscope checks (pictures of a cube)."""
    lists_poses: bool = False
    """The six poses, listed each with its picture, captured in any order."""
    any_pose: bool = False
    """Poses of the person's choosing, as many as the fit needs (a sphere of the directions covered)."""


WIZARD_PROTOCOLS = (
    WizardProtocol("six", "six positions", session=True, flow="flow_six", lists_poses=True),
    WizardProtocol("cube24", "24 positions of a cube", session=True, flow="flow_cube", has_turns=True),
    WizardProtocol("free", "free poses, no jig", session=True, flow="flow_free", any_pose=True),
    WizardProtocol("compass", "the compass: turn it through all directions", template="wizard_compass.html"),
    WizardProtocol(
        "noise", "the noise: a still recording of a chosen length", phone=False, template="wizard_noise.html"
    ),
)
"""Every capture protocol, in the order the pages offer them: the one list of their names. The pages read it
(app/web/pages.py), the guided sessions take theirs from it (app.guided.protocols ``SESSION_PROTOCOLS``), and
``trical capture`` runs each of them on a board (app.guided.protocols ``BOARD_PROTOCOLS``)."""

CAPTURE_PROTOCOLS = tuple(p.name for p in WIZARD_PROTOCOLS)
"""The flows a board can be calibrated with (``trical capture --protocol``, the page's board source): all."""

SESSION_PROTOCOL_NAMES = tuple(p.name for p in WIZARD_PROTOCOLS if p.session)
"""The protocols a guided session runs (``POST /api/v1/sessions``' ``protocol``)."""

SIX_ASKED_ORDER = ("+z", "-z", "+y", "-y", "+x", "-x")
"""The six flow's pose named next among those to do, on the page (app.web.tables ``poses.asked``) and in the
terminal: flat ones first (the easiest to place), then standing, then on the side edges; any other remaining one
is accepted as well."""

FREE_FIT_FROM = 10
"""The free flow fits the triangular model from this many poses on: nine parameters, and one more so
that every fit without one pose (the cross-validation) is still determined."""

FREE_TARGET_MIN_POSES = 12
"""The free flow reaches its target only with at least this many poses."""

FREE_MAX_ANGLE_DEG = 180.0
"""A free pose need not be near an axis: any direction is a pose (its label is the nearest axis)."""

FREE_MIN_ANGLE_DEG = MIN_SEPARATION_DEG
"""A free pose must point at least this far from every earlier one (the advice keeps to it too)."""

CAPTURE_S_DEFAULT = 5.0
"""Seconds captured per position unless the session asks for another duration."""

CAPTURE_S_RANGE = (0.5, 30.0)
"""The seconds per position a session accepts (the API's and the wizard page's bounds)."""

CUBE_FACE_MAX_ANGLE_DEG = 45.0
"""The cube may stand on an inclined plane: its up face is the nearest axis within 45° (as Särkkä et al.'s
sequence check, app.calibration.cube.sequence)."""

PAGE_CUBE_FACE_MAX_ANGLE_DEG = 40.0
"""The wizard page captures a cube position only within 40° of a face, inside the server's 45°,
so that what it sends is not refused for the angle."""

MAX_ROTATION_DEG_S = 5.0
"""A still capture whose mean rotation rate exceeds this (°/s) was turning, whatever the
accelerometer says; a phone gyroscope's bias is well below it."""

PAGE_STILL_ENTER_DEG_S = 3.0
PAGE_STILL_LEAVE_DEG_S = MAX_ROTATION_DEG_S
"""The wizard page calls the device still when the mean rotation rate over its window falls below
3 °/s and moving again above the server's 5 °/s (hysteresis, static/js/motion.js)."""

PAGE_STILL_ENTER_STD = 0.1
PAGE_STILL_LEAVE_STD = 0.25
"""The same for the accelerometer, in m/s²: the largest per-axis standard deviation over the
window; the page leaves "still" below the server's limit (app.calibration.shared.capture.STILL_MAX_STD_G,
0.03 g = 0.29 m/s²), so that a capture it completes is still for the server too."""

CAPTURE_WINDOW_MS = 500
"""The capture machine's moving window of the mean and spread (ms): the page's (static/js/motion.js) and the
terminal's (app.cli.board)."""

CAPTURE_HOLD_MS = 1500
"""Still in a valid pose this long before a capture starts (ms)."""


def capture_thresholds() -> dict:
    """The options of the capture machine (the page's CaptureMachine, static/js/motion.js, which the page's tables
    hand it; and ``trical capture``'s, app.cli.board), each from the server check it stays inside."""
    return {
        "windowMs": CAPTURE_WINDOW_MS,
        "holdMs": CAPTURE_HOLD_MS,
        "spreadLow": PAGE_STILL_ENTER_STD,
        "spreadHigh": PAGE_STILL_LEAVE_STD,
        "gyrLow": PAGE_STILL_ENTER_DEG_S,
        "gyrHigh": PAGE_STILL_LEAVE_DEG_S,
        "maxAngleDeg": LABEL_MAX_ANGLE_DEG,
    }
