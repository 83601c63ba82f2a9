"""The one family of calibration results: what every method's frozen result shares.

Every result of the core derives from :class:`CalibrationResult`.  It carries its model type, the
units of the readings it was fitted on, ``ok`` / ``reasons`` / ``warnings``, a versioned plain-dict
form (:meth:`CalibrationResult.to_dict`, :meth:`CalibrationResult.from_dict`) and the correction
firmware applies, ``f = M (m − o)`` (:class:`~app.calibration.correction.AffineCorrection`), one
per sensor.  Subclasses register themselves by their ``RESULT_TYPE``, so a stored result is rebuilt
by :meth:`CalibrationResult.from_dict` whatever its method.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .correction import AffineCorrection, correction_of
from .errors import CalibrationError
from .headlines import SENSOR_WORDS, accelerometer_headline
from .norm_metrics import evaluate_still, relative_norm_errors
from .validation import as_samples

SCHEMA_VERSION = 1
"""Version of the plain-dict form; :meth:`CalibrationResult.from_dict` reads this version and the
unversioned bodies stored before it (the same fields)."""

OUTPUT_UNIT = {"m/s^2": "m/s^2", "g": "g", "raw": "m/s^2"}
"""What an accelerometer calibration calibrates into: readings in g into g; m/s² and raw counts
into m/s² (the reference of raw readings stays in m/s² and the model maps it to counts)."""

_REGISTRY: dict[str, type["CalibrationResult"]] = {}

CORRECTION, FIGURES, DRIFT = "correction", "figures", "drift"
"""What a result is, for the verdict and the exports (:attr:`CalibrationResult.KIND`): a correction
``f = M (m − o)`` to apply; figures that correct nothing (a noise characterisation); offsets that drift
with temperature, applied with each reading's temperature."""


@dataclass(frozen=True)
class Figure:
    """The figure a calibration stands on: its error ``before`` and ``after`` (None where it has none),
    their ``unit`` (``mg``, ``µT``, ``counts``, ``°/s``; empty without a figure) and the ``basis`` in words
    (``error on new orientations``, …)."""

    before: float | None = None
    after: float | None = None
    unit: str = ""
    basis: str = ""

    @property
    def grew(self) -> bool:
        """True when the calibrated error is larger than the raw one."""
        return self.before is not None and self.after is not None and self.after > self.before


NO_FIGURE = Figure()

FIGURE_METRICS = ("holdout_error_before_mg", "holdout_error_after_mg", "count_control", "cv_error_mg",
                  "cv_error_max_mg", "cv_note", "error_before_mg", "error_after_mg", "cv_error_ut", "cv_error_max_ut",
                  "fit_error_ut", "raw_error_ut", "drift_raw_max", "drift_cv_max")
"""The metrics a result chooses its figure and its headline by: only the result classes read them to decide
(tests/test_result_decides.py)."""


def holdout_figure(m: dict) -> Figure | None:
    """Readings the request held out (``holdout_*``): the most honest figure, when given."""
    if m.get("holdout_error_after_mg") is None:
        return None
    return Figure(m.get("holdout_error_before_mg"), m["holdout_error_after_mg"], "mg",
                  "error on the readings you held out")


def cv_figure(m: dict) -> Figure | None:
    """The cross-validated error (each reading calibrated by the fit made without it) against the same
    readings raw: a reading's raw error does not depend on the fit."""
    if m.get("cv_error_mg") is None:
        return None
    return Figure(m.get("error_before_mg"), m["cv_error_mg"], "mg", "error on new orientations")


def in_sample_figure(m: dict) -> Figure | None:
    """The in-sample error of the fitted readings, named as such."""
    if m.get("error_after_mg") is None:
        return None
    poses = f"{m['count']} poses" if m.get("count") else "poses"
    return Figure(m.get("error_before_mg"), m["error_after_mg"], "mg", f"error on the {poses} fitted")


def first_figure(metrics: dict, sources) -> Figure:
    """The first figure ``sources`` (functions of the metrics, most honest first) find, else :data:`NO_FIGURE`."""
    for source in sources:
        found = source(metrics)
        if found is not None:
            return found
    return NO_FIGURE


def registered_types() -> tuple[str, ...]:
    """The result types :meth:`CalibrationResult.from_dict` can rebuild."""
    _load_all()
    return tuple(_REGISTRY)


