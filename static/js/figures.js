// Every figure of a calibration in words (app/web/metric_words.py through the page's tables): its name,
// value with its unit, and one line saying what it is; never the stored key. Shared by every result.
import { formatNumber } from "./readings.js";
import { TABLES } from "./tables.js";
import { withInterval } from "./result.js";
import { el } from "./dom.js";

const UNIT_WORDS = TABLES.unitWords; // each unit in words (app/words.py)
const SUFFIX_UNITS = [["_mg", "mg"], ["_ut", "µT"], ["_deg", "°"], ["_hz", "Hz"], ["_s", "s"], ["_pct", "%"]];

// A name made from a key the table does not list: its words, its unit from its suffix.
function fallback(key) {
  let unit = "";
  let words = key;
  for (const [suffix, u] of SUFFIX_UNITS) {
    if (key.endsWith(suffix)) { unit = u; words = key.slice(0, -suffix.length); break; }
  }
  const name = words.replace(/_/g, " ");
  return [name.charAt(0).toUpperCase() + name.slice(1), unit, ""];
}

function valueText(v) {
  if (typeof v === "boolean") return v ? "yes" : "no";
  if (Array.isArray(v)) {
    return v.length ? v.map((x) => (typeof x === "number" ? formatNumber(x, 4) : String(x))).join(", ") : "none";
  }
  return formatNumber(v);
}

// [{name, value, unit, meaning}] of the calibration's metrics; a sensor's block (noise) is named by its sensor.
export function figureRows(cal) {
  const inputUnit = UNIT_WORDS[cal.unit] || cal.unit || "";
  const row = (key, v, sensor = null) => {
    const [name, unit, meaning] = TABLES.metrics[key] || fallback(key);
    const shownUnit = unit === "input unit" ? inputUnit : unit === "sensor unit" ? "" : unit;
    const lower = `${name.charAt(0).toLowerCase()}${name.slice(1)}`;
    return { key, name: sensor ? `${TABLES.sensorWords[sensor] || sensor}: ${lower}` : name,
      value: valueText(v), unit: v === null || v === undefined ? "" : shownUnit, meaning };
  };
  return Object.entries(cal.metrics || {}).flatMap(([k, v]) => (v && typeof v === "object" && !Array.isArray(v)
    ? Object.entries(v).map(([k2, v2]) => row(k2, v2, k)) : [row(k, v)]));
}

// The nouns of counts among the figures' units (app/web/metric_words.py), in the singular.
const SINGULAR = { readings: "reading", points: "point", segments: "segment", positions: "position",
  samples: "sample", turns: "turn", "rests and moves": "rest or move" };

// The figures into a table: the name with its line in a row header, the value with its unit.
export function fillFigures(table, cal) {
  table.replaceChildren(...figureRows(cal).map((r) => {
    const tr = document.createElement("tr");
    tr.dataset.key = r.key;
    const th = document.createElement("th");
    th.scope = "row";
    th.textContent = r.name;
    if (r.meaning) {
      const small = document.createElement("span");
      small.className = "meaning";
      small.textContent = r.meaning;
      th.append(small);
    }
    const td = document.createElement("td");
    // A count of one takes its noun in the singular: "1 reading", not "1 readings".
    const unit = r.value === "1" && SINGULAR[r.unit] ? SINGULAR[r.unit] : r.unit;
    td.textContent = unit && r.value !== "—" ? `${r.value} ${unit}` : r.value;
    tr.append(th, td);
    return tr;
  }));
}

// A matrix (rows of numbers) into a table, each number with its 95 % half-width when given.
export function fillMatrix(table, rows, halfWidths = null, digits = 6) {
  table.replaceChildren(...rows.map((row, i) => {
    const tr = el("tr");
    row.forEach((v, j) => tr.append(el("td", withInterval(v, halfWidths?.[i]?.[j], (x) => formatNumber(x, digits)))));
    return tr;
  }));
}

// A vector as the one-column rows of a matrix.
export const column = (v) => (v ? v.map((x) => [x]) : null);
