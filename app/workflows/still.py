"""Still readings: the known-orientation methods (six_position, orientations), the magnitude models
(nonorthogonal, triangular) and ``auto``, which chooses between them.

What differs between the four methods is data, a :class:`StillFit` each (the fit, which segments it
takes, whether it is cross-validated, whether it advises poses); the steps around them are shared.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from app.calibration import (
    CANONICAL_SIX,
    STANDARD_GRAVITY,
    CalibrationError,
    fit_orientations,
    fit_six_position,
    nearest_orientation,
)
from app.calibration.segments.static import MIN_DURATION_S
from app.calibration.shared.errors import InsufficientDataError
from app.calibration.shared.orientations import WITHIN_LABEL_ANGLE
from app.calibration.shared.validation import as_vectors
from app.calibration.still.cross_validation import SIX_POSITION_NOTE, cross_validated_error
from app.calibration.still.trust import review
from app.io.log import ACC_PHYSICAL_UNITS
from app.io.plural import counted
from app.workflows.calibration import Calibration
from app.workflows.compass import auto_compass
from app.workflows.gravity import reference_gravity
from app.workflows.recordings import RecordingSource, require_accelerometer
from app.workflows.requests import AutoRequest, KnownOrientationRequest, MagnitudeRequest, SolvedRequest, StillRequest
from app.workflows.results import holdout_metrics, pose_advice

if TYPE_CHECKING:
    from app.calibration.shared.result import StillReadingsResult
    from app.calibration.still.affine import AffineCalibration
    from app.calibration.still.nonorthogonal import NonOrthogonalCalibration
    from app.calibration.still.triangular import TriangularCalibration


@dataclass(frozen=True)
class Reading:
    """One averaged still reading handed to a known-orientation method."""

    mean: tuple[float, ...]
    up: str | None = None
    expected: tuple[float, ...] | None = None
    std: tuple[float, ...] | None = None
    count: int | None = None


def _first_of_each_axis(segments: list[dict[str, Any]]) -> list[int]:
    """The first still segment of each of the six orientations (six_position), or a refusal naming those
    missing."""
    first: dict[str, int] = {}
    for i, seg in enumerate(segments):
        if seg["up"] is not None and seg["up"] not in first:
            first[seg["up"]] = i
    missing = [lab for lab in CANONICAL_SIX if lab not in first]
    if missing:
        found = ", ".join(f"{lab} (segment {i})" for lab, i in first.items()) or "none"
        raise InsufficientDataError(
            f"the recording has no still segment with {', '.join(missing)} up; found {found}. "
            "Record the device resting a few seconds in each of the six orientations"
        )
    return sorted(first.values())


def _every_labelled(segments: list[dict[str, Any]]) -> list[int]:
    """Every still segment within 20° of an axis (orientations), or a refusal when none is."""
    chosen = [i for i, seg in enumerate(segments) if seg["up"] is not None]
    if not chosen:
        raise InsufficientDataError(
            f"none of the recording's {counted(len(segments), 'still segment')} lies {WITHIN_LABEL_ANGLE} of an axis: "
            "method "
            "orientations needs poses with an axis up; use a magnitude method (triangular, nonorthogonal) "
            "for free poses"
        )
    return chosen


def _fit_six(
    readings: list[Reading], *, gravity: float, stds: list[tuple[float, ...]] | None, gates: dict[str, Any]
) -> AffineCalibration:
    if any(r.up is None for r in readings):
        raise CalibrationError(f"six_position readings each need an `up` label ({', '.join(CANONICAL_SIX)})")
    return fit_six_position([r.mean for r in readings], [r.up for r in readings], gravity=gravity, stds=stds, **gates)


def _fit_orientations(
    readings: list[Reading], *, gravity: float, stds: list[tuple[float, ...]] | None, gates: dict[str, Any]
) -> AffineCalibration:
    return fit_orientations(
        [r.mean for r in readings],
        [r.up for r in readings],
        expected=[r.expected for r in readings],
        gravity=gravity,
        stds=stds,
        **gates,
    )


def _fit_nonorthogonal(
    m: np.ndarray, *, gravity: float, solver: str, gates: dict[str, Any]
) -> NonOrthogonalCalibration:
    # scipy.optimize when it runs: see calibrate_unknown
    from app.calibration.still.nonorthogonal import fit_nonorthogonal

    return fit_nonorthogonal(m, gravity=gravity, **gates)


def _fit_triangular(m: np.ndarray, *, gravity: float, solver: str, gates: dict[str, Any]) -> TriangularCalibration:
    from app.calibration.still.triangular import fit_triangular  # scipy.optimize when it runs: see calibrate_unknown

    return fit_triangular(m, gravity=gravity, solver=solver, **gates)


@dataclass(frozen=True)
class StillFit:
    """How one method of still readings fits: the data in which the four methods differ.

    Attributes
    ----------
    name : str
        The method's name.
    fit : callable
        Known orientations (``pick`` given): ``fit(readings, gravity=, stds=, gates=)`` of :class:`Reading`;
        a magnitude model: ``fit(means, gravity=, solver=, gates=)`` of an N×3 array.
    pick : callable or None
        Known orientations: ``pick(segments)``, the indices of a recording's still segments it takes when
        none are listed; None for a magnitude model (every segment).
    cv_note : str or None
        None: the fit is cross-validated on readings left out; else why it is not, reported instead.
    advises : bool
        Its result comes with the next poses to add (D-optimal, :func:`app.workflows.results.pose_advice`).
    """

    name: str
    fit: Callable[..., StillReadingsResult]
    pick: Callable[[list[dict[str, Any]]], list[int]] | None = None
    cv_note: str | None = None
    advises: bool = False


SIX_POSITION = StillFit("six_position", fit=_fit_six, pick=_first_of_each_axis, cv_note=SIX_POSITION_NOTE)
ORIENTATIONS = StillFit("orientations", fit=_fit_orientations, pick=_every_labelled)
NONORTHOGONAL = StillFit("nonorthogonal", fit=_fit_nonorthogonal, advises=True)  # Georgieva et al., Approach 1
TRIANGULAR = StillFit("triangular", fit=_fit_triangular, advises=True)  # Farago, Maczak and Gingl, IEEE Access
STILL_FITS = {spec.name: spec for spec in (SIX_POSITION, ORIENTATIONS, NONORTHOGONAL, TRIANGULAR)}
"""The four fits of still readings by name (``auto`` reports its choice by name; the wizard's sessions name
theirs)."""
AUTO_CHOICES = (SIX_POSITION.name, ORIENTATIONS.name, TRIANGULAR.name)
"""The fits ``auto`` chooses among on still readings (:func:`choose_model`)."""


def still_fit(method: StillFit | str) -> StillFit:
    """The fit a name (or the fit itself) stands for; a name of no still-readings method is refused."""
    if isinstance(method, StillFit):
        return method
    if method not in STILL_FITS:
        raise CalibrationError(f"unknown still-readings method {method!r}: use one of {', '.join(STILL_FITS)}")
    return STILL_FITS[method]


def _gates(unit: str) -> dict[str, Any]:
    """Raw readings: the reference stays in m/s² and the model maps it to counts, so the scale and offset
    gates do not apply."""
    return dict(plausible_scale=None, max_offset=math.inf) if unit == "raw" else {}


def readings_from_segments(
    recording: dict[str, Any], method: StillFit | str, indices: list[int] | None
) -> tuple[list[Reading], list[int]]:
    """Readings from a recording's static segments, and the indices of the segments used.

    ``method`` (a :class:`StillFit` of known orientations, or its name) picks them unless ``indices`` lists them:
    ``six_position`` the first segment of each orientation, ``orientations`` every labelled segment.
    """
    spec = still_fit(method)
    segments = require_segments(recording, spec.name)
    if indices is not None:
        chosen: list[int] = []
        for i in indices:
            if not 0 <= i < len(segments):
                raise CalibrationError(
                    f"segment {i} does not exist: the recording has {len(segments)} static segments "
                    f"(0–{len(segments) - 1})"
                )
            if segments[i]["up"] is None:
                raise CalibrationError(
                    f"segment {i} has no recognised orientation (no axis {WITHIN_LABEL_ANGLE} of its direction): "
                    "leave it out, or send its mean with an explicit `expected` vector"
                )
            chosen.append(i)
    else:
        # ``method`` is a fit of known orientations (its callers': six_position, orientations), which picks segments.
        assert spec.pick is not None, "a fit of known orientations picks its segments"
        chosen = spec.pick(segments)
    readings = [
        Reading(
            mean=tuple(segments[i]["acc_mean"]),
            up=segments[i]["up"],
            std=tuple(segments[i]["acc_std"]),
            count=segments[i].get("count"),
        )
        for i in chosen
    ]
    return readings, chosen


def calibrate_known(
    method: StillFit | str,
    readings: list[Reading],
    *,
    unit: str,
    gravity: float,
    holdout: Sequence[Sequence[float]] | None = None,
) -> tuple[StillReadingsResult, dict[str, Any]]:
    """Run a known-orientation method (:data:`SIX_POSITION`, :data:`ORIENTATIONS`, or its name) on readings,
    reviewed (app.calibration.still.trust); returns the result and the holdout's metrics."""
    spec = still_fit(method)
    stds = None
    if readings and all(r.std is not None for r in readings):
        stds = [r.std for r in readings]
    gates = _gates(unit)

    def fit(idx: Iterable[int]) -> StillReadingsResult:
        return spec.fit(
            [readings[i] for i in idx],
            gravity=gravity,
            stds=None if stds is None else [stds[i] for i in idx],
            gates=gates,
        )

    result = fit(range(len(readings)))
    if spec.cv_note is None:
        cv = cross_validated_error(fit, [r.mean for r in readings], gravity)
    else:
        cv = {"cv_error_mg": None, "cv_error_max_mg": None, "cv_note": spec.cv_note}
    result = review(result, cv, raw_unit=unit == "raw")
    return result, holdout_metrics(result, holdout)


