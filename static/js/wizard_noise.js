// The noise page (/wizard?protocol=noise): a board's still recording of a chosen length, uploaded as a
// log (POST /api/v1/recordings, its time column the board's) and characterised by the Allan deviation
// (POST /api/v1/calibrations, method noise). The board's samples come from board_panel.js, the same
// source as the wizard's flows. On the wizard's state (wizard_state.js) and dom.js: the steps change the
// state, render alone writes the page, with the noise's render hook for its result (noiseView) and the
// wizard's render loop for the files and the live region (wizard_render.js).
import { createCalibration, exportUrl, uploadRecording } from "./api.js";
import { BoardPanel } from "./board_panel.js";
import { cue, unlockCues } from "./cues.js";
import { showNotes } from "./notes.js";
import { formatNumber } from "./readings.js";
import { kindOf } from "./result_kinds.js";
import { fetchDownloads, resetUse, showVerdict } from "./use_calibration.js";
import { VIEW_DEFAULTS, announce, newState, showResult } from "./wizard_state.js";
import { newRendered, renderDownloads, renderVoice } from "./wizard_render.js";
import { $, setHidden, setText } from "./dom.js";

const state = newState({ protocol: "noise", captureS: null });
state.noise = {
  recording: null, // the samples so far while recording
  lengthS: 0,
  busy: false, // recording, uploading or characterising
  ready: false, // the board reads and its unit is known
  message: null, // the line under Record (the template's until the first)
  progress: null, // the recording's share done, or null: no progress bar
};
const n = state.noise;

function say(text) { announce(state, text); }

function message(text) { n.message = text; }

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
  if (!n.ready) {
    n.ready = true;
    message("The board reads: put it down still, choose the length and press Record.");
    render(state);
  }
  const rec = n.recording;
  if (!rec || !sample.acc) return;
  rec.push(sample);
  const span = (sample.t - rec[0].t) / 1000;
  n.progress = Math.min(1, span / n.lengthS);
  if (rec.length % 25 === 0) message(`Recording: ${Math.floor(span)} of ${n.lengthS} s. Leave the board alone.`);
  render(state);
  if (span >= n.lengthS) finish(rec);
}

function record() {
  unlockCues();
  n.lengthS = Number($("#noise-length").value);
  n.recording = [];
  n.busy = true;
  n.progress = 0;
  state.view.result = false;
  cue("start");
  message(`Recording ${$("#noise-length").selectedOptions[0].textContent}: leave the board alone.`);
  say("Recording: leave the board alone.");
  render(state);
}

async function finish(samples) {
  n.recording = null;
  cue("captured");
  message(`Recorded ${samples.length} readings: uploading and computing the Allan deviation…`);
  render(state);
  try {
    const data = new FormData();
    data.append("file", new Blob([recordingCsv(samples)], { type: "text/csv" }), "board_still.csv");
    const rec = await uploadRecording(data);
    const cal = await createCalibration({ method: "noise", recording_id: rec.id,
      device_id: $("#device-name").value.trim() || null });
    showResult(state, cal);
    say(`Done. ${cal.verdict.words}`);
    message(`Recorded ${samples.length} readings at ${formatNumber(rec.sampling_rate_hz, 4)} Hz.`);
    fetchDownloads(cal).then((downloads) => {
      if (state.view.calibration !== cal) return;
      state.view.downloads = downloads;
      render(state);
    });
  } catch (err) {
    cue("refused");
    message(`The recording could not be characterised: ${err.message}. Record again (longer, or stiller).`);
    say(`Refused: ${err.message}`);
  } finally {
    n.busy = false;
    n.progress = null;
    render(state);
  }
}

// --- rendering: the state onto the page --------------------------------------------------------

const rendered = newRendered();

function render(s) {
  const v = s.view;
  if (n.message !== null) setText($("#noise-msg"), n.message);
  const bar = $("#noise-progress");
  setHidden(bar, n.progress === null);
  if (n.progress !== null && bar.value !== n.progress) bar.value = n.progress;
  const disabled = !(board.connected && n.ready) || n.busy;
  if ($("#noise-record").disabled !== disabled) $("#noise-record").disabled = disabled;
  setHidden($("#result"), !v.result);
  if (v.calibration && v.calibration !== rendered.calibration) {
    rendered.calibration = v.calibration;
    resetUse(); // an earlier result's files go; this one's follow as they are fetched
    noiseView.result(v.calibration);
  }
  renderDownloads(v, rendered);
  renderVoice(v, rendered);
}

// The noise's render hook: the verdict, the Allan plot the server draws, and per sensor its noise terms
// per axis with their units (Kalibr's).
function result(cal) {
  showVerdict(cal);
  $("#result-headline").textContent = cal.headline || "";
  const ok = $("#result-ok");
  ok.className = cal.ok ? "ok" : "bad";
  ok.textContent = cal.ok ? `Characterisation ${cal.id} passed its checks.`
    : `Characterisation ${cal.id} failed its checks: ${(cal.reasons || []).join("; ")}`;
  $("#result-allan img").src = exportUrl(cal.id, "allan_svg");
  $("#result-model").replaceChildren(...kindOf(cal).model(cal)); // the start page's drawing (result_kinds.js)
  showNotes($("#result-warnings"), cal.warnings);
}

const noiseView = { ...VIEW_DEFAULTS, result };

const board = new BoardPanel({
  needAcc: true,
  onConnect: () => {
    n.ready = false;
    message("Connected: keep the board still while the page checks its unit…");
    render(state);
  },
  onSample,
  onClose: (why) => {
    n.ready = false;
    if (n.recording) { n.recording = null; n.busy = false; n.progress = null; }
    message(`${why} Connect it again to record.`);
    render(state);
  },
});
$("#noise-record").addEventListener("click", record);
if ($("#board").hidden || $("#board-connect").hidden) {
  message("This page reads a board over USB or Bluetooth, in Chrome, Edge or Opera on a computer. Elsewhere, record "
    + "the board still with its serial monitor and upload the log on the start page (Characterise the noise).");
  render(state);
}
