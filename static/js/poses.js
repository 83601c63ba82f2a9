// Pictures of the phone in each of the six poses, as SVG strings (pure, no DOM).
// The label names the device axis pointing up, away from the Earth (x right, y up along the
// screen, z out of the screen). Standing poses are drawn from the front, lying ones from above
// at an angle; a table line and an "up" arrow give the direction. The poses' names come from the
// server's tables (tables.js).

import { TABLES } from "./tables.js";

const W = 120;
const H = 120;
const TABLE_Y = 108;

// A phone seen from the front, portrait, centred on (0, 0): body, screen, earpiece, axis arrows.
function frontPhone() {
  return `
    <rect x="-21" y="-38" width="42" height="76" rx="6" fill="#222" />
    <rect x="-17" y="-31" width="34" height="60" rx="2" fill="#8fc3ff" />
    <rect x="-6" y="-35.5" width="12" height="2" rx="1" fill="#777" />
    <path d="M0 0 H13 M10 -3 L13 0 L10 3" stroke="#b00000" stroke-width="2" fill="none" />
    <text x="5" y="-3" font-size="8" fill="#b00000">x</text>
    <path d="M0 0 V-18 M-3 -15 L0 -18 L3 -15" stroke="#0a5a14" stroke-width="2" fill="none" />
    <text x="-8" y="-10" font-size="8" fill="#0a5a14">y</text>`;
}

// A phone lying on the table, drawn as a slanted slab; screen up or down.
function flatPhone(screenUp) {
  const top = "30,80 82,80 98,62 46,62";
  const face = screenUp
    ? `<polygon points="36,77 80,77 92,65 48,65" fill="#8fc3ff" />
       <circle cx="64" cy="71" r="2.5" fill="#b00000" />
       <text x="58" y="58" font-size="9" fill="#b00000">z</text>
       <path d="M64 71 V52 M61 55 L64 52 L67 55" stroke="#b00000" stroke-width="2" fill="none" />`
    : `<circle cx="84" cy="66" r="3.5" fill="#555" stroke="#999" />
       <text x="36" y="76" font-size="8" fill="#ddd">back</text>`;
  return `
    <polygon points="30,80 82,80 82,85 30,85" fill="#111" />
    <polygon points="82,80 98,62 98,67 82,85" fill="#333" />
    <polygon points="${top}" fill="#222" />
    ${face}`;
}

// Rotation (degrees, clockwise on screen) of the front view that puts the label's axis up.
const STANDING = { "+y": 0, "-y": 180, "+x": -90, "-x": 90 };

const DESCRIPTIONS = TABLES.poses.names;

export function describePose(label) { return DESCRIPTIONS[label] || label; }

// An SVG picture of the phone with `label`'s axis pointing up. `size` in CSS pixels.
export function poseSvg(label, size = 96) {
  if (!(label in DESCRIPTIONS)) throw new Error(`unknown pose ${label}`);
  let body;
  if (label in STANDING) {
    const angle = STANDING[label];
    const halfHeight = angle % 180 === 0 ? 38 : 21; // the phone stands on the table line
    body = `<g transform="translate(56 ${TABLE_Y - halfHeight}) rotate(${angle})">${frontPhone()}</g>`;
  } else {
    body = `<g transform="translate(-4 ${TABLE_Y - 86})">${flatPhone(label === "+z")}</g>`;
  }
  const arrow = `<path d="M108 60 V14 M103 20 L108 14 L113 20" stroke="#111" stroke-width="3" fill="none" />
    <text x="98" y="72" font-size="10" font-weight="700" fill="#111">up</text>`;
  return `<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 ${W} ${H}" width="${size}" height="${size}" `
    + `role="img" aria-label="Phone ${describePose(label)} (${label} up)">`
    + `<line x1="2" y1="${TABLE_Y}" x2="${W - 2}" y2="${TABLE_Y}" stroke="#7a3e00" stroke-width="3" />`
    + body + arrow + `</svg>`;
}
