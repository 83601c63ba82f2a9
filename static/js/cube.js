// The cube24 protocol on the page (pure logic, no DOM): the positions and turns of docs/architecture.md
// section 4, their pictures as SVG strings, and the motion log that gives each capture its move.
//
// Calibration frame: position 1 is the sensor frame (z up, x along the jig). A rotation is a
// right-hand quarter turn about a calibration axis fixed in space: z+ turns the cube
// counter-clockwise seen from above; x± tips it over the jig edge, its top moving towards ∓y.
// The protocol itself comes from the server's tables (tables.js: protocols.cube24()).

import { POSES } from "./motion.js";
import { TABLES } from "./tables.js";

const PROTOCOL = TABLES.cube24;

export const CUBE24_ROTATIONS = PROTOCOL.rotations;
export const CUBE_POSITIONS = CUBE24_ROTATIONS.length + 1;

// The server's words for each turn (app/calibration/cube/turns.py TURN_WORDS), so that the page and
// the server's refusals say the same thing.
export const TURN_WORDS = PROTOCOL.turnWords;

// R_k (sensor → calibration frame) of each position, R_1 = I, R_{k+1} = Rot_k R_k (Särkkä et al. Fig. 1), as
// protocols.cube24() chains them.
export const CUBE24_ATTITUDES = PROTOCOL.attitudes;

// The sensor axis pointing up in position k (1-based): the third row of R_k, i.e. R_kᵀ e_z, as the
// server gives it.
export function upOf(k) { return PROTOCOL.ups[k - 1]; }

// The turn that leads into position k (k ≥ 2), as {label, words}.
export function turnInto(k) {
  const label = CUBE24_ROTATIONS[k - 2];
  return { label, words: TURN_WORDS[label] };
}

// Let a CaptureMachine (motion.js) capture only the face that position k has up.
export function expectPosition(machine, k) {
  const up = upOf(k);
  machine.setDone(POSES.filter((p) => p !== up));
}

// --- pictures ---------------------------------------------------------------------------------

const COS30 = Math.cos(Math.PI / 6);
const SCALE = 34;
const CX = 60;
const CY = 66;
const AXIS_COLOURS = ["#b00000", "#0a5a14", "#0b4f9c"];

// Isometric view from (1, 1, 1), right-handed: calibration x to the lower left, y to the lower
// right, z up.
function project([x, y, z]) {
  return [CX + (y - x) * COS30 * SCALE, CY + ((x + y) * 0.5 - z) * SCALE];
}

const pt = (p) => project(p).map((v) => v.toFixed(1)).join(",");
const polygon = (points, attrs) => `<polygon points="${points.map(pt).join(" ")}" ${attrs} />`;

function arrowHead(tip, from, colour) {
  const [tx, ty] = project(tip);
  const [fx, fy] = project(from);
  const len = Math.hypot(tx - fx, ty - fy) || 1;
  const ux = (tx - fx) / len;
  const uy = (ty - fy) / len;
  const a = [tx - 7 * ux + 4 * uy, ty - 7 * uy - 4 * ux];
  const b = [tx - 7 * ux - 4 * uy, ty - 7 * uy + 4 * ux];
  return `<polygon points="${tx.toFixed(1)},${ty.toFixed(1)} ${a.map((v) => v.toFixed(1)).join(",")} `
    + `${b.map((v) => v.toFixed(1)).join(",")}" fill="${colour}" />`;
}

// A curved arrow for a turn about a calibration axis, drawn where it reads best.
function turnArrow(label) {
  const sign = label[1] === "+" ? 1 : -1;
  const points = [];
  for (let i = 0; i <= 16; i += 1) {
    const f = i / 16;
    if (label[0] === "z") { // around the top, on the front side
      const t = (sign > 0 ? -40 + 150 * f : 110 - 150 * f) * (Math.PI / 180);
      points.push([0.82 * Math.cos(t), 0.82 * Math.sin(t), 0.62]);
    } else if (label[0] === "x") { // in front of the +x face, over the top
      const t = (sign > 0 ? 40 + 100 * f : 140 - 100 * f) * (Math.PI / 180);
      points.push([0.62, 0.85 * Math.cos(t), 0.85 * Math.sin(t) - 0.1]);
    } else { // in front of the +y face, over the top
      const t = (sign > 0 ? 140 - 100 * f : 40 + 100 * f) * (Math.PI / 180);
      points.push([0.85 * Math.cos(t), 0.62, 0.85 * Math.sin(t) - 0.1]);
    }
  }
  const colour = "#c05000";
  const d = points.map((p, i) => `${i ? "L" : "M"}${pt(p)}`).join(" ");
  return `<path d="${d}" stroke="${colour}" stroke-width="3.5" fill="none" />`
    + arrowHead(points[points.length - 1], points[points.length - 3], colour);
}

