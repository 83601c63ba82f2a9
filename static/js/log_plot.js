// A small plot of an uploaded log (pure, no DOM): the norm of its accelerometer (or magnetometer)
// over time, each bin's smallest to largest value as a band, the still segments shaded and
// labelled with the face up. The server sends the overview (app.workflows.recordings.overview) and segments.

const W = 320;
const H = 120;
const LEFT = 34;
const RIGHT = 6;
const TOP = 18;
const BOTTOM = 22;

function esc(text) {
  return String(text).replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" }[c]));
}

// The column-name options of a file's first line: "time,ax,ay,az" → ["time", "ax", "ay", "az"].
export function headerColumns(firstLine) {
  const line = firstLine.replace(/^\uFEFF/, "").trim();
  const sep = [",", ";", "\t"].find((d) => line.includes(d));
  return (sep ? line.split(sep) : line.split(/\s+/)).map((c) => c.trim().replace(/^"(.*)"$/, "$1")).filter(Boolean);
}

// `columns` for the upload from a mapping {fileColumn: role} (roles acc_x … time_s; "" skips one).
export function columnsField(mapping) {
  return Object.entries(mapping).filter(([, role]) => role).map(([name, role]) => `${role}:${name}`).join(",");
}

// The numbers of a table's first lines, one array per column (a table without a header row).
export function tableColumns(text, maxLines = 2000) {
  const rows = text.replace(/^\uFEFF/, "").split(/\r?\n/).filter((l) => l.trim() && !l.trim().startsWith("#"))
    .slice(0, maxLines).map((l) => l.trim().split(/\s*[,;\t]\s*|\s+/).map(Number));
  const width = rows.length ? rows[0].length : 0;
  const whole = rows.filter((r) => r.length === width && r.every(Number.isFinite));
  return Array.from({ length: width }, (_, c) => whole.map((r) => r[c]));
}

// A column's values as a small line (no axes): what the column does over the file's first lines.
export function columnSparkSvg(values, width = 150, height = 36) {
  if (!values.length) return "";
  const lo = Math.min(...values);
  const hi = Math.max(...values);
  const span = hi - lo || 1;
  const step = Math.max(1, Math.floor(values.length / width));
  const points = [];
  for (let i = 0; i < values.length; i += step) {
    points.push(`${((i / Math.max(1, values.length - 1)) * (width - 2) + 1).toFixed(1)},`
      + `${(height - 2 - ((values[i] - lo) / span) * (height - 4)).toFixed(1)}`);
  }
  return `<svg class="spark" viewBox="0 0 ${width} ${height}" width="${width}" height="${height}" role="img" `
    + `aria-label="from ${esc(formatShort(lo))} to ${esc(formatShort(hi))}"><polyline points="${points.join(" ")}" `
    + `fill="none" stroke="#0b4f9c" stroke-width="1" /></svg>`;
}

function formatShort(v) {
  return Math.abs(v) >= 1000 || v === Math.round(v) ? String(Math.round(v)) : v.toPrecision(3);
}

// A log without a sampling rate (no time column, none given) is drawn over its samples.
// `words`: the sensor and the unit in words, as the server's tables say them (index.js passes them).
export function logPlotSvg(overview, segments, samplingRateHz, words) {
  const perSample = samplingRateHz ? 1 / samplingRateHz : 1;
  const axis = samplingRateHz ? "s" : "samples";
  const t = overview.t_s ?? (overview.start || []);
  const lows = overview.low.filter((v) => v !== null);
  const highs = overview.high.filter((v) => v !== null);
  if (!t.length || !lows.length) return "";
  const end = Math.max(t[t.length - 1], ...segments.map((s) => s.end * perSample));
  const lo = Math.min(...lows);
  const hi = Math.max(...highs);
  const pad = (hi - lo) * 0.08 || Math.abs(hi) * 0.05 || 1;
  const x = (sec) => LEFT + (sec / (end || 1)) * (W - LEFT - RIGHT);
  const y = (v) => TOP + (1 - (v - (lo - pad)) / (hi - lo + 2 * pad)) * (H - TOP - BOTTOM);
  const parts = [];
  segments.forEach((s) => {
    const x0 = x(s.start * perSample);
    const x1 = Math.max(x(s.end * perSample), x0 + 1.5);
    parts.push(`<rect class="still" x="${x0.toFixed(1)}" y="${TOP}" width="${(x1 - x0).toFixed(1)}" `
      + `height="${H - TOP - BOTTOM}" fill="#cfe8d2" />`);
    if (x1 - x0 >= 14 && s.up) {
      parts.push(`<text x="${((x0 + x1) / 2).toFixed(1)}" y="${TOP - 5}" font-size="10" text-anchor="middle">`
        + `${esc(s.up)}</text>`);
    }
  });
  const band = [];
  t.forEach((ti, i) => {
    if (overview.high[i] !== null) band.push(`${x(ti).toFixed(1)},${y(overview.high[i]).toFixed(1)}`);
  });
  for (let i = t.length - 1; i >= 0; i -= 1) {
    if (overview.low[i] !== null) band.push(`${x(t[i]).toFixed(1)},${y(overview.low[i]).toFixed(1)}`);
  }
  parts.push(`<polygon points="${band.join(" ")}" fill="#0b4f9c" stroke="#0b4f9c" stroke-width="1" />`);
  const unit = words.unit ? ` (${esc(words.unit)})` : "";
  parts.push(
    `<line x1="${LEFT}" y1="${H - BOTTOM}" x2="${W - RIGHT}" y2="${H - BOTTOM}" stroke="#111" />`,
    `<text x="${LEFT}" y="${H - 6}" font-size="10">0 ${axis}</text>`,
    `<text x="${W - RIGHT}" y="${H - 6}" font-size="10" text-anchor="end">`
      + `${end.toFixed(samplingRateHz ? 1 : 0)} ${axis}</text>`,
    `<text x="2" y="${(y(hi) + 4).toFixed(1)}" font-size="10">${hi.toPrecision(3)}</text>`,
    `<text x="2" y="${(y(lo) + 4).toFixed(1)}" font-size="10">${lo.toPrecision(3)}</text>`,
  );
  const what = words.sensor;
  const label = `The ${what}'s norm${unit} over the ${end.toFixed(samplingRateHz ? 1 : 0)} ${axis} of the log; `
    + `${segments.length} still `
    + `${segments.length === 1 ? "segment" : "segments"} shaded green, labelled with the face up`;
  return `<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 ${W} ${H}" width="100%" role="img" `
    + `aria-label="${esc(label)}">${parts.join("")}</svg>`;
}
