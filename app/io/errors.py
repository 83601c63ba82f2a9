"""Errors of reading logs and writing exports."""


class LogFormatError(ValueError):
    """A file cannot be read as a log; the message names the problem and how to fix it.

    ``status`` is the HTTP status the API answers with (422 by default, 415 for non-text files,
    413 for files above the upload limit).
    """

    code: str | None = None
    """The API's code when it is not the status's own (``bad_line``: a line that is not numbers)."""

    def __init__(self, message: str, *, status: int = 422, code: str | None = None):
        super().__init__(message)
        self.status = status
        if code is not None:
            self.code = code


class ExportError(ValueError):
    """A calibration cannot be exported in the requested format (the message says why)."""
