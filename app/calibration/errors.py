"""Errors raised by the numerical core.

Invalid input raises a subclass of :class:`ValueError` whose message says what is wrong and
what to do about it.  A fit that runs but is poor does *not* raise: it returns a result with
``ok = False`` and its reasons.
"""


class CalibrationError(ValueError):
    """The input cannot be calibrated as given (wrong shape, non-finite values, bad labels...)."""


class InsufficientDataError(CalibrationError):
    """The input is well formed but holds too little information to determine the model."""
