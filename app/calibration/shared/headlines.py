"""The line a person reads first about a calibration: what to expect on new orientations.

The cross-validated error (each reading calibrated by the fit made without it) comes first, labelled
as what to expect; the in-sample error of the fitted readings beside it, labelled as such, since it
flatters every fit (zero for an exact one). Each result class chooses its line
(:meth:`app.calibration.shared.result.CalibrationResult.headline`); these functions write it.
"""

from __future__ import annotations

from .angles import compass_inclination, degrees_text, heading_error_deg, tilt_error_deg


def _mg(value) -> str:
    return "n/a" if value is None else f"{value:.2f} mg"


def accelerometer_headline(metrics: dict, *, held_out: bool) -> str:
    """``metrics`` of an accelerometer calibration in one line: new orientations first (and the tilt it can
    give a level, app.calibration.shared.angles), in-sample and raw beside.

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
        return first
    which = "on the control points (held out)" if held_out else "on the poses fitted (in-sample)"
    return f"{first}; {which} {_mg(metrics['error_after_mg'])}, raw {_mg(metrics.get('error_before_mg'))}"


def compass_headline(metrics: dict, label: str = "µT") -> str:
    """A compass calibration's line: the error of |h| on directions left out (and the heading error it can
    give at the field's inclination, app.calibration.shared.angles), then in-sample and raw;
    ``label`` is ``counts`` for a magnetometer left in counts (its ``_ut`` figures are then counts)."""

    def ut(value) -> str:
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


SENSOR_WORDS = {"acc": "accelerometer", "gyr": "gyroscope", "mag": "magnetometer"}
TEMPERATURE_SENSORS = ("acc", "gyr")
"""The sensors a temperature calibration models, in the order its figures are told."""
FIGURE_WORDS = {"mg": "mg", "deg/s": "°/s"}


def amount(value: float, unit: str) -> str:
    """A drift in mg or °/s with three significant figures, the unit after a no-break space."""
    return f"{value:.3g}\u00a0{FIGURE_WORDS.get(unit, unit)}"


def temperature_headline(model: dict, metrics: dict) -> str:
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
