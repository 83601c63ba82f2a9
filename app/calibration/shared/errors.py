"""Errors raised by the numerical core.

Invalid input raises a subclass of :class:`ValueError` whose message says what is wrong and
what to do about it, and whose ``code`` names the kind of problem for programs.  A fit that runs
but is poor does *not* raise: it returns a result with ``ok = False`` and its reasons.
"""


class CalibrationError(ValueError):
    """The input cannot be calibrated as given (wrong shape, non-finite values, bad labels...).

    Parameters
    ----------
    message : str
        What is wrong and how to fix it.
    code : str, optional
        A stable name of the problem (``wrong_turn``, ``not_still``…); the class's ``code`` by default.
    """

    code = "calibration_refused"

    def __init__(self, message: str = "", *, code: str | None = None):
        super().__init__(message)
        if code is not None:
            self.code = code


class InsufficientDataError(CalibrationError):
    """The input is well formed but holds too little information to determine the model.

    Every method raises this one error for too little data (too few readings, positions,
    orientations or rotations), so that callers treat it alike (code ``insufficient_data``).
    """

    code = "insufficient_data"


class NotStillError(CalibrationError):
    """A capture that should be still was taken while the device moved."""

    code = "not_still"
