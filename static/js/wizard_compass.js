// The compass wizard (/wizard?protocol=compass): reads the browser's Magnetometer (the Generic
// Sensor API), fills the sphere of directions as the phone turns, and posts the readings to
// POST /api/v1/calibrations (method magnetometer) once the faces are covered. Where the browser has
// no magnetometer, it says so and points to a recording app and the upload on the start page.
// With ?check=ID (a calibration's page offers it) the turn checks that calibration instead: its readings go to
// POST /api/v1/calibrations/{id}/check, and the verdict is shown in place of a result.
// The wizard's state (wizard_state.js) and render loop (wizard_render.js): the steps below change the
// state, render(state) alone writes the page, with the compass's hooks (compass_view.js).
import { checkTurn, createCalibration } from "./api.js";
import { checkBlock } from "./check_view.js";
import { cue, unlockCues } from "./cues.js";
import { keepScreenOn, letScreenSleep } from "./wake_lock.js";
import { CompassCoverage, COVERAGE_TO_SOLVE } from "./compass_flow.js";
import { compassView } from "./compass_view.js";
import { offerSend } from "./send.js";
import { TABLES } from "./tables.js";
import { BoardPanel } from "./board_panel.js";
import { SOURCE } from "./source.js";
import { candidates } from "./tokens.js";
import { fetchDownloads } from "./use_calibration.js";
import { announce, newState, showResult } from "./wizard_state.js";
import { bindStartOver, newRendered, renderShared } from "./wizard_render.js";
import { $, setHidden, setText } from "./dom.js";

const WIZARD_URL = location.pathname + location.search; // before a result moves to /c/{id}
const NO_READING_MS = 3000;
const DRAW_MS = 150; // the sphere is redrawn at most this often
const CHECK = $("#compass").dataset.check || null; // the calibration this turn checks, if any
const SOLVE = $("#compass-solve").textContent; // the button's words: "Calibrate now", or "Check now"

const state = newState({ protocol: "compass", captureS: null, device: SOURCE });
state.compass = {
  coverage: new CompassCoverage(),
  status: null, // the coverage's status last drawn
  message: null, // what stands in for the missing faces until the next draw (a refusal, a stop)
  whereText: null, // what came of the location asked for
  sensor: null, place: null, solving: false, autoSolved: false, drawnAt: 0, timer: null, drawTimer: null,
  reading: false, boardOn: false,
  checked: null, // the check's answer (CHECK): {verdict, reasons, sensors}
};
const c = state.compass;

// The cues of the other flows, for a turn that has no poses: "start" when the first reading after
// a Start (or "Keep turning") tap arrives, so the person hears that the magnetometer really reads
// and the turn can begin; "finished" when the coverage is complete (stop turning: the page
// calibrates by itself); "refused" when the turn cannot go on as it is: the server refused the
// readings sent (keep turning, then Calibrate now) or the magnetometer stopped in the middle of it.
// A done cue per pose has no equivalent: the faces fill continuously and the sphere shows them.

// --- rendering: the state onto the page ------------------------------------------------------

const rendered = newRendered();

function render(s) {
  const v = s.view;
  setHidden($("#compass-start"), !v.start);
  if ($("#compass-none")) setHidden($("#compass-none"), !v.problem); // a phone's page only
  if (v.problem) setText($("#compass-none-why"), v.problem.detail);
  setHidden($("#compass-capture"), !v.capture);
  compassView.capture(s);
  if (CHECK) {
    setHidden($("#compass-check"), !c.checked);
    if (c.checked && rendered.checked !== c.checked) $("#check-result").replaceChildren(checkBlock(c.checked));
    rendered.checked = c.checked;
  }
  renderShared(s, rendered, compassView);
}

function say(text) { announce(state, text); }

// --- no magnetometer -------------------------------------------------------------------------

function noMagnetometer(why) {
  stopSensor();
  letScreenSleep();
  const v = state.view;
  v.start = false;
  v.capture = false;
  v.problem = { kind: "noMagnetometer", detail: why };
  v.focus = "#compass-none";
  say("This browser gives no magnetometer readings: record with a sensor app and upload the log.");
  render(state);
}

const WHY = {
  SecurityError: "the browser refused the sensor on this page (it needs HTTPS and the magnetometer permission)",
  NotAllowedError: "access to the magnetometer was not allowed",
  NotReadableError: "the browser has the interface but could not read a magnetometer on this device",
};

