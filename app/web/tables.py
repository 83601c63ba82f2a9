"""The constants the pages share with the server, as one table the page routes render into the page.

Python is their only source: the poses and their up vectors, the cube24 positions and turns, and
the thresholds the page's capture machine uses to stay inside the server's checks (app.guided.capture_rules).
The routes put :func:`page_tables` into the template as JSON (``<script type="application/json"
id="trical-tables">``, data the CSP lets through since it is never run); static/js/tables.js reads
it once.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import numpy as np

from app.calibration import CANONICAL_SIX, STANDARD_GRAVITY
from app.calibration.check import VERDICT_WORDS as CHECK_VERDICT_WORDS
from app.calibration.cube.protocols import CUBE24_ROTATIONS, cube24
from app.calibration.cube.turns import TURN_WORDS
from app.calibration.magnetometer import coverage as compass
from app.calibration.magnetometer.fit import MIN_READINGS as COMPASS_MIN_READINGS
from app.calibration.registry import as_fitted_words
from app.calibration.shared.headlines import SENSOR_WORDS
from app.calibration.shared.orientations import POSE_NAMES, UP_VECTORS
from app.calibration.temperature import MIN_SPAN_C as TEMPERATURE_MIN_SPAN_C
from app.guided import capture_rules
from app.io.board.formats import board_tables
from app.io.log import UNITS_IN
from app.io.readers.chips import CHIPS
from app.methods import TABLE as METHOD_TABLE
from app.web.metric_words import METRICS
from app.web.result_pages import page_kinds
from app.web.sketches import sketch_table
from app.web.uses import uses_table
from app.words import UNIT_WORDS

COVERAGE_TO_SOLVE = 0.9
"""Share of the 20 icosahedron faces the compass page waits for before it solves by itself; the
server's own gate (``MIN_COVERAGE`` in app/calibration/magnetometer/fit.py) is lower, so a turn the
page accepts is never refused for coverage alone."""

COMPASS_FREQUENCY_HZ = 10
"""The rate the compass page asks of the browser's Magnetometer (Hz): a slow turn puts several
readings in each face."""

_SIDE = {"x": ("right edge", "left edge"), "y": ("top edge", "bottom edge"), "z": ("screen", "back")}
_TOWARDS = {"x": ("right", "left"), "y": ("top", "bottom"), "z": ("screen", "back")}
_BOARD_SIDE = {
    "x": ("X arrow's edge", "edge behind the X arrow"),
    "y": ("Y arrow's edge", "edge behind the Y arrow"),
    "z": ("component side", "underside"),
}
_BOARD_TOWARDS = {
    "x": ("X arrow", "back of the X arrow"),
    "y": ("Y arrow", "back of the Y arrow"),
    "z": ("component side", "underside"),
}


def face_words(name: str, source: str = "phone") -> str:
    """A compass face in plain words: the side of the phone (or the board) the field comes out of.

    ``+z+y`` → ``screen, towards the top``; ``+x+y+z`` → ``screen, top-right corner``; a board's
    ``+z+y`` → ``component side, towards the Y arrow``, ``+x+y+z`` → ``component side, the corner
    the X and Y arrows point to``, ``+x-y-z`` → ``underside, the corner the X arrow points to, away from
    the Y arrow``.
    """
    signs = [(name[i + 1], name[i] == "+") for i in range(0, len(name), 2)]
    word = dict(signs)
    board = source == "board"
    side, towards = (_BOARD_SIDE, _BOARD_TOWARDS) if board else (_SIDE, _TOWARDS)

    def pick(table, axis):
        return table[axis][0 if word[axis] else 1]

    if len(signs) == 3 and board:
        to = [a.upper() for a in "xy" if word[a]]
        away = [a.upper() for a in "xy" if not word[a]]
        said = []
        if to:
            said.append(
                f"the corner the {' and '.join(to)} arrow{'s' if len(to) == 2 else ''} "
                f"point{'' if len(to) == 2 else 's'} to"
            )
        if away:
            said.append(
                f"{'the corner ' if not to else ''}away from the {' and '.join(away)} "
                f"arrow{'s' if len(away) == 2 else ''}"
            )
        return f"{pick(side, 'z')}, {', '.join(said)}"
    if len(signs) == 3:
        return f"{pick(side, 'z')}, {pick(towards, 'y')}-{pick(towards, 'x')} corner"
    (main, _), (toward, _) = signs
    return f"{pick(side, main)}, towards the {pick(towards, toward)}"


def compass_tables() -> dict:
    """The compass page's faces (app/calibration/magnetometer/coverage.py) and thresholds."""
    return {
        "faceCentres": compass.FACE_CENTRES.round(12).tolist(),
        "faceNames": list(compass.FACE_NAMES),
        "faceWords": {source: [face_words(n, source) for n in compass.FACE_NAMES] for source in SOURCES},
        "vertices": compass.ICOSAHEDRON_VERTICES.round(12).tolist(),
        "faces": compass.ICOSAHEDRON_FACES.tolist(),
        "coverageToSolve": COVERAGE_TO_SOLVE,
        "minReadings": COMPASS_MIN_READINGS,
        "frequencyHz": COMPASS_FREQUENCY_HZ,
    }