def require_segments(recording: dict[str, Any], method: str) -> list[dict[str, Any]]:
    """A recording's still segments, or a refusal saying what to record and what to check: a method of
    still poses has nothing to fit without them (the unit first: readings in a unit other than the one
    read find no rest near the expected gravity)."""
    segments: list[dict[str, Any]] = recording["segments"]
    if not segments:
        unit = (recording.get("units") or {}).get("acc")
        norm = _median_norm_in_g(recording)
        duration = recording.get("duration_s")
        if duration is not None and duration < MIN_DURATION_S:  # shorter than one rest: nothing else to say
            raise InsufficientDataError(
                f"the recording is too short: it lasts {duration:.2g} s ({recording['n_samples']} samples), less "
                f"than one rest ({MIN_DURATION_S:g} s): method {method} needs the device resting still in several "
                "orientations — record it a few seconds in each, untouched"
            )
        if norm is not None and abs(norm - 1.0) <= 0.15:  # its unit is right: it never rested
            raise InsufficientDataError(
                f"the recording has no still segments: it never rested (its accelerometer reads about 1 g, a median "
                f"norm of {norm:.2f} g over {recording['n_samples']} samples, but never holds still for "
                f"{MIN_DURATION_S:g} s): method {method} needs the device resting still in several orientations — "
                "record it a few seconds in each, untouched"
            )
        said = "" if norm is None else f", a median norm of {norm:.2f} g"
        if recording.get("flight"):  # a flight controller's log states its unit: no unit to give
            raise InsufficientDataError(
                f"the log has no still segments: its IMU never rested for {MIN_DURATION_S:g} s "
                f"({recording['n_samples']} samples{said}): method {method} needs the board resting still in several "
                "orientations — log it a few seconds on each side, untouched, motors off"
            )
        raise InsufficientDataError(
            f"the recording has no still segments ({recording['n_samples']} samples, its accelerometer read in "
            f"{unit}{said}; a rest lasts at least {MIN_DURATION_S:g} s with the accelerometer reading about 1 g): "
            f"method {method} needs the device resting still in several orientations — record it a few seconds in "
            "each; if it did rest, its readings are not in the unit they were read in: give acc_unit (or chip for "
            "counts)"
        )
    return segments


