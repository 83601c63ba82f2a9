// Parsing of pasted readings (pure functions, no DOM; the canonical order from tables.js).

import { TABLES } from "./tables.js";

export const CANONICAL = TABLES.poses.order;
const LABEL = /^[+-][xyz]$/;

// Lines "label x y z" or "x y z" (canonical order); separators: spaces, tabs, commas, semicolons.
export function parseReadings(text) {
  const lines = text.split(/\r?\n/).map((l) => l.trim()).filter((l) => l && !l.startsWith("#"));
  if (lines.length !== 6) throw new Error(`expected 6 lines, got ${lines.length}`);
  return lines.map((line, i) => {
    const parts = line.split(/[\s,;]+/).filter(Boolean);
    let up = CANONICAL[i];
    if (LABEL.test(parts[0])) up = parts.shift();
    if (parts.length !== 3) throw new Error(`line ${i + 1}: expected three numbers`);
    const mean = parts.map(Number);
    if (!mean.every(Number.isFinite)) throw new Error(`line ${i + 1}: ${parts.join(" ")} are not all numbers`);
    return { up, mean };
  });
}

export function formatNumber(v, digits = 6) {
  if (v === null || v === undefined) return "—";
  if (typeof v !== "number") return String(v);
  if (Number.isInteger(v) && Math.abs(v) < 1e9) return String(v); // a count is a count: 6, not 6.000000
  return Math.abs(v) >= 1e4 || (Math.abs(v) < 1e-3 && v !== 0) ? v.toExponential(4) : v.toFixed(digits);
}
