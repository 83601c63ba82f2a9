// The compass wizard (/wizard?protocol=compass): reads the browser's Magnetometer (the Generic
// Sensor API), fills the sphere of directions as the phone turns, and posts the readings to
// POST /api/v1/calibrations (method magnetometer) once the faces are covered. Where the browser has
// no magnetometer, it says so and points to a recording app and the upload on the start page.
import { createCalibration } from "./api.js";
import { cue, unlockCues } from "./cues.js";
import { keepScreenOn, letScreenSleep } from "./wake_lock.js";
import { CompassCoverage, COVERAGE_TO_SOLVE, MIN_READINGS, missingWords } from "./compass_flow.js";
import { magResultSvgs, magSphereSvg } from "./mag_sphere.js";
import { formatNumber } from "./readings.js";
import { showCorrection } from "./correction_view.js";
import { fillFigures, pageWords } from "./figures.js";
import { offerSend } from "./send.js";
import { withInterval } from "./result.js";
import { TABLES } from "./tables.js";
import { BoardPanel } from "./board_panel.js";
import { fetchDownloads, resetUse, showUse, showVerdict } from "./use_calibration.js";
import { $, el } from "./dom.js";

const WIZARD_URL = location.pathname + location.search; // before a result moves to /c/{id}
const NO_READING_MS = 3000;
const DRAW_MS = 150; // the sphere is redrawn at most this often
const DRAWN_POINTS = 600; // the latest readings drawn

const state = { shown: null, sensor: null, coverage: new CompassCoverage(), place: null, solving: false, autoSolved: false,
  drawnAt: 0, timer: null, drawTimer: null, reading: false };

// The cues of the other flows, for a turn that has no poses: "start" when the first reading after
// a Start (or "Keep turning") tap arrives, so the person hears that the magnetometer really reads
// and the turn can begin; "finished" when the coverage is complete (stop turning: the page
// calibrates by itself); "refused" when the turn cannot go on as it is: the server refused the
// readings sent (keep turning, then Calibrate now) or the magnetometer stopped in the middle of it.
// A done cue per pose has no equivalent: the faces fill continuously and the sphere shows them.

function say(text) { $("#status").textContent = text; }
const pct = (v) => `${Math.round(100 * v)} %`;

// --- no magnetometer -------------------------------------------------------------------------

function noMagnetometer(why) {
  stopSensor();
  letScreenSleep();
  $("#compass-start").hidden = true;
  $("#compass-capture").hidden = true;
  $("#compass-none-why").textContent = why;
  $("#compass-none").hidden = false;
  $("#compass-none").focus();
  say("This browser gives no magnetometer readings: record with a sensor app and upload the log.");
}

const WHY = {
  SecurityError: "the browser refused the sensor on this page (it needs HTTPS and the magnetometer permission)",
  NotAllowedError: "access to the magnetometer was not allowed",
  NotReadableError: "the browser has the interface but could not read a magnetometer on this device",
};

function refused(err) {
  if (state.coverage.count > 0) { // it stopped mid-turn: the readings so far are kept
    stopSensor();
    cue("refused");
    const text = `The magnetometer stopped (${err && (err.message || err.name)}): tap Calibrate now to use the `
      + `${state.coverage.count} readings so far, or Start over.`;
    $("#compass-missing").textContent = text;
    say(text);
    return;
  }
  const why = WHY[err && err.name] || `the sensor failed (${err && (err.message || err.name)})`;
  noMagnetometer(`The Generic Sensor API's Magnetometer is present, but ${why}.`);
}

function stopSensor() {
  clearTimeout(state.timer);
  if (state.sensor) {
    try { state.sensor.stop(); } catch { /* already stopped */ }
    state.sensor.removeEventListener("reading", onReading);
  }
  state.sensor = null;
}

// --- the turn --------------------------------------------------------------------------------

function onReading() {
  const s = state.sensor;
  if (s) take([s.x, s.y, s.z]);
}

// One reading of the magnetometer, the phone's (the Generic Sensor API's) or a board's (its lines).
function take(m) {
  clearTimeout(state.timer);
  if (!state.coverage.push(m)) return;
  if (!state.reading) { state.reading = true; cue("start"); }
  const now = performance.now();
  if (now - state.drawnAt >= DRAW_MS) show();
  else if (!state.drawTimer) state.drawTimer = setTimeout(show, DRAW_MS);
}