SENSOR_TITLES = {sensor: words.capitalize() for sensor, words in SENSOR_WORDS.items()}
"""Each sensor's word as a heading or a menu's label (``Accelerometer``), from the core's words."""


def unit_tables() -> dict:
    """The start page's unit menus: each sensor's units in words (its name: ``sensorWords``), and the chips
    (app.io.readers.chips) that turn its counts into a physical unit, by sensor, with their datasheet scale in
    words."""
    return {
        "units": {s: [[u, UNIT_WORDS[u]] for u in units] for s, units in UNITS_IN.items()},
        "chips": {s: [[c.name, c.label] for c in CHIPS.values() if c.sensor == s] for s in UNITS_IN},
    }


POSE_SHORT = {
    "+z": "screen up",
    "-z": "screen down",
    "+y": "standing",
    "-y": "upside down",
    "+x": "left edge down",
    "-x": "right edge down",
}
"""Each of the six poses in two or three words, under its thumbnail (the axis code is a grey note)."""

SOURCES: dict[str, dict[str, Any]] = {
    "phone": {
        "noun": "phone",
        "title": "Calibrate this phone",
        "compassTitle": "Calibrate this phone's compass",
        "sides": ["screen side", "back side"],
        "ups": ["screen up", "screen down"],
        "axes": "x to the phone's right edge, y to its top edge, z out of the screen",
        "poseNames": dict(POSE_NAMES),
        "poseShort": POSE_SHORT,
    },
    "board": {
        "noun": "board",
        "title": "Calibrate this board",
        "compassTitle": "Calibrate this board's compass",
        "sides": ["component side", "underside"],
        "ups": ["component side up", "underside up"],
        "axes": "x and y along the arrows printed on the board (its silkscreen), z out of its component side",
        # A board: its printed X and Y arrows (the sensor's axes, as breakout boards mark them) and its
        # component side (z out of it).
        "poseNames": {
            "+z": "flat, component side up",
            "-z": "flat, component side down",
            "+y": "on an edge, its Y arrow pointing up",
            "-y": "on an edge, its Y arrow pointing down",
            "+x": "on an edge, its X arrow pointing up",
            "-x": "on an edge, its X arrow pointing down",
        },
        "poseShort": {
            "+z": "components up",
            "-z": "components down",
            "+y": "Y arrow up",
            "-y": "Y arrow down",
            "+x": "X arrow up",
            "-x": "X arrow down",
        },
    },
}
"""The words of each sensor source the wizard pages take (``/wizard?source=phone|board``): the
templates read them, and the page's scripts read them from :func:`page_tables` (``sources``)."""


