"""The one family of calibration results: what every method's frozen result shares.

Every result of the core derives from :class:`CalibrationResult`.  It carries its model type, the
units of the readings it was fitted on, ``ok`` / ``reasons`` / ``warnings``, a versioned plain-dict
form (:meth:`CalibrationResult.to_dict`, :meth:`CalibrationResult.from_dict`) and the correction
firmware applies, ``f = M (m − o)`` (:class:`~app.calibration.shared.correction.AffineCorrection`), one
per sensor.  Subclasses register themselves by their ``RESULT_TYPE``, so a stored result is rebuilt
by :meth:`CalibrationResult.from_dict` whatever its method; this base imports none of them, and the core's
registry (:mod:`app.calibration.registry`) is what loads them all.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from contextvars import ContextVar
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, ClassVar, TypeVar

import numpy as np

from .correction import AffineCorrection, correction_of
from .errors import CalibrationError
from .headlines import SENSOR_WORDS
from .norm_metrics import evaluate_still, relative_norm_errors
from .plausible import correction_figures, implausible, is_plausibility_reason
from .uncertainty import CONFIDENCE, half_widths
from .validation import as_samples

SCHEMA_VERSION = 1
"""Version of the plain-dict form; :meth:`CalibrationResult.from_dict` reads this version and the
unversioned bodies stored before it (the same fields)."""

OUTPUT_UNIT = {"m/s^2": "m/s^2", "g": "g", "raw": "m/s^2"}
"""What an accelerometer calibration calibrates into: readings in g into g; m/s² and raw counts
into m/s² (the reference of raw readings stays in m/s² and the model maps it to counts)."""

_REGISTRY: dict[str, type[CalibrationResult]] = {}

_Entry = TypeVar("_Entry")

_READING_STORED: ContextVar[bool] = ContextVar("reading_stored", default=False)
"""Set while :meth:`CalibrationResult.from_dict` rebuilds a stored body, whose gates are not judged again."""

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

FIGURE_METRICS = (
    "holdout_error_before_mg",
    "holdout_error_after_mg",
    "count_control",
    "cv_error_mg",
    "cv_error_max_mg",
    "cv_note",
    "error_before_mg",
    "error_after_mg",
    "cv_error_ut",
    "cv_error_max_ut",
    "fit_error_ut",
    "raw_error_ut",
    "drift_raw_max",
    "drift_cv_max",
)
"""The metrics a result chooses its figure and its headline by: only the result classes read them to decide
(tests/test_result_decides.py)."""


@dataclass(frozen=True)
class NormErrors:
    """The norm errors (mg of g) a fit of still readings tells: on new orientations (cross-validated), and raw
    and calibrated on the readings it reports them on (Farago et al., IEEE Access, Table 3); None where it has
    none. Built from a plain body's ``metrics`` or a row of its ``comparison`` (autocal's) by :meth:`of`, so that
    a reader of the plain form (the CLI's tables) asks the result, not the metric keys."""

    on_new_orientations: float | None
    before: float | None
    after: float | None

    @classmethod
    def of(cls, figures: dict) -> NormErrors:
        """The errors of ``figures``: the ``metrics`` of a plain body, or one row of its ``comparison``."""
        return cls(figures.get("cv_error_mg"), figures.get("error_before_mg"), figures.get("error_after_mg"))


def holdout_figure(m: dict) -> Figure | None:
    """Readings the request held out (``holdout_*``): the most honest figure, when given."""
    if m.get("holdout_error_after_mg") is None:
        return None
    return Figure(
        m.get("holdout_error_before_mg"), m["holdout_error_after_mg"], "mg", "error on the readings you held out"
    )


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


def registered() -> Mapping[str, type[CalibrationResult]]:
    """The result classes registered so far, by their type (a read-only view): each class enters when its module is
    imported (:meth:`CalibrationResult.__init_subclass__`). This base imports none of them; the core's registry
    (:mod:`app.calibration.registry`) imports them all."""
    return MappingProxyType(_REGISTRY)


PARAMETER = {"parameter": True}
"""The metadata of a result's fields that are its model's parameters (``X: np.ndarray = parameter()``):
:meth:`CalibrationResult.model_dict` and :meth:`CalibrationResult.parameters_from` are built from them."""


def parameter():
    """A dataclass field that is one of the model's parameters (no default: every fit gives it)."""
    return field(metadata=PARAMETER)


def _plain(value):
    """A parameter as JSON has it: an array as nested lists, a number as a float."""
    a = np.asarray(value, dtype=float)
    return a.tolist() if a.ndim else float(a)


class Gated:
    """What every fit with quality gates shares: ``metrics``, ``warnings`` and ``reasons`` (gate failures,
    each one sentence), and ``ok``, exactly when no gate gave a reason (docs/conventions.md)."""

    warnings: tuple
    reasons: tuple

    @property
    def ok(self) -> bool:
        """True when no quality gate failed."""
        return not self.reasons


@dataclass(frozen=True)
class GatedFit(Gated):
    """A part of a result with its own gates (a cube's sensor): its metrics, warnings and reasons as keyword
    fields after its own."""

    metrics: dict = field(default_factory=dict, kw_only=True)
    warnings: tuple = field(default=(), kw_only=True)
    reasons: tuple = field(default=(), kw_only=True)

    def gate_dict(self) -> dict:
        """The plain form of its metrics, ``ok``, warnings and reasons."""
        return {
            "metrics": dict(self.metrics),
            "ok": self.ok,
            "warnings": list(self.warnings),
            "reasons": list(self.reasons),
        }


def gate_fields(data: dict) -> dict:
    """``metrics``, ``warnings`` and ``reasons`` of a plain form, as a result's constructor takes them."""
    return dict(
        metrics=dict(data.get("metrics", {})),
        warnings=tuple(data.get("warnings", ())),
        reasons=tuple(data.get("reasons", ())),
    )


class CalibrationResult(Gated):
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
    AS_FITTED: ClassVar[str] = ""
    """How the model as fitted relates to its correction, in a line for the result's Details (the page shows it
    under the correction, by model type: :func:`as_fitted_words`); empty where there is nothing to relate."""
    KIND: ClassVar[str] = CORRECTION
    """:data:`CORRECTION`, :data:`FIGURES` or :data:`DRIFT`: which verdict and which exports fit it. A class
    answer, so that a body cut short (no model) is still told apart."""
    PER_SENSOR: ClassVar[bool] = False
    """Whether its corrections are named by sensor in the exports (the cube: one per sensor)."""
    EXACT_PARAMETERS: ClassVar[bool] = False
    """Whether its corrections are a firmware's own per-axis numbers (an imported calibration): the firmware
    exports then write them as they are, every sensor, rather than fit the firmware's model on the correction."""

    if TYPE_CHECKING:  # what every subclass has: a frozen dataclass's fields (metrics may be a property)
        __dataclass_fields__: ClassVar[dict[str, dataclasses.Field]]
        method: str
        gravity: float | None

        @property
        def metrics(self) -> dict: ...

        @property
        def unit(self) -> str: ...

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if cls.__dict__.get("RESULT_TYPE"):
            _REGISTRY[cls.RESULT_TYPE] = cls

    def __post_init__(self):
        # The one plausibility gate (app/calibration/shared/plausible.py): every result made here — fitted, or given
        # its unit afterwards (dataclasses.replace) — is not ok with a figure no MEMS part can have. Its reasons
        # come first; those of an earlier making (another unit) are dropped and judged again, so that they
        # always say what this result holds. A result read back from a stored body (:meth:`from_dict`) keeps
        # the reasons it was stored with: a body is not rewritten on reading (a limit that changes is a new
        # SCHEMA_VERSION and its migration).
        if _READING_STORED.get():
            return
        found = tuple(self.plausibility())
        reasons = tuple(r for r in self.reasons if not is_plausibility_reason(r))
        warnings = tuple(w for w in self.warnings if not is_plausibility_reason(w))
        if found or reasons != tuple(self.reasons):
            object.__setattr__(self, "reasons", found + reasons)
            object.__setattr__(self, "warnings", found + warnings)

    def physical_figures(self) -> list:
        """Its figures a MEMS part bounds (:class:`~app.calibration.shared.plausible.PhysicalFigure`): by default
        each correction's scale and offset (a gyroscope's bias); a result with other figures adds its own
        (a compass's field, a noise characterisation's densities)."""
        out = []
        for sensor, c in self.corrections().items():
            out += correction_figures(sensor, c.M, c.o, c.input_unit, c.output_unit)
        return out

    def plausibility(self) -> list[str]:
        """One reason per figure no MEMS part can have, naming the likely cause (the unit, the columns, the
        chip) and what to give (:func:`app.calibration.shared.plausible.implausible`); empty when all are plausible."""
        return implausible(self.physical_figures())

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
        raise CalibrationError(
            f"a {self.MODEL_TYPE} calibration has only {'an' if word[0] in 'aeiou' else 'a'} {word} model{fix}"
        )

    def corrected_sensors(self) -> tuple[str, ...]:
        """The sensors it has a correction of (the keys of :meth:`corrections`, without computing them)."""
        return ("acc",)

    @classmethod
    def filter_gaps(cls, metrics: dict) -> tuple:
        """A result whose figures are for a filter (:attr:`KIND` ``figures``: the noise) says which figures a
        filter needs that its metrics lack; others lack none."""
        return ()

    def figure_sensors(self) -> tuple[str, ...]:
        """The sensors its figures are of: a question the reading left open about one of them (its unit)
        leaves this result not ok. A correction's are the sensors it corrects."""
        return self.corrected_sensors()

    @property
    def correction(self) -> AffineCorrection:
        """The accelerometer's correction ``a = M (m − o)``.

        Every accelerometer model of the papers is affine in the reading (Georgieva et al.,
        ESGI'95, eqs. (16), (20); Farago, Maczak and Gingl, IEEE Access, eq. (6)), so M and o
        follow from applying the model to the origin and the unit vectors.
        """
        return correction_of(
            self.apply, input_unit=self.unit, output_unit=self.output_unit, source=self.CORRECTION_SOURCE
        )

    def corrections(self) -> dict[str, AffineCorrection]:
        """Every sensor's correction by sensor name (``acc``, and ``gyr``, ``mag`` for the cube)."""
        return {"acc": self.correction}

    def still_readings(self) -> np.ndarray | None:
        """The accelerometer's still readings (N, 3) its correction was fitted on, in :attr:`unit`; None where
        it holds none (the firmware exports then fit their model on its correction alone)."""
        return None

    # -- plain form --------------------------------------------------------------------------

    def model_dict(self) -> dict:
        """Its model's parameters (the fields marked :func:`parameter`, in their order) as plain lists and
        floats; a result whose model is not its fields says its own."""
        return {f.name: _plain(getattr(self, f.name)) for f in dataclasses.fields(self) if f.metadata == PARAMETER}

    @classmethod
    def parameters_from(cls, model: dict) -> dict:
        """The parameter fields of a plain form's ``model`` (the reverse of :meth:`model_dict`): arrays and floats."""
        return {
            f.name: np.asarray(model[f.name], dtype=float) if isinstance(model[f.name], list) else float(model[f.name])
            for f in dataclasses.fields(cls)
            if f.metadata == PARAMETER
        }

    def body_dict(self) -> dict:  # pragma: no cover - every subclass defines it
        raise NotImplementedError

    def uncertainty(self) -> dict:  # pragma: no cover - every subclass defines it
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
    def from_dict(cls, data: dict) -> CalibrationResult:
        """The result whose :meth:`to_dict` produced ``data``, of the class its type names (among the classes
        registered: :func:`app.calibration.registry.from_dict` loads them all first).

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
        token = _READING_STORED.set(True)
        try:
            return target._from_body(data)
        finally:
            _READING_STORED.reset(token)

    @staticmethod
    def class_of(data: dict) -> type[CalibrationResult]:
        """The result class a plain form names (its method where that names a result kind of its own, else
        its model type), without rebuilding it: enough for the class answers (:attr:`KIND`,
        :meth:`figures_from`) of a body cut short. Among the classes registered
        (:func:`app.calibration.registry.class_of` loads them all first).

        Raises
        ------
        CalibrationError
            If the type is unknown.
        """
        kind = result_type_of(data)
        target = _REGISTRY.get(kind) if kind is not None else None
        if target is None:
            raise CalibrationError(f"unknown model type {kind!r}; known: {', '.join(_REGISTRY)}")
        return target

    @classmethod
    def _from_body(cls, data: dict) -> CalibrationResult:  # pragma: no cover - every subclass defines it
        raise NotImplementedError


def by_class_name(table: Mapping[str, _Entry], cls: type) -> _Entry:
    """A presenter's entry for a result class, its tables keyed by class name (so that they import no method's
    module): the class's own entry, else its nearest base's.

    Raises
    ------
    StopIteration
        If neither the class nor a base has an entry (every table has one for :class:`CalibrationResult`).
    """
    return next(table[base.__name__] for base in cls.__mro__ if base.__name__ in table)


def result_type_of(data: dict) -> str | None:
    """The registry key of a plain form: its method where that names a result kind of its own
    (``autocal``, whose model is ``triangular``), else its model type."""
    method = data.get("method")
    return method if method in _REGISTRY else (data.get("model") or {}).get("type")


@dataclass(frozen=True)
class StillReadingsResult(CalibrationResult, GatedFit):
    """A result fitted on averaged still readings (``means``) with a parameter covariance:
    the known-orientation and magnitude models. Adds the readings and the covariance to the
    plain form, and rebuilds the fields they share.

    The fields they share are keyword fields after each model's own: ``gravity`` (the reference
    magnitude, in the unit of the readings), ``means`` (the fitted readings, (N, 3)), ``covariance`` (of
    the parameters in the model's order; None without degrees of freedom), ``dof`` (residual degrees of
    freedom), ``unit`` (of the readings: ``m/s^2``, ``g`` or ``raw``), and :class:`GatedFit`'s metrics,
    warnings and reasons.
    """

    gravity: float = field(kw_only=True)
    means: np.ndarray = field(kw_only=True)
    covariance: np.ndarray | None = field(kw_only=True)
    dof: int = field(kw_only=True)
    unit: str = field(default="m/s^2", kw_only=True)

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
            ``improvement`` (eq. (21) of Farago et al., a fraction):
            :func:`app.calibration.shared.norm_metrics.evaluate_still`.
        """
        out = evaluate_still(means, self.apply, self.gravity)
        if not self.REPORTS_IMPROVEMENT:
            del out["improvement"]
        return out

    @classmethod
    def figures_from(cls, metrics: dict, output_unit: str | None) -> tuple[Figure, ...]:
        return (first_figure(metrics, cls.FIGURE_SOURCES),)

    @property
    def error_on_new_orientations(self) -> float | None:
        """The cross-validated error (mg; each reading calibrated by the fit made without it), or None when the
        fit has none: what ``auto`` ranks its candidates by and the free flow measures its progress with."""
        return self.metrics.get("cv_error_mg")

    @property
    def largest_error_on_new_orientations(self) -> float | None:
        """The largest of those errors (mg), or None."""
        return self.metrics.get("cv_error_max_mg")

    NO_INTERVALS: ClassVar[str] = (
        "no intervals: {n} positions fit the 9 parameters exactly (0 residual degrees "
        "of freedom) or the fit is degenerate; add positions"
    )
    """Why there are no intervals without a covariance (``{n}``: the readings fitted)."""

    def uncertainty(self) -> dict:
        """95 % half-widths of the parameters, shaped as the model (:meth:`interval_dict`), or nulls with the
        reason when there is no covariance (no residual degrees of freedom, or a degenerate fit)."""
        out: dict = {"confidence": CONFIDENCE, "dof": self.dof}
        if self.covariance is None:
            out.update(dict.fromkeys(self.model_dict()), note=self.NO_INTERVALS.format(n=len(self.means)))
        else:
            out.update(self.interval_dict(half_widths(self.covariance, self.dof)))
        return out

    def interval_dict(self, hw: np.ndarray) -> dict:  # pragma: no cover - every subclass defines it
        """The half-widths ``hw`` (in the covariance's order) as the model's parameters."""
        raise NotImplementedError

    def still_readings(self) -> np.ndarray:
        return np.asarray(self.means, dtype=float).reshape(-1, 3)

    def readings(self) -> list[dict]:
        """Per-reading detail: the model's own fields (:meth:`reading_detail`) and the relative norm errors
        after and before the calibration."""
        means = np.asarray(self.means, dtype=float)
        calibrated = self.apply(means)
        after = relative_norm_errors(calibrated, self.gravity)
        before = relative_norm_errors(means, self.gravity)
        return [
            {
                "index": i,
                **self.reading_detail(i, m, c),
                "norm_error": float(after[i]),
                "norm_error_raw": float(before[i]),
            }
            for i, (m, c) in enumerate(zip(means, calibrated))
        ]

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
            **gate_fields(data),
            method=data.get("method", cls.MODEL_TYPE),
            unit=data.get("unit", "m/s^2"),
        )
        return model, readings, common


