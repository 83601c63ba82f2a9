// The result of a calibration: its norms per position and their chart, advice and intervals in words (pure, no DOM).

import { norm } from "./motion.js";
import { sourcePoseWords } from "./poses.js";
import { counted } from "./dom.js";

// One advised pose in words, with what it would gain.
export function adviceText(a) {
  const words = sourcePoseWords(a.words);
  return a.gain === null || a.gain === undefined ? words
    : `${words} — shrinks the parameters' uncertainty (generalized variance) by ${Math.round(100 * a.gain)} %`;
}

// One row of the norm chart: a reading's position, |m| raw and |a| calibrated, both vectors as the
// server gives them (the reading's mean and its correction, M (m − o)): the page does no model maths.
export function normRow(position, mean, calibrated) {
  return { position, raw: norm(mean), calibrated: norm(calibrated) };
}

// A dot chart of |m| − g (hollow, raw) and |a| − g (filled, calibrated) per position, in % of g.
export function normChartSvg(rows, gravity) {
  const rowH = 26;
  const left = 40;
  const right = 12;
  const width = 320;
  const top = 22;
  const height = top + rows.length * rowH + 26;
  const dev = (v) => (100 * (v - gravity)) / gravity;
  const extent = Math.max(0.5, ...rows.flatMap((r) => [Math.abs(dev(r.raw)), Math.abs(dev(r.calibrated))])) * 1.15;
  const x = (pct) => left + ((pct + extent) / (2 * extent)) * (width - left - right);
  const parts = [
    `<line x1="${x(0)}" y1="${top - 6}" x2="${x(0)}" y2="${height - 22}" stroke="#111" stroke-width="1.5" />`,
    `<text x="${x(0)}" y="${top - 9}" font-size="11" text-anchor="middle">g = ${gravity}</text>`,
    `<text x="${left}" y="${height - 6}" font-size="11">−${extent.toFixed(2)} %</text>`,
    `<text x="${width - right}" y="${height - 6}" font-size="11" text-anchor="end">+${extent.toFixed(2)} %</text>`,
  ];
  rows.forEach((r, k) => {
    const cy = top + k * rowH + rowH / 2;
    parts.push(
      `<text x="4" y="${cy + 4}" font-size="12" font-weight="700">${r.position}</text>`,
      `<line x1="${left}" y1="${cy}" x2="${width - right}" y2="${cy}" stroke="#c8c8c8" />`,
      `<line x1="${x(dev(r.raw))}" y1="${cy}" x2="${x(dev(r.calibrated))}" y2="${cy}" `
        + `stroke="#0b4f9c" stroke-width="2" />`,
      `<circle cx="${x(dev(r.raw))}" cy="${cy}" r="5.5" fill="#fff" stroke="#a00000" stroke-width="2.5" />`,
      `<circle cx="${x(dev(r.calibrated))}" cy="${cy}" r="5" fill="#0b4f9c" />`,
    );
  });
  const worst = (key) => Math.max(...rows.map((r) => Math.abs(dev(r[key])))).toFixed(3);
  const label = `Norm minus g per position: raw up to ${worst("raw")} % of g (hollow red), `
    + `calibrated up to ${worst("calibrated")} % (filled blue)`;
  return `<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 ${width} ${height}" width="100%" `
    + `role="img" aria-label="${label}">${parts.join("")}</svg>`;
}

export function withInterval(value, halfWidth, format) {
  return halfWidth === undefined || halfWidth === null ? format(value) : `${format(value)} ± ${format(halfWidth)}`;
}

// The gyroscope's bias at rest over the still captures (app.calibration.still.gyro_bias), in °/s with its 95 %
// half-widths.
export function gyroBiasText(bias) {
  const list = (v) => v.map((x) => x.toFixed(3)).join(", ");
  const over = bias.interval_from === "samples" ? "1 still capture, interval from its samples"
    : counted(bias.count, "still capture");
  return `Gyroscope bias: ${list(bias.deg_s)} °/s ± ${list(bias.half_width_deg_s)} °/s `
    + `(${Math.round(100 * bias.confidence)} %, ${over})`;
}
