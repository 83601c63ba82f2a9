// The directions a free-pose session has covered and where the next pose should point, as an SVG
// string (pure, no DOM). Two orthographic views of the unit sphere of up-directions in the device
// frame (x right, y up the screen, z out of the screen): the half with the screen up (z ≥ 0) seen
// from the screen side, and the half with the screen down (z < 0) seen from the back, mirrored so
// that x still points the way it does on the phone's back.

const R = 62; // disc radius
const PAD = 18;
const GAP = 34;
const SIZE = 2 * R + 2 * PAD;

function unit(v) {
  const n = Math.hypot(v[0], v[1], v[2]);
  return n > 0 ? [v[0] / n, v[1] / n, v[2] / n] : [0, 0, 1];
}

// Which disc a direction falls in (0: screen up, 1: screen down) and where on it.
export function project(v) {
  const [x, y, z] = unit(v);
  const back = z < 0;
  const cx = (back ? SIZE + GAP : 0) + PAD + R;
  return { disc: back ? 1 : 0, x: cx + (back ? -x : x) * R, y: PAD + R - y * R };
}

const fmt = (v) => v.toFixed(1);

function disc(k, title) {
  const cx = k * (SIZE + GAP) + PAD + R;
  const cy = PAD + R;
  const sign = k ? -1 : 1;
  return `<circle cx="${cx}" cy="${cy}" r="${R}" fill="#f4f8fd" stroke="#555" stroke-width="1.5" />`
    + `<circle cx="${cx}" cy="${cy}" r="${fmt(R * Math.sin(Math.PI / 4))}" fill="none" stroke="#c8c8c8" `
    + `stroke-dasharray="3 3" />`
    + `<line x1="${cx - R}" y1="${cy}" x2="${cx + R}" y2="${cy}" stroke="#c8c8c8" />`
    + `<line x1="${cx}" y1="${cy - R}" x2="${cx}" y2="${cy + R}" stroke="#c8c8c8" />`
    + `<text x="${cx + sign * (R + 3)}" y="${cy + 4}" font-size="11" text-anchor="${k ? "end" : "start"}">+x</text>`
    + `<text x="${cx}" y="${PAD - 5}" font-size="11" text-anchor="middle">+y</text>`
    + `<text x="${cx}" y="${cy + 4}" font-size="10" text-anchor="middle" fill="#555">${k ? "−z" : "+z"}</text>`
    + `<text x="${cx}" y="${SIZE + 12}" font-size="12" font-weight="700" text-anchor="middle">${title}</text>`;
}

// covered: directions captured; advice: directions advised, best first; current: the live direction or null;
// titles: the two discs' names (the source's: app/web/tables.py SOURCES "ups").
export function sphereSvg({ covered = [], advice = [], current = null, titles = ["screen up", "screen down"] } = {}) {
  const parts = [disc(0, titles[0]), disc(1, titles[1])];
  for (const v of covered) {
    const p = project(v);
    parts.push(`<circle class="covered" cx="${fmt(p.x)}" cy="${fmt(p.y)}" r="5" fill="#0a5a14" stroke="#fff" `
      + `stroke-width="1" />`);
  }
  advice.forEach((v, i) => {
    const p = project(v);
    parts.push(`<g class="advised"><circle cx="${fmt(p.x)}" cy="${fmt(p.y)}" r="${i ? 7 : 9}" fill="#fff" `
      + `stroke="#b35c00" stroke-width="${i ? 2 : 3}" />`
      + `<text x="${fmt(p.x)}" y="${fmt(p.y + 4)}" font-size="11" font-weight="700" text-anchor="middle" `
      + `fill="#7a3e00">${i + 1}</text></g>`);
  });
  if (current) {
    const p = project(current);
    parts.push(`<g class="current" stroke="#a00000" stroke-width="2.5"><line x1="${fmt(p.x - 7)}" y1="${fmt(p.y)}" `
      + `x2="${fmt(p.x + 7)}" y2="${fmt(p.y)}" />`
      + `<line x1="${fmt(p.x)}" y1="${fmt(p.y - 7)}" x2="${fmt(p.x)}" y2="${fmt(p.y + 7)}" /></g>`);
  }
  const width = 2 * SIZE + GAP;
  const height = SIZE + 16;
  const label = `Directions covered: ${covered.length} poses (green dots); `
    + `next poses advised: ${advice.length} (numbered rings)`;
  return `<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 ${width} ${height}" width="100%" `
    + `style="max-width:${width * 1.4}px" role="img" aria-label="${label}">${parts.join("")}</svg>`;
}