@dataclass(frozen=True)
class PerSensorResult(CalibrationResult):
    """A result made of one part per sensor, ``sensors``: name → its ``model``, ``uncertainty``, ``metrics``
    and the method's own pieces (the noise characterisation, the temperature calibration). Its model,
    uncertainty and metrics are its sensors'; it holds no affine correction. Its warnings, reasons,
    gravity and unit are keyword fields after the method's own."""

    sensors: dict
    warnings: tuple = field(default=(), kw_only=True)
    reasons: tuple = field(default=(), kw_only=True)
    gravity: float | None = field(default=None, kw_only=True)
    unit: str = field(default="", kw_only=True)

    @property
    def metrics(self) -> dict:
        return {name: part["metrics"] for name, part in self.sensors.items()}

    def corrections(self) -> dict:
        return {}

    def figure_sensors(self) -> tuple[str, ...]:
        return tuple(self.sensors)

    def model_dict(self) -> dict:
        return {name: part["model"] for name, part in self.sensors.items()}

    def uncertainty(self) -> dict:
        return {"confidence": CONFIDENCE, **{name: part["uncertainty"] for name, part in self.sensors.items()}}

    @staticmethod
    def parts_from(data: dict, *pieces: str) -> dict:
        """Each sensor's part of a plain form: its model, uncertainty and metrics, and ``pieces`` (the
        method's own, each stored by sensor at the top of the form)."""
        names = [k for k in data["model"] if k != "type"]
        return {
            name: {
                "model": data["model"][name],
                "uncertainty": data["uncertainty"][name],
                "metrics": data["metrics"].get(name, {}),
                **{p: data[p][name] for p in pieces},
            }
            for name in names
        }
