"""Whether to apply a calibration, in the words a person reads first.

A calibration is worth applying when it makes the sensor better on readings the fit did not see,
by enough to matter. The verdict says so in one sentence with the figure it stands on (``Apply it:
error on new orientations 36.0 mg → 1.4 mg``), or says why not. It never says "apply" when its own
figure grew, whatever the gates said: ``ok`` true on a calibration that makes the sensor worse would
be a bug elsewhere, and the verdict does not pass it on.

The figure is the most honest one the calibration has; the result decides which
(:meth:`app.calibration.shared.result.CalibrationResult.figure`, each class in its own order):

1. readings the request held out (``holdout_*``), or autocal's control points, held out of its fit;
2. the cross-validated error (each reading calibrated by the fit made without it), against the same
   readings raw — a reading's raw error does not depend on the fit;
3. the in-sample error of the fitted readings, named as such (six poses leave none out to test
   on; a cube's 24 positions are fitted with their known attitudes).

Decisions (written here because no paper makes them): a calibration must cut the error by at least
:data:`MIN_GAIN_FRACTION` and by :data:`MIN_GAIN_MG` (:data:`MIN_GAIN_UT` for a compass) to be worth
applying; below that it is "no need": the sensor is already as good as the calibration can tell.
"""

from __future__ import annotations

from app.calibration import registry
from app.calibration.noise.characterise import TERM_WORDS, duration_words
from app.calibration.shared.angles import figure_degrees
from app.calibration.shared.errors import CalibrationError
from app.calibration.shared.headlines import SENSOR_WORDS
from app.calibration.shared.result import CORRECTION, DRIFT, FIGURES, NO_FIGURE, CalibrationResult
from app.headlines import headline, verdict_note

MIN_GAIN_FRACTION = 0.2
"""The calibrated error must be at most 80 % of the raw one."""

MIN_GAIN_MG = 0.5
"""…and smaller by 0.5 mg of g: five times the averaging noise of a few-second still reading of a phone
(app.calibration.still.trust.NORM_GROWTH_TOLERANCE_MG)."""

MIN_GAIN_UT = 0.5
"""The compass's: 0.5 µT, about 1 % of the Earth's field and a quarter of a degree of heading at most."""

MIN_GAIN_DEG = 0.5
"""A compass calibrated from a flight, by its heading error: half a degree, below what a pilot or a
position controller notices, and about the spread of one flight's heading error from segment to segment."""

MIN_GAIN = {"µT": MIN_GAIN_UT, "°": MIN_GAIN_DEG}
"""The least gain worth applying by the figure's unit where it is not :data:`MIN_GAIN_MG` (mg, and counts)."""


def _amount(value: float, unit: str) -> str:
    """``36.0 mg``, ``1.40 mg``: three significant figures or so, the unit after a no-break space (a
    figure never wraps away from its unit)."""
    gap = "" if unit == "°" else "\u00a0"  # an angle's degree sign follows its number (SI Brochure, 5.4.3)
    return f"{value:.1f}{gap}{unit}" if value >= 10 else f"{value:.2f}{gap}{unit}"


def _short_reason(reasons: list[str]) -> str:
    """The first reason, which says what to do (the others are in the details)."""
    first = (reasons or ["it failed its checks"])[0]
    return first[0].upper() + first[1:]


def rebuilt(body: dict) -> CalibrationResult | None:
    """The result a stored body rebuilds (:func:`app.calibration.registry.from_dict`, the body's metrics as stored),
    or None for a body cut short (no model: written by hand, or by a client), whose class still answers."""
    try:
        return registry.from_dict(body)
    except (CalibrationError, LookupError, TypeError, ValueError):
        return None


