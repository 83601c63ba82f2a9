// The history: every calibration this browser can read (no token or the API key it was given, and
// each wizard session's token kept in tokens.js), newest first, filtered by device; a device's
// latest calibration is one link, /c/latest?device=NAME. One row per recording and method: a reading of the
// same upload again supersedes the earlier ones, which "N earlier" under its date shows in place.
import { compareCalibrations, getCalibration, importCalibration, listCalibrations, listEarlier } from "./api.js";
import { comparisonBlock } from "./check_view.js";
import { kindOf } from "./result_kinds.js";
import { TABLES } from "./tables.js";
import { apiKey, linkedCalibrations, rememberApiKey, sessionTokens } from "./tokens.js";
import { $, cell, el } from "./dom.js";

const root = $("#history");
let items = [];
const readWith = new Map(); // calibration id → the token that read it (its earlier ones read with the same)
const earlierOf = new Map(); // calibration id → its earlier calibrations, once shown


function when(iso) { return iso ? iso.slice(0, 16).replace("T", " ") : "—"; }

// Each owner's list, merged (one calibration once), newest first. A server with keys answers 401
// without one: the person is asked for it.
async function readAll() {
  const owners = [apiKey(), ...sessionTokens()]; // no key: null, the keyless owner
  let needKey = null;
  const lists = await Promise.all(owners.map(async (token) => {
    try {
      const { items: found } = await listCalibrations(token);
      for (const cal of found) readWith.set(cal.id, token);
      return found;
    } catch (err) {
      if (err.code === "unauthorized" && (token === null || token === apiKey())) needKey = err;
      return [];
    }
  }));
  // Those a link sent here opened: one each, while the link holds.
  const linked = await Promise.all(
    linkedCalibrations().map(([id, token]) => getCalibration(id, token).catch(() => null)));
  const seen = new Map();
  for (const cal of [...lists.flat(), ...linked.filter(Boolean)]) seen.set(cal.id, cal);
  return { cals: [...seen.values()].sort((a, b) => (a.created_at < b.created_at ? 1 : -1)), needKey };
}

function row(cal, earlierThan = null) {
  const tr = document.createElement("tr");
  tr.dataset.id = cal.id;
  const date = cell("th", "");
  date.scope = "row";
  date.append(Object.assign(cell("a", when(cal.created_at)), { href: `/c/${encodeURIComponent(cal.id)}` }));
  if (earlierThan) {
    tr.dataset.earlierThan = earlierThan;
    tr.classList.add("earlier");
    date.append(el("span", "an earlier reading", { class: "hint earlier-note" }));
  } else if (cal.earlier) {
    const open = earlierOf.has(cal.id);
    const button = el("button", `${cal.earlier} earlier`, { type: "button", class: "secondary earlier-toggle" });
    button.setAttribute("aria-expanded", String(open));
    button.title = "The earlier readings of the same upload with this method";
    button.addEventListener("click", () => toggleEarlier(cal));
    date.append(button);
  }
  const verdict = cell("td", cal.verdict.words);
  verdict.dataset.kind = cal.verdict.kind;
  const named = (label, text) => { const td = cell("td", text); td.dataset.label = label; return td; };
  const device = named("Device", cal.device_id || "—");
  const method = named("Method", (TABLES.methods[cal.method] || cal.method) + compassOf(cal));
  verdict.dataset.label = "Verdict";
  tr.append(date, device, method, verdict);
  return tr;
}

// A flight log's compass: which one it was, and whether the firmware takes it for external (its row is its own:
// compass 1's calibration is no later reading of compass 0's).
function compassOf(cal) {
  const flight = cal.flight;
  if (!flight || flight.instance == null) return "";
  const where = flight.external === true ? " (external)" : flight.external === false ? " (internal)" : "";
  return `, compass ${flight.instance}${where}`;
}

// "N earlier": the earlier calibrations of the row's recording and method, under it; again hides them.
async function toggleEarlier(cal) {
  if (earlierOf.has(cal.id)) {
    earlierOf.delete(cal.id);
  } else {
    try {
      earlierOf.set(cal.id, (await listEarlier(cal.id, readWith.get(cal.id) ?? null)).items);
    } catch (err) {
      $("#history-msg").textContent = `The earlier calibrations could not be read: ${err.message}.`;
      return;
    }
  }
  render();
  $(`#history-table tr[data-id="${cal.id}"] .earlier-toggle`).focus();
}

