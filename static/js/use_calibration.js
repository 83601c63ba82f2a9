// The top of every result page: the verdict in words (app/verdict.py), then "Use this calibration":
// the one file for what the person uses it with (app/web/uses.py; the choice is remembered), one line
// on how to apply it, and every format under it. A calibration that must not be applied offers none.
// Shared by the start page, the wizard and the compass page (templates/_use.html).

import { fetchExport, getUse } from "./api.js";
import { kindOf } from "./result_kinds.js";
import { TABLES } from "./tables.js";
import { $, el } from "./dom.js";

const REMEMBER = "trical.use";
let blobUrls = [];



// The verdict card; returns the verdict (every calibration the server returns carries one).
export function showVerdict(cal) {
  const v = cal.verdict;
  const box = $("#verdict");
  box.dataset.kind = v.kind;
  box.dataset.apply = String(v.apply);
  $("#verdict-words").textContent = v.words;
  $("#verdict-why").textContent = v.why || "";
  $("#verdict-why").hidden = !v.why;
  return v;
}

// Every format of the calibration fetched once, as {key, name, url, filename} or {key, name, error}:
// an export the server refuses shows its reason instead of a link that answers 422. None for a
// calibration that must not be applied.
export async function fetchDownloads(cal, token = null) {
  blobUrls.forEach((u) => URL.revokeObjectURL(u));
  blobUrls = [];
  if (!cal.verdict.apply) return [];
  const kind = kindOf(cal);
  const names = TABLES.uses.sets[kind.uses].formats;
  // The paste-ready lines of each use (app/io/exports/snippets.py): a correction's only.
  const snippets = !kind.snippets ? Promise.resolve(null) : getUse(cal.id, token).catch(() => null);
  const downloads = await Promise.all(names.map(async ([key, name]) => {
    try {
      const { blob, filename } = await fetchExport(cal.id, key, token);
      const url = URL.createObjectURL(blob);
      blobUrls.push(url);
      return { key, name, url, filename };
    } catch (err) {
      return { key, name, error: err.message };
    }
  }));
  downloads.snippets = await snippets;
  return downloads;
}

let connected = null;

// Where the readings come from when the calibration does not say (a board connected to this page).
export function preferSource(source) { connected = source; }

// Where a calibration's readings came from: its own `source` (a session's, or its recording's format), a flight
// compass's firmware, else what this page is connected to.
export function sourceOf(cal) { return cal.source || cal.flight?.firmware || connected || "any"; }

// The use offered first: the person's own choice for calibrations of this source, else the source's default
// (app/web/uses.py DEFAULT_USES, the one rule), else the kind's first use; among the uses whose file the server
// gives, where any does (a noise without a random walk: not Kalibr, but the JSON).
function chosenUse(uses, kind, source, works) {
  let saved = null;
  try { saved = localStorage.getItem(`${REMEMBER}.${kind}.${source}`); } catch { /* private mode: no memory */ }
  const usable = uses.filter(works);
  const among = usable.length ? usable : uses;
  const byDefault = (TABLES.uses.defaults[source] || []).map((key) => among.find((u) => u.key === key)).find(Boolean);
  return among.find((u) => u.key === saved) || byDefault || among[0];
}

// Before a new calibration's files are fetched: nothing stale on show.
export function resetUse() {
  $("#use").hidden = true;
  $("#downloads").replaceChildren();
  delete $("#downloads").dataset.ready;
}

// "Use this calibration" from the fetched downloads; hidden for a calibration that must not be applied.
export function showUse(cal, downloads) {
  const box = $("#use");
  const list = $("#downloads");
  box.hidden = !cal.verdict.apply;
  list.dataset.ready = "true";
  if (!cal.verdict.apply) {
    list.replaceChildren();
    return;
  }
  const entry = kindOf(cal);
  const kind = entry.uses;
  // A kind may offer only the uses that fit this calibration (a flight's compass: its own log's firmware).
  const usesOfKind = TABLES.uses.sets[kind].uses;
  const uses = entry.usesFor ? entry.usesFor(cal, usesOfKind) : usesOfKind;
  const source = sourceOf(cal);
  const listed = `${kind}:${source}:${uses.map((u) => u.key).join(",")}`;
  const select = $("#use-with");
  if (select.dataset.kind !== listed) {
    select.dataset.kind = listed;
    select.replaceChildren(...uses.map((u) => el("option", u.name, { value: u.key })));
    select.onchange = () => {
      try { localStorage.setItem(`${REMEMBER}.${kind}.${source}`, select.value); } catch { /* no memory */ }
      showUse(cal, downloads);
    };
  }
  const use = chosenUse(uses, kind, source, (u) => Boolean(downloads.find((d) => d.key === u.format)?.url));
  select.value = use.key;
  const file = downloads.find((d) => d.key === use.format);
  // A firmware's offsets and scales (app/io/exports/params.py): what they reach on the readings, and the file
  // offered only where that is better than raw.
  const firmware = file?.url ? downloads.snippets?.firmware?.[use.format] : null;
  const offered = Boolean(file?.url) && (!firmware || firmware.improves);
  const link = $("#use-file");
  const problem = $("#use-problem");
  link.hidden = !offered;
  problem.hidden = offered;
  $("#use-firmware").textContent = offered && firmware ? firmware.words : "";
  $("#use-firmware").hidden = !(offered && firmware);
  if (offered) {
    link.href = file.url;
    link.download = file.filename;
    link.dataset.format = file.key;
    link.textContent = `Download the ${file.name} file`;
    link.title = file.filename;
    $("#use-how").textContent = use.how;
  } else {
    $("#use-how").textContent = "";
    const why = firmware ? firmware.words : file ? file.error : "no file for it";
    problem.textContent = `${use.name}: ${why}. Pick another use, or a format below.`;
  }
  showSnippet(use, file?.url ? downloads.snippets : null);
  list.replaceChildren(...downloads.map((d) => {
    const li = el("li");
    if (d.url) li.append(el("a", d.name, { href: d.url, download: d.filename, "data-format": d.key }));
    else li.append(el("span", `${d.name}: ${d.error}`));
    return li;
  }));
}

// The lines of the chosen use under its file, with what to check: a scale from counts that is a
// common part's figure, not the person's.
function showSnippet(use, snippets) {
  const text = use.snippet && snippets ? snippets[use.snippet] : null;
  $("#use-snippet-box").hidden = !text;
  $("#use-snippet code").textContent = text || "";
  $("#use-copy").textContent = "Copy these lines";
  const guessed = Object.entries(snippets?.scales || {}).filter(([, s]) => s && !s.known);
  $("#use-snippet-note").textContent = guessed.map(([sensor, s]) => `The ${TABLES.sensorWords[sensor].toLowerCase()}'s `
    + `counts are scaled by ${s.words.replace(/: set your part's figure$/, "")}: `
    + "set your part's figure from its datasheet.").join(" ");
  $("#use-snippet-note").hidden = !guessed.length;
}

// Copy the lines: the Clipboard API where the page may use it, else the text selected for the person to copy.
const copy = document.querySelector("#use-copy");
if (copy) {
  copy.addEventListener("click", async () => {
    const code = $("#use-snippet code");
    try {
      await navigator.clipboard.writeText(code.textContent);
      copy.textContent = "Copied";
    } catch {
      getSelection().selectAllChildren(code);
      copy.textContent = "Selected: copy with Ctrl+C or ⌘C";
    }
  });
}