def _median_norm_in_g(recording: dict[str, Any]) -> float | None:
    """The accelerometer's median norm in g, from the recording's overview (each bin's middle), or None."""
    overview = recording.get("overview") or {}
    unit = (recording.get("units") or {}).get("acc")
    per_g = {"g": 1.0, "m/s^2": STANDARD_GRAVITY}.get(unit or "")
    mids = [(lo + hi) / 2 for lo, hi in zip(overview.get("low") or [], overview.get("high") or []) if lo is not None]
    if overview.get("sensor") != "acc" or per_g is None or not mids:
        return None
    return float(np.median(mids)) / per_g


def means_from_segments(
    recording: dict[str, Any], indices: list[int] | None, method: str = "the method"
) -> tuple[list[list[float]], list[int]]:
    """Means of a recording's static segments (all, or the listed ones), orientation unknown."""
    segments = require_segments(recording, method)
    chosen = list(range(len(segments))) if indices is None else list(indices)
    for i in chosen:
        if not 0 <= i < len(segments):
            raise CalibrationError(f"segment {i} does not exist: the recording has {len(segments)} static segments")
    return [segments[i]["acc_mean"] for i in chosen], chosen


def calibrate_unknown(
    method: StillFit | str,
    means: ArrayLike,
    *,
    unit: str,
    gravity: float,
    solver: str = "lm",
    holdout: Sequence[Sequence[float]] | None = None,
) -> tuple[StillReadingsResult, dict[str, Any]]:
    """Run a magnitude model (:data:`NONORTHOGONAL`, Georgieva et al. Approach 1; :data:`TRIANGULAR`, Farago et
    al.; or its name) on still readings, reviewed with their cross-validated error (app.calibration.still.trust); the
    extra metrics are the holdout's."""
    # The fits import scipy.optimize when they run, not at the top: the CLI's autocal imports it on the
    # other core while detection runs (tests/test_cli_autocal.py).
    spec = still_fit(method)
    m = as_vectors(means, "means")
    gates = _gates(unit)

    def fit(idx: np.ndarray) -> StillReadingsResult:
        return spec.fit(m[idx], gravity=gravity, solver=solver, gates=gates)

    result = review(fit(np.arange(len(m))), cross_validated_error(fit, m, gravity), raw_unit=unit == "raw")
    return result, holdout_metrics(result, holdout)


