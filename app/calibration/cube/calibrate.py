"""The cube method of Särkkä et al., IEEE Sensors Journal 17(11) 2017 end to end: one recording in,
three sensors out.

:func:`calibrate_cube` segments the recording into still positions and rotations, matches them
to the protocol, removes the drift when the device returned to position 1 (section II), checks
the sequence (section VII-A-1), and calibrates the accelerometer and the magnetometer
(sections III-C, IV-B) and the gyroscope (sections III-B, IV-A) from the positions and rotations
before the first mistake.  Every sensor follows ``raw = S f + b`` (Särkkä et al., IEEE Sensors Journal
17(11) 2017, eq. (1)).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from ..shared.correction import AffineCorrection
from ..shared.errors import CalibrationError, InsufficientDataError
from ..shared.gates import Gates
from ..shared.norm_metrics import norm_errors
from ..shared.result import NO_FIGURE, CalibrationResult, Figure, gate_fields
from ..shared.uncertainty import CONFIDENCE
from ..shared.validation import as_vectors, check_gravity
from .accmag import FieldSensorCalibration, drift_covariance, fit_field_sensor
from .drift import Drift, estimate_drift
from .gyro import GyroCalibration, fit_gyroscope, fit_gyroscope_full_turns
from .matching import Match, match_protocol
from .protocols import Protocol, get_protocol
from .sections import from_sections
from .segmentation import Segmentation, segment_recording
from .sequence import SequenceCheck, check_sequence, saturated_samples

MODEL_TYPE = "cube"

RETURN_TOLERANCE = 0.05
"""The return position must read within 5 % of the accelerometer's span of position 1."""