function show() {
  clearTimeout(state.drawTimer);
  state.drawTimer = null;
  state.drawnAt = performance.now();
  const st = state.coverage.status();
  const box = $("#compass-coverage");
  box.dataset.count = String(st.count);
  box.dataset.coverage = st.coverage.toFixed(2);
  const covered = st.covered.filter(Boolean).length;
  box.textContent = st.centre
    ? `Coverage ${pct(st.coverage)} (${covered} of ${st.covered.length} directions), ${st.count} readings.`
    : `${st.count} readings: keep turning, the sphere fills once the ${state.board ? "board" : "phone"} has turned a little.`;
  $("#compass-progress").value = st.coverage;
  const words = missingWords(st.missing);
  $("#compass-missing").textContent = !st.centre ? ""
    : words.length ? `Still missing: ${words.join("; ")}.` : "All directions covered.";
  $("#compass-sphere").innerHTML = magSphereSvg({ covered: st.covered, points: st.directions.slice(-DRAWN_POINTS),
    current: st.current, label: "Field directions reached" });
  $("#compass-solve").disabled = st.count < MIN_READINGS || state.solving;
  if (!state.autoSolved && state.coverage.ready(st)) {
    state.autoSolved = true;
    cue("finished");
    say(`Coverage ${pct(st.coverage)}: calibrating.`);
    solve();
  }
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
  state.sensor = sensor;
  state.reading = false; // the start cue waits for this turn's first reading
  sensor.addEventListener("reading", onReading);
  sensor.addEventListener("error", (event) => refused(event.error));
  sensor.start();
  state.timer = setTimeout(() => {
    if (state.coverage.count === 0) noMagnetometer("The Generic Sensor API's Magnetometer is present, but it sent no reading.");
  }, NO_READING_MS);
  $("#compass-start").hidden = true;
  $("#compass-capture").hidden = false;
  if ($("#start-over-ask").hidden) $("#start-over").hidden = false; // not while it asks
  $("#compass-capture-h").focus();
  say("Reading the magnetometer: turn the phone slowly through all directions.");
}

// The place only when the person allowed it (never waited for), with today's date for the field
// model; without a place the server uses no date (it would only warn that it went unused).
function payload() {
  const body = { method: "magnetometer", mag: state.coverage.readings, label: "compass wizard" };
  if (state.place) Object.assign(body, state.place, { date: new Date().toISOString().slice(0, 10) });
  return body;
}

async function solve() {
  if (state.solving) return;
  state.solving = true;
  $("#compass-solve").disabled = true;
  try {
    const cal = await createCalibration(payload());
    stopSensor();
    state.boardOn = false;
    showResult(cal);
  } catch (err) {
    say(`The calibration could not be computed: ${err.message}`);
    cue("refused");
    $("#compass-missing").textContent = `The server refused: ${err.message}. Keep turning, then tap Calibrate now.`;
  } finally {
    state.solving = false;
    $("#compass-solve").disabled = state.coverage.count < MIN_READINGS;
  }
}

// --- the result ------------------------------------------------------------------------------

function fillMatrix(table, rows, half) {
  table.replaceChildren(...rows.map((row, i) => {
    const tr = el("tr");
    row.forEach((v, j) => tr.append(el("td", withInterval(v, half?.[i]?.[j], (x) => formatNumber(x, 4)))));
    return tr;
  }));
}

function showResult(cal) {
  letScreenSleep();
  const m = cal.metrics;
  state.shown = cal;
  showVerdict(cal);
  $("#compass-capture").hidden = true;
  const box = $("#result");
  box.hidden = false;
  $("#result-headline").textContent = cal.headline || "";
  const ok = $("#result-ok");
  ok.className = cal.ok ? "ok" : "bad";
  ok.textContent = cal.ok ? `Calibration ${cal.id} passed its checks.` : `Calibration ${cal.id} failed its checks:`;
  $("#result-reasons").replaceChildren(...(cal.reasons || []).map((r) => el("li", r)));
  const source = { given: "given", model: "IGRF model at your place", estimated: "estimated" }[m.field_source] || m.field_source;
  $("#result-summary").textContent = `Field ${formatNumber(m.field_ut, 1)} µT (${source}); spread of |h| `
    + `${formatNumber(m.norm_spread_raw_ut, 2)} µT before → ${formatNumber(m.norm_spread_ut, 2)} µT after; `
    + `error on new directions ${formatNumber(m.cv_error_ut, 2)} µT (raw ${formatNumber(m.raw_error_ut, 2)} µT); `
    + `coverage ${pct(m.coverage)} of ${m.count} readings.`;
  const svgs = magResultSvgs(cal);
  $("#result-mag").replaceChildren(figure(svgs.before, "Before: the raw readings m"), figure(svgs.after, "After: h = M (m − b)"),
    el("p", "The sphere has the field's radius F; green faces: directions covered. Raw readings sit off it (the hard "
      + "iron b moves them, soft iron stretches them); calibrated ones lie on it.", { class: "hint legend" }));
  const unc = cal.uncertainty || {};
  fillMatrix($("#result-M"), cal.model.M, unc.M);
  fillMatrix($("#result-b"), cal.model.b.map((v) => [v]), unc.b && unc.b.map((v) => [v]));
  $("#result-warnings").replaceChildren(...((cal.warnings || []).length ? cal.warnings : ["none"]).map((w) => el("li", pageWords(w))));
  fillFigures($("#result-metrics"), cal);
  showCorrection($("#result-correction"), cal, null, $("#result-fitted-note"));
  resetUse();
  // Its own address (/c/{id}): a reload, a bookmark or the history finds it again.
  history.pushState({ calibration: cal.id }, "", `/c/${encodeURIComponent(cal.id)}`);
  board.offer(cal);
  offerSend(cal);
  fetchDownloads(cal).then((downloads) => { if (state.shown === cal) showUse(cal, downloads); });
  box.focus();
  cue(cal.verdict.apply ? "captured" : "refused");
  say(`Calibration done. ${cal.verdict.words}`);
}