def _unit_gravity(
    request: StillRequest, inline: Sequence[Sequence[float]] | None, recording: RecordingSource | None
) -> tuple[str, float, list[str]]:
    """The unit, the reference magnitude and notes for a request on inline readings or a recording."""
    unit = request.unit
    notes: list[str] = []
    if recording is not None:
        meta = recording.meta
        require_accelerometer(meta["units"], request.method)
        if request.unit != meta["units"]["acc"]:
            notes.append(
                f"the recording's accelerometer unit is {meta['units']['acc']}; the request's unit "
                f"{request.unit} was replaced by it"
            )
        unit = meta["units"]["acc"]
        if meta.get("quantization_step"):
            notes.append(
                f"the recording's values are rounded to {meta['quantization_step']} m/s² (as browsers "
                "round motion sensor data): each reading's mean is still precise when averaged over many samples"
            )
    else:
        unit = inline_unit(request, inline, notes)
    gravity, more = reference_gravity(unit, request.gravity, request.latitude_deg, request.height_m)
    return unit, gravity, notes + more


def inline_unit(request: StillRequest, means: Sequence[Sequence[float]] | None, notes: list[str]) -> str:
    """The unit of a request's inline readings, checked against their magnitude as an upload's is
    (app.io.readers.units): readings resting at about 1 are in g, at about 9.8 in m/s²; where the
    request's unit (given, or the default) says otherwise the data win, and a note says both."""
    from app.io.readers.units import infer_acc_unit

    unit: str = request.unit
    if unit not in ACC_PHYSICAL_UNITS or not means:
        return unit
    inferred = infer_acc_unit(np.asarray(means, dtype=float))
    if inferred in ACC_PHYSICAL_UNITS and inferred != unit:
        norm = float(np.median(np.linalg.norm(np.asarray(means, dtype=float), axis=1)))
        said = "the request's unit said" if "unit" in request.model_fields_set else "the request gave no unit, so"
        notes.append(
            f"{said} {unit}, but its readings' median norm is {norm:.3g}, about 1 g in {inferred}: "
            f"calibrated in {inferred}"
        )
        return inferred
    return unit


