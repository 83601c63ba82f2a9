"""Whether to apply a calibration, in the words a person reads first.

A calibration is worth applying when it makes the sensor better on readings the fit did not see,
by enough to matter. The verdict says so in one sentence with the figure it stands on (``Apply it:
error on new orientations 36.0 mg → 1.4 mg``), or says why not. It never says "apply" when its own
figure grew, whatever the gates said: ``ok`` true on a calibration that makes the sensor worse would
be a bug elsewhere, and the verdict does not pass it on.

The figure is the most honest one the calibration has, in this order:

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

import numpy as np

from app.calibration.norm_metrics import norm_errors

MIN_GAIN_FRACTION = 0.2
"""The calibrated error must be at most 80 % of the raw one."""

MIN_GAIN_MG = 0.5
"""…and smaller by 0.5 mg of g: five times the averaging noise of a few-second still reading of a phone
(app.calibration.trust.NORM_GROWTH_TOLERANCE_MG)."""

MIN_GAIN_UT = 0.5
"""The compass's: 0.5 µT, about 1 % of the Earth's field and a quarter of a degree of heading at most."""


def figure_unit(body: dict) -> str:
    """The unit of a compass calibration's figures: µT, or counts for a magnetometer left in counts
    (no chip, no field given: its ``_ut`` metrics are then in counts)."""
    return "counts" if body.get("output_unit") == "raw" else "µT"


def _figure(body: dict) -> tuple[float | None, float | None, str, str]:
    """``(before, after, unit, basis)`` of a calibration: its most honest error figure."""
    m = body.get("metrics") or {}
    if "cv_error_ut" in m:  # the compass: |h| against the field on directions left out
        unit = figure_unit(body)
        if m.get("cv_error_ut") is not None:
            return m.get("raw_error_ut"), m["cv_error_ut"], unit, "error of the field strength on new directions"
        return m.get("raw_error_ut"), m.get("fit_error_ut"), unit, "error of the field strength on the readings fitted"
    if m.get("holdout_error_after_mg") is not None:
        return m.get("holdout_error_before_mg"), m["holdout_error_after_mg"], "mg", "error on the readings you held out"
    if "count_control" in m and m.get("error_after_mg") is not None:
        return m.get("error_before_mg"), m["error_after_mg"], "mg", "error on control points held out of the fit"
    if m.get("cv_error_mg") is not None:
        return m.get("error_before_mg"), m["cv_error_mg"], "mg", "error on new orientations"
    if m.get("error_after_mg") is not None:
        poses = f"{m['count']} poses" if m.get("count") else "poses"
        return m.get("error_before_mg"), m["error_after_mg"], "mg", f"error on the {poses} fitted"
    if (body.get("model") or {}).get("type") == "cube":
        return _cube_figure(body)
    return None, None, "", ""


def _cube_figure(body: dict) -> tuple[float | None, float | None, str, str]:
    """The cube's accelerometer: mean | |m| − g | of its positions raw, and of S⁻¹ (m − b) (Särkkä et al.,
    IEEE Sensors Journal 17(11) 2017, eq. (1)), in mg of g: in-sample, the positions are fitted."""
    acc = (body.get("details") or {}).get("acc") or {}
    model = (body.get("model") or {}).get("acc")
    positions = acc.get("positions") or []
    if not model or not positions:
        return None, None, "", ""
    means = np.array([p["mean"] for p in positions], dtype=float)
    S, b = np.asarray(model["S"], dtype=float), np.asarray(model["b"], dtype=float)
    g = float(body.get("gravity") or np.mean(np.linalg.norm(means, axis=1)))
    errors = norm_errors(means, lambda m: np.linalg.solve(S, (m - b).T).T, g)
    return (errors["error_before_mg"], errors["error_after_mg"], "mg",
            f"accelerometer error on the {len(means)} positions fitted")


def _amount(value: float, unit: str) -> str:
    """``36.0 mg``, ``1.40 mg``: three significant figures or so, the unit after a no-break space (a
    figure never wraps away from its unit)."""
    return f"{value:.1f}\u00a0{unit}" if value >= 10 else f"{value:.2f}\u00a0{unit}"


def _short_reason(reasons: list[str]) -> str:
    """The first reason, which says what to do (the others are in the details)."""
    first = (reasons or ["it failed its checks"])[0]
    return first[0].upper() + first[1:]


def verdict(body: dict) -> dict:
    """The verdict on a calibration: whether to apply it, in words, and the figure it stands on.

    Parameters
    ----------
    body : dict
        A stored calibration (``ok``, ``reasons``, ``metrics``, ``model``, ``method``).

    Returns
    -------
    dict
        ``apply`` (offer its files to a device), ``kind`` (``apply``, ``no_gain``, ``worse``, ``failed``,
        or ``figures`` for a noise characterisation, which corrects nothing), ``words`` (the sentence),
        ``why`` (one line more), and ``before``, ``after``, ``unit``, ``basis`` of its figure (null
        where it has none).
    """
    ok = bool(body.get("ok"))
    reasons = list(body.get("reasons") or [])
    if body.get("method") == "noise":
        if ok:
            return _out(True, "figures", "Use these figures in your filter: the sensors' noise is characterised.",
                        "White noise, random walk and bias instability per axis (IEEE Std 952), for a Kalman "
                        "filter's noise model.")
        return _out(False, "failed", "Don't use these figures: the noise could not be characterised.",
                    _short_reason(reasons))
    if body.get("method") == "temperature":
        return _temperature_verdict(body, ok, reasons)
    before, after, unit, basis = _figure(body)
    change = ("" if after is None else f"{basis} {_amount(before, unit)} → {_amount(after, unit)}"
              if before is not None else f"{basis} {_amount(after, unit)}")
    figures = dict(before=before, after=after, unit=unit or None, basis=basis or None)
    if before is not None and after is not None and after > before:
        return _out(False, "worse", f"Don't apply it: your sensor is already better than this ({change}).",
                    ("It would make your sensor worse; keep it as it is. "
                     + (_short_reason(reasons) if reasons else "")).strip(),
                    **figures)
    if not ok:
        return _out(False, "failed", "Don't apply it: the calibration failed its checks.", _short_reason(reasons),
                    **figures)
    if before is not None and after is not None:
        floor = MIN_GAIN_UT if unit == "µT" else MIN_GAIN_MG
        if after > (1.0 - MIN_GAIN_FRACTION) * before or before - after < floor:
            return _out(False, "no_gain", f"No need to apply it: it changes too little to matter ({change}).",
                        "Your sensor is about as good without it; keep it as it is.", **figures)
    words = f"Apply it: {change}." if change else "Apply it: it passed every check."
    why = ("Six poses leave none out to test on: the figure is on the poses fitted. A free session "
           "measures the error on new orientations." if body.get("method") == "six_position" and before is not None
           else "It passed every check." if change else "")
    return _out(True, "apply", words, why, **figures)


def _temperature_verdict(body: dict, ok: bool, reasons: list[str]) -> dict:
    """A temperature calibration: its offset drift over the range, raw against bands of temperature left out
    (each predicted by the fit made without it), the accelerometer's in mg first, else the gyroscope's in °/s."""
    from app.summary import temperature_headline

    metrics, model = body.get("metrics") or {}, body.get("model") or {}
    sensors = [s for s in ("acc", "gyr") if s in metrics]
    if not sensors:
        return _out(False, "failed", "Don't apply it: the calibration has no temperature model.", _short_reason(reasons))
    first = metrics[sensors[0]]
    unit = {"mg": "mg", "deg/s": "°/s"}[first["unit"]]
    change = temperature_headline(model, metrics)
    figures = dict(before=first["drift_raw_max"], after=first["drift_cv_max"], unit=unit,
                   basis="offset drift over the temperature range, on bands of temperature left out")
    grew = [s for s in sensors if metrics[s]["drift_cv_max"] > metrics[s]["drift_raw_max"]]
    if grew:
        return _out(False, "worse", f"Don't apply it: the drift would grow ({change}).",
                    ("It would make your sensor worse; keep its temperature calibration off. "
                     + (_short_reason(reasons) if reasons else "")).strip(), **figures)
    if not ok:
        return _out(False, "failed", "Don't apply it: the calibration failed its checks.", _short_reason(reasons),
                    **figures)
    if all(metrics[s]["drift_cv_max"] > (1.0 - MIN_GAIN_FRACTION) * metrics[s]["drift_raw_max"] for s in sensors):
        return _out(False, "no_gain", f"No need to apply it: it changes too little to matter ({change}).",
                    "Your sensor drifts about as little without it; keep it as it is.", **figures)
    return _out(True, "apply", f"Apply it: {change}.",
                "Each band of temperature was predicted by the fit made without it: the figure is what to expect "
                "between the temperatures recorded.", **figures)


def with_verdict(body: dict) -> dict:
    """The body with its verdict: calibrations stored before verdicts existed get theirs on reading."""
    return body if "verdict" in body else {**body, "verdict": verdict(body)}


def _out(apply: bool, kind: str, words: str, why: str, *, before=None, after=None, unit=None, basis=None) -> dict:
    return {"apply": apply, "kind": kind, "words": words, "why": why, "before": before, "after": after,
            "unit": unit, "basis": basis}