function refused(err) {
  if (c.coverage.count > 0) { // it stopped mid-turn: the readings so far are kept
    stopSensor();
    cue("refused");
    const text = `The magnetometer stopped (${err && (err.message || err.name)}): tap ${SOLVE} to use the `
      + `${c.coverage.count} readings so far, or Start over.`;
    c.message = text;
    say(text);
    render(state);
    return;
  }
  const why = WHY[err && err.name] || `the sensor failed (${err && (err.message || err.name)})`;
  noMagnetometer(`The Generic Sensor API's Magnetometer is present, but ${why}.`);
}

function stopSensor() {
  clearTimeout(c.timer);
  if (c.sensor) {
    try { c.sensor.stop(); } catch { /* already stopped */ }
    c.sensor.removeEventListener("reading", onReading);
  }
  c.sensor = null;
}

// --- the turn --------------------------------------------------------------------------------

function onReading() {
  const s = c.sensor;
  if (s) take([s.x, s.y, s.z]);
}

// One reading of the magnetometer, the phone's (the Generic Sensor API's) or a board's (its lines).
function take(m) {
  clearTimeout(c.timer);
  if (!c.coverage.push(m)) return;
  if (!c.reading) { c.reading = true; cue("start"); }
  const now = performance.now();
  if (now - c.drawnAt >= DRAW_MS) show();
  else if (!c.drawTimer) c.drawTimer = setTimeout(show, DRAW_MS);
}

// The coverage so far onto the page (at most every DRAW_MS); the solve once it is complete.
function show() {
  clearTimeout(c.drawTimer);
  c.drawTimer = null;
  c.drawnAt = performance.now();
  const st = c.coverage.status();
  c.status = st;
  c.message = null;
  render(state);
  if (!c.autoSolved && c.coverage.ready(st)) {
    c.autoSolved = true;
    cue("finished");
    say(`Coverage ${Math.round(100 * st.coverage)} %: ${CHECK ? "checking" : "calibrating"}.`);
    render(state);
    solve();
  }
}

// The capture card, its start-over (not while it asks) and the focus on its heading.
function turning(text) {
  const v = state.view;
  v.problem = null;
  v.start = false;
  v.result = false;
  v.capture = true;
  v.startOver = true;
  v.focus = "#compass-capture-h";
  say(text);
  render(state);
}

function start() {
  unlockCues(); // sound needs a tap
  keepScreenOn(); // the turn takes a minute without a tap
  let sensor;
  try {
    // eslint-disable-next-line no-undef
    sensor = new Magnetometer({ frequency: TABLES.compass.frequencyHz });
  } catch (err) {
    refused(err);
    return;
  }
  c.sensor = sensor;
  c.reading = false; // the start cue waits for this turn's first reading
  sensor.addEventListener("reading", onReading);
  sensor.addEventListener("error", (event) => refused(event.error));
  sensor.start();
  c.timer = setTimeout(() => {
    if (c.coverage.count === 0) {
      noMagnetometer("The Generic Sensor API's Magnetometer is present, but it sent no reading.");
    }
  }, NO_READING_MS);
  turning("Reading the magnetometer: turn the phone slowly through all directions.");
}

// The place only when the person allowed it (never waited for), with today's date for the field
// model; without a place the server uses no date (it would only warn that it went unused).
function payload() {
  const body = { method: "magnetometer", mag: c.coverage.readings, label: "compass wizard", source: SOURCE,
    device_id: $("#device-name").value.trim() || null };
  if (c.place) Object.assign(body, c.place, { date: new Date().toISOString().slice(0, 10) });
  return body;
}

// The check of CHECK on this turn's readings, with the first token this browser keeps that reads it (tokens.js).
async function checked() {
  let last = null;
  for (const token of candidates(CHECK)) {
    try {
      return await checkTurn(CHECK, c.coverage.readings, token);
    } catch (err) {
      if (err.code !== "unauthorized" && err.code !== "not_found") throw err;
      last ??= err;
    }
  }
  throw last;
}

