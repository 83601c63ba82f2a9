// Notes a person reads (the reader's and the calibration's warnings): each once, the decisions first as a short
// list — the units, the columns and the clock trical read the file with — grouped by the file they are about when
// there are several, else by the sensor, and the rest folded under "Details". Used by the start page and every
// result.

import { cell } from "./dom.js";

// What trical decided about reading a file: a unit, a column, the time column or the clock, a sign, a merge.
const DECISION = new RegExp("\\bunit\\b|\\binferred\\b|\\bcolumns?\\b|time column|\\bclock\\b|\\bsign\\b|\\bnegated\\b"
  + "|\\bmerged\\b|\\bread as\\b|\\bcounts\\b", "i");
// A note about one file of several names it first: "gyro.csv: …" or "gyro.csv (the gyroscope) …".
const FILE = /^([\w.()+-]+\.(?:csv|txt|tsv|json|zip|npy|parquet|ulg|bin))\b/i;

// Each note once, split into the decisions and the rest.
export function sortNotes(notes) {
  const unique = [...new Set((notes || []).filter(Boolean))];
  return {
    decisions: unique.filter((n) => DECISION.test(n)),
    details: unique.filter((n) => !DECISION.test(n)),
  };
}

// The sensor a note is about: its first word of a sensor, a compass being the magnetometer.
const SENSORS = ["accelerometer", "gyroscope", "magnetometer"];
const SENSOR = /\b(?:(accelerometer)|(gyroscope)|(magnetometer|compass))\b/i;

// The notes by the file each names first where they name two files or more, else by the sensor each is about
// where they speak of two sensors or more (else one group, ""): a person reads what concerns one thing together.
function byFile(notes) {
  const fileOf = (note) => note.match(FILE)?.[1] || "";
  const sensorOf = (note) => {
    const m = note.match(SENSOR);
    return m ? SENSORS[m.slice(1).findIndex(Boolean)] : "";
  };
  const files = new Set(notes.map(fileOf).filter(Boolean));
  const sensors = new Set(notes.map(sensorOf).filter(Boolean));
  const keyOf = files.size > 1 ? fileOf : sensors.size > 1 ? sensorOf : () => "";
  const groups = new Map([["", []]]);
  for (const note of notes) {
    const key = keyOf(note);
    if (!groups.has(key)) groups.set(key, []);
    groups.get(key).push(note);
  }
  if (!groups.get("").length) groups.delete("");
  return groups;
}

function list(notes) {
  const groups = byFile(notes);
  const ul = document.createElement("ul");
  ul.className = "note";
  for (const [file, items] of groups) {
    if (!file) { ul.append(...items.map((n) => cell("li", n))); continue; }
    const li = cell("li", "");
    li.append(cell("strong", file.includes(".") ? file : file[0].toUpperCase() + file.slice(1))); // a sensor: a title
    const inner = document.createElement("ul");
    inner.append(...items.map((n) => cell("li", n)));
    li.append(inner);
    ul.append(li);
  }
  return ul;
}

// The notes as nodes for `box`: the decisions' list, then "Details (N)" folded.
export function showNotes(box, notes) {
  const { decisions, details } = sortNotes(notes);
  const nodes = [];
  if (decisions.length) nodes.push(list(decisions));
  if (details.length) {
    const fold = document.createElement("details");
    fold.className = "notes-details";
    fold.append(cell("summary", `Details (${details.length})`), list(details));
    nodes.push(fold);
  }
  box.replaceChildren(...nodes);
  box.hidden = !nodes.length;
}
