"""The Allan deviation of a noise characterisation as a standalone SVG picture.

One panel per sensor (stacked): the log–log overlapping Allan deviation σ(τ) of each axis with its
95 % band, the fitted slopes of the noise terms and their marks, as read in IEEE Std 952-1997,
Annex C, and El-Sheimy, Hou and Niu, *Analysis and Modeling of Inertial Sensors Using Allan
Variance*, IEEE Trans. Instrum. Meas. 57(1) 2008, Table I:

- white noise, slope −½: σ(τ) = N / √τ, read at τ = 1 s;
- random walk, slope +½: σ(τ) = K √(τ / 3), read at τ = 3 s;
- bias instability, the flat floor σ = √(2 ln 2 / π) B ≈ 0.664 B, at the minimum of the curve.

No plotting library: plain SVG elements with presentation attributes, a ``<title>`` and a
``<desc>`` that states every value, text labels, and axes told apart by dash pattern and marker as
well as colour. Terms that are null (a recording too short to show them) are not drawn, and the
panel says so.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from html import escape

import numpy as np

from app.calibration.noise.characterise import TERM_WORDS
from app.calibration.shared.headlines import SENSOR_WORDS
from app.calibration.shared.result import FIGURES

from ..errors import ExportError
from .common import Export, result_class

AXES = ("x", "y", "z")
SENSOR_ORDER = ("acc", "gyr", "mag")
FLOOR = math.sqrt(2 * math.log(2) / math.pi)  # 0.664: IEEE Std 952-1997 Annex C, bias instability
TAU_N, TAU_K = 1.0, 3.0  # where the −½ and +½ lines are read (El-Sheimy et al. 2008, Table I)

# Okabe–Ito colours (distinguishable with the common colour-vision deficiencies), each axis with its
# own dash pattern and marker so that the picture reads in grey too.
COLOURS = {"x": "#0072b2", "y": "#d55e00", "z": "#009e73"}
DASHES = {"x": None, "y": "7 3", "z": "2 2.5"}
GLYPHS = {"x": "●", "y": "■", "z": "▲"}
FIT_DASH = "9 3 2 3"
FONT = 'font-family="DejaVu Sans, Verdana, sans-serif"'

WIDTH = 400
MARGIN = {"left": 56, "right": 12, "top": 30, "bottom": 44}
PLOT_H = 250
LINE_H = 15

TERMS = (  # key in the model, mark class, symbol, where it is read
    ("noise_density", "noise-density", "N", "at τ = 1 s"),
    ("random_walk", "random-walk", "K", "at τ = 3 s"),
    ("bias_instability", "bias-instability", "B", "(floor 0.664 B)"),
)


@dataclass(frozen=True)
class LogAxes:
    """The plot area of one panel and its log–log transform (τ in s, σ in the sensor's unit)."""

    left: float
    top: float
    width: float
    height: float
    tau_decades: tuple[int, int]
    adev_decades: tuple[int, int]

    def x(self, tau: float) -> float:
        a, b = self.tau_decades
        return self.left + (math.log10(tau) - a) / (b - a) * self.width

    def y(self, sigma: float) -> float:
        a, b = self.adev_decades
        return self.top + (b - math.log10(sigma)) / (b - a) * self.height

    def inside(self, px: float, py: float) -> bool:
        return (
            self.left - 0.5 <= px <= self.left + self.width + 0.5
            and self.top - 0.5 <= py <= self.top + self.height + 0.5
        )


def svg_picture(width: int, height: int, title: str, desc: str, parts: list[str]) -> str:
    """A standalone SVG picture of ``width`` × ``height`` user units on white, with its ``<title>`` and a
    ``<desc>`` stating its figures (what a screen reader says of it): the envelope of every plot trical draws."""
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" '
        f'role="img"><title>{escape(title)}</title><desc>{escape(desc)}</desc>'
        f'<rect width="100%" height="100%" fill="#fff"/>' + "".join(parts) + "</svg>\n"
    )


def number(v: float) -> str:
    """Three significant digits; below 0.01 or from 10⁴ on, as 5.09×10⁻⁴ rather than 0.000509."""
    if v == 0 or 0.01 <= abs(v) < 1e4:
        return f"{v:.3g}"
    mantissa, exponent = f"{v:.2e}".split("e")
    mantissa = mantissa.rstrip("0").rstrip(".")
    return f"{mantissa}×10{_superscript(int(exponent))}"