@dataclass(frozen=True)
class CubeCalibration(CalibrationResult):
    """Result of :func:`calibrate_cube`.

    Attributes
    ----------
    acc, mag : FieldSensorCalibration or None
        Accelerometer and magnetometer (None when not given or not possible).
    gyr : GyroCalibration or None
        Gyroscope (None when too few usable rotations).
    protocol : Protocol
    sequence : tuple of dict
        The check of every transition (Särkkä et al. section VII-A-1).
    first_wrong_rotation : int or None
        1-based number of the first rotation that did not match the protocol.
    segmentation : Segmentation
    drift : dict
        Sensor → :class:`Drift` removed (empty without a return to position 1).
    sampling_rate_hz, gravity, field_ut : float
    metrics, warnings, reasons
        ``ok`` is true when ``reasons`` is empty (every sensor's own reasons included).
    units : dict
        Unit of each sensor's recorded values (``acc``: m/s², g or raw; ``gyr``: rad/s, deg/s or
        raw; ``mag``: uT, nT or raw); gyroscope and magnetometer samples were converted to rad/s
        and µT before the fit unless raw.
    """

    acc: FieldSensorCalibration | None
    gyr: GyroCalibration | None
    mag: FieldSensorCalibration | None
    protocol: Protocol
    sequence: tuple
    first_wrong_rotation: int | None
    segmentation: Segmentation | None
    drift: dict
    sampling_rate_hz: float
    gravity: float
    field_ut: float | None = None
    metrics: dict = field(default_factory=dict)
    warnings: tuple = ()
    reasons: tuple = ()
    units: dict = field(default_factory=dict)

    RESULT_TYPE = MODEL_TYPE
    MODEL_TYPE = MODEL_TYPE
    CORRECTION_SOURCE = "Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (1): raw = S f + b, so M = S^-1, o = b"
    AS_FITTED = (
        "As fitted (Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (1)): raw = S f + b per sensor, "
        "so S = M⁻¹ and b = o."
    )
    method = MODEL_TYPE
    PER_SENSOR = True
    CUBE_SENSORS = ("acc", "gyr", "mag")
    CALIBRATED_UNITS: ClassVar[dict[str, str]] = {"gyr": "rad/s", "mag": "uT"}
    """What the gyroscope and magnetometer corrections calibrate into."""

    @property
    def unit(self) -> str:
        """The accelerometer's unit."""
        return self.units.get("acc", "m/s^2")

    @property
    def correction(self) -> AffineCorrection:
        """The accelerometer's correction (Särkkä et al. eq. (1)); raises when there is no accelerometer model."""
        try:
            return self.corrections()["acc"]
        except KeyError:
            raise CalibrationError("this cube calibration has no accelerometer model") from None

    def corrections(self) -> dict[str, AffineCorrection]:
        """Each calibrated sensor's ``f = S⁻¹ (m − b)`` (Särkkä et al., eq. (1)), acc, gyr, mag in order."""
        out = {}
        for sensor in self.CUBE_SENSORS:
            res = getattr(self, sensor)
            if res is None or getattr(res, "S", None) is None:
                continue
            if sensor == "acc":
                units = (self.unit, self.output_unit)
            else:
                out_unit = self.CALIBRATED_UNITS[sensor]
                units = ("raw" if self.units.get(sensor) == "raw" else out_unit, out_unit)
            out[sensor] = AffineCorrection(
                np.linalg.inv(res.S), np.asarray(res.b, dtype=float), *units, self.CORRECTION_SOURCE, sensor
            )
        return out

    def apply(self, samples=None, sensor: str | None = None, *, acc=None, gyr=None, mag=None):
        """Calibrate samples: ``f = S⁻¹ (raw − b)`` (Särkkä et al. eq. (1)).

        ``apply(samples, sensor)`` calibrates one sensor's samples (the accelerometer's by default) and
        returns the array; ``apply(acc=…, gyr=…, mag=…)`` calibrates each sensor given and returns
        ``{"acc": ..., "gyr": ..., "mag": ...}``.

        Raises
        ------
        CalibrationError
            A sensor this calibration has no model of.
        """
        if samples is not None:
            return self._sensor(sensor or "acc").apply(samples)
        return {
            name: self._sensor(name).apply(raw)
            for name, raw in (("acc", acc), ("gyr", gyr), ("mag", mag))
            if raw is not None
        }

    def _sensor(self, name: str):
        res = getattr(self, name) if name in self.CUBE_SENSORS else None
        if res is None:
            raise CalibrationError(f"this calibration has no {name} model")
        return res

    def physical_figures(self) -> list:
        """Each sensor's correction's scale and offset, when the sensors' units are known (``units``): the
        readings of a cube whose units were not given (a simulation in arbitrary units) are not judged."""
        return super().physical_figures() if self.units else []

    def corrected_sensors(self) -> tuple[str, ...]:
        return tuple(name for name in self.CUBE_SENSORS if getattr(self, name) is not None)

    def still_readings(self) -> np.ndarray | None:
        """The accelerometer's means of its positions (Särkkä et al. section VI), or None without its model."""
        return None if self.acc is None else np.asarray(self.acc.means, dtype=float).reshape(-1, 3)

    def figures(self) -> tuple[Figure, ...]:
        """The accelerometer's mean | |m| − g | of its positions raw, and of S⁻¹ (m − b) (Särkkä et al., IEEE
        Sensors Journal 17(11) 2017, eq. (1)), in mg of g: in-sample, the positions are fitted with their
        known attitudes."""
        if self.acc is None or not len(self.acc.means):
            return (NO_FIGURE,)
        means = self.acc.means
        g = float(self.gravity or np.mean(np.linalg.norm(means, axis=1)))
        errors = norm_errors(means, self.acc.apply, g)
        return (
            Figure(
                errors["error_before_mg"],
                errors["error_after_mg"],
                "mg",
                f"accelerometer error on the {len(means)} positions fitted",
            ),
        )

    def model_dict(self) -> dict:
        """``{"acc": {...}, "gyr": {...}, "mag": {...}}``, each sensor's S, b and their parts."""
        return {
            "acc": None if self.acc is None else self.acc.model(),
            "gyr": None if self.gyr is None else self.gyr.model(),
            "mag": None if self.mag is None else self.mag.model(),
        }

    def uncertainty(self) -> dict:
        """95 % half-widths mirroring :meth:`model` (Särkkä et al. Appendices A and B)."""
        return {
            "confidence": CONFIDENCE,
            "acc": None if self.acc is None else self.acc.uncertainty(),
            "gyr": None if self.gyr is None else self.gyr.uncertainty(),
            "mag": None if self.mag is None else self.mag.uncertainty(),
        }

    def body_dict(self) -> dict:
        """The sequence check, protocol, segments, drift, field and each sensor's details."""
        return {
            "units": dict(self.units),
            "sequence": [dict(s) for s in self.sequence],
            "first_wrong_rotation": self.first_wrong_rotation,
            "protocol": self.protocol.to_dict(),
            "segments": None if self.segmentation is None else self.segmentation.to_dict(),
            "drift": {k: v.to_dict() for k, v in self.drift.items()},
            "sampling_rate_hz": self.sampling_rate_hz,
            "field_ut": self.field_ut,
            "details": {
                "acc": None if self.acc is None else self.acc.to_dict(),
                "gyr": None if self.gyr is None else self.gyr.to_dict(),
                "mag": None if self.mag is None else self.mag.to_dict(),
            },
        }

    @classmethod
    def _from_body(cls, data: dict) -> CubeCalibration:
        """Rebuild a result from :meth:`to_dict` output (the segmentation is not kept)."""
        det = data["details"]
        p = data["protocol"]
        from . import quaternion as quat
        from .protocols import parse_rotation

        rotations = tuple(None if r is None else parse_rotation(r) for r in p["rotations"])
        attitudes = np.asarray(p["attitudes"], dtype=float)
        protocol = Protocol(
            name=p["name"],
            attitudes=attitudes,
            quaternions=np.array([quat.from_matrix(R) for R in attitudes]),
            rotations=rotations,
            ups=tuple(p["ups"]),
            heading_known=bool(p["heading_known"]),
        )
        drift = {
            k: Drift(
                rate=np.asarray(v["rate_per_s"]),
                t0_s=float(v["t0_s"]),
                change=np.asarray(v["change"]),
                z=None if v.get("z") is None else np.asarray(v["z"]),
            )
            for k, v in (data.get("drift") or {}).items()
        }
        return cls(
            acc=None if det.get("acc") is None else FieldSensorCalibration.from_dict(det["acc"]),
            gyr=None if det.get("gyr") is None else GyroCalibration.from_dict(det["gyr"]),
            mag=None if det.get("mag") is None else FieldSensorCalibration.from_dict(det["mag"]),
            protocol=protocol,
            sequence=tuple(data.get("sequence", ())),
            first_wrong_rotation=data.get("first_wrong_rotation"),
            segmentation=None,
            drift=drift,
            sampling_rate_hz=float(data["sampling_rate_hz"]),
            gravity=float(data["gravity"]),
            field_ut=data.get("field_ut"),
            **gate_fields(data),
            units=dict(data.get("units") or {"acc": data.get("unit", "m/s^2")}),
        )