function figure(svg, caption) {
  const f = el("figure", null, { class: "mag-fig" });
  const pic = el("div");
  pic.innerHTML = svg;
  f.append(pic, el("figcaption", caption));
  return f;
}

// --- a board --------------------------------------------------------------------------------

// A board's magnetometer, from its lines (board.js): the same turn, the same sphere, in its own unit
// (µT from Raw: and Uni: lines; counts or whatever a CSV prints: the fit keeps that unit).
function startBoard() {
  state.board = true;
  state.boardOn = true;
  state.reading = false;
  unlockCues();
  stopSensor();
  $("#compass-none").hidden = true;
  $("#compass-start").hidden = true;
  $("#compass-capture").hidden = false;
  $("#compass-capture-h").textContent = "Turn the board slowly through all directions";
  if ($("#start-over-ask").hidden) $("#start-over").hidden = false;
  $("#compass-capture-h").focus();
  say("The board is connected: turn it slowly through all directions.");
}

const board = new BoardPanel({
  needAcc: false,
  onConnect: startBoard,
  onSample: (sample) => { if (state.boardOn && sample.mag) take(sample.mag); },
  onClose: (why) => { state.boardOn = false; if (!$("#compass-capture").hidden) $("#compass-missing").textContent = why; },
});

// --- controls --------------------------------------------------------------------------------

$("#compass-start-btn").addEventListener("click", start);
$("#compass-solve").addEventListener("click", solve);
$("#compass-more").addEventListener("click", () => {
  history.replaceState(null, "", WIZARD_URL); // turning again: the wizard's address until the next result
  $("#result").hidden = true;
  $("#compass-capture").hidden = false;
  if (state.board) { state.autoSolved = false; startBoard(); } else start();
});
// Start over in two taps (the readings are lost): the first asks in place, Keep it goes back.
function askStartOver(ask) {
  $("#start-over").hidden = ask;
  $("#start-over-ask").hidden = !ask;
  $(ask ? "#start-over-no" : "#start-over").focus();
}
$("#start-over").addEventListener("click", () => askStartOver(true));
$("#start-over-no").addEventListener("click", () => askStartOver(false));
$("#start-over-yes").addEventListener("click", () => { letScreenSleep(); location.assign(WIZARD_URL); });
$("#compass-where").addEventListener("click", () => {
  const text = $("#compass-where-text");
  if (!navigator.geolocation) { text.textContent = "This browser gives no location: the strength will be estimated."; return; }
  text.textContent = "Asking for the location… (you can start meanwhile)";
  navigator.geolocation.getCurrentPosition((pos) => {
    state.place = { latitude_deg: pos.coords.latitude, longitude_deg: pos.coords.longitude };
    text.textContent = `Location ${pos.coords.latitude.toFixed(2)}°, ${pos.coords.longitude.toFixed(2)}°: the reference field comes from the IGRF model.`;
  }, (err) => {
    text.textContent = `No location (${err.message || "refused"}): the field's strength will be estimated.`;
  }, { maximumAge: 600000, timeout: 20000 });
});

$("#compass-coverage").dataset.solveAt = String(COVERAGE_TO_SOLVE);
if (!("Magnetometer" in window)) {
  noMagnetometer(window.isSecureContext
    ? "This browser has no Magnetometer (the Generic Sensor API's): Chrome on Android has it behind a flag "
      + "(chrome://flags, “Generic Sensor Extra Classes”); Safari and Firefox do not have it."
    : "The magnetometer needs HTTPS: run trical serve --https and open the https address it prints.");
}
