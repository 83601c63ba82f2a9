"""A compass calibrated from a flight as a standalone SVG picture: the flight seen by its compass.

Three panels over the flight's time, from the calibration's thinned ``series``
(:class:`app.calibration.magnetometer.FlightCompassCalibration`):

1. each axis of the field in the body frame: the one the attitude and the geomagnetic model expect
   (dashed) against the compass's, calibrated by trical (solid) — where they part, the compass is wrong;
2. the field's strength |h|, trical's and the firmware's, beside the model's F, with the battery current
   (or the throttle) on its own scale — a strength that follows the current is the motors' interference;
3. the heading error, the firmware's own calibration (before) and trical's (after, each segment calibrated by
   the fit made without it), in degrees.

No plotting library: plain SVG elements, a ``<title>`` and a ``<desc>`` stating the figures, axes told
apart by dash pattern as well as colour (the Okabe–Ito colours of :mod:`.allan_plot`).
"""

from __future__ import annotations

from html import escape

import numpy as np

from ..errors import ExportError
from .allan_plot import COLOURS, DASHES, FONT, svg_picture
from .common import Export
from .temperature import ticks

WIDTH, PANEL_H = 640, 200
LEFT, RIGHT, TOP, BOTTOM = 56, 56, 30, 34
BEFORE, AFTER, POWER, MODEL = "#d55e00", "#0072b2", "#777777", "#000000"


def _f(v: float) -> str:
    return f"{v:.1f}"


def _column(series: dict, key: str, n: int) -> np.ndarray | None:
    value = series.get(key)
    if value is None:
        return None
    a = np.asarray([np.nan if v is None else v for v in np.asarray(value, dtype=object).reshape(-1)], dtype=float)
    return a.reshape(n, -1) if a.size % n == 0 and a.size > n else a


class _Panel:
    """One panel's axes: time across, ``lo``–``hi`` up, at ``top`` of the picture."""

    def __init__(self, top: float, t: np.ndarray, lo: float, hi: float):
        pad = 0.05 * ((hi - lo) or 1.0)
        self.top, self.t0, self.t1, self.lo, self.hi = top, float(t[0]), float(t[-1]), lo - pad, hi + pad
        self.w, self.h = WIDTH - LEFT - RIGHT, PANEL_H - TOP - BOTTOM

    def x(self, t):
        return LEFT + (np.asarray(t, dtype=float) - self.t0) / ((self.t1 - self.t0) or 1.0) * self.w

    def y(self, v, lo=None, hi=None):
        lo = self.lo if lo is None else lo
        hi = self.hi if hi is None else hi
        return self.top + TOP + (hi - np.asarray(v, dtype=float)) / ((hi - lo) or 1.0) * self.h

    def frame(self, title: str, unit: str) -> list[str]:
        out = [
            f'<text x="{LEFT}" y="{_f(self.top + 20)}" font-size="13" font-weight="bold" {FONT}>{escape(title)}</text>',
            f'<rect x="{LEFT}" y="{_f(self.top + TOP)}" width="{self.w}" height="{self.h}" fill="none" stroke="#888"/>',
        ]
        for v in ticks(self.lo, self.hi, 4):
            y = float(self.y(v))
            out.append(f'<line x1="{LEFT}" x2="{LEFT + self.w}" y1="{_f(y)}" y2="{_f(y)}" stroke="#e4e4e4"/>')
            out.append(f'<text x="{LEFT - 4}" y="{_f(y + 4)}" font-size="10" text-anchor="end" {FONT}>{v:g}</text>')
        for v in ticks(self.t0, self.t1, 6):
            out.append(
                f'<text x="{_f(float(self.x(v)))}" y="{_f(self.top + TOP + self.h + 14)}" font-size="10" '
                f'text-anchor="middle" {FONT}>{v:g}</text>'
            )
        out.append(
            f'<text x="{LEFT + self.w / 2}" y="{_f(self.top + TOP + self.h + 28)}" font-size="10" '
            f'text-anchor="middle" {FONT}>time in the log, s</text>'
        )
        out.append(
            f'<text x="{LEFT - 4}" y="{_f(self.top + TOP - 4)}" font-size="10" text-anchor="end" {FONT}>'
            f"{escape(unit)}</text>"
        )
        return out

    def line(
        self, t, v, colour: str, *, dash: str | None = None, cls: str = "", width: float = 1.4, lo=None, hi=None
    ) -> str:
        good = np.isfinite(v)
        points = " ".join(f"{float(a):.1f},{float(b):.1f}" for a, b in zip(self.x(t[good]), self.y(v[good], lo, hi)))
        dashed = f' stroke-dasharray="{dash}"' if dash else ""
        return (
            f'<polyline class="{cls}" points="{points}" fill="none" stroke="{colour}" stroke-width="{width}"{dashed}/>'
        )

    def legend(self, k: int, colour: str, words: str, dash: str | None = None) -> str:
        x = LEFT + 8 + 150 * k
        y = self.top + TOP + 12
        dashed = f' stroke-dasharray="{dash}"' if dash else ""
        return (
            f'<line x1="{x}" x2="{x + 18}" y1="{y - 4}" y2="{y - 4}" stroke="{colour}" stroke-width="2"{dashed}/>'
            f'<text x="{x + 22}" y="{y}" font-size="10" {FONT}>{escape(words)}</text>'
        )


