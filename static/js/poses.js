// Pictures of the phone in each of the six poses, as SVG strings (pure, no DOM).
// The label names the device axis pointing up, away from the Earth (x right, y up along the
// screen, z out of the screen). Standing poses are drawn from the front, lying ones from above at
// an angle. What a person recognises carries the picture: the screen, the earpiece and front
// camera at the top edge, the charging port at the bottom, the back camera; the edge or face that
// touches the table is drawn in orange on the table line, and an arrow leaves the side that points
// up. The axis code is a small grey note in the corner. The poses' words come from the server's
// tables (tables.js).

import { TABLES } from "./tables.js";
import { SOURCE } from "./source.js";

const W = 120;
const H = 120;
const TABLE_Y = 110;
const TOUCH = "#e07000"; // the edge or face on the table
const UP = "#111";

// A phone seen from the front, portrait, centred on (0, 0): body, screen, earpiece and front camera
// at the top, charging port at the bottom; `down` names the edge on the table (coloured) and `up`
// the one an arrow leaves from.
function frontPhone(down, up) {
  const edges = { bottom: "M-19 38 H19", top: "M-19 -38 H19", left: "M-21 -36 V36", right: "M21 -36 V36" };
  const arrows = { top: "M0 -40 V-56 M-5 -50 L0 -56 L5 -50", bottom: "M0 40 V56 M-5 50 L0 56 L5 50",
    left: "M-23 0 H-39 M-33 -5 L-39 0 L-33 5", right: "M23 0 H39 M33 -5 L39 0 L33 5" };
  return `
    <rect x="-21" y="-38" width="42" height="76" rx="6" fill="#222" />
    <rect x="-17" y="-30" width="34" height="58" rx="2" fill="#8fc3ff" />
    <rect x="-7" y="-35" width="12" height="2.4" rx="1.2" fill="#888" />
    <circle cx="9" cy="-33.8" r="2" fill="#555" stroke="#aaa" stroke-width=".8" />
    <rect x="-5" y="34" width="10" height="2.4" rx="1.2" fill="#888" />
    <path d="${edges[down]}" stroke="${TOUCH}" stroke-width="5" stroke-linecap="round" />
    <path d="${arrows[up]}" stroke="${UP}" stroke-width="3" fill="none" />`;
}

// A phone lying on the table, drawn as a slanted slab: its upper face (screen or back) and, under
// it, the face on the table as an orange band; an arrow up from the upper face.
function flatPhone(screenUp) {
  const top = "14,84 80,84 102,60 36,60";
  const face = screenUp
    ? `<polygon points="22,81 78,81 94,63 38,63" fill="#8fc3ff" />
       <path d="M88 63 L92 61" stroke="#888" stroke-width="2.4" stroke-linecap="round" />`
    : `<circle cx="88" cy="65" r="5" fill="#444" stroke="#aaa" stroke-width="1.2" />
       <circle cx="88" cy="65" r="2" fill="#8fc3ff" />`;
  return `
    <polygon points="14,84 80,84 80,91 14,91" fill="${TOUCH}" />
    <polygon points="80,84 102,60 102,67 80,91" fill="#b35a00" />
    <polygon points="${top}" fill="#222" />
    ${face}
    <path d="M58 72 V38 M53 44 L58 38 L63 44" stroke="${UP}" stroke-width="3" fill="none" />`;
}

// Rotation (degrees, clockwise on screen) of the front view that puts the label's axis up, with the
// edge on the table and the one pointing up in the phone's own terms.
const STANDING = {
  "+y": { angle: 0, down: "bottom", up: "top" },
  "-y": { angle: 180, down: "top", up: "bottom" },
  "+x": { angle: -90, down: "left", up: "right" },
  "-x": { angle: 90, down: "right", up: "left" },
};

// The page's source (source.js), "phone" or "board": which pictures and words describePose and poseSvg
// give; a board's page shows a board from its first screen.
const device = SOURCE;

// Each pose in words, the phone's or the board's (app/web/tables.py SOURCES: a board's printed X and Y
// arrows and its component side): two or three words under a thumbnail ("screen up", a board's "X arrow
// up"), and the whole pose (a phone lying flat with its screen up).
const poseWords = () => TABLES.sources[device];
// The server names an advised pose's nearest axis in a phone's words (app/calibration/still/advice.py
// describe_up, the table of TABLES.poses.names); a board's page says the board's.
export function sourcePoseWords(text) {
  if (device === "phone") return text;
  return Object.entries(TABLES.poses.names)
    .reduce((t, [label, name]) => t.replace(`(${name})`, `(${describePose(label)})`), text);
}

export function shortPose(label) { return poseWords().poseShort[label] || label; }