def verdict(body: dict, result: CalibrationResult | None = None) -> dict:
    """The verdict on a calibration: whether to apply it, in words, and the figure it stands on.

    Parameters
    ----------
    body : dict
        A stored calibration (``ok``, ``reasons``, ``metrics``, ``model``, ``method``).
    result : CalibrationResult, optional
        The result ``body`` rebuilds, where the caller has it; rebuilt here otherwise.

    Returns
    -------
    dict
        ``apply`` (offer its files to a device), ``kind`` (``apply``, ``no_gain``, ``worse``, ``failed``,
        or ``figures`` for a noise characterisation, which corrects nothing), ``words`` (the sentence),
        ``why`` (one line more), and ``before``, ``after``, ``unit``, ``basis`` of its figure (null
        where it has none), and ``degrees``: the figure as a level's tilt or a compass's heading error
        (app.calibration.shared.angles.figure_degrees; null for a figure that is no error of gravity or of the field).

    The result decides what it stands on: its kind (:attr:`CalibrationResult.KIND`), its figures
    (:meth:`CalibrationResult.figures`), its headline and the note under its figure. A body cut short
    (no model) is judged by its class on its metrics.
    """
    result = rebuilt(body) if result is None else result
    if result is not None:
        cls, figures, line = type(result), result.figures(), headline(result)
        ok, reasons = result.ok, list(result.reasons)
    else:
        try:
            cls = registry.class_of(body)
        except CalibrationError:
            cls = CalibrationResult
        figures, line = cls.figures_from(body.get("metrics") or {}, body.get("output_unit")), body.get("headline")
        ok, reasons = bool(body.get("ok")), list(body.get("reasons") or [])
    return _VERDICTS[cls.KIND](cls, body.get("method"), figures, line, ok, reasons, body.get("metrics") or {})


def _figures_verdict(cls, method, figures, line, ok: bool, reasons: list[str], metrics: dict) -> dict:
    """A noise characterisation corrects nothing: its figures are for a filter. Where a filter's noise model
    lacks one of them (a sensor not recorded, a random walk a short rest does not show), it says what is missing
    and how long to record; what was measured is still offered (the JSON, the CSV, the plot)."""
    if not ok:
        return _out(
            False, "failed", "Don't use these figures: the noise could not be characterised.", _short_reason(reasons)
        )
    gaps = cls.filter_gaps(metrics)
    if not gaps:
        return _out(
            True,
            "figures",
            "Use these figures in your filter: the sensors' noise is characterised.",
            "White noise, random walk and bias instability per axis (IEEE Std 952), for a Kalman filter's noise model.",
        )
    return _out(
        True,
        "figures",
        f"Not enough for a filter yet: {_gaps_words(gaps)}.",
        f"A filter's noise model (Kalibr, OpenVINS, VINS-Fusion) takes the {FILTER_NEEDS}. The figures measured are "
        "in the JSON and CSV files and the Allan plot.",
    )


FILTER_NEEDS = "accelerometer's and the gyroscope's white noise and random walk"


def _gaps_words(gaps) -> str:
    """What a filter lacks, its cause first and what to record second: "the gyroscope's random walk did not show
    in this rest — record the device still for 27 s"."""
    missing = [SENSOR_WORDS.get(g.sensor, g.sensor) for g in gaps if g.term is None]
    unseen: dict[str, list[str]] = {}
    for g in gaps:
        if g.term is not None:
            unseen.setdefault(SENSOR_WORDS.get(g.sensor, g.sensor), []).append(TERM_WORDS.get(g.term, g.term))
    causes = [f"the recording has no {' and no '.join(missing)}"] if missing else []
    if unseen:
        terms = " and ".join(f"the {sensor}'s {' and '.join(words)}" for sensor, words in unseen.items())
        causes.append(f"{terms} did not show in this rest")
    records = [g.record_s for g in gaps if g.record_s is not None]
    remedies = ["record the accelerometer and the gyroscope together"] if missing else []
    if records:
        remedies.append(f"record the device still for {duration_words(max(records))}")
    elif unseen:
        remedies.append("sample faster, or check that the readings are not filtered or rounded")
    return f"{'; '.join(causes)} — {', and '.join(remedies)}"