def _known(spec: StillFit, request: KnownOrientationRequest, recording: RecordingSource | None) -> Calibration:
    inline = None if request.readings is None else [r.mean for r in request.readings]
    unit, gravity, notes = _unit_gravity(request, inline, recording)
    source: dict[str, Any] = {}
    if recording is not None:
        with _naming_missing_poses(recording):
            readings, used = readings_from_segments(recording.meta, spec, request.segments)
        source = {**recording.source_fields, "segments_used": used}
    else:
        readings = [
            Reading(
                mean=tuple(r.mean),
                up=r.up,
                expected=None if r.expected is None else tuple(r.expected),
                std=None if r.std is None else tuple(r.std),
                count=r.count,
            )
            for r in request.readings or ()
        ]
    result, extra = calibrate_known(spec, readings, unit=unit, gravity=gravity, holdout=request.holdout)
    return name_sources(
        Calibration.of(
            result, extra, unit=unit, notes=notes, device_id=request.device_id, label=request.label, **source
        ),
        recording,
    )


def _means_and_source(
    request: MagnitudeRequest, recording: RecordingSource | None
) -> tuple[list[list[float]], dict[str, Any]]:
    """The still readings of a request on means: inline, or the recording's segments (and their fields)."""
    if recording is None:
        return [list(m) for m in request.means or ()], {}
    means, used = means_from_segments(recording.meta, request.segments, request.method)
    return means, {**recording.source_fields, "segments_used": used}


def missing_named_poses(meta: dict[str, Any]) -> str:
    """On a recording of pose files, the poses their names promise that no still reading shows, and the
    files whose readings point elsewhere ("" when the names and the data agree, or name no pose)."""
    parts = meta.get("parts") or []
    named = {p["pose_from_name"] for p in parts if p.get("pose_from_name")}
    seen = {seg["up"] for seg in meta.get("segments") or []}
    missing = sorted(named - seen)
    if not missing:
        return ""
    wrong = sorted(
        {
            f"{seg['source']} holds {seg['up'] or 'no axis'} up"
            for seg in meta["segments"]
            if seg.get("pose_from_name") in missing and seg["up"] != seg["pose_from_name"]
        }
    )
    return (
        f"The files' names promise {', '.join(missing)} up, but no still reading shows it"
        + (f" ({'; '.join(wrong)})" if wrong else "")
        + ": record that pose again, or check which file holds which pose"
    )


@contextmanager
def _naming_missing_poses(recording: RecordingSource | None) -> Iterator[None]:
    """Too few still readings of a recording of pose files: the refusal also names the poses the files'
    names promise that no still reading shows (:func:`missing_named_poses`)."""
    try:
        yield
    except InsufficientDataError as exc:
        hint = missing_named_poses(recording.meta) if recording is not None else ""
        if not hint:
            raise
        raise InsufficientDataError(f"{str(exc).rstrip('.')}. {hint}") from None


