// Notes a person reads (the reader's and the calibration's warnings): each once, the decisions first as a short
// list — the units, the columns and the clock trical read the file with — grouped by the file they are about when
// there are several, and the rest folded under "Details". Used by the start page and every result.

import { cell } from "./dom.js";

// What trical decided about reading a file: a unit, a column, the time column or the clock, a sign, a merge.
const DECISION = new RegExp("\\bunit\\b|\\binferred\\b|\\bcolumns?\\b|time column|\\bclock\\b|\\bsign\\b|\\bnegated\\b"
  + "|\\bmerged\\b|\\bread as\\b|\\bcounts\\b", "i");
// A note about one file of several names it first: "gyro.csv: …" or "gyro.csv (the gyroscope) …".
const FILE = /^([\w.()+-]+\.(?:csv|txt|tsv|json|zip|npy|parquet|ulg|bin))\b/i;

// Each note once, split into the decisions and the rest, each list grouped by the file a note names.
export function sortNotes(notes) {
  const unique = [...new Set((notes || []).filter(Boolean))];
  return {
    decisions: unique.filter((n) => DECISION.test(n)),
    details: unique.filter((n) => !DECISION.test(n)),
  };
}

// The notes by the file each names first, where they name two files or more (else one group, "").
function byFile(notes) {
  const fileOf = (note) => note.match(FILE)?.[1] || "";
  const files = new Set(notes.map(fileOf).filter(Boolean));
  const groups = new Map();
  for (const note of notes) {
    const file = files.size > 1 ? fileOf(note) : "";
    if (!groups.has(file)) groups.set(file, []);
    groups.get(file).push(note);
  }
  return groups;
}

function list(notes) {
  const groups = byFile(notes);
  const ul = document.createElement("ul");
  ul.className = "note";
  for (const [file, items] of groups) {
    if (!file) { ul.append(...items.map((n) => cell("li", n))); continue; }
    const li = cell("li", "");
    li.append(cell("strong", file));
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