def _load_all() -> None:
    # The models register on import; the core's package imports only the light ones.
    from . import affine, autocal, magnetometer, noise, nonorthogonal, temperature, triangular  # noqa: F401
    from .cube import calibrate  # noqa: F401


class CalibrationResult:
    """Base of every frozen result dataclass of the core.

    A subclass is a frozen dataclass with at least the fields ``gravity``, ``metrics``,
    ``warnings``, ``reasons``, ``method`` and ``unit``, sets ``RESULT_TYPE`` and ``MODEL_TYPE``,
    and defines ``model_dict()`` (its parameters as plain lists and floats), ``uncertainty()``,
    ``body_dict()`` (its other plain fields), the classmethod ``_from_body(data)`` and ``apply``.
    """

    RESULT_TYPE: ClassVar[str] = ""
    """Key of the registry: the model type, or the method where one model type has several
    result kinds (``autocal`` wraps a ``triangular`` model)."""
    MODEL_TYPE: ClassVar[str] = ""
    CORRECTION_SOURCE: ClassVar[str] = ""
    """Where the correction ``f = M (m − o)`` of this model comes from (paper and equation)."""
    KIND: ClassVar[str] = CORRECTION
    """:data:`CORRECTION`, :data:`FIGURES` or :data:`DRIFT`: which verdict and which exports fit it. A class
    answer, so that a body cut short (no model) is still told apart."""
    PER_SENSOR: ClassVar[bool] = False
    """Whether its corrections are named by sensor in the exports (the cube: one per sensor)."""

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if cls.__dict__.get("RESULT_TYPE"):
            _REGISTRY[cls.RESULT_TYPE] = cls

    # -- the shared verdict ------------------------------------------------------------------

    @property
    def ok(self) -> bool:
        """True when no quality gate failed."""
        return not self.reasons

    @property
    def output_unit(self) -> str:
        """The unit the accelerometer correction calibrates into (:data:`OUTPUT_UNIT`)."""
        return OUTPUT_UNIT.get(self.unit, self.unit)

    @property
    def corrects(self) -> bool:
        """Whether it corrects anything (a noise characterisation only measures)."""
        return self.KIND != FIGURES

    # -- what a person reads first -----------------------------------------------------------

    @classmethod
    def figures_from(cls, metrics: dict, output_unit: str | None) -> tuple[Figure, ...]:
        """The figures a result of this class stands on, from its metrics: one, most honest first (each
        class its own order); one per sensor for a temperature calibration. Read from the class, so that a
        stored body cut short still has its figure."""
        return (NO_FIGURE,)

    def figures(self) -> tuple[Figure, ...]:
        """Every figure the verdict weighs (:meth:`figures_from` of its own metrics)."""
        return self.figures_from(self.metrics, self.output_unit)

    def figure(self) -> Figure:
        """The figure it stands on: ``before``, ``after``, ``unit``, ``basis``."""
        return (self.figures() or (NO_FIGURE,))[0]

    def headline(self) -> str | None:
        """The line a person reads first about its figures, or None where it has none."""
        return None

    @classmethod
    def verdict_note(cls, method: str | None, figure: Figure) -> str:
        """One line more under an "apply it" verdict on ``figure``, where the figure needs it."""
        return ""

    # -- corrections -------------------------------------------------------------------------

    def apply(self, samples, sensor: str | None = None) -> np.ndarray:
        """Calibrate raw samples of one sensor with its correction.

        Parameters
        ----------
        samples : array_like, shape (3,) or (N, 3)
        sensor : {"acc", "gyr", "mag"}, optional
            The sensor whose correction to apply (:meth:`corrections`); by default the result's first
            (the accelerometer's, the compass's magnetometer).

        Returns
        -------
        numpy.ndarray of the same shape as ``samples``.

        Raises
        ------
        CalibrationError
            When the result has no correction of that sensor.
        """
        self.require_sensor(sensor)
        m = as_samples(samples)
        return self._calibrate(m.reshape(-1, 3)).reshape(m.shape)

    def _calibrate(self, rows: np.ndarray) -> np.ndarray:  # pragma: no cover - every correcting subclass defines it
        """The model's own formula on readings (N, 3): exactly its correction ``M (m − o)``."""
        raise NotImplementedError

    def require_sensor(self, sensor: str | None) -> None:
        """Refuse a sensor the result has no correction of, saying which it has."""
        if sensor is None:
            return
        have = self.corrected_sensors()
        if sensor in have:
            return
        if len(have) != 1:
            raise CalibrationError(f"this calibration has no {sensor} model")
        word = SENSOR_WORDS[have[0]]
        fix = "; drop `sensor`" if have[0] == "acc" else f': send `sensor: "{have[0]}"`'
        raise CalibrationError(f"a {self.MODEL_TYPE} calibration has only {'an' if word[0] in 'aeiou' else 'a'} "
                               f"{word} model{fix}")

    def corrected_sensors(self) -> tuple[str, ...]:
        """The sensors it has a correction of (the keys of :meth:`corrections`, without computing them)."""
        return ("acc",)


    @property
    def correction(self) -> AffineCorrection:
        """The accelerometer's correction ``a = M (m − o)``.

        Every accelerometer model of the papers is affine in the reading (Georgieva et al.,
        ESGI'95, eqs. (16), (20); Farago, Maczak and Gingl, IEEE Access, eq. (6)), so M and o
        follow from applying the model to the origin and the unit vectors.
        """
        return correction_of(self.apply, input_unit=self.unit, output_unit=self.output_unit,
                             source=self.CORRECTION_SOURCE)

    def corrections(self) -> dict[str, AffineCorrection]:
        """Every sensor's correction by sensor name (``acc``, and ``gyr``, ``mag`` for the cube)."""
        return {"acc": self.correction}

    # -- plain form --------------------------------------------------------------------------

    def model_dict(self) -> dict:  # pragma: no cover - every subclass defines it
        raise NotImplementedError

    def body_dict(self) -> dict:  # pragma: no cover - every subclass defines it
        raise NotImplementedError

    def to_dict(self) -> dict:
        """Plain-JSON form (version :data:`SCHEMA_VERSION`): method, model (with its type),
        metrics, uncertainty, units, ok, warnings, reasons and the method's own fields."""
        return {
            "schema_version": SCHEMA_VERSION,
            "method": self.method,
            "model": {"type": self.MODEL_TYPE, **self.model_dict()},
            "metrics": dict(self.metrics),
            "uncertainty": self.uncertainty(),
            "gravity": self.gravity,
            "unit": self.unit,
            "output_unit": self.output_unit,
            **self.body_dict(),
            "ok": self.ok,
            "warnings": list(self.warnings),
            "reasons": list(self.reasons),
        }

    @classmethod
    def from_dict(cls, data: dict) -> "CalibrationResult":
        """The result whose :meth:`to_dict` produced ``data``, of the class its type names.

        Called on a subclass, the data must be of that subclass's type.

        Raises
        ------
        CalibrationError
            If the type is unknown, of another class than asked for, or the version is newer.
        """
        version = data.get("schema_version", SCHEMA_VERSION)
        if not isinstance(version, int) or version > SCHEMA_VERSION:
            raise CalibrationError(
                f"calibration schema_version {version!r} is newer than this trical reads ({SCHEMA_VERSION}): "
                "upgrade trical"
            )
        target = CalibrationResult.class_of(data)
        if cls is not CalibrationResult and not issubclass(target, cls):
            raise CalibrationError(f"not a {cls.MODEL_TYPE} model: type {result_type_of(data)!r}")
        return target._from_body(data)

    @staticmethod
    def class_of(data: dict) -> type["CalibrationResult"]:
        """The result class a plain form names (its method where that names a result kind of its own, else
        its model type), without rebuilding it: enough for the class answers (:attr:`KIND`,
        :meth:`figures_from`) of a body cut short.

        Raises
        ------
        CalibrationError
            If the type is unknown.
        """
        _load_all()
        kind = result_type_of(data)
        target = _REGISTRY.get(kind)
        if target is None:
            raise CalibrationError(f"unknown model type {kind!r}; known: {', '.join(_REGISTRY)}")
        return target

    @classmethod
    def _from_body(cls, data: dict) -> "CalibrationResult":  # pragma: no cover - every subclass defines it
        raise NotImplementedError


