// A stored calibration's own page, /c/{id} (or /c/latest?device=NAME): read through the API with
// the token this browser keeps for it (tokens.js), then shown by the one result view (result_view.js).
import { ApiError, checkCalibration, getCalibration, listCalibrations, openLink, uploadRecording } from "./api.js";
import { checkBlock } from "./check_view.js";
import { kindOf } from "./result_kinds.js";
import { showCalibration } from "./result_view.js";
import { TABLES } from "./tables.js";
import { candidates, rememberApiKey, rememberToken, sessionTokens } from "./tokens.js";
import { $, counted, el } from "./dom.js";

const root = $("#calibration-page");
let id = root.dataset.id;
const link = root.dataset.link;
const device = root.dataset.device;

// The first token that opens it: 401 (a server with keys) and 404 (another owner's) try the next;
// when none does, the answer to the most specific one (a key refused says so) is the one shown.
async function read() {
  if (!id) return latest();
  let last = null;
  for (const token of candidates(id)) {
    try {
      return { cal: await getCalibration(id, token), token };
    } catch (err) {
      if (err.code !== "unauthorized" && err.code !== "not_found") throw err;
      last ??= err;
    }
  }
  throw last;
}

// A device's latest (/c/latest?device=NAME): the newest of what each token this browser keeps reads of it —
// its wizard sessions' (each reads its own calibration), the API key's, and none (a server without keys).
async function latest() {
  const found = [];
  let last = null;
  for (const token of [...sessionTokens(), ...candidates(null)]) {
    try {
      const { items } = await listCalibrations(token, device, 1);
      if (items.length) found.push({ cal: items[0], token });
    } catch (err) {
      if (err.code !== "unauthorized" && err.code !== "not_found") throw err;
      last ??= err;
    }
  }
  if (!found.length) {
    throw last ?? new ApiError(`no calibration of the device “${device}” is readable here`, 404, "not_found");
  }
  return found.sort((a, b) => b.cal.created_at.localeCompare(a.cal.created_at))[0];
}

function when(iso) { return iso ? iso.replace("T", " ").replace(/\.\d+Z$/, " UTC") : ""; }

// A short link sent from the phone (/s/CODE): the calibration it opens, its token kept for the
// calibration's own address, which replaces the link's in the address bar.
// The readings of the same upload around this one (app/store: a later one of the same recording, method
// and device supersedes): the newer one a tap away, or how many earlier ones the history holds under it.
function showReadings(cal) {
  const p = $("#cal-readings");
  p.replaceChildren();
  if (cal.superseded_by) {
    p.append("A newer reading of the same upload superseded this one (it is kept): ",
      el("a", "open the newer reading", { href: `/c/${encodeURIComponent(cal.superseded_by)}` }), ".");
  } else if (cal.earlier) {
    p.append(
      `This reading superseded ${counted(cal.earlier, "earlier reading")} of the same upload, kept under its row in `,
      el("a", "your calibrations", { href: "/history" }), ".");
  }
  p.hidden = !p.childNodes.length;
}

async function follow() {
  const opened = await openLink(link);
  id = opened.calibration_id;
  rememberToken(id, opened.token);
  history.replaceState(null, "", `/c/${encodeURIComponent(id)}`);
}

async function load() {
  $("#cal-loading").hidden = false;
  $("#cal-access").hidden = true;
  try {
    if (link && !id) await follow();
    const { cal, token } = await read();
    $("#cal-loading").hidden = true;
    const meta = $("#cal-meta");
    const method = TABLES.methods[cal.method] || cal.method;
    // A calibration a device already held says what it was read from (its firmware, version and file).
    const from = cal.read_from;
    const source = from && `read from ${[from.firmware, from.version].filter(Boolean).join(" ")} (${from.file_kind})`;
    meta.textContent = [cal.device_id && `Device ${cal.device_id}`, `Method: ${method}`, source,
      `made ${when(cal.created_at)}`, `id ${cal.id}`].filter(Boolean).join(" · ");
    meta.hidden = false;
    showReadings(cal);
    document.title = `${cal.device_id ? `${cal.device_id}: ` : ""}calibration ${cal.id} — trical`;
    showCalibration(cal, token);
    offerCheck(cal, token);
    $("#status").textContent = `Calibration ${cal.id}. ${cal.verdict.words}`;
  } catch (err) {
    $("#cal-loading").hidden = true;
    const box = $("#cal-access");
    const why = err.code === "unauthorized"
      ? `Not readable here: ${err.message}.`
      : err.code === "not_found"
        ? (id ? `No calibration ${id} is readable with what this browser keeps: a phone calibration opens only in `
          + "the browser that made it (or with the link it sends), an upload only with the API key that made it."
          : `${err.message}.`)
        : `The calibration could not be read: ${err.message}.`;
    $("#cal-access-why").textContent = why;
    $("#cal-key-form").hidden = Boolean(link) || (err.code !== "unauthorized" && err.code !== "not_found");
    box.hidden = false;
    box.focus();
    $("#status").textContent = why;
  }
}

// Check it on a new recording (POST …/{id}/check): the upload, then the verdict. Only a correction is checked,
// and not through a short link (lnk_…), which reads its one calibration only.
let checking = null;
function offerCheck(cal, token) {
  checking = { cal, token };
  $("#check-card").hidden = !kindOf(cal).correction || Boolean(token?.startsWith("lnk_"));
  // A compass's calibration from a phone's or a board's turn: the compass page's live turn on that phone or board
  // checks it, with no file to record first.
  const live = kindOf(cal).live_check && ["phone", "board"].includes(cal.source);
  $("#check-live").hidden = !live;
  if (!live) return;
  const query = new URLSearchParams({ protocol: "compass", source: cal.source, check: cal.id });
  $("#check-live-link").href = `/wizard?${query}`;
  $("#check-live-link").textContent = `Turn the ${cal.source} for a minute`;
}

$("#check-form").addEventListener("submit", async (event) => {
  event.preventDefault();
  if (!checking) return;
  const { cal, token } = checking;
  const file = $("#check-file").files[0];
  if (!file) return;
  const data = new FormData();
  data.append("file", file);
  $("#check-result").replaceChildren();
  $("#check-msg").textContent = "Uploading…";
  try {
    const rec = await uploadRecording(data, token);
    $("#check-msg").textContent = "Checking…";
    const out = await checkCalibration(cal.id, rec.id, token);
    $("#check-msg").textContent = "";
    $("#check-result").replaceChildren(checkBlock(out));
    $("#status").textContent = `Checked: ${TABLES.checkVerdicts[out.verdict]}.`;
  } catch (err) {
    $("#check-msg").textContent = `The check could not be made: ${err.message}.`;
  }
});

$("#cal-key-form").addEventListener("submit", (event) => {
  event.preventDefault();
  rememberApiKey($("#cal-key").value.trim());
  load();
});

load();