def name_sources(calibration: Calibration, recording: RecordingSource | None) -> Calibration:
    """On a recording made of several files (one per pose), each reading of the calibration names its
    file (``source``), and a warning names each file whose name gives a pose its reading contradicts."""
    if recording is None or not recording.meta.get("parts"):
        return calibration
    segments = recording.meta["segments"]
    used = [segments[i] for i in calibration.fields.get("segments_used") or []]
    warnings = [
        f"{seg.get('source')} names {seg['pose_from_name']} up, but its still reading points "
        f"{seg['up'] or f'to no axis {WITHIN_LABEL_ANGLE}'}{' up' if seg['up'] else ''}: "
        "the data's pose was used — check "
        "the file's name, or how the board lay"
        for seg in used
        if seg.get("pose_from_name") and seg["up"] != seg["pose_from_name"]
    ]
    return replace(calibration.noting(*warnings), reading_sources=tuple(seg.get("source") for seg in used))


def _magnitude(
    spec: StillFit, request: MagnitudeRequest, recording: RecordingSource | None, solver: str = "lm"
) -> Calibration:
    unit, gravity, notes = _unit_gravity(request, request.means, recording)
    means, source = _means_and_source(request, recording)
    result, extra = calibrate_unknown(spec, means, unit=unit, gravity=gravity, solver=solver, holdout=request.holdout)
    advice = {"advice": pose_advice(result)} if spec.advises else {}
    return name_sources(
        Calibration.of(
            result, extra, unit=unit, notes=notes, device_id=request.device_id, label=request.label, **advice, **source
        ),
        recording,
    )


def six_position(request: KnownOrientationRequest, recording: RecordingSource | None) -> Calibration:
    """Method ``six_position``: the first still reading of each of the six axis orientations."""
    return _known(SIX_POSITION, request, recording)


def orientations(request: KnownOrientationRequest, recording: RecordingSource | None) -> Calibration:
    """Method ``orientations``: every still reading within 20° of an axis, cross-validated."""
    return _known(ORIENTATIONS, request, recording)


def nonorthogonal(request: MagnitudeRequest, recording: RecordingSource | None) -> Calibration:
    """Method ``nonorthogonal``: Georgieva et al.'s model of shifts, scales and angles between the axes."""
    return _magnitude(NONORTHOGONAL, request, recording)


def triangular(request: SolvedRequest, recording: RecordingSource | None) -> Calibration:
    """Method ``triangular``: Farago et al.'s lower-triangular model, by the request's solver."""
    return _magnitude(TRIANGULAR, request, recording, solver=request.solver)


def choose_model(
    means: ArrayLike,
    *,
    unit: str,
    gravity: float,
    solver: str = "lm",
    holdout: Sequence[Sequence[float]] | None = None,
) -> tuple[StillReadingsResult, dict[str, Any], dict[str, Any]]:
    """The ``auto`` method: the model these still readings support, fitted, and why it was chosen.

    Readings each within 20° of an axis, covering all six, are known orientations: ``six_position``
    for exactly six, else ``orientations`` (Georgieva et al., ESGI'95, section 3.3). Nine or more
    readings also support the magnitude model ``triangular`` (Farago et al.). Where both apply,
    a calibration that passes its gates beats one that does not, then the lower error on readings
    left out of the fit wins (a tilted "axis" pose shows there).

    Returns
    -------
    result, extra, choice
        The chosen fit, its extra metrics, and ``{"method", "why", "candidates"}``.

    Raises
    ------
    InsufficientDataError
        Fewer than 9 readings that are not six axis-aligned ones.
    """
    m = as_vectors(means, "means")
    labels = [nearest_orientation(v) for v in m]
    aligned = None not in labels and set(labels) == set(CANONICAL_SIX)
    candidates: dict[str, tuple[StillReadingsResult, dict[str, Any]]] = {}
    if aligned:
        known = SIX_POSITION if len(m) == 6 else ORIENTATIONS
        readings = [Reading(mean=tuple(v), up=lab) for v, lab in zip(m, labels)]
        candidates[known.name] = calibrate_known(known, readings, unit=unit, gravity=gravity, holdout=holdout)
    if len(m) >= 9:
        try:
            candidates[TRIANGULAR.name] = calibrate_unknown(
                TRIANGULAR, m, unit=unit, gravity=gravity, solver=solver, holdout=holdout
            )
        except InsufficientDataError:
            if not candidates:  # nothing else applies: say what the magnitude model lacks
                raise
    if not candidates:
        raise InsufficientDataError(
            f"{counted(len(m), 'still reading')} {'is' if len(m) == 1 else 'are'} not the six axis-aligned poses "
            f"(each {WITHIN_LABEL_ANGLE} of one of ±x, ±y, ±z) "
            f"and a magnitude model needs at least 9 free poses (12 or more recommended): add "
            f"{9 - len(m)} or more poses in other directions"
        )

    def rank(name: str) -> tuple[bool, float]:
        result = candidates[name][0]
        cv = result.error_on_new_orientations
        return (not result.ok, math.inf if cv is None else cv)

    chosen = min(candidates, key=rank)
    fits = {name: r for name, (r, _) in candidates.items()}
    summary = {name: {"ok": r.ok, "cv_error_mg": r.error_on_new_orientations} for name, r in fits.items()}
    why = _why(fits, aligned, len(m))
    result, extra = candidates[chosen]
    return result, extra, {"method": chosen, "why": why, "candidates": summary}