def result_type_of(data: dict) -> str | None:
    """The registry key of a plain form: its method where that names a result kind of its own
    (``autocal``, whose model is ``triangular``), else its model type."""
    method = data.get("method")
    return method if method in _REGISTRY else (data.get("model") or {}).get("type")


class StillReadingsResult(CalibrationResult):
    """A result fitted on averaged still readings (``means``) with a parameter covariance:
    the known-orientation and magnitude models. Adds the readings and the covariance to the
    plain form, and rebuilds the fields they share."""

    N_PARAMS: ClassVar[int] = 0
    FIGURE_SOURCES: ClassVar[tuple] = (holdout_figure, cv_figure, in_sample_figure)
    """Where its figure comes from, most honest first: readings the request held out, the cross-validated
    error, the in-sample error of the fitted readings."""
    REPORTS_IMPROVEMENT: ClassVar[bool] = False
    """Whether :meth:`evaluate` reports Farago et al.'s improvement ratio (eq. (21)), as their model's does."""

    def evaluate(self, means) -> dict:
        """Norm errors of further still readings of unknown orientation, e.g. held-out positions or control
        points (Georgieva et al., ESGI'95, sections 2.4 and 3.5; Farago et al., IEEE Access, Table 3).

        Parameters
        ----------
        means : array_like, shape (M, 3)
            Still readings; their true norm is ``gravity``.

        Returns
        -------
        dict
            ``count``, ``norm_error_max`` and ``norm_error_max_raw`` (relative), ``error_before_mg`` and
            ``error_after_mg`` (mean | |a| − g | in thousandths of g), and for the models that report it
            ``improvement`` (eq. (21) of Farago et al., a fraction): :func:`app.calibration.norm_metrics.evaluate_still`.
        """
        out = evaluate_still(means, self.apply, self.gravity)
        if not self.REPORTS_IMPROVEMENT:
            del out["improvement"]
        return out

    @classmethod
    def figures_from(cls, metrics: dict, output_unit: str | None) -> tuple[Figure, ...]:
        return (first_figure(metrics, cls.FIGURE_SOURCES),)

    def headline(self) -> str | None:
        """Its error on new orientations, then in-sample and raw (every fit of still readings reports a
        cross-validated error, ``cv_error_mg``, or says why it has none)."""
        if "cv_error_mg" not in self.metrics:
            return None
        return accelerometer_headline(self.metrics, held_out=False)

    def readings(self) -> list[dict]:
        """Per-reading detail: the model's own fields (:meth:`reading_detail`) and the relative norm errors
        after and before the calibration."""
        means = np.asarray(self.means, dtype=float)
        calibrated = self.apply(means)
        after = relative_norm_errors(calibrated, self.gravity)
        before = relative_norm_errors(means, self.gravity)
        return [{"index": i, **self.reading_detail(i, m, c), "norm_error": float(after[i]),
                 "norm_error_raw": float(before[i])} for i, (m, c) in enumerate(zip(means, calibrated))]

    def reading_detail(self, index: int, mean: np.ndarray, calibrated: np.ndarray) -> dict:
        """What a reading's plain form holds besides its index and norm errors: its mean and calibrated vector."""
        return {"mean": mean.tolist(), "calibrated": calibrated.tolist()}

    def body_dict(self) -> dict:
        return {
            "covariance": None if self.covariance is None else np.asarray(self.covariance).tolist(),
            "readings": self.readings(),
        }

    @classmethod
    def common_from_dict(cls, data: dict) -> tuple[dict, list, dict]:
        """The model dict, the readings and the shared constructor arguments of a plain form."""
        model = data["model"]
        readings = data.get("readings") or []
        cov = data.get("covariance")
        common = dict(
            gravity=float(data["gravity"]),
            means=np.asarray([r["mean"] for r in readings], dtype=float).reshape(-1, 3),
            covariance=None if cov is None else np.asarray(cov, dtype=float),
            dof=int((data.get("uncertainty") or {}).get("dof", max(len(readings) - cls.N_PARAMS, 0))),
            metrics=dict(data.get("metrics", {})),
            warnings=tuple(data.get("warnings", ())),
            reasons=tuple(data.get("reasons", ())),
            method=data.get("method", cls.MODEL_TYPE),
            unit=data.get("unit", "m/s^2"),
        )
        return model, readings, common