def _position_stats(raw: np.ndarray, static) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mean, sample covariance and count of each still interval (Särkkä et al., IEEE Sensors Journal
    17(11) 2017, Appendix A)."""
    means, covs, counts = [], [], []
    for a, b in static:
        seg = raw[a:b]
        means.append(seg.mean(axis=0))
        covs.append(np.cov(seg.T) if len(seg) > 1 else np.zeros((3, 3)))
        counts.append(len(seg))
    return np.array(means), np.array(covs), np.array(counts)


@dataclass(frozen=True)
class _Stages:
    """What the per-sensor stages of :func:`calibrate_cube` share: the recording's segmentation,
    the protocol, the sequence check and the drift removed."""

    seg: Segmentation
    proto: Protocol
    fs: float
    seq: SequenceCheck
    n_valid: int
    drift: dict
    centres_s: np.ndarray

    def significant_drift(self, name: str) -> bool:
        return name in self.drift and self.drift[name].significant


def _validated(acc, gyr, mag, *, gravity, sampling_rate_hz, field_ut):
    """Checked samples of the three sensors (one clock), gravity and rate."""
    if gyr is None:
        raise CalibrationError(
            "the cube method needs the gyroscope: the rotations between positions are found, checked "
            "and calibrated with it (Särkkä et al. section III-B); record the gyroscope together with the accelerometer"
        )
    a = as_vectors(acc, "acc samples", min_rows=2)
    w = as_vectors(gyr, "gyr samples", min_rows=2)
    m = None if mag is None else as_vectors(mag, "mag samples", min_rows=2)
    if len(w) != len(a) or (m is not None and len(m) != len(a)):
        raise CalibrationError(
            f"the sensors must be sampled together: acc has {len(a)} samples, gyr {len(w)}"
            + ("" if m is None else f", mag {len(m)}")
            + "; resample them to one clock first"
        )
    g = check_gravity(gravity)
    fs = float(sampling_rate_hz)
    if not (np.isfinite(fs) and fs > 0):
        raise CalibrationError(f"sampling_rate_hz must be a positive number; got {sampling_rate_hz!r}")
    if m is not None and (field_ut is None or not np.isfinite(field_ut) or field_ut <= 0):
        raise CalibrationError(
            "a magnetometer needs the magnitude of the local field: give field_ut in µT "
            "(e.g. from a geomagnetic model for the place and date)"
        )
    return a, w, m, g, fs


def _segment(a, w, fs: float, proto: Protocol, g: float, sections, static_threshold, min_static_s: float) -> Match:
    """Still positions and rotations matched to the protocol (:mod:`.matching`), or the regions of an
    annotated section list (:mod:`.sections`)."""
    if sections is not None:
        if not (proto.full_turns and not proto.heading_known):
            raise CalibrationError(
                f"sections (an annotated Ferraris section list: x_p … z_rot) go with protocol ferraris, not "
                f"{proto.name}: drop sections, or use protocol ferraris"
            )
        seg, built = from_sections(sections, a, w, sampling_rate_hz=fs, gravity=g)
        return Match(seg, built, False)
    seg = segment_recording(w, sampling_rate_hz=fs, threshold=static_threshold, min_static_s=min_static_s)
    return match_protocol(a, w, seg, proto, sampling_rate_hz=fs, gravity=g)


def _readings(proto: Protocol, static, n: int | None = None) -> list[int]:
    """Positions (0-based, the first n) whose rests are readings of the field sensors and the gyroscope bias."""
    return [k for k in range(len(static) if n is None else n) if proto.uses_reading(k)]


def _remove_drift(a, w, m, seg: Segmentation, fs: float, gates: Gates):
    """The affine drift of Särkkä et al., IEEE Sensors Journal 17(11) 2017, section II, from the
    return to position 1; only a significant drift is removed (removing noise only adds error)."""
    drift: dict = {}
    a_first = a[seg.static[0][0] : seg.static[0][1]].mean(axis=0)
    a_last = a[seg.static[-1][0] : seg.static[-1][1]].mean(axis=0)
    span = np.ptp(np.array([a[s0:s1].mean(axis=0) for s0, s1 in seg.static]), axis=0).max()
    if np.linalg.norm(a_last - a_first) > RETURN_TOLERANCE * span:
        gates.warn(
            "the last position does not read like position 1, so it is not the return of Särkkä et al. section II: "
            "no drift was removed"
        )
        return a, w, m, drift
    removed = []
    for name, raw in (("acc", a), ("gyr", w), ("mag", m)):
        if raw is None:
            continue
        d = estimate_drift(raw, seg.static[0], seg.static[-1], sampling_rate_hz=fs)
        drift[name] = d
        if d.significant:
            removed.append(name)
    if "acc" in removed:
        a = drift["acc"].remove(a, fs)
    if "gyr" in removed:
        w = drift["gyr"].remove(w, fs)
    if "mag" in removed:
        m = drift["mag"].remove(m, fs)
    if removed:
        gates.warn(
            f"drift removed from {', '.join(removed)} (Särkkä et al. section II); the intervals do not include "
            "the uncertainty of the drift estimate"
        )
    return a, w, m, drift


def _check_sequence(a, w, w_raw, seg: Segmentation, proto: Protocol, fs: float, g: float, gyro_range, gates: Gates):
    """The check of every transition (Särkkä et al., IEEE Sensors Journal 17(11) 2017, section
    VII-A-1): the first mistake and the saturated rotations before it are reasons.  Returns the
    check and the number of positions before the first mistake."""
    acc_means = _position_stats(a, seg.static)[0]
    gyro_bias = np.vstack([w[seg.static[k][0] : seg.static[k][1]] for k in _readings(proto, seg.static)]).mean(axis=0)
    sat = saturated_samples(w_raw, gyro_range)
    seq = check_sequence(
        w,
        acc_means,
        seg.rotations,
        proto,
        sampling_rate_hz=fs,
        gyro_bias=gyro_bias,
        gravity=g,
        saturated=sat,
    )
    if (reason := seq.reason()) is not None:  # the first wrong rotation
        gates.fail(reason)
    for entry in seq.rotations:
        if (
            entry["saturated"]
            and entry["rotation"] <= len(proto.rotations)
            and (seq.first_wrong is None or entry["rotation"] < seq.first_wrong)
        ):
            gates.fail(entry["message"])
    return seq, min(seq.valid_positions, proto.n_positions)


def _fit_field(rec: _Stages, raw, ref: float, name: str, gates: Gates) -> FieldSensorCalibration | None:
    """Accelerometer or magnetometer from the positions before the first mistake (Särkkä et al.,
    IEEE Sensors Journal 17(11) 2017, sections III-C, IV-B), with a removed drift's covariance."""
    means, covs, counts = _position_stats(raw, rec.seg.static)
    n_valid = rec.n_valid
    use = _readings(rec.proto, rec.seg.static, n_valid)
    extra = None
    if rec.significant_drift(name):
        idx = use + [len(rec.seg.static) - 1]
        extra = drift_covariance(rec.centres_s[idx], covs[idx], counts[idx])
    try:
        return fit_field_sensor(
            means[use],
            covs[use],
            counts[use],
            rec.proto.attitudes[use],
            reference=ref,
            sensor=name,
            estimate_angles=rec.proto.heading_known,
            positions=tuple(k + 1 for k in use),
            mean_covariance_extra=extra,
        )
    except InsufficientDataError as exc:
        if rec.seq.first_wrong is None:
            raise
        gates.fail(f"{name} not calibrated: {exc}")
        return None


