// The page's small DOM helpers, one copy for every module: a selector and an element with its text and
// attributes (text is set as text, never parsed as HTML), and the writes a render loop makes on every
// frame, which touch the page only when the value changed.

export const $ = (sel) => document.querySelector(sel);

export function el(tag, text, attrs = {}) {
  const e = document.createElement(tag);
  if (text !== undefined && text !== null) e.textContent = text;
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  return e;
}

// An element with its text only (a table cell, a list item).
export function cell(tag, text) { return el(tag, text); }

// A count with its noun in the number it takes: "1 still reading", "6 still readings" (app/io/plural.py).
export function counted(n, noun, plural = `${noun}s`) { return `${n} ${n === 1 ? noun : plural}`; }

// A moment (ISO 8601) as a date and a time in this browser's zone, named: "4 December 2026, 13:51 CET" (a link
// opened tomorrow or in another zone, a calibration made some day; the API gives ISO 8601 in UTC).
export function dateTimeWords(iso) {
  const when = new Date(iso);
  const date = when.toLocaleDateString("en-GB", { day: "numeric", month: "long", year: "numeric" });
  const time = when.toLocaleTimeString("en-GB", { hour: "2-digit", minute: "2-digit", timeZoneName: "short" });
  return `${date}, ${time}`;
}

export function setText(node, text) { if (node.textContent !== text) node.textContent = text; }
export function setHidden(node, hidden) { if (node.hidden !== hidden) node.hidden = hidden; }
