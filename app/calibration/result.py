"""The one family of calibration results: what every method's frozen result shares.

Every result of the core derives from :class:`CalibrationResult`.  It carries its model type, the
units of the readings it was fitted on, ``ok`` / ``reasons`` / ``warnings``, a versioned plain-dict
form (:meth:`CalibrationResult.to_dict`, :meth:`CalibrationResult.from_dict`) and the correction
firmware applies, ``f = M (m − o)`` (:class:`~app.calibration.correction.AffineCorrection`), one
per sensor.  Subclasses register themselves by their ``RESULT_TYPE``, so a stored result is rebuilt
by :meth:`CalibrationResult.from_dict` whatever its method.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from .correction import AffineCorrection, correction_of
from .errors import CalibrationError
from .norm_metrics import evaluate_still, relative_norm_errors

SCHEMA_VERSION = 1
"""Version of the plain-dict form; :meth:`CalibrationResult.from_dict` reads this version and the
unversioned bodies stored before it (the same fields)."""

OUTPUT_UNIT = {"m/s^2": "m/s^2", "g": "g", "raw": "m/s^2"}
"""What an accelerometer calibration calibrates into: readings in g into g; m/s² and raw counts
into m/s² (the reference of raw readings stays in m/s² and the model maps it to counts)."""

_REGISTRY: dict[str, type["CalibrationResult"]] = {}


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

    # -- corrections -------------------------------------------------------------------------

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
        _load_all()
        kind = result_type_of(data)
        target = _REGISTRY.get(kind)
        if target is None:
            raise CalibrationError(f"unknown model type {kind!r}; known: {', '.join(_REGISTRY)}")
        if cls is not CalibrationResult and not issubclass(target, cls):
            raise CalibrationError(f"not a {cls.MODEL_TYPE} model: type {kind!r}")
        return target._from_body(data)

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