def pretty_unit(unit: str) -> str:
    """A unit as people write it: m/s^2 → m/s², uT → µT."""
    return unit.replace("^2", "²").replace("^3", "³").replace("uT", "µT")


def _superscript(n: int) -> str:
    return str(n).translate(str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹"))


def _decade_label(k: int) -> str:
    return {0: "1", 1: "10"}.get(k, f"10{_superscript(k)}")


def _f(v: float) -> str:
    return f"{v:.2f}".rstrip("0").rstrip(".")


def _rows(values, n: int) -> np.ndarray:
    """A list of [x, y, z] rows (entries may be null) as an n × 3 float array, NaN for null."""
    if values is None:
        return np.full((n, 3), np.nan)
    out = np.array([[np.nan if v is None else float(v) for v in row] for row in values], dtype=float)
    return out.reshape(n, 3)


def _term(values, i: int) -> float | None:
    if values is None or values[i] is None or not math.isfinite(values[i]) or values[i] <= 0:
        return None
    return float(values[i])


def _points(axes: LogAxes, tau: np.ndarray, sigma: np.ndarray) -> list[list[tuple[float, float]]]:
    """Runs of drawable points (finite, positive), split where a value is missing."""
    runs, run = [], []
    for t, s in zip(tau, sigma):
        if math.isfinite(s) and s > 0:
            run.append((axes.x(t), axes.y(s)))
        elif run:
            runs.append(run)
            run = []
    if run:
        runs.append(run)
    return runs


def _path(runs) -> str:
    return " ".join("M " + " L ".join(f"{_f(x)} {_f(y)}" for x, y in run) for run in runs if run)


def _marker(axis: str, x: float, y: float, r: float = 3.2) -> str:
    fill = COLOURS[axis]
    if axis == "x":
        return f'<circle cx="{_f(x)}" cy="{_f(y)}" r="{_f(r)}" fill="{fill}" stroke="#fff" stroke-width="0.8"/>'
    if axis == "y":
        return (
            f'<rect x="{_f(x - r)}" y="{_f(y - r)}" width="{_f(2 * r)}" height="{_f(2 * r)}" fill="{fill}" '
            f'stroke="#fff" stroke-width="0.8"/>'
        )
    h = r * 1.2
    return (
        f'<path d="M {_f(x)} {_f(y - h)} L {_f(x + h)} {_f(y + h * 0.8)} L {_f(x - h)} {_f(y + h * 0.8)} Z" '
        f'fill="{fill}" stroke="#fff" stroke-width="0.8"/>'
    )


def _stroke(axis: str, width: float, dash: str | None) -> str:
    d = f' stroke-dasharray="{dash}"' if dash else ""
    return f'fill="none" stroke="{COLOURS[axis]}" stroke-width="{width}"{d} stroke-linejoin="round"'


def _text(
    x: float,
    y: float,
    content: str,
    size: float = 11,
    anchor: str = "start",
    extra: str = "",
    markup: str | None = None,
) -> str:
    """A text element; ``markup`` (already escaped, e.g. with a coloured tspan) replaces ``content``."""
    return (
        f'<text x="{_f(x)}" y="{_f(y)}" font-size="{size}" text-anchor="{anchor}" {FONT} fill="#222"'
        f"{extra}>{escape(content) if markup is None else markup}</text>"
    )


HALO = ' stroke="#fff" stroke-width="3" stroke-linejoin="round" paint-order="stroke"'
"""A white outline under the glyphs keeps a label readable where it crosses a line."""


def _halo_text(x: float, y: float, content: str, size: float = 11, anchor: str = "start") -> str:
    return _text(x, y, content, size, anchor, HALO)


@dataclass
class _Sensor:
    """One panel's data, read from the body."""

    name: str
    unit: str
    tau: np.ndarray
    value: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    terms: dict  # term key -> [value or None] × 3
    units: dict  # term key -> unit text


def _read_sensor(body: dict, sensor: str) -> _Sensor:
    model = body["model"][sensor]
    curve = (body.get("adev") or {}).get(sensor) or {}
    tau = np.asarray(curve.get("tau_s") or [], dtype=float)
    n = tau.size
    return _Sensor(
        sensor,
        pretty_unit(model.get("unit") or ""),
        tau,
        _rows(curve.get("value"), n),
        _rows(curve.get("lo"), n),
        _rows(curve.get("hi"), n),
        {key: [_term(model.get(key), i) for i in range(3)] for key, *_ in TERMS},
        {key: pretty_unit(model.get(f"{key}_unit") or "") for key, *_ in TERMS},
    )


def _decades(values: list[float], pad: float) -> tuple[int, int]:
    logs = [math.log10(v) for v in values if math.isfinite(v) and v > 0]
    if not logs:
        return 0, 1
    a, b = math.floor(min(logs) - pad), math.ceil(max(logs) + pad / 4)
    return (a, b) if b > a else (a, a + 1)


def _room(decades: tuple[int, int]) -> tuple[int, int]:
    """Fewer than five decades of σ leave too little room for the labels: one more below."""
    return (decades[0] - 1, decades[1]) if decades[1] - decades[0] < 5 else decades


def _floor_tau(s: _Sensor, i: int) -> float | None:
    """τ of the curve's minimum for axis i: where the bias-instability floor is read."""
    v = s.value[:, i]
    ok = np.isfinite(v) & (v > 0)
    return float(s.tau[ok][np.argmin(v[ok])]) if ok.any() else None


def _mark_points(s: _Sensor) -> dict:
    """Each term's mark per axis: (τ, σ) on its fitted line, or None for a null term."""
    out: dict[str, list] = {}
    for key, *_ in TERMS:
        out[key] = []
        for i in range(3):
            v = s.terms[key][i]
            if v is None:
                out[key].append(None)
            elif key == "noise_density":
                out[key].append((TAU_N, v))  # σ(1 s) = N
            elif key == "random_walk":
                out[key].append((TAU_K, v))  # σ(3 s) = K √(3/3) = K
            else:
                tau_min = _floor_tau(s, i)
                out[key].append(None if tau_min is None else (tau_min, FLOOR * v))
    return out


def _fit_lines(s: _Sensor, axes: LogAxes, marks: dict) -> tuple[list[str], list]:
    """The fitted slopes, drawn across the whole plot and clipped to it, and their end points."""
    a, b = (10.0**d for d in axes.tau_decades)
    out, ends_px = [], []
    for i, axis in enumerate(AXES):
        lines = []
        if (n := s.terms["noise_density"][i]) is not None:
            lines.append(("white-noise", [(a, n / math.sqrt(a)), (b, n / math.sqrt(b))]))
        if (k := s.terms["random_walk"][i]) is not None:
            lines.append(("random-walk", [(a, k * math.sqrt(a / 3)), (b, k * math.sqrt(b / 3))]))
        if marks["bias_instability"][i] is not None:
            tau_min, level = marks["bias_instability"][i]
            lines.append(("bias-instability", [(max(a, tau_min / 10), level), (min(b, tau_min * 10), level)]))
        for cls, ends in lines:
            ends_px.append([(axes.x(t), axes.y(v)) for t, v in ends])
            d = _path([ends_px[-1]])
            out.append(
                f'<path class="fit {cls}" data-axis="{axis}" d="{d}" {_stroke(axis, 1.2, FIT_DASH)} opacity="0.85"/>'
            )
    return out, ends_px


def _place(
    axes: LogAxes,
    anchor: tuple[float, float],
    w: float,
    h: float,
    obstacles: np.ndarray,
    placed: list[tuple[float, float, float, float]],
) -> tuple[float, float]:
    """The top-left corner of a w × h label inside the plot that covers the least: each obstacle
    point costs its weight, another label forbids, and every 40 px away from the anchor costs one."""
    xs = np.arange(axes.left + 2, axes.left + axes.width - w - 1, 6.0)
    ys = np.arange(axes.top + 2, axes.top + axes.height - h - 1, 6.0)
    if not xs.size or not ys.size:
        return axes.left + 2, axes.top + 2
    x0, y0 = np.meshgrid(xs, ys, indexing="ij")
    x0, y0 = x0.ravel(), y0.ravel()
    cost = np.zeros(x0.size)
    if obstacles.size:
        px, py, weight = obstacles[:, 0], obstacles[:, 1], obstacles[:, 2]
        inside = (px >= x0[:, None]) & (px <= x0[:, None] + w) & (py >= y0[:, None]) & (py <= y0[:, None] + h)
        cost += inside @ weight
    for q in placed:
        cost += 1000 * ((x0 < q[2]) & (q[0] < x0 + w) & (y0 < q[3]) & (q[1] < y0 + h))
    ax, ay = anchor
    dx = np.maximum(np.maximum(x0 - ax, ax - (x0 + w)), 0)
    dy = np.maximum(np.maximum(y0 - ay, ay - (y0 + h)), 0)
    cost += np.hypot(dx, dy) / 40
    k = int(np.argmin(cost))
    return float(x0[k]), float(y0[k])


def _obstacles(runs_by_axis: list, fits: list, marks: list[tuple[float, float]]) -> np.ndarray:
    """Points a label should not cover, with their weights: the curves every 3 px (1), the fitted
    lines (0.3) and the marks (40: never hide one)."""
    rows = []
    for runs, weight in [(r, 1.0) for r in runs_by_axis] + [([f], 0.3) for f in fits]:
        for run in runs:
            for (xa, ya), (xb, yb) in itertools.pairwise(run):
                n = max(1, int(math.hypot(xb - xa, yb - ya) / 3))
                t = np.linspace(0, 1, n, endpoint=False)
                rows.append(np.column_stack([xa + t * (xb - xa), ya + t * (yb - ya), np.full(n, weight)]))
    if marks:
        rows.append(np.column_stack([np.asarray(marks, dtype=float), np.full(len(marks), 40.0)]))
    return np.vstack(rows) if rows else np.zeros((0, 3))


def _label_blocks(s: _Sensor, axes: LogAxes, marks: dict, obstacles: np.ndarray) -> list[str]:
    """One block of text per term, next to its marks: the symbol, where it is read, the unit, and
    one line per axis with its marker glyph and value. Each block goes where it covers the fewest
    drawn points, inside the plot."""
    placed: list[tuple[float, float, float, float]] = []
    out = []
    for key, cls, symbol, where in TERMS:
        pts = [(axes.x(p[0]), axes.y(p[1])) for p in marks[key] if p is not None]
        pts = [p for p in pts if axes.inside(*p)]
        values = s.terms[key]
        if not any(v is not None for v in values):
            continue
        head = [f"{symbol} {where}", f"in {s.units[key]}"]
        lines = head + [f"{GLYPHS[a]} {a}  {number(v)}" for a, v in zip(AXES, values) if v is not None]
        w = max(len(t) for t in lines) * 6.6 + 6
        h = len(lines) * 14 + 4
        if pts:
            cx, cy = sum(p[0] for p in pts) / len(pts), sum(p[1] for p in pts) / len(pts)
        else:
            cx, cy = axes.left + axes.width / 2, axes.top + axes.height / 2
        x0, y0 = _place(axes, (cx, cy), w, h, obstacles, placed)
        placed.append((x0, y0, x0 + w, y0 + h))
        body = "".join(_halo_text(x0 + 3, y0 + 14 * (j + 1), t, 11) for j, t in enumerate(head))
        body += "".join(
            _text(
                x0 + 3,
                y0 + 14 * (j + 3),
                "",
                11,
                extra=HALO,
                markup=f'<tspan fill="{COLOURS[a]}">{GLYPHS[a]}</tspan> {a}  {escape(number(v))}',
            )
            for j, (a, v) in enumerate((a, v) for a, v in zip(AXES, values) if v is not None)
        )
        out.append(f'<g class="label {cls}">{body}</g>')
    return out


def _panel(s: _Sensor, top: float, index: int) -> tuple[str, float, str]:
    """The SVG group of one sensor's panel, its height, and the sentence that describes it."""
    marks = _mark_points(s)
    taus = list(s.tau) + [p[0] for key in marks for p in marks[key] if p is not None]
    sigmas = [v for arr in (s.value, s.lo, s.hi) for v in arr.ravel()]
    sigmas += [p[1] for key in marks for p in marks[key] if p is not None]
    axes = LogAxes(
        MARGIN["left"],
        top + MARGIN["top"],
        WIDTH - MARGIN["left"] - MARGIN["right"],
        PLOT_H,
        _decades(taus, 0.0),
        _room(_decades(sigmas, 0.3)),
    )
    title = f"{SENSOR_WORDS[s.name].capitalize()} ({s.unit})" if s.unit else SENSOR_WORDS[s.name].capitalize()
    clip = f"plot-{index}"
    g = [
        f'<g class="panel" data-sensor="{s.name}">',
        _text(axes.left, top + 18, title, 14, extra=' font-weight="bold"'),
        f'<clipPath id="{clip}"><rect x="{_f(axes.left)}" y="{_f(axes.top)}" width="{_f(axes.width)}" '
        f'height="{_f(axes.height)}"/></clipPath>',
        f'<rect class="plot-area" x="{_f(axes.left)}" y="{_f(axes.top)}" width="{_f(axes.width)}" '
        f'height="{_f(axes.height)}" fill="#fff" stroke="#888" stroke-width="1" '
        f'data-log-tau="{axes.tau_decades[0]} {axes.tau_decades[1]}" '
        f'data-log-adev="{axes.adev_decades[0]} {axes.adev_decades[1]}"/>',
    ]
    g += _grid(axes, s.unit)
    plot = []
    curves, mark_px = [], []
    for i, axis in enumerate(AXES):
        lo, hi = s.lo[:, i], s.hi[:, i]
        ok = np.isfinite(lo) & np.isfinite(hi) & (lo > 0) & (hi > 0)
        if ok.sum() >= 2:
            upper = [(axes.x(t), axes.y(v)) for t, v in zip(s.tau[ok], hi[ok])]
            lower = [(axes.x(t), axes.y(v)) for t, v in zip(s.tau[ok], lo[ok])][::-1]
            plot.append(
                f'<path class="band" data-axis="{axis}" d="{_path([upper + lower])} Z" '
                f'fill="{COLOURS[axis]}" fill-opacity="0.13" stroke="none"/>'
            )
    fits, fit_ends = _fit_lines(s, axes, marks)
    plot += fits
    for i, axis in enumerate(AXES):
        runs = _points(axes, s.tau, s.value[:, i])
        if not runs:
            continue
        plot.append(f'<path class="adev" data-axis="{axis}" d="{_path(runs)}" {_stroke(axis, 2, DASHES[axis])}/>')
        flat = [p for run in runs for p in run]
        curves.append(runs)
        step = max(1, len(flat) // 8)
        plot += [_marker(axis, x, y) for x, y in flat[i * step // 3 :: step]]
    g.append(f'<g clip-path="url(#{clip})">{"".join(plot)}</g>')
    for key, cls, _symbol, _ in TERMS:
        for axis, p in zip(AXES, marks[key]):
            if p is None or not axes.inside(axes.x(p[0]), axes.y(p[1])):
                continue
            x, y = axes.x(p[0]), axes.y(p[1])
            g.append(
                f'<g class="mark {cls}" data-axis="{axis}" data-tau="{p[0]:.6g}" data-value="{p[1]:.6g}">'
                f"{_ring(axis, x, y)}</g>"
            )
            mark_px.append((x, y))
    g += _label_blocks(s, axes, marks, _obstacles(curves, fit_ends, mark_px))
    y = axes.top + axes.height + 40
    g += _legend(axes.left, y + 10)
    y += 10 + 2 * LINE_H
    missing = _missing(s)
    if missing:
        note = f"Not drawn: {missing} (the recording is too short to show them)."
        for line in _wrap(note, 56):
            y += LINE_H
            g.append(_text(axes.left, y, line, 11, extra=' class="note" font-style="italic"'))
    if not s.tau.size:
        g.append(
            _halo_text(
                axes.left + axes.width / 2,
                axes.top + axes.height / 2,
                "No Allan deviation in this calibration",
                12,
                "middle",
            )
        )
    g.append("</g>")
    return "".join(g), y + 12 - top, _describe(s, marks, missing)


def _ring(axis: str, x: float, y: float) -> str:
    """A mark: a larger hollow marker of the axis, ringed in black so it stands out of the curves."""
    return f'<circle cx="{_f(x)}" cy="{_f(y)}" r="6.5" fill="none" stroke="#111" stroke-width="1.4"/>' + _marker(
        axis, x, y, 3.4
    )


def _grid(axes: LogAxes, unit: str) -> list[str]:
    out = []
    bottom = axes.top + axes.height
    for k in range(axes.tau_decades[0], axes.tau_decades[1] + 1):
        x = axes.x(10.0**k)
        out.append(
            f'<line class="tick tau" data-log10="{k}" x1="{_f(x)}" y1="{_f(axes.top)}" x2="{_f(x)}" '
            f'y2="{_f(bottom + 4)}" stroke="#ddd" stroke-width="1"/>'
        )
        out.append(_text(x, bottom + 17, _decade_label(k), 12, "middle", f' class="tick-label tau" data-log10="{k}"'))
        for m in range(2, 10) if k < axes.tau_decades[1] else ():
            xm = axes.x(m * 10.0**k)
            out.append(f'<line x1="{_f(xm)}" y1="{_f(bottom - 3)}" x2="{_f(xm)}" y2="{_f(bottom)}" stroke="#888"/>')
    for k in range(axes.adev_decades[0], axes.adev_decades[1] + 1):
        y = axes.y(10.0**k)
        out.append(
            f'<line class="tick adev" data-log10="{k}" x1="{_f(axes.left - 4)}" y1="{_f(y)}" '
            f'x2="{_f(axes.left + axes.width)}" y2="{_f(y)}" stroke="#ddd" stroke-width="1"/>'
        )
        out.append(
            _text(axes.left - 6, y + 4, _decade_label(k), 12, "end", f' class="tick-label adev" data-log10="{k}"')
        )
        for m in range(2, 10) if k < axes.adev_decades[1] else ():
            ym = axes.y(m * 10.0**k)
            out.append(
                f'<line x1="{_f(axes.left)}" y1="{_f(ym)}" x2="{_f(axes.left + 3)}" y2="{_f(ym)}" stroke="#888"/>'
            )
    out.append(_text(axes.left + axes.width / 2, bottom + 33, "τ (s)", 13, "middle", ' class="axis-label"'))
    cy = axes.top + axes.height / 2
    out.append(
        _text(
            14,
            cy,
            f"Allan deviation ({unit})" if unit else "Allan deviation",
            13,
            "middle",
            f' class="axis-label" transform="rotate(-90 14 {_f(cy)})"',
        )
    )
    return out


def _legend(x: float, y: float) -> list[str]:
    out = []
    for j, axis in enumerate(AXES):
        x0 = x + j * 62
        out.append(f'<path d="M {_f(x0)} {_f(y - 4)} L {_f(x0 + 28)} {_f(y - 4)}" {_stroke(axis, 2, DASHES[axis])}/>')
        out.append(_marker(axis, x0 + 14, y - 4))
        out.append(_text(x0 + 33, y, axis, 11))
    x0 = x + 3 * 62
    out.append(f'<rect x="{_f(x0)}" y="{_f(y - 10)}" width="16" height="11" fill="#555" fill-opacity="0.2"/>')
    out.append(_text(x0 + 21, y, "95 % band", 11))
    y += LINE_H
    out.append(
        f'<path d="M {_f(x)} {_f(y - 4)} L {_f(x + 28)} {_f(y - 4)}" fill="none" stroke="#444" '
        f'stroke-width="1.2" stroke-dasharray="{FIT_DASH}"/>'
    )
    out.append(_text(x + 33, y, "fitted: −½ (N), +½ (K), floor 0.664 B", 11))
    out.append(f'<circle cx="{_f(x + 296)}" cy="{_f(y - 4)}" r="5.5" fill="none" stroke="#111" stroke-width="1.4"/>')
    out.append(_text(x + 305, y, "mark", 11))
    return out


def _missing(s: _Sensor) -> str:
    parts = []
    for key, _, symbol, _ in TERMS:
        axes = [a for a, v in zip(AXES, s.terms[key]) if v is None]
        if axes:
            parts.append(f"{TERM_WORDS[key]} {symbol} of {', '.join(axes)}")
    return "; ".join(parts)


def _wrap(text: str, width: int) -> list[str]:
    lines, line = [], ""
    for word in text.split():
        if line and len(line) + 1 + len(word) > width:
            lines.append(line)
            line = word
        else:
            line = f"{line} {word}" if line else word
    return lines + [line] if line else lines


def _describe(s: _Sensor, marks: dict, missing: str) -> str:
    if s.tau.size:
        span = f"for τ from {number(float(s.tau.min()))} s to {number(float(s.tau.max()))} s"
    else:
        span = "with no curve"
    parts = [
        f"{SENSOR_WORDS[s.name].capitalize()}: Allan deviation in {s.unit} of axes x, y, z {span}, with 95 % bands."
    ]
    for key, _, symbol, where in TERMS:
        vals = [f"{a} {number(v)}" for a, v in zip(AXES, s.terms[key]) if v is not None]
        if vals:
            parts.append(f"{TERM_WORDS[key].capitalize()} {symbol} {where} in {s.units[key]}: {', '.join(vals)}.")
    if missing:
        parts.append(f"Not available: {missing}.")
    return " ".join(parts)


def _sensors(body: dict, sensor: str | None) -> list[str]:
    model = body.get("model") or {}
    if result_class(body).KIND != FIGURES:
        raise ExportError(
            f"the allan_svg export draws a noise characterisation (method noise); "
            f"this calibration is {body.get('method')!r}: export it as json, c, yaml or csv"
        )
    present = [k for k in SENSOR_ORDER if isinstance(model.get(k), dict)]
    if sensor is None:
        if not present:
            raise ExportError("the noise calibration holds no sensor (acc, gyr or mag) to draw")
        return present
    if sensor not in present:
        raise ExportError(f"the noise calibration holds no {sensor!r} sensor: choose one of {', '.join(present)}")
    return [sensor]


def allan_svg(body: dict, sensor: str | None = None) -> str:
    """The log–log Allan deviation of a noise calibration as a standalone SVG document.

    Parameters
    ----------
    body : dict
        A stored calibration of ``method: "noise"``: ``model[sensor]`` with ``unit`` and the terms
        ``noise_density``, ``random_walk``, ``bias_instability`` (3 entries each, null when the
        recording is too short) and their units; ``adev[sensor]`` with ``tau_s`` (n) and
        ``value``, ``lo``, ``hi`` (n rows of x, y, z).
    sensor : {"acc", "gyr", "mag"}, optional
        One sensor's panel; by default one panel per sensor the calibration holds, stacked.

    Returns
    -------
    str
        The SVG document (UTF-8 text), with a ``<title>`` and a ``<desc>`` stating every value.

    Raises
    ------
    ExportError
        The body is not a noise calibration, or holds no such sensor.
    """
    panels, descs, top = [], [], 0.0
    for index, name in enumerate(_sensors(body, sensor)):
        svg, height, desc = _panel(_read_sensor(body, name), top, index)
        panels.append(svg)
        descs.append(desc)
        top += height
    names = ", ".join(SENSOR_WORDS[p] for p in _sensors(body, sensor))
    title = f"Allan deviation of the {names}" + (f", calibration {body['id']}" if body.get("id") else "")
    desc = (
        "Log–log overlapping Allan deviation against the averaging time τ, one line per axis; "
        "fitted lines: white noise σ = N/√τ (slope −½), random walk σ = K·√(τ/3) (slope +½), "
        "bias instability floor 0.664 B. " + " ".join(descs)
    )
    height = math.ceil(top)
    return (
        f'<?xml version="1.0" encoding="UTF-8"?>\n'
        f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{WIDTH * 3 // 2}" '
        f'height="{height * 3 // 2}" viewBox="0 0 {WIDTH} {height}" role="img" '
        f'aria-labelledby="allan-title allan-desc">\n'
        f'<title id="allan-title">{escape(title)}</title>\n<desc id="allan-desc">{escape(desc)}</desc>\n'
        f'<rect width="{WIDTH}" height="{height}" fill="#fff"/>\n' + "\n".join(panels) + "\n</svg>\n"
    )


def to_allan_svg(body: dict) -> Export:
    """The export of a noise calibration's Allan deviation plot (``format=allan_svg``)."""
    return Export(allan_svg(body), "image/svg+xml", f"allan_{body.get('id', 'noise')}.svg")