def _why(fits: dict[str, StillReadingsResult], aligned: bool, n: int) -> str:
    """Why the chosen model fits these poses, in words that do not name it again: the page and the command line say
    the method first ("Method: six positions, chosen because …")."""
    if not aligned:
        return (
            f"the {n} poses are free (not all {WITHIN_LABEL_ANGLE} of an axis, or not all six axes), "
            "and a magnitude model "
            "(Farago et al.) needs no orientation"
        )
    if len(fits) == 1:
        return (
            f"the {n} poses are the six axis orientations (each {WITHIN_LABEL_ANGLE} of ±x, ±y, ±z), "
            "which determine the "
            "affine model in closed form (Georgieva et al.); nine or more distinct poses would also allow a "
            "magnitude model to check it"
        )

    def figure(name: str) -> str:
        cv = fits[name].error_on_new_orientations
        return f"{name} {'n/a' if cv is None else f'{cv:.2f} mg'}{'' if fits[name].ok else ' (not ok)'}"

    return (
        f"the {n} poses cover the six axes, so both a known-orientation and a magnitude model apply; "
        f"on poses left out: {', '.join(figure(k) for k in fits)}"
    )


def auto(request: AutoRequest, recording: RecordingSource | None) -> Calibration:
    """Method ``auto``: the model the still readings support (:func:`choose_model`); a recording of the
    magnetometer alone is the compass's (:func:`app.workflows.compass.auto_compass`)."""
    if recording is not None and "acc" not in recording.meta["units"] and "mag" in recording.meta["units"]:
        return auto_compass(request, recording)
    given = {"date": request.date, "longitude_deg": request.longitude_deg, "field_ut": request.field_ut}
    compass_only = [f for f, value in given.items() if value is not None]
    if compass_only:
        raise CalibrationError(
            f"{', '.join(compass_only)} {'is' if len(compass_only) == 1 else 'are'} for a recording of the "
            "magnetometer alone (the compass's field); these are the accelerometer's still readings: leave "
            f"{'it' if len(compass_only) == 1 else 'them'} out"
        )
    unit, gravity, notes = _unit_gravity(request, request.means, recording)
    means, source = _means_and_source(request, recording)
    with _naming_missing_poses(recording):
        result, extra, choice = choose_model(means, unit=unit, gravity=gravity, holdout=request.holdout)
    if STILL_FITS[choice["method"]].advises:  # a magnitude model: which poses to add next
        source["advice"] = pose_advice(result)
    return name_sources(
        Calibration.of(
            result,
            extra,
            unit=unit,
            notes=notes,
            device_id=request.device_id,
            label=request.label,
            choice=choice,
            **source,
        ),
        recording,
    )
