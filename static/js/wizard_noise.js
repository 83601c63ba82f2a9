// The noise page (/wizard?protocol=noise): a board's still recording of a chosen length, uploaded as a
// log (POST /api/v1/recordings, its time column the board's) and characterised by the Allan deviation
// (POST /api/v1/calibrations, method noise). The board's samples come from board_panel.js, the same
// source as the wizard's flows.
import { createCalibration, exportUrl, uploadRecording } from "./api.js";
import { BoardPanel } from "./board_panel.js";
import { cue, unlockCues } from "./cues.js";
import { formatNumber } from "./readings.js";
import { fetchDownloads, resetUse, showUse, showVerdict } from "./use_calibration.js";
import { $, el } from "./dom.js";

const state = { recording: null, lengthS: 0, busy: false, ready: false };

function say(text) { $("#status").textContent = text; }

function message(text) { $("#noise-msg").textContent = text; }

function canRecord() { $("#noise-record").disabled = !(board.connected && state.ready) || state.busy; }

// The recording as the CSV trical's log readers know: the board's time in s, then m/s² and °/s.
export function recordingCsv(samples) {
  const t0 = samples[0].t;
  const gyr = samples.every((s) => s.gyr);
  const head = ["time_s", "acc_x (m/s^2)", "acc_y (m/s^2)", "acc_z (m/s^2)"];
  if (gyr) head.push("gyr_x (deg/s)", "gyr_y (deg/s)", "gyr_z (deg/s)");
  const rows = samples.map((s) => [((s.t - t0) / 1000).toPrecision(12), ...s.acc.map(String),
    ...(gyr ? s.gyr.map(String) : [])].join(","));
  return `${head.join(",")}\n${rows.join("\n")}\n`;
}

function onSample(sample) {
  if (!state.ready) { state.ready = true; canRecord(); message("The board reads: put it down still, choose the length and press Record."); }
  const rec = state.recording;
  if (!rec || !sample.acc) return;
  rec.push(sample);
  const span = (sample.t - rec[0].t) / 1000;
  $("#noise-progress").value = Math.min(1, span / state.lengthS);
  if (rec.length % 25 === 0) message(`Recording: ${Math.floor(span)} of ${state.lengthS} s. Leave the board alone.`);
  if (span >= state.lengthS) finish(rec);
}

function record() {
  unlockCues();
  state.lengthS = Number($("#noise-length").value);
  state.recording = [];
  state.busy = true;
  canRecord();
  $("#noise-progress").hidden = false;
  $("#noise-progress").value = 0;
  $("#result").hidden = true;
  cue("start");
  message(`Recording ${$("#noise-length").selectedOptions[0].textContent}: leave the board alone.`);
  say("Recording: leave the board alone.");
}

async function finish(samples) {
  state.recording = null;
  cue("captured");
  message(`Recorded ${samples.length} readings: uploading and computing the Allan deviation…`);
  try {
    const data = new FormData();
    data.append("file", new Blob([recordingCsv(samples)], { type: "text/csv" }), "board_still.csv");
    const rec = await uploadRecording(data);
    const cal = await createCalibration({ method: "noise", recording_id: rec.id });
    showResult(cal, rec);
    message(`Recorded ${samples.length} readings at ${formatNumber(rec.sampling_rate_hz, 4)} Hz.`);
  } catch (err) {
    cue("refused");
    message(`The recording could not be characterised: ${err.message}. Record again (longer, or stiller).`);
    say(`Refused: ${err.message}`);
  } finally {
    state.busy = false;
    $("#noise-progress").hidden = true;
    canRecord();
  }
}

const TERMS = [["noise_density", "noise density"], ["random_walk", "random walk"],
  ["bias_instability", "bias instability"], ["bias", "bias"]];

function showResult(cal) {
  showVerdict(cal);
  $("#result").hidden = false;
  $("#result-headline").textContent = cal.headline || "";
  const ok = $("#result-ok");
  ok.className = cal.ok ? "ok" : "bad";
  ok.textContent = cal.ok ? `Characterisation ${cal.id} passed its checks.` : `Characterisation ${cal.id} failed its checks: ${(cal.reasons || []).join("; ")}`;
  $("#result-allan img").src = exportUrl(cal.id, "allan_svg");
  $("#result-model").replaceChildren(...Object.entries(cal.model).filter(([k]) => k !== "type").map(([sensor, m]) => {
    const box = el("div", null, { class: "scroll", tabindex: "0" });
    const table = el("table", null, { id: `result-noise-${sensor}` });
    const head = el("tr");
    head.append(el("th", sensor, { scope: "col" }), ...["x", "y", "z"].map((a) => el("th", a, { scope: "col" })), el("th", "unit", { scope: "col" }));
    table.append(head);
    for (const [key, words] of TERMS) {
      const tr = el("tr");
      tr.dataset.term = key;
      tr.append(el("th", words, { scope: "row" }), ...(m[key] || [null, null, null]).map((v) => el("td", formatNumber(v, 6))),
        el("td", m[`${key}_unit`] || m.unit || ""));
      table.append(tr);
    }
    box.append(table);
    return box;
  }));
  $("#result-warnings").replaceChildren(...((cal.warnings || []).length ? cal.warnings : ["none"]).map((w) => el("li", w)));
  resetUse();
  fetchDownloads(cal).then((downloads) => showUse(cal, downloads));
  $("#result").focus();
  say(`Done. ${cal.verdict.words}`);
}

const board = new BoardPanel({
  needAcc: true,
  onConnect: () => { state.ready = false; message("Connected: keep the board still while the page checks its unit…"); canRecord(); },
  onSample,
  onClose: (why) => {
    state.ready = false;
    if (state.recording) { state.recording = null; state.busy = false; $("#noise-progress").hidden = true; }
    message(`${why} Connect it again to record.`);
    canRecord();
  },
});
$("#noise-record").addEventListener("click", record);
if ($("#board").hidden || $("#board-connect").hidden) {
  message("This page reads a board over USB or Bluetooth, in Chrome, Edge or Opera on a computer. Elsewhere, record "
    + "the board still with its serial monitor and upload the log on the start page (Characterise the noise).");
}
