"""The constants the pages share with the server, as one table the page routes render into the page.

Python is their only source: the poses and their up vectors, the cube24 positions and turns, and
the thresholds the page's capture machine uses to stay inside the server's checks.  The routes put
:func:`page_tables` into the template as JSON (``<script type="application/json"
id="trical-tables">``, data the CSP lets through since it is never run); static/js/tables.js reads
it once.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from app import sessions
from app.calibration import CANONICAL_SIX, STANDARD_GRAVITY
from app.calibration.cube.protocols import CUBE24_ROTATIONS, cube24
from app.calibration.cube.turns import TURN_WORDS
from app.calibration.orientations import LABEL_MAX_ANGLE_DEG, POSE_NAMES, UP_VECTORS  # noqa: F401 (POSE_NAMES re-exported)

CAPTURE_WINDOW_MS = 500
"""The page's moving window of the mean and spread (ms)."""

CAPTURE_HOLD_MS = 1500
"""Still in a valid pose this long before the page starts a capture (ms)."""


def capture_thresholds() -> dict:
    """The options of the page's CaptureMachine (static/js/motion.js), each from the server check
    it stays inside."""
    return {
        "windowMs": CAPTURE_WINDOW_MS,
        "holdMs": CAPTURE_HOLD_MS,
        "spreadLow": sessions.PAGE_STILL_ENTER_STD,
        "spreadHigh": sessions.PAGE_STILL_LEAVE_STD,
        "gyrLow": sessions.PAGE_STILL_ENTER_DEG_S,
        "gyrHigh": sessions.PAGE_STILL_LEAVE_DEG_S,
        "maxAngleDeg": LABEL_MAX_ANGLE_DEG,
    }


@lru_cache(maxsize=1)
def page_tables() -> dict:
    """Everything the pages take from the server's constants, as plain JSON-ready data.

    Returns
    -------
    dict
        ``gravity`` (m/s²); ``poses`` (``order``, ``up`` vectors, ``names``); ``capture`` (the
        capture machine's options); ``cube`` (the cube flow's face angle); ``free`` (the free flow's
        angle to an axis, any; its least angle between poses, the poses it fits from and those its target needs); ``cube24`` (the 23
        ``rotations``, the 24 ``ups``, the integer ``attitudes`` R_k, sensor → calibration frame,
        and the ``turnWords`` the server's refusals use).
    """
    protocol = cube24()
    attitudes = np.rint(protocol.attitudes).astype(int) + 0  # quarter turns: exact integers
    return {
        "gravity": STANDARD_GRAVITY,
        "poses": {
            "order": list(CANONICAL_SIX),
            "up": {label: [int(v) for v in UP_VECTORS[label]] for label in CANONICAL_SIX},
            "names": {label: POSE_NAMES[label] for label in CANONICAL_SIX},
        },
        "capture": capture_thresholds(),
        "cube": {"maxAngleDeg": sessions.PAGE_CUBE_FACE_MAX_ANGLE_DEG},
        "free": {"maxAngleDeg": sessions.FREE_MAX_ANGLE_DEG, "minAngleDeg": sessions.FREE_MIN_ANGLE_DEG,
                 "fitFrom": sessions.FREE_FIT_FROM,
                 "targetPoses": sessions.FREE_TARGET_MIN_POSES},
        "cube24": {
            "rotations": list(CUBE24_ROTATIONS),
            "ups": list(protocol.ups),
            "attitudes": attitudes.tolist(),
            "turnWords": dict(TURN_WORDS),
        },
    }
