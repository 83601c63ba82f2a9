"""The line a person reads first about a calibration, and the note under its verdict: by result class.

The core's results hold the figures (their metrics); how they are told is said here, once per result class
(:data:`HEADLINES`, :data:`VERDICT_NOTES`, by the class's name; a class without an entry has its nearest base's). The
cross-validated error (each reading calibrated by the fit made without it) comes first, labelled as what to
expect; the in-sample error of the fitted readings beside it, labelled as such, since it flatters every fit
(zero for an exact one). The headline is computed once, from the final result, where its plain form is made
(app.workflows.calibration) and by the verdict (app.verdict).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from app.calibration.shared.angles import compass_inclination, degrees_text, heading_error_deg, tilt_error_deg
from app.calibration.shared.headlines import FIGURE_WORDS, SENSOR_WORDS, TEMPERATURE_SENSORS
from app.calibration.shared.result import CalibrationResult, Figure, StillReadingsResult, by_class_name

if TYPE_CHECKING:  # the methods' classes are named, not imported: a command loads only its own method's models
    from app.calibration.autocal import AutoCalibration
    from app.calibration.imported import ImportedCalibration
    from app.calibration.magnetometer.flight_calibration import FlightCompassCalibration
    from app.calibration.magnetometer.result import MagnetometerResult
    from app.calibration.temperature import TemperatureResult


def _mg(value: float | None) -> str:
    return "n/a" if value is None else f"{value:.2f} mg"


def accelerometer_headline(metrics: dict[str, Any], *, held_out: bool) -> str:
    """``metrics`` of an accelerometer calibration in one line: new orientations first (and the tilt it can
    give a level, app.calibration.angles), in-sample and raw beside.

    ``held_out``: its ``error_*_mg`` are control points held out of the fit (autocal's), not the fitted
    readings.
    """
    scheme = metrics.get("cv_scheme")
    if metrics.get("cv_error_mg") is not None:
        first = (
            f"on new orientations expect {_mg(metrics['cv_error_mg'])} of g, a level off by "
            f"{degrees_text(tilt_error_deg(metrics['cv_error_mg']))} at most "
            f"(up to {_mg(metrics.get('cv_error_max_mg'))}; {scheme})"
        )
    else:
        first = metrics.get("cv_note") or "no figure for new orientations"
    if metrics.get("error_after_mg") is None:
        return str(first)
    which = "on the control points (held out)" if held_out else "on the poses fitted (in-sample)"
    return f"{first}; {which} {_mg(metrics['error_after_mg'])}, raw {_mg(metrics.get('error_before_mg'))}"


def compass_headline(metrics: dict[str, Any], label: str = "µT") -> str:
    """A compass calibration's line: the error of |h| on directions left out (and the heading error it can
    give at the field's inclination, app.calibration.angles), then in-sample and raw;
    ``label`` is ``counts`` for a magnetometer left in counts (its ``_ut`` figures are then counts)."""

    def ut(value: float | None) -> str:
        return "n/a" if value is None else f"{value:.2f} {label}"

    if metrics.get("cv_error_ut") is not None:
        inclination, _ = compass_inclination(metrics)
        heading = degrees_text(heading_error_deg(metrics["cv_error_ut"], metrics["field_ut"], inclination))
        first = (
            f"on new directions expect {ut(metrics['cv_error_ut'])} of the {metrics['field_ut']:.1f} {label} field, "
            f"a heading off by {heading} at most at a dip of {abs(inclination):.0f}° "
            f"(up to {ut(metrics.get('cv_error_max_ut'))}; {metrics.get('cv_scheme')})"
        )
    else:
        first = metrics.get("cv_note") or "no figure for new directions"
    raw = "" if metrics.get("raw_error_ut") is None else f", raw {ut(metrics['raw_error_ut'])}"
    return f"{first}; on the readings fitted (in-sample) {ut(metrics.get('fit_error_ut'))}{raw}"


def amount(value: float, unit: str) -> str:
    """A drift in mg or °/s with three significant figures, the unit after a no-break space."""
    return f"{value:.3g}\u00a0{FIGURE_WORDS.get(unit, unit)}"


def temperature_headline(model: dict[str, Any], metrics: dict[str, Any]) -> str:
    """A temperature calibration's line: the offset drift over the range raw, then on bands left out.

    ``offset drift over 15–55 °C: accelerometer 13.7 mg → 0.83 mg, gyroscope 0.226 °/s → 0.0175 °/s
    on bands of temperature left out (largest axis)``.
    """
    sensors = [s for s in TEMPERATURE_SENSORS if s in metrics]
    if not sensors:
        return "no temperature model"
    lo = min(model[s]["t_min_c"] for s in sensors)
    hi = max(model[s]["t_max_c"] for s in sensors)
    parts = [
        f"{SENSOR_WORDS[s]} {amount(metrics[s]['drift_raw_max'], metrics[s]['unit'])} → "
        f"{amount(metrics[s]['drift_cv_max'], metrics[s]['unit'])}"
        for s in sensors
    ]
    return (
        f"offset drift over {lo:.0f}–{hi:.0f} °C: {', '.join(parts)} on bands of temperature left out "
        "(largest axis, peak to peak)"
    )


def _still_readings(result: StillReadingsResult) -> str | None:
    """Its error on new orientations, then in-sample and raw (every fit of still readings reports a
    cross-validated error, ``cv_error_mg``, or says why it has none)."""
    if "cv_error_mg" not in result.metrics:
        return None
    return accelerometer_headline(result.metrics, held_out=False)


def _autocal(result: AutoCalibration) -> str | None:
    """Its error on new orientations, then on its control points (held out) and raw."""
    if "cv_error_mg" not in result.metrics:
        return None
    return accelerometer_headline(result.metrics, held_out=True)


def _compass(result: MagnetometerResult) -> str | None:
    """The error of |h| on directions left out, then in-sample and raw."""
    from app.calibration.magnetometer.result import figure_unit  # loaded with the result being told

    if "cv_error_ut" not in result.metrics:
        return None
    return compass_headline(result.metrics, figure_unit(result.output_unit))


def _flight_compass(result: FlightCompassCalibration) -> str | None:
    """The heading error on segments left out and its 95th percentile, then the firmware's."""
    m = result.metrics
    if m.get("heading_error_after_deg") is None:
        return None
    line = (
        f"on flight segments left out expect a heading error of {m['heading_error_after_deg']:.1f}° rms "
        f"(95 % within {m['heading_error_after_p95_deg']:.1f}°)"
    )
    if m.get("heading_error_before_deg") is not None:
        line += (
            f"; with the firmware's own calibration {m['heading_error_before_deg']:.1f}° rms "
            f"(95 % within {m['heading_error_before_p95_deg']:.1f}°)"
        )
    return line


def _temperature(result: TemperatureResult) -> str | None:
    """The offset drift over the range raw, then on bands left out, per sensor."""
    return temperature_headline(result.model_dict(), result.metrics)


def _imported(result: ImportedCalibration) -> str | None:
    """What was read, from which firmware and file: an imported calibration has no error to tell."""
    sensors = ", ".join(SENSOR_WORDS[s] for s in result.corrected_sensors())
    version = f" {result.version}" if result.version else ""
    return f"imported from {result.firmware}{version} ({result.file_kind}): {sensors}; read, not fitted"


def _none(result: CalibrationResult) -> str | None:
    """No line: a result without a figure to tell first (a cube's, a noise characterisation's)."""
    return None


HEADLINES: dict[str, Callable[[Any], str | None]] = {
    CalibrationResult.__name__: _none,
    StillReadingsResult.__name__: _still_readings,
    "AutoCalibration": _autocal,
    "MagnetometerResult": _compass,
    "FlightCompassCalibration": _flight_compass,
    "TemperatureResult": _temperature,
    "ImportedCalibration": _imported,
}
"""By result class (its name: the methods' modules are not imported here, and a test holds every name to a class
of the core's registry), how its headline is told from it."""


def _six_poses(method: str | None, figure: Figure) -> str:
    """Six poses' figure is in-sample: say so, and how to measure the error on new orientations."""
    if method == "six_position" and figure.before is not None:
        return (
            "Six poses leave none out to test on: the figure is on the poses fitted. A free session "
            "measures the error on new orientations."
        )
    return ""


def _no_note(method: str | None, figure: Figure) -> str:
    return ""


def _imported_note(method: str | None, figure: Figure) -> str:
    return (
        "It is the device's own calibration, read from its firmware's parameters, not measured: its numbers are "
        "within the firmware's ranges. Whether it still holds, a check on a new recording of the device tells."
    )


VERDICT_NOTES: dict[str, Callable[[str | None, Figure], str]] = {
    CalibrationResult.__name__: _no_note,
    "ImportedCalibration": _imported_note,
    "AffineCalibration": _six_poses,
}
"""By result class, the line under an "apply it" verdict on its figure, where the figure needs one."""


def headline(result: CalibrationResult) -> str | None:
    """The line a person reads first about a result's figures, or None where it has none."""
    return by_class_name(HEADLINES, type(result))(result)


def verdict_note(cls: type[CalibrationResult], method: str | None, figure: Figure) -> str:
    """One line more under an "apply it" verdict on ``figure`` of a result of class ``cls``, or ""."""
    return by_class_name(VERDICT_NOTES, cls)(method, figure)