def flight_compass_svg(body: dict) -> str:
    """The flight seen by its compass (see the module's docstring), with a ``<title>`` and a ``<desc>``."""
    series = body.get("series") or {}
    t = np.asarray(series.get("time_s") or [], dtype=float)
    n = len(t)
    expected, corrected = _column(series, "expected", n), _column(series, "corrected", n)
    if n < 2 or expected is None or corrected is None or expected.shape != (n, 3) or corrected.shape != (n, 3):
        raise ExportError(
            "this compass calibration keeps no series of the flight to draw: calibrate the flight log again"
        )
    firmware = _column(series, "firmware", n)
    power = _column(series, "power", n)
    before, after = _column(series, "heading_error_before", n), _column(series, "heading_error_after", n)
    flight, metrics = body.get("flight") or {}, body.get("metrics") or {}
    panels = [
        _field_panel(t, expected, corrected),
        _strength_panel(t, corrected, firmware, power, flight, metrics),
        _heading_panel(t, before, after, metrics),
    ]
    parts = [part for panel_parts, _ in panels for part in panel_parts]
    said = [words for _, words in panels if words]
    height = PANEL_H * (3 if panels[2][0] else 2)
    return svg_picture(WIDTH, height, f"The flight seen by its compass, {body.get('id', '')}", " ".join(said), parts)


def _field_panel(t, expected, corrected) -> tuple[list[str], str]:
    """1. The field per axis, expected against calibrated."""
    parts = []
    lo, hi = float(np.nanmin([expected.min(), corrected.min()])), float(np.nanmax([expected.max(), corrected.max()]))
    p = _Panel(0, t, lo, hi)
    parts += p.frame("The field in the vehicle's frame: expected (dashed) and calibrated (solid)", "µT")
    for i, axis in enumerate("xyz"):
        parts.append(p.line(t, expected[:, i], COLOURS[axis], dash="5 3", cls=f"expected-{axis}"))
        parts.append(p.line(t, corrected[:, i], COLOURS[axis], cls=f"corrected-{axis}"))
        parts.append(p.legend(i, COLOURS[axis], f"{axis} ({['forward', 'right', 'down'][i]})", DASHES[axis]))
    return parts, (
        "The field's three axes in the vehicle's frame over the flight, expected from the attitude and "
        "the geomagnetic model, and as the compass reads it calibrated."
    )


def _strength_panel(t, corrected, firmware, power, flight: dict, metrics: dict) -> tuple[list[str], str]:
    """2. |h| beside the current."""
    parts = []
    F = metrics.get("field_ut")
    strength = np.linalg.norm(corrected, axis=1)
    values = [strength] + ([np.linalg.norm(firmware, axis=1)] if firmware is not None else [])
    lo = float(min(np.nanmin(v) for v in values + ([np.array([F])] if F else [])))
    hi = float(max(np.nanmax(v) for v in values + ([np.array([F])] if F else [])))
    p = _Panel(PANEL_H, t, lo, hi)
    parts += p.frame(
        "The field's strength |h|, and the motors' " + ("current" if flight.get("motor") != "throttle" else "throttle"),
        "µT",
    )
    if F:
        parts.append(p.line(np.array([t[0], t[-1]]), np.array([F, F]), MODEL, dash="2 2", cls="model-field"))
    if firmware is not None:
        parts.append(p.line(t, values[1], BEFORE, cls="strength-firmware"))
    parts.append(p.line(t, strength, AFTER, cls="strength-trical", width=1.8))
    parts.append(p.legend(0, AFTER, "trical"))
    if firmware is not None:
        parts.append(p.legend(1, BEFORE, "the firmware's"))
    if F:
        parts.append(p.legend(2, MODEL, f"the model's {F:.1f} µT", "2 2"))
    if power is not None and np.isfinite(power).any():
        plo, phi = float(np.nanmin(power)), float(np.nanmax(power))
        phi = phi if phi > plo else plo + 1.0
        parts.append(p.line(t, power, POWER, dash="1 2", cls="power", lo=plo, hi=phi))
        unit = "A" if flight.get("power_source") is None or "hrottle" not in str(flight.get("power_source")) else ""
        parts.append(
            f'<text x="{WIDTH - RIGHT + 4}" y="{_f(p.top + TOP + 8)}" font-size="10" {FONT}>{phi:.3g} '
            f'{unit}</text><text x="{WIDTH - RIGHT + 4}" y="{_f(p.top + TOP + p.h)}" font-size="10" {FONT}>'
            f"{plo:.3g} {unit}</text>"
        )
        parts.append(p.legend(3, POWER, "power (right)", "1 2"))
    return parts, "The calibrated field's strength against the model's, with the power on its own scale."


def _heading_panel(t, before, after, metrics: dict) -> tuple[list[str], str | None]:
    """3. The heading error (no panel without one)."""
    errors = [a for a in (before, after) if a is not None and np.isfinite(a).any()]
    if not errors:
        return [], None
    parts = []
    lo = float(min(np.nanmin(a) for a in errors))
    hi = float(max(np.nanmax(a) for a in errors))
    p = _Panel(2 * PANEL_H, t, min(lo, 0.0), max(hi, 0.0))
    parts += p.frame("Heading error: the firmware's calibration and trical's, on segments left out", "°")
    if before is not None:
        parts.append(p.line(t, before, BEFORE, cls="heading-before"))
        parts.append(p.legend(0, BEFORE, "before (the firmware's)"))
    if after is not None:
        parts.append(p.line(t, after, AFTER, cls="heading-after", width=1.8))
        parts.append(p.legend(1, AFTER, "after (trical's)"))
    b, a = metrics.get("heading_error_before_deg"), metrics.get("heading_error_after_deg")
    return parts, (
        "The heading error over the flight, rms "
        + (f"{b:.1f}° before and " if b is not None else "")
        + (f"{a:.1f}° after." if a is not None else "not measured after.")
    )


def to_flight_compass_svg(body: dict) -> Export:
    return Export(flight_compass_svg(body), "image/svg+xml", f"{body.get('id', 'compass')}_flight.svg")