@lru_cache(maxsize=1)
def page_tables() -> dict:
    """Everything the pages take from the server's constants, as plain JSON-ready data.

    Returns
    -------
    dict
        ``gravity`` (m/s²); ``poses`` (``order``, ``up`` vectors, ``names``); ``capture`` (the
        capture machine's options); ``flightLog`` (the least temperature span a flight log needs for the
        temperature method); ``free`` (the free flow's
        angle to an axis, any; its least angle between poses, the poses it fits from and those its target needs);
        ``cube24`` (the 23
        ``rotations``, the 24 ``ups``, the integer ``attitudes`` R_k, sensor → calibration frame,
        the ``turnWords`` the server's refusals use and the flow's face angle ``maxAngleDeg``);
        ``compass`` (:func:`compass_tables`);
        ``uses`` (app.web.uses: the file for each use of a calibration and how to apply it);
        ``units`` (:func:`unit_tables`: the start page's unit and chip menus per sensor); ``board``
        (:func:`app.io.board.formats.board_tables`: the lines boards print, baud rates, the Nordic UART);
        ``sketches`` (:func:`app.web.sketches.sketch_table`: what a maker flashes, its baud rate and file);
        ``methods`` (each method in words, from the method table, app.methods); ``metrics``
        (app.web.metric_words: each figure's name, unit and meaning); ``sensorWords`` (:data:`SENSOR_TITLES`);
        ``unitWords`` (app.words: each unit as a person reads it) and ``asFitted`` (by model type, how the
        model as fitted relates to its correction: the result classes' ``AS_FITTED``); ``kinds`` (by model
        type, what the result page shows of a result and which drawing draws it: the result classes' ``PAGE``);
        ``checkVerdicts`` (a check's verdicts in words: app.calibration.check).
    """
    protocol = cube24()
    attitudes = np.rint(protocol.attitudes).astype(int) + 0  # quarter turns: exact integers
    return {
        "gravity": STANDARD_GRAVITY,
        "poses": {
            "order": list(CANONICAL_SIX),
            "asked": list(capture_rules.SIX_ASKED_ORDER),
            "up": {label: [int(v) for v in UP_VECTORS[label]] for label in CANONICAL_SIX},
            "names": {label: POSE_NAMES[label] for label in CANONICAL_SIX},
            "short": {label: POSE_SHORT[label] for label in CANONICAL_SIX},
        },
        "capture": capture_rules.capture_thresholds(),
        "flightLog": {"temperatureMinSpanC": TEMPERATURE_MIN_SPAN_C},
        "free": {
            "maxAngleDeg": capture_rules.FREE_MAX_ANGLE_DEG,
            "minAngleDeg": capture_rules.FREE_MIN_ANGLE_DEG,
            "fitFrom": capture_rules.FREE_FIT_FROM,
            "targetPoses": capture_rules.FREE_TARGET_MIN_POSES,
        },
        "cube24": {
            "rotations": list(CUBE24_ROTATIONS),
            "ups": list(protocol.ups),
            "attitudes": attitudes.tolist(),
            "turnWords": dict(TURN_WORDS),
            "maxAngleDeg": capture_rules.PAGE_CUBE_FACE_MAX_ANGLE_DEG,
        },
        "compass": compass_tables(),
        "uses": uses_table(),
        "units": unit_tables(),
        "board": board_tables(),
        "sketches": sketch_table(),
        "methods": {method.name: method.words for method in METHOD_TABLE},
        "calibrationWords": {method.name: method.page_words for method in METHOD_TABLE},
        "recordingMethods": [method.name for method in METHOD_TABLE if "recording_id" in method.request.model_fields],
        "metrics": {key: list(words) for key, words in METRICS.items()},
        "sensorWords": dict(SENSOR_TITLES),
        "unitWords": dict(UNIT_WORDS),
        "asFitted": as_fitted_words(),
        "kinds": page_kinds(),
        "sources": SOURCES,
        "checkVerdicts": dict(CHECK_VERDICT_WORDS),
    }