def _gyro_drift(rec: _Stages, w, used: list[int]) -> dict:
    """The removed drift's error e = error of (m_E − m_1), entering sample i as τ_i e."""
    if not rec.significant_drift("gyr"):
        return {}
    seg, fs, centres_s = rec.seg, rec.fs, rec.centres_s
    (f0, f1), (e0, e1) = seg.static[0], seg.static[-1]
    v0 = np.cov(w[f0:f1].T) / (f1 - f0)
    v1 = np.cov(w[e0:e1].T) / (e1 - e0)
    span = centres_s[-1] - centres_s[0]
    return {
        "rate_error_weights": [(np.arange(*seg.rotations[k]) / fs - centres_s[0]) / span for k in used],
        "rate_error_covariance": v0 + v1,
    }


def _fit_gyro(rec: _Stages, w, lam, gates: Gates) -> tuple[GyroCalibration | None, list[int]]:
    """Gyroscope from the known rotations before the mistake that did not saturate (Särkkä et al.,
    IEEE Sensors Journal 17(11) 2017, sections III-B, IV-A), or from full turns (ferraris)."""
    seg, proto, seq, n_valid, fs = rec.seg, rec.proto, rec.seq, rec.n_valid, rec.fs
    used = [
        k
        for k, rot in enumerate(proto.rotations)
        if rot is not None and k + 1 < n_valid and not seq.rotations[k]["saturated"]
    ]
    static_valid = [seg.static[k] for k in _readings(proto, seg.static, n_valid)]
    still_covs = np.array([np.cov(w[s0:s1].T) for s0, s1 in static_valid])
    still_counts = np.array([s1 - s0 for s0, s1 in static_valid])
    noise_cov = np.average(still_covs, axis=0, weights=still_counts - 1)
    bias0 = np.vstack([w[s0:s1] for s0, s1 in static_valid]).mean(axis=0)
    estimate_bias = len(used) >= 4
    full_turns = bool(used) and all(abs(proto.rotations[k].angle_deg) >= 360.0 for k in used)
    rates = [w[seg.rotations[k][0] : seg.rotations[k][1]] for k in used]
    common = dict(
        sampling_rate_hz=fs,
        noise_cov=noise_cov,
        bias_covariance=noise_cov / still_counts.sum(),
        rotation_numbers=[k + 1 for k in used],
    )
    if full_turns and len(used) == 3:
        res = fit_gyroscope_full_turns(
            rates,
            [proto.attitudes[k].T @ proto.rotations[k].axis for k in used],
            [proto.rotations[k].angle_deg for k in used],
            bias=bias0,
            **common,
        )
        return res, used
    if 3 * len(used) < (12 if estimate_bias else 9):
        if seq.first_wrong is None and not any(r["saturated"] for r in seq.rotations):
            raise InsufficientDataError(
                f"protocol {proto.name} has {len(used)} known rotation(s); the gyroscope needs at least 3"
            )
        gates.fail(
            f"gyr not calibrated: {len(used)} usable known rotation(s) before the mistake; at least 3 "
            "(4 to estimate the bias) are needed"
        )
        return None, used
    res = fit_gyroscope(
        rates,
        proto.quaternions[list(used)],
        proto.quaternions[[k + 1 for k in used]],
        bias0=bias0,
        lam=lam,
        estimate_bias=estimate_bias,
        **common,
        **_gyro_drift(rec, w, used),
    )
    return res, used


