"""What the page shows of a calibration, by its result's class: the presenter of the core's results for the page.

The core's results hold numbers, units and reasons; how a page draws one of them — its set of uses, its
model's drawing, its plot and the box it goes in — is said here, once per result class (:data:`PAGE_FACTS`),
and sent by model type in the page's tables (``kinds``: :func:`page_kinds`), which static/js/result_kinds.js
draws. A class without an entry has its nearest base's facts.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

from app.calibration.noise.characterise import TERM_WORDS
from app.calibration.registry import registered_classes
from app.calibration.shared.result import FIGURES, CalibrationResult, by_class_name


@dataclass(frozen=True)
class PageFacts:
    """What the page shows of a result of one class; whether it has a correction to apply comes from the
    class's :attr:`~app.calibration.shared.result.CalibrationResult.KIND`."""

    uses: str = "calibration"
    """The set of uses and export formats it offers (app/web/uses.py ``USE_SETS``)."""
    snippets: bool = True
    """Paste-ready lines of its correction under its file (``GET …/{id}/use``)."""
    heading: str = "The model as fitted"
    model: str = "parameters"
    """The drawing of its model: ``parameters`` (each parameter a small table) or ``noiseTerms``."""
    terms: tuple[tuple[str, str], ...] = ()
    """``noiseTerms``: the rows of each sensor's table, each a key of the model and its words."""
    norms: str = ""
    """The drawing of its norms per position: ``readings`` (labelled readings), ``captures`` (a session's
    poses), ``positions`` (a cube's captures, calibrated by the server); empty: none."""
    spheres: bool = False
    """The compass's raw and calibrated readings on the field's sphere."""
    plot: str = ""
    """The export format of the figure the server draws for it, shown in the page's box ``box``."""
    box: str = ""
    caption: str = ""
    """The drawing of the plot's caption (``flight``: what a flight's compass calibration found)."""
    firmware_uses: bool = False
    """Whether it offers only the uses of the firmware whose log it came from (and the JSON)."""
    live_check: bool = False
    """Whether a live turn on the compass page checks it (``/wizard?protocol=compass&check=ID``: a compass's
    calibration from a turn, which the same device's next turn checks; POST …/check with ``mag``)."""
    packet: tuple[str, ...] = ("acc",)
    """The parts of a board's calibration packet it holds, by sensor: ``acc`` (the accelerometer's and
    gyroscope's offsets), ``mag`` (the compass's hard iron, soft iron and field); a model with a magnetometer's
    part (a cube's) holds the compass's too."""


PAGE_FACTS: dict[str, PageFacts] = {
    CalibrationResult.__name__: PageFacts(),
    "AffineCalibration": PageFacts(norms="readings"),
    "TriangularCalibration": PageFacts(norms="captures"),
    "AutoCalibration": PageFacts(norms="captures"),  # its model is a triangular one
    "CubeCalibration": PageFacts(norms="positions"),
    "MagnetometerResult": PageFacts(uses="compassCalibration", spheres=True, live_check=True, packet=("mag",)),
    "ImportedCalibration": PageFacts(heading="The firmware's numbers, as read (f = M (m − o) per sensor)"),
    "FlightCompassCalibration": PageFacts(
        uses="flightCompass",
        snippets=False,
        heading="The compass's model, h = M (Q m − b − k p)",
        plot="flight_svg",
        box="#result-flight",
        caption="flight",
        firmware_uses=True,  # its numbers are in the frames of the firmware whose log it came from
    ),
    "TemperatureResult": PageFacts(
        uses="thermalCompensation",
        snippets=False,
        heading="Each axis's offset polynomial",
        plot="temperature_svg",
        box="#result-temperature",
    ),
    "NoiseResult": PageFacts(
        uses="noiseFigures",
        snippets=False,
        heading="The noise terms",
        model="noiseTerms",
        terms=tuple(TERM_WORDS.items()),
        plot="allan_svg",
        box="#result-allan",
    ),
}
"""By result class (its name, as :data:`app.headlines.HEADLINES` keys its lines: a test holds every name to a class
of the core's registry), what the page shows of it."""


def page_facts(cls: type[CalibrationResult]) -> PageFacts:
    """The page's facts of a result class: its own entry of :data:`PAGE_FACTS`, else its nearest base's."""
    return by_class_name(PAGE_FACTS, cls)


def page_kinds() -> dict[str, dict[str, Any]]:
    """By model type, what the page shows of a result (:class:`PageFacts`, and ``correction``: whether it has
    a correction to apply); results that share a model type (autocal's triangular model) share their facts.
    The key ``""`` holds the base class's: a correction's, for a body whose model type is not known."""
    classes: list[type[CalibrationResult]] = [CalibrationResult, *registered_classes()]
    return {
        cls.MODEL_TYPE: {**dataclasses.asdict(page_facts(cls)), "correction": cls.KIND != FIGURES} for cls in classes
    }
