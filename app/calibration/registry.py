"""Every method's result class, known by its type: what a stored calibration is read back as.

Each result class enters the base's registry by its ``RESULT_TYPE`` when its module is imported
(:meth:`CalibrationResult.__init_subclass__`, :mod:`app.calibration.shared.result`); the base imports none of them.
This module knows them all: whoever rebuilds a stored body (:func:`from_dict`), asks for its class (:func:`class_of`)
or lists every kind (:func:`registered_types`, :func:`registered_classes`, :func:`as_fitted_words`) calls it, and
it imports the methods' result modules first. It imports them when it needs them, not at its own import: a body whose
method's class is loaded names it, and the cube's module imports scipy.stats (~0.7 s), which `trical autocal` has no
use for.
"""

from __future__ import annotations

from .shared.result import CalibrationResult, registered


def load_all() -> None:
    """Import every method's result module (each class registers itself on import: these imports are used by that
    effect, which F401 does not see)."""
    from . import autocal, imported, magnetometer, temperature  # noqa: F401
    from .cube import calibrate  # noqa: F401
    from .noise import characterise  # noqa: F401
    from .still import affine, nonorthogonal, triangular  # noqa: F401


def _load_for(data: dict) -> None:
    """Every result class loaded, unless the class a body's method names is (its method names its kind:
    :func:`~app.calibration.shared.result.result_type_of`)."""
    if data.get("method") not in registered():
        load_all()


def from_dict(data: dict) -> CalibrationResult:
    """The result a stored body rebuilds, of the class its type names (:meth:`CalibrationResult.from_dict`).

    Raises
    ------
    CalibrationError
        If the type is unknown or the version newer than this trical reads.
    """
    _load_for(data)
    return CalibrationResult.from_dict(data)


def class_of(data: dict) -> type[CalibrationResult]:
    """The result class a body names, without rebuilding it (:meth:`CalibrationResult.class_of`): enough for the
    class answers of a body cut short.

    Raises
    ------
    CalibrationError
        If the type is unknown.
    """
    _load_for(data)
    return CalibrationResult.class_of(data)


def registered_types() -> tuple[str, ...]:
    """The result types :func:`from_dict` can rebuild."""
    load_all()
    return tuple(registered())


def as_fitted_words() -> dict[str, str]:
    """By model type, how the model as fitted relates to its correction (:attr:`CalibrationResult.AS_FITTED`),
    for the models that say it."""
    load_all()
    return {cls.MODEL_TYPE: cls.AS_FITTED for cls in registered().values() if cls.AS_FITTED}


def registered_classes() -> tuple[type[CalibrationResult], ...]:
    """Every result class :func:`from_dict` can rebuild, in the order they registered."""
    load_all()
    return tuple(registered().values())