def _correction_verdict(cls, method, figures, line, ok: bool, reasons: list[str], metrics: dict) -> dict:
    """A correction: its one figure, the most honest it has (the result's order), and what it means as an angle
    (app.calibration.shared.angles.figure_degrees): a level's tilt for an accelerometer, a heading for a compass."""
    figure = figures[0] if figures else NO_FIGURE
    before, after, unit, basis = figure.before, figure.after, figure.unit, figure.basis
    change = (
        ""
        if after is None
        else f"{basis} {_amount(before, unit)} → {_amount(after, unit)}"
        if before is not None
        else f"{basis} {_amount(after, unit)}"
    )
    degrees = figure_degrees(before, after, unit, metrics)
    figures_out = dict(before=before, after=after, unit=unit or None, basis=basis or None, degrees=degrees)
    told = f"{change}; {degrees['words']}" if degrees and change else change
    if figure.grew:
        return _out(
            False,
            "worse",
            f"Don't apply it: your sensor is already better than this ({told}).",
            (
                "It would make your sensor worse; keep it as it is. " + (_short_reason(reasons) if reasons else "")
            ).strip(),
            **figures_out,
        )
    if not ok:
        return _out(
            False, "failed", "Don't apply it: the calibration failed its checks.", _short_reason(reasons), **figures_out
        )
    if (
        before is not None
        and after is not None
        and (after > (1.0 - MIN_GAIN_FRACTION) * before or before - after < MIN_GAIN.get(unit, MIN_GAIN_MG))
    ):
        return _out(
            False,
            "no_gain",
            f"No need to apply it: it changes too little to matter ({told}).",
            "Your sensor is about as good without it; keep it as it is.",
            **figures_out,
        )
    words = (
        f"Apply it: {change} ({degrees['words']})."
        if degrees and change
        else (f"Apply it: {change}." if change else "Apply it: it passed every check.")
    )
    why = verdict_note(cls, method, figure) or ("It passed every check." if change else "")
    return _out(True, "apply", words, why, **figures_out)


def _drift_verdict(cls, method, figures, line, ok: bool, reasons: list[str], metrics: dict) -> dict:
    """A temperature calibration: its offset drift over the range, raw against bands of temperature left out
    (each predicted by the fit made without it), the accelerometer's in mg first, else the gyroscope's in °/s;
    worse when any sensor's drift grew, no gain when none shrank enough. The accelerometer's drift is also told
    as the tilt it gives a level (app.calibration.shared.angles.figure_degrees)."""
    if not figures:
        return _out(
            False, "failed", "Don't apply it: the calibration has no temperature model.", _short_reason(reasons)
        )
    first = figures[0]
    degrees = next((d for f in figures if (d := figure_degrees(f.before, f.after, f.unit, metrics))), None)
    change = f"{line}; {degrees['words']}" if line and degrees else (line or "")
    figures_out = dict(before=first.before, after=first.after, unit=first.unit, basis=first.basis, degrees=degrees)
    if any(f.grew for f in figures):
        return _out(
            False,
            "worse",
            f"Don't apply it: the drift would grow ({change}).",
            (
                "It would make your sensor worse; keep its temperature calibration off. "
                + (_short_reason(reasons) if reasons else "")
            ).strip(),
            **figures_out,
        )
    if not ok:
        return _out(
            False, "failed", "Don't apply it: the calibration failed its checks.", _short_reason(reasons), **figures_out
        )
    if all(f.after > (1.0 - MIN_GAIN_FRACTION) * f.before for f in figures):
        return _out(
            False,
            "no_gain",
            f"No need to apply it: it changes too little to matter ({change}).",
            "Your sensor drifts about as little without it; keep it as it is.",
            **figures_out,
        )
    return _out(
        True,
        "apply",
        f"Apply it: {change}.",
        "Each band of temperature was predicted by the fit made without it: the figure is what to expect "
        "between the temperatures recorded.",
        **figures_out,
    )


_VERDICTS = {CORRECTION: _correction_verdict, FIGURES: _figures_verdict, DRIFT: _drift_verdict}
"""The verdict of each kind of result (:attr:`CalibrationResult.KIND`)."""


def with_verdict(body: dict) -> dict:
    """The body with its verdict: calibrations stored before verdicts existed get theirs on reading."""
    return body if "verdict" in body else {**body, "verdict": verdict(body)}


def _out(
    apply: bool, kind: str, words: str, why: str, *, before=None, after=None, unit=None, basis=None, degrees=None
) -> dict:
    return {
        "apply": apply,
        "kind": kind,
        "words": words,
        "why": why,
        "before": before,
        "after": after,
        "unit": unit,
        "basis": basis,
        "degrees": degrees,
    }
