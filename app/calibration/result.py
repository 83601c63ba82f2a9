"""What every calibration result shares: its plain-dict form and its rebuilding from it."""

from __future__ import annotations

import numpy as np

from .errors import CalibrationError


class SerialisableResult:
    """Mixin for the frozen result dataclasses of the core.

    A subclass has the fields ``method, gravity, means, covariance, dof, metrics, warnings,
    reasons``, the class attributes ``MODEL_TYPE`` and ``N_PARAMS``, and defines ``model_dict()``
    (the model's parameters as plain lists and floats), ``uncertainty()`` and ``readings()``.
    """

    MODEL_TYPE: str = ""
    N_PARAMS: int = 0

    @property
    def ok(self) -> bool:
        """True when no quality gate failed."""
        return not self.reasons

    def model_dict(self) -> dict:  # pragma: no cover - every subclass defines it
        raise NotImplementedError

    def extra_dict(self) -> dict:
        """Top-level fields a method adds to the plain form (e.g. the solver)."""
        return {}

    def to_dict(self) -> dict:
        """Plain-JSON form: model, metrics, uncertainty, ok, warnings, reasons and readings."""
        return {
            "method": self.method,
            **self.extra_dict(),
            "model": {"type": self.MODEL_TYPE, **self.model_dict()},
            "metrics": dict(self.metrics),
            "uncertainty": self.uncertainty(),
            "covariance": None if self.covariance is None else np.asarray(self.covariance).tolist(),
            "gravity": self.gravity,
            "ok": self.ok,
            "warnings": list(self.warnings),
            "reasons": list(self.reasons),
            "readings": self.readings(),
        }

    @classmethod
    def common_from_dict(cls, data: dict) -> tuple[dict, list, dict]:
        """The model dict, the readings and the shared constructor arguments of a plain form.

        Raises
        ------
        CalibrationError
            If the plain form holds another model type.
        """
        model = data["model"]
        if model.get("type") != cls.MODEL_TYPE:
            raise CalibrationError(f"not a {cls.MODEL_TYPE} model: type {model.get('type')!r}")
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
        )
        return model, readings, common
