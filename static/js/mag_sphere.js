// The compass's sphere of field directions, as SVG strings (pure, no DOM), after MotionCal's view:
// the 20 faces of an icosahedron on the sphere (app/calibration/magnetometer/coverage.py, from
// tables.js), green once covered, and the readings as dots. Each sphere is drawn from two sides, so
// that every face shows: from the screen side, above and to the right (x right, y up the screen, z
// out of it), and from the opposite side (the back: x then points left). Orthographic projection;
// a face reaching behind the sphere is cut at its rim. Shared by the compass wizard (live) and the
// start page (a result, before and after).

import { TABLES } from "./tables.js";
import { WORDS } from "./source.js";

const C = TABLES.compass;
const R = 66; // disc radius at scale 1
const PAD = 20;
const SIZE = 2 * R + 2 * PAD;
const GAP = 14;
const EDGE_STEPS = 6; // each face edge drawn as a polyline on the sphere

function unit(v) {
  const n = Math.hypot(v[0], v[1], v[2]);
  return n > 0 ? [v[0] / n, v[1] / n, v[2] / n] : [0, 0, 0];
}
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const fmt = (v) => v.toFixed(1);

// The camera: towards it d, the screen's right e1 and up e2 (y of the phone stays up the picture).
function camera(d) {
  const toward = unit(d);
  const e1 = unit(cross([0, 1, 0], toward));
  return { d: toward, e1, e2: cross(toward, e1) };
}
// The two views, titled by the sides of the device (a phone's screen side, a board's component side).
export const VIEWS = [{ cam: camera([0.45, 0.55, 1]) }, { cam: camera([-0.45, -0.55, -1]) }];

// The words of the device a stored calibration's readings came from (its `source`): a phone's, a board's
// (a flight controller is a board); without one, the page's own.
export function sourceWords(cal) {
  if (!cal || !cal.source) return WORDS;
  return TABLES.sources[cal.source === "phone" ? "phone" : "board"];
}

// A point of the unit sphere behind the picture plane is moved onto the rim (the cut).
function onFront(p, cam) {
  const depth = dot(p, cam.d);
  if (depth >= 0) return p;
  return unit([p[0] - depth * cam.d[0], p[1] - depth * cam.d[1], p[2] - depth * cam.d[2]]);
}

// The spherical triangle of face k as the corners of a polygon on the sphere.
function faceOutline(k) {
  const [a, b, c] = C.faces[k].map((i) => C.vertices[i]);
  const out = [];
  for (const [p, q] of [[a, b], [b, c], [c, a]]) {
    for (let s = 0; s < EDGE_STEPS; s += 1) {
      const t = s / EDGE_STEPS;
      out.push(unit([p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t, p[2] + (q[2] - p[2]) * t]));
    }
  }
  return out;
}
const OUTLINES = C.faces.map((_, k) => faceOutline(k));

const AXES = [["x", [1, 0, 0]], ["y", [0, 1, 0]], ["z", [0, 0, 1]]];

// One disc: the faces near the camera, the near half of the points (near of the plane through
// their own centre, so that a cloud off the sphere still shows as a cloud), the current reading, the
// axes. points, centre and current are in units of the sphere's radius (1: on the sphere).
function disc(view, k, { covered, points, centre, current, radius, title }) {
  const { cam } = view;
  const cx = k * (SIZE + GAP) + PAD + R;
  const cy = PAD + R;
  const at = (p, r = R * radius) => [cx + r * dot(p, cam.e1), cy - r * dot(p, cam.e2)];
  const parts = [
    `<circle cx="${cx}" cy="${cy}" r="${fmt(R * radius)}" fill="#fafafa" stroke="#555" stroke-width="1.5" />`,
  ];
  C.faces.forEach((_, f) => {
    const outline = OUTLINES[f];
    if (!outline.some((p) => dot(p, cam.d) > 0)) return;
    const d = outline.map((p) => at(onFront(p, cam)))
      .map(([x, y], i) => `${i ? "L" : "M"}${fmt(x)} ${fmt(y)}`).join("") + "Z";
    const on = covered[f];
    parts.push(`<path class="face${on ? " covered" : ""}" data-face="${C.faceNames[f]}" d="${d}" `
      + `fill="${on ? "#8fd19a" : "#ffffff"}" stroke="#8a8a8a" stroke-width="0.8" />`);
  });
  for (const p of points) {
    if (dot([p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]], cam.d) < 0) continue;
    const [x, y] = at(p);
    parts.push(`<circle cx="${fmt(x)}" cy="${fmt(y)}" r="1.8" fill="#0b4f9c" />`);
  }
  if (current && dot(current, cam.d) >= 0) {
    const [x, y] = at(current);
    parts.push(`<g class="current" stroke="#a00000" stroke-width="2.5">`
      + `<line x1="${fmt(x - 7)}" y1="${fmt(y)}" x2="${fmt(x + 7)}" y2="${fmt(y)}" />`
      + `<line x1="${fmt(x)}" y1="${fmt(y - 7)}" x2="${fmt(x)}" y2="${fmt(y + 7)}" /></g>`);
  }
  for (const [name, axis] of AXES) {
    const sign = dot(axis, cam.d) >= 0 ? 1 : -1;
    const tip = axis.map((v) => sign * v);
    const [x0, y0] = at(tip, R * radius);
    const [x1, y1] = at(tip, R * radius + 14);
    parts.push(`<line x1="${fmt(x0)}" y1="${fmt(y0)}" x2="${fmt(x1)}" y2="${fmt(y1)}" `
      + `stroke="#333" stroke-width="1.2" />`
      + `<text x="${fmt(x1)}" y="${fmt(y1 + 4)}" font-size="11" text-anchor="middle" fill="#111" stroke="#fff" `
      + `stroke-width="3" paint-order="stroke">${sign > 0 ? "+" : "−"}${name}</text>`);
  }
  parts.push(`<text x="${cx}" y="${SIZE + 10}" font-size="12" font-weight="700" text-anchor="middle">${title}</text>`);
  return parts.join("");
}