// The pose the wizard names next among those still to do: flat ones first (the easiest to place),
// then standing, then on the side edges.
export const NEXT_ORDER = TABLES.poses.asked; // app/guided/capture_rules.py SIX_ASKED_ORDER
export function nextPose(remaining) { return NEXT_ORDER.find((p) => remaining.includes(p)) || null; }

export function describePose(label) { return poseWords().poseNames[label] || label; }

// A board seen from its component side, centred on (0, 0), with its X arrow to the right and its Y
// arrow up (as printed on it), the chip in the middle and a row of header pins at the bottom; `down`
// names the edge on the table, `up` the one an arrow leaves from.
function frontBoard(down, up) {
  const edges = { bottom: "M-27 25 H27", top: "M-27 -25 H27", left: "M-29 -23 V23", right: "M29 -23 V23" };
  const arrows = { top: "M0 -27 V-45 M-5 -39 L0 -45 L5 -39", bottom: "M0 27 V45 M-5 39 L0 45 L5 39",
    left: "M-31 0 H-49 M-43 -5 L-49 0 L-43 5", right: "M31 0 H49 M43 -5 L49 0 L43 5" };
  const pins = [-20, -12, -4, 4, 12, 20]
    .map((x) => `<rect x="${x - 2.5}" y="16" width="5" height="5" fill="#d9b44a" />`).join("");
  return `
    <rect x="-29" y="-25" width="58" height="50" rx="3" fill="#1f6f43" />
    <rect x="-8" y="-8" width="16" height="16" fill="#222" />
    <path d="M-22 2 H-4 M-8 -2 L-4 2 L-8 6" stroke="#fff" stroke-width="1.6" fill="none" />
    <text x="-24" y="-3" font-size="7" fill="#fff">X</text>
    <path d="M-18 8 V-12 M-22 -8 L-18 -12 L-14 -8" stroke="#fff" stroke-width="1.6" fill="none" />
    <text x="-16" y="-14" font-size="7" fill="#fff">Y</text>
    ${pins}
    <path d="${edges[down]}" stroke="${TOUCH}" stroke-width="5" stroke-linecap="round" />
    <path d="${arrows[up]}" stroke="${UP}" stroke-width="3" fill="none" />`;
}

// A board lying on the table as a slanted slab: its component side (the chip, the printed arrows)
// or its bare back up, the face on the table as an orange band, an arrow up from the upper face.
function flatBoard(componentsUp) {
  const face = componentsUp
    ? `<polygon points="50,77 62,77 68,70 56,70" fill="#222" />
       <path d="M26 80 L44 80 M40 77 L44 80 L40 83" stroke="#fff" stroke-width="1.4" fill="none" />`
    : `<path d="M30 79 H70 M40 70 H80" stroke="#3c8a5e" stroke-width="1.2" />`;
  return `
    <polygon points="14,84 80,84 80,89 14,89" fill="${TOUCH}" />
    <polygon points="80,84 102,60 102,65 80,89" fill="#b35a00" />
    <polygon points="14,84 80,84 102,60 36,60" fill="#1f6f43" />
    ${face}
    <path d="M58 72 V38 M53 44 L58 38 L63 44" stroke="${UP}" stroke-width="3" fill="none" />`;
}

// An SVG picture of the phone with `label`'s axis pointing up. `size` in CSS pixels (null: fill the
// width of its box).
export function poseSvg(label, size = 160) {
  if (!(label in TABLES.poses.names)) throw new Error(`unknown pose ${label}`);
  let body;
  const board = device === "board";
  if (label in STANDING) {
    const { angle, down, up } = STANDING[label];
    // the phone (the board) stands on the table line
    const halfHeight = board ? (angle % 180 === 0 ? 25 : 29) : (angle % 180 === 0 ? 38 : 21);
    body = `<g transform="translate(60 ${TABLE_Y - halfHeight - 2}) rotate(${angle})">`
      + `${board ? frontBoard(down, up) : frontPhone(down, up)}</g>`;
  } else {
    const flat = board ? flatBoard(label === "+z") : flatPhone(label === "+z");
    body = `<g transform="translate(0 ${TABLE_Y - 92})">${flat}</g>`;
  }
  const dims = size ? `width="${size}" height="${size}"` : `width="100%"`;
  return `<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 ${W} ${H}" ${dims} `
    + `role="img" aria-label="${board ? "Board" : "Phone"} ${describePose(label)} (${label} up)">`
    + `<line x1="2" y1="${TABLE_Y}" x2="${W - 2}" y2="${TABLE_Y}" stroke="#7a5a3a" stroke-width="3" />`
    + body
    + `<text x="${W - 3}" y="11" font-size="10" fill="#666" text-anchor="end">${label} up</text></svg>`;
}