def calibrate_cube(
    acc,
    gyr,
    mag=None,
    *,
    sampling_rate_hz: float,
    protocol="cube24",
    gravity: float,
    field_ut: float | None = None,
    gyro_range: float | None = None,
    lam: float | None = None,
    static_threshold: float | None = None,
    min_static_s: float = 1.0,
    sections: dict | None = None,
) -> CubeCalibration:
    """Calibrate accelerometer, gyroscope and magnetometer from one cube recording (Särkkä et al., IEEE
    Sensors Journal 17(11) 2017).

    Parameters
    ----------
    acc : array_like, shape (N, 3)
        Raw accelerometer samples (any unit; S maps m/s² — or g — to it).
    gyr : array_like, shape (N, 3)
        Raw gyroscope samples in pre-adjusted rad/s (datasheet scale), required: the rotations
        are found and checked with it.
    mag : array_like, shape (N, 3), optional
        Raw magnetometer samples.
    sampling_rate_hz : float
        Common sampling rate of the three sensors.
    protocol : str, Protocol or dict
        ``cube24`` (docs/methods.md), ``ferraris``, or ``{"rotations": [...], "ups": [...]}``.
    gravity : float
        Magnitude of gravity in the accelerometer's output unit (m/s², or 1 for g).
    field_ut : float, optional
        Magnitude of the Earth's field in µT; required with ``mag``.
    gyro_range : float, optional
        Gyroscope full scale in rad/s, to flag rotations that exceed it (otherwise clipping is
        detected from flat tops).
    lam : float, optional
        Fixed λ of Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (9); by default the saturation
        rule of section IV-A-1.
    static_threshold, min_static_s : float
        Segmentation settings (see :func:`segment_recording`).
    sections : dict, optional
        An annotated Ferraris section list (imucal's ``{"x_p": {"start", "end"}, …, "z_rot"}``,
        sample indices, :mod:`.sections`) instead of the detected rests and turns; protocol
        ferraris only.

    Returns
    -------
    CubeCalibration

    Raises
    ------
    CalibrationError
        Missing gyroscope, mismatched lengths, non-finite samples, a magnetometer without
        ``field_ut``, a recording whose still positions do not match the protocol, or invalid
        ``sections``.
    InsufficientDataError
        Too few still positions or rotations for the models.
    """
    a, w, m, g, fs = _validated(acc, gyr, mag, gravity=gravity, sampling_rate_hz=sampling_rate_hz, field_ut=field_ut)
    match = _segment(a, w, fs, get_protocol(protocol), g, sections, static_threshold, min_static_s)
    seg, proto, has_return = match.segmentation, match.protocol, match.has_return
    gates = Gates()
    gates.warn(match.warnings)
    w_raw = w
    drift: dict = {}
    if has_return:
        a, w, m, drift = _remove_drift(a, w, m, seg, fs, gates)
    seq, n_valid = _check_sequence(a, w, w_raw, seg, proto, fs, g, gyro_range, gates)
    rec = _Stages(
        seg=seg,
        proto=proto,
        fs=fs,
        seq=seq,
        n_valid=n_valid,
        drift=drift,
        centres_s=np.array([0.5 * (s0 + s1 - 1) / fs for s0, s1 in seg.static]),
    )
    acc_res = _fit_field(rec, a, g, "acc", gates)
    # _validated refused a magnetometer without the field
    mag_res = None if m is None or field_ut is None else _fit_mag(rec, m, float(field_ut), gates)
    gyr_res, used = _fit_gyro(rec, w, lam, gates)
    for res in (acc_res, gyr_res, mag_res):
        if res is not None:
            gates.merge(res, unique=True)
    return CubeCalibration(
        acc=acc_res,
        gyr=gyr_res,
        mag=mag_res,
        protocol=proto,
        sequence=seq.rotations,
        first_wrong_rotation=seq.first_wrong,
        segmentation=seg,
        drift=drift,
        sampling_rate_hz=fs,
        gravity=g,
        field_ut=None if field_ut is None else float(field_ut),
        metrics=_cube_metrics(rec, len(a), used, has_return),
        **gates.fields(),
    )


def _fit_mag(rec: _Stages, m, field_ut: float, gates: Gates):
    """The magnetometer as the accelerometer (:func:`_fit_field`), when the protocol knows the headings
    between positions; else None, with a warning saying why."""
    if not rec.proto.heading_known:
        gates.warn(
            f"mag not calibrated: protocol {rec.proto.name} leaves the headings unknown, so the field's "
            "direction changes between positions in an unknown way; use cube24 or a protocol of known rotations"
        )
        return None
    return _fit_field(rec, m, field_ut, "mag", gates)


def _cube_metrics(rec: _Stages, n_samples: int, used: list[int], has_return: bool) -> dict:
    """What the recording held and what the fits used: positions found and used, rotations used, return."""
    seg = rec.seg
    return {
        "n_samples": int(n_samples),
        "n_positions_found": len(seg.static),
        "n_still_found": seg.n_still_found,
        "n_handling": len(seg.handling),
        "positions_from": seg.source,
        "n_positions_used": rec.n_valid,
        "rotations_used": [k + 1 for k in used],
        "returned_to_start": has_return,
        "duration_s": n_samples / rec.fs,
    }