// The sensor's axes drawn through the cube: axis i is column i of R_k in the calibration frame.
function sensorAxes(R) {
  const parts = [];
  for (let i = 0; i < 3; i += 1) {
    const d = [R[0][i], R[1][i], R[2][i]];
    const tip = d.map((v) => 0.95 * v);
    const hidden = d[0] + d[1] + d[2] < 0; // pointing away from the viewer
    const [x0, y0] = project([0, 0, 0]);
    const [x1, y1] = project(tip);
    parts.push(`<line x1="${x0.toFixed(1)}" y1="${y0.toFixed(1)}" x2="${x1.toFixed(1)}" y2="${y1.toFixed(1)}" `
      + `stroke="${AXIS_COLOURS[i]}" stroke-width="2.5"${hidden ? ' stroke-dasharray="3 2"' : ""} />`);
    parts.push(arrowHead(tip, d.map((v) => 0.5 * v), AXIS_COLOURS[i]));
    const [lx, ly] = project(d.map((v) => 1.12 * v));
    parts.push(`<text x="${(lx - 3).toFixed(1)}" y="${(ly + 4).toFixed(1)}" font-size="11" font-weight="700" `
      + `fill="${AXIS_COLOURS[i]}">${"xyz"[i]}</text>`);
  }
  return parts.join("");
}

// An SVG picture of the cube in position k: the plane, the jig edge along x, the cube with its up
// face highlighted, the sensor axes, and optionally the arrow of the turn `turn` (a label) made next.
export function cubeSvg(k, { turn = null, size = 120 } = {}) {
  if (!(k >= 1 && k <= CUBE_POSITIONS)) throw new Error(`no position ${k} in cube24`);
  const R = CUBE24_ATTITUDES[k - 1];
  const h = 0.5;
  const up = upOf(k);
  const parts = [
    polygon([[-1.1, -1.1, -h], [1.1, -1.1, -h], [1.1, 1.1, -h], [-1.1, 1.1, -h]], 'fill="#efe6da" stroke="#7a3e00"'),
    `<path d="M${pt([-1.1, -0.62, -h])} L${pt([1.1, -0.62, -h])}" stroke="#7a3e00" stroke-width="5" />`,
    polygon([[h, -h, -h], [h, h, -h], [h, h, h], [h, -h, h]], 'fill="#d4d4d4" stroke="#333"'),
    polygon([[-h, h, -h], [h, h, -h], [h, h, h], [-h, h, h]], 'fill="#bdbdbd" stroke="#333"'),
    polygon([[-h, -h, h], [h, -h, h], [h, h, h], [-h, h, h]], 'fill="#ffd54a" stroke="#333" data-face="top"'),
    sensorAxes(R),
    `<text x="4" y="13" font-size="12" font-weight="700">${k}</text>`,
    `<text x="116" y="13" font-size="11" text-anchor="end">${up} up</text>`,
    `<text x="${project([1.1, -0.62, -h])[0].toFixed(1)}" y="${(project([1.1, -0.62, -h])[1] - 5).toFixed(1)}" `
      + 'font-size="9" text-anchor="end" fill="#7a3e00">jig</text>',
  ];
  if (turn) parts.push(turnArrow(turn));
  const name = `Position ${k}: the cube with sensor ${up} up (highlighted top face)`
    + (turn ? `; arrow: ${TURN_WORDS[turn] || turn}` : "");
  return `<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 120 120" width="${size}" height="${size}" `
    + `role="img" aria-label="${name}" data-position="${k}"${turn ? ` data-turn="${turn}"` : ""}>`
    + parts.join("") + "</svg>";
}

// --- the motion log ---------------------------------------------------------------------------

// Every sample since the page started reading the sensors, with the end time of each accepted
// capture, so that a capture's `motion` is exactly the samples from the end of the capture before
// it to the start of its own still window. `from` is that start (exclusive); −∞ = the log's start
// (a resumed session: the person put the cube back in the last captured position).
export class MotionLog {
  constructor({ maxSamples = 60000 } = {}) {
    this.samples = [];
    this.ends = new Map(); // position (number) → end time (ms) of its accepted capture
    this.from = -Infinity;
    this.maxSamples = maxSamples;
  }

  push(sample) {
    this.samples.push(sample);
    if (this.samples.length > this.maxSamples) { // drop what neither the next move nor a redo needs
      const last = Math.max(0, ...this.ends.keys());
      const keep = Math.min(this.from, this.ends.get(last - 1) ?? this.from);
      const cut = this.samples.findIndex((s) => s.t > keep);
      this.samples.splice(0, cut < 0 ? this.samples.length - 1 : cut);
    }
  }

  // Capture of position k accepted, its last sample at endT: the next move starts after it.
  accept(k, endT) {
    this.ends.set(k, endT);
    this.from = endT;
  }

  // Redo position k (the last one captured): its move again runs from the end of position k − 1.
  // Returns false when that end is not in this log (a resumed session): the move then runs from
  // now, so the cube must stand in position k − 1 already.
  redo(k, nowT) {
    this.ends.delete(k);
    if (k === 1) return true;
    if (this.ends.has(k - 1)) {
      this.from = this.ends.get(k - 1);
      return true;
    }
    this.from = nowT;
    return false;
  }

  // The move into a capture whose still window starts at startT: {t_ms, gyr, acc}.
  motion(startT) {
    const part = this.samples.filter((s) => s.t > this.from && s.t < startT);
    return { t_ms: part.map((s) => s.t), gyr: part.map((s) => s.gyr), acc: part.map((s) => s.acc) };
  }
}