// covered: 20 booleans in the order of the tables' faces; points: [x, y, z] in units of the sphere's
// radius; current: the latest reading, or null; scale: the picture's radius in those units (above 1
// when points lie outside the sphere); centre: the points' own centre (default the sphere's);
// label: the picture's accessible name.
export function magSphereSvg({
  covered, points = [], centre = [0, 0, 0], current = null, scale = 1.15, label, className = "", sides = WORDS.sides,
}) {
  const radius = 1 / scale; // the sphere's radius in the picture, its disc R
  const discs = VIEWS.map((view, k) => disc(view, k, { covered, points, centre, current, radius, title: sides[k] }));
  const width = 2 * SIZE + GAP;
  const height = SIZE + 16;
  const nCovered = covered.filter(Boolean).length;
  const name = `${label}: ${nCovered} of ${covered.length} directions covered, ${points.length} readings`;
  return `<svg xmlns="http://www.w3.org/2000/svg" class="mag-sphere ${className}" viewBox="0 0 ${width} ${height}" `
    + `width="100%" role="img" aria-label="${name}">${discs.join("")}</svg>`;
}

// Which faces the names cover: all but the missing ones.
export function coveredFromMissing(missing) {
  const gone = new Set(missing || []);
  return C.faceNames.map((n) => !gone.has(n));
}

function apply(M, b, m) {
  const d = [m[0] - b[0], m[1] - b[1], m[2] - b[2]];
  return M.map((row) => dot(row, d));
}

// A compass calibration drawn before and after, side by side: the raw readings (samples.raw_ut)
// around zero, and the calibrated h = M (m − b), both in units of the field F (the sphere). The
// faces are the server's coverage (metrics.missing_directions).
export function magResultSvgs(cal) {
  const raw = (cal.samples && cal.samples.raw_ut) || [];
  const field = cal.metrics.field_ut;
  const unit = cal.output_unit === "raw" ? "counts" : "µT"; // a magnetometer left in counts: its figures are counts
  const covered = coveredFromMissing(cal.metrics.missing_directions);
  const after = raw.map((m) => apply(cal.model.M, cal.model.b, m));
  const inUnits = (pts) => pts.map((p) => p.map((v) => v / field));
  const reach = (pts) => Math.max(1.15, ...pts.map((p) => 1.05 * Math.hypot(p[0], p[1], p[2])));
  const before = inUnits(raw);
  const calibrated = inUnits(after);
  const mean = (pts) => [0, 1, 2].map((i) => pts.reduce((sum, p) => sum + p[i], 0) / Math.max(1, pts.length));
  const { sides } = sourceWords(cal);
  return {
    before: magSphereSvg({
      covered, points: before, centre: mean(before), scale: reach(before), className: "before", sides,
      label: `Raw readings m around zero, the sphere of radius F = ${field.toFixed(1)} ${unit}` }),
    after: magSphereSvg({ covered, points: calibrated, scale: reach(calibrated), className: "after", sides,
      label: `Calibrated h = M (m − b), the sphere of radius F = ${field.toFixed(1)} ${unit}` }),
  };
}
