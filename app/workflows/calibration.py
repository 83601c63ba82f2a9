"""A calibration as the workflow computes it, typed, until an edge needs its plain form.

A method's handler returns a :class:`Calibration`: the core's result, the metrics and notes of the request,
and the fields of its caller (device, label, the recording's id and segments, the model chosen and why).
What comes after the handler adds to that value, never to a plain form: the reader's warnings
(:meth:`Calibration.read_from`) and the questions the reading left open, which are reasons of the result,
so that ``ok`` falls with them. Its headline, its verdict and its plain form are computed once, from the
final result, by :meth:`Calibration.body`; nothing changes ``ok`` or ``reasons`` after them (docs/architecture.md,
"One verdict from the final result").
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any

from app.calibration.shared.result import CalibrationResult
from app.headlines import headline
from app.verdict import verdict


@dataclass(frozen=True)
class Calibration:
    """A computed calibration, before its plain form.

    Attributes
    ----------
    result : CalibrationResult
        The core's frozen result, in the unit of the readings it was fitted on.
    extra_metrics : dict
        Metrics of the request beside the result's own (readings held out, the capture rates).
    notes : tuple of str
        Warnings of the request and of the reading, in the order a person reads them, after the result's own.
    fields : dict
        The caller's fields of the plain form: ``device_id``, ``label``, the recording's id and the segments used,
        the model chosen and why (``choice``), the poses advised next, …
    reading_sources : tuple or None
        On a recording of several files, the file each still reading came from (the plain form's
        ``readings[i].source``).
    read_warnings : tuple of str
        What the reader decided against the header or the caller (units, columns, clock): read first.
    asked : tuple of str
        The questions the reading left open that the result's figures hang on: reasons of the result (so not
        ok), listed first in the plain form (the cause a person can answer).
    """

    result: CalibrationResult
    extra_metrics: dict[str, Any] = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    fields: dict[str, Any] = field(default_factory=dict)
    reading_sources: tuple[str | None, ...] | None = None
    read_warnings: tuple[str, ...] = ()
    asked: tuple[str, ...] = ()

    @classmethod
    def of(
        cls, result: CalibrationResult, extra_metrics: dict[str, Any], *, unit: str, notes: list[str], **fields: Any
    ) -> Calibration:
        """A handler's calibration: the core's ``result`` in ``unit`` (the core fits numbers; the caller knows
        their unit), the request's metrics and notes, the caller's fields."""
        if result.unit != unit:
            result = dataclasses.replace(result, unit=unit)
        return cls(result, dict(extra_metrics), tuple(notes), dict(fields))

    @property
    def final(self) -> CalibrationResult:
        """The result as answered and stored: the request's metrics beside its own (its headline and figure see
        readings held out), its reasons those of the fit and of the reading."""
        if not self.extra_metrics:
            return self.result
        return dataclasses.replace(self.result, metrics={**self.result.metrics, **self.extra_metrics})

    def read_from(self, warnings: list[str], questions: list[dict[str, Any]]) -> Calibration:
        """This calibration of a recording: the reader's ``warnings`` first (what it decided against the header or
        the caller: units, columns, clock), and the ``questions`` it left open (a gyroscope's unit) as reasons of
        the result where its figures are of that sensor (:meth:`CalibrationResult.figure_sensors`): a figure
        that hangs on an open question is not ok."""
        said = tuple(w for w in warnings if w not in self.result.warnings and w not in self.notes)
        said = tuple(dict.fromkeys(said + self.read_warnings))
        sensors = self.result.figure_sensors()
        asked = [q["detail"] for q in questions if q["sensor"] in sensors]
        result = self.result
        if asked:
            result = dataclasses.replace(
                result, reasons=tuple(asked) + tuple(r for r in result.reasons if r not in asked)
            )
        return dataclasses.replace(self, result=result, read_warnings=said, asked=tuple(asked))

    def noting(self, *notes: str) -> Calibration:
        """This calibration with more notes after its own."""
        return dataclasses.replace(self, notes=self.notes + notes)

    def with_fields(self, **fields: Any) -> Calibration:
        """This calibration with more of the caller's fields (``trical calibrate``'s captures, ``auto``'s choice)."""
        return dataclasses.replace(self, fields={**self.fields, **fields})

    def body(self) -> dict[str, Any]:
        """The plain form that the API answers and the store keeps: the final result's, with its headline,
        the notes after its warnings, the caller's fields, and its verdict (app.verdict), each computed once
        from the final result."""
        result = self.final
        out = result.to_dict()
        line = headline(result)  # the line a person reads first
        if line is not None:
            out["headline"] = line
        out["warnings"] = [*self.read_warnings, *out["warnings"], *self.notes]
        out["reasons"] = [*self.asked, *(r for r in out["reasons"] if r not in self.asked)]
        out.update(self.fields)
        if self.reading_sources is not None:
            for reading, source in zip(out.get("readings") or [], self.reading_sources):
                reading["source"] = source
        out["verdict"] = verdict(out, result)
        return out