// The check's verdict in place of a result: the turn is not kept as a calibration.
function showCheck(out) {
  letScreenSleep();
  const v = state.view;
  v.capture = false;
  v.startOver = true;
  v.focus = "#compass-check";
  c.checked = out;
  cue(out.verdict === "keep" ? "captured" : "refused");
  say(`Checked: ${TABLES.checkVerdicts[out.verdict] || out.verdict}. ${out.reasons[0] || ""}`);
}

async function solve() {
  if (c.solving) return;
  c.solving = true;
  render(state);
  try {
    if (CHECK) {
      const out = await checked();
      stopSensor();
      c.boardOn = false;
      showCheck(out);
      return;
    }
    const cal = await createCalibration(payload());
    stopSensor();
    c.boardOn = false;
    c.solving = false;
    finish(cal);
  } catch (err) {
    say(`The ${CHECK ? "check could not be made" : "calibration could not be computed"}: ${err.message}`);
    cue("refused");
    c.message = `The server refused: ${err.message}. Keep turning, then tap ${SOLVE}.`;
  } finally {
    c.solving = false;
    render(state);
  }
}

// --- the result ------------------------------------------------------------------------------

function finish(cal) {
  letScreenSleep();
  const v = state.view;
  showResult(state, cal);
  cue(cal.verdict.apply ? "captured" : "refused");
  render(state);
  // Its own address (/c/{id}): a reload, a bookmark or the history finds it again.
  history.pushState({ calibration: cal.id }, "", `/c/${encodeURIComponent(cal.id)}`);
  board.offer(cal);
  offerSend(cal);
  fetchDownloads(cal).then((downloads) => {
    if (v.calibration !== cal) return;
    v.downloads = downloads;
    render(state);
  });
}

// --- a board --------------------------------------------------------------------------------

// A board's magnetometer, from its lines (board.js): the same turn, the same sphere, in its own unit
// (µT from Raw: and Uni: lines; counts or whatever a CSV prints: the fit keeps that unit).
function startBoard() {
  state.board = board;
  c.boardOn = true;
  c.reading = false;
  unlockCues();
  stopSensor();
  turning("The board is connected: turn it slowly through all directions.");
}

const board = new BoardPanel({
  needAcc: false,
  onConnect: startBoard,
  onSample: (sample) => { if (c.boardOn && sample.mag) take(sample.mag); },
  onClose: (why) => {
    c.boardOn = false;
    if (state.view.capture) { c.message = why; render(state); }
  },
});

// --- controls --------------------------------------------------------------------------------

if (SOURCE === "phone") $("#compass-start-btn").addEventListener("click", start);
$("#compass-solve").addEventListener("click", solve);
$("#compass-more").addEventListener("click", () => {
  history.replaceState(null, "", WIZARD_URL); // turning again: the wizard's address until the next result
  state.view.result = false;
  state.view.capture = true;
  if (state.board) { c.autoSolved = false; startBoard(); } else start();
});
// Start over (the readings are lost).
bindStartOver(state, render, () => { letScreenSleep(); location.assign(WIZARD_URL); });
$("#compass-where")?.addEventListener("click", () => { // not on a check's page: it takes the calibration's field
  const where = (text) => { c.whereText = text; render(state); };
  if (!navigator.geolocation) { where("This browser gives no location: the strength will be estimated."); return; }
  where("Asking for the location… (you can start meanwhile)");
  navigator.geolocation.getCurrentPosition((pos) => {
    c.place = { latitude_deg: pos.coords.latitude, longitude_deg: pos.coords.longitude };
    where(`Location ${pos.coords.latitude.toFixed(2)}°, ${pos.coords.longitude.toFixed(2)}°: `
      + "the reference field comes from the IGRF model.");
  }, (err) => {
    where(`No location (${err.message || "refused"}): the field's strength will be estimated.`);
  }, { maximumAge: 600000, timeout: 20000 });
});

$("#compass-coverage").dataset.solveAt = String(COVERAGE_TO_SOLVE);
if (SOURCE === "phone" && !("Magnetometer" in window)) { // a board's page reads the board's lines
  noMagnetometer(window.isSecureContext
    ? "This browser has no Magnetometer (the Generic Sensor API's): Chrome on Android has it behind a flag "
      + "(chrome://flags, “Generic Sensor Extra Classes”); Safari and Firefox do not have it."
    : "The magnetometer needs HTTPS: on the computer that runs trical, scan the QR code of its start page "
      + "(Open on your phone): it opens this page over HTTPS.");
}