function render() {
  const device = $("#history-device").value;
  const shown = items.filter((c) => !device || c.device_id === device);
  $("#history-table tbody").replaceChildren(...shown.flatMap((cal) => [row(cal),
    ...(earlierOf.get(cal.id) || []).map((old) => row(old, cal.id))]));
  $("#history-table").hidden = !shown.length;
  $("#history-msg").textContent = shown.length ? `${shown.length} calibration${shown.length === 1 ? "" : "s"}.`
    : device ? `No calibration of ${device} here.` : "No calibration readable in this browser yet: upload a log or "
      + "run the wizard on the start page.";
  const latest = $("#history-latest");
  latest.hidden = !device || !shown.length;
  if (device) {
    $("#history-latest-link").href = `/c/latest?device=${encodeURIComponent(device)}`;
    $("#history-latest-link").textContent = `The latest calibration of ${device}`;
  }
  offerComparison(shown);
  const url = device ? `/history?device=${encodeURIComponent(device)}` : "/history";
  if (location.pathname + location.search !== url) history.replaceState(null, "", url);
}

// Compare two of the calibrations shown (GET …/{id}/compare?with=…): the older A, the newer B by default.
function offerComparison(shown) {
  const cals = shown.filter((c) => kindOf(c).correction);
  const option = (c) => Object.assign(cell("option", `${when(c.created_at)} · ${c.device_id || "no device"} · `
    + `${TABLES.methods[c.method] || c.method}`), { value: c.id });
  for (const [id, pick] of [["#compare-a", Math.min(1, cals.length - 1)], ["#compare-b", 0]]) {
    const select = $(id);
    const kept = select.value;
    select.replaceChildren(...cals.map(option));
    select.value = cals.some((c) => c.id === kept) ? kept : cals[pick]?.id ?? "";
  }
  $("#compare-card").hidden = cals.length < 2;
}

$("#compare-form").addEventListener("submit", async (event) => {
  event.preventDefault();
  const a = $("#compare-a").value;
  const b = $("#compare-b").value;
  $("#compare-result").replaceChildren();
  if (!a || !b || a === b) {
    $("#compare-msg").textContent = "Choose two different calibrations.";
    return;
  }
  $("#compare-msg").textContent = "Comparing…";
  try {
    const out = await compareCalibrations(a, b, readWith.get(a) ?? null);
    $("#compare-msg").textContent = "";
    $("#compare-result").replaceChildren(comparisonBlock(out));
  } catch (err) {
    $("#compare-msg").textContent = `They could not be compared: ${err.message}.`;
  }
});

async function load() {
  const { cals, needKey } = await readAll();
  items = cals;
  const devices = [...new Set(items.map((c) => c.device_id).filter(Boolean))].sort();
  const select = $("#history-device");
  const wanted = select.value || root.dataset.device;
  select.replaceChildren(Object.assign(cell("option", "every device"), { value: "" }),
    ...devices.map((d) => Object.assign(cell("option", d), { value: d })));
  if (wanted && !devices.includes(wanted)) select.append(Object.assign(cell("option", wanted), { value: wanted }));
  select.value = wanted || "";
  $("#cal-access").hidden = !needKey;
  if (needKey) $("#cal-access-why").textContent = `The server answered: ${needKey.message}.`;
  render();
}

$("#history-device").addEventListener("change", () => {
  render();
  if ($("#history-device").value) $("#import-device").value = $("#history-device").value;
});

// A device's own calibration, from its firmware's file: stored as the device's, then opened on its page.
$("#import-form").addEventListener("submit", async (event) => {
  event.preventDefault();
  const form = new FormData($("#import-form"));
  for (const name of ["device_id", "firmware"]) if (!form.get(name)) form.delete(name);
  $("#import-submit").disabled = true;
  $("#import-msg").textContent = "Reading the file…";
  try {
    const cal = await importCalibration(form, apiKey());
    $("#import-msg").textContent = cal.headline || "Stored.";
    location.assign(`/c/${encodeURIComponent(cal.id)}`);
  } catch (err) {
    $("#import-msg").textContent = `Not brought in: ${err.message}.`;
  } finally {
    $("#import-submit").disabled = false;
  }
});
$("#cal-key-form").addEventListener("submit", (event) => {
  event.preventDefault();
  rememberApiKey($("#cal-key").value.trim());
  load();
});

load();
