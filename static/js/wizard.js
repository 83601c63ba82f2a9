// The wizard page: the only module here that touches the DOM.
import { createSession, fetchExport, getCalibration, getSession, postCapture, solveSession } from "./api.js";
import { CaptureMachine, POSES, SignDetector, STANDARD_GRAVITY, isApplePlatform, sampleFromMotionEvent, toW3C }
  from "./motion.js";
import { CUBE_POSITIONS, MotionLog, cubeSvg, expectPosition, turnInto, upOf } from "./cube.js";
import { describePose, poseSvg } from "./poses.js";
import { formatNumber } from "./readings.js";
import { TABLES } from "./tables.js";
import { normChartSvg, normRows, withInterval } from "./result.js";

const $ = (sel) => document.querySelector(sel);
const root = $("#wizard");
const protocol = root.dataset.protocol;
const formats = JSON.parse(root.dataset.formats);
const storeKey = `trical.wizard.${protocol}`;
const NO_MOTION_MS = 2000;
const cube = protocol === "cube24";
const NO_GYRO_SAMPLES = 10; // motion events without rotationRate before the cube flow gives up

let captureS = Number(root.dataset.captureS);
let session = null; // the server's session object
let token = null;
let apiKey = null;
let machine = null;
let sign = null;
let listening = false;
let gotMotion = false;
let creating = false;
let noMotionTimer = null;
let lastT = null;
let lastLive = 0;
let lastAnnounced = "";
let blobUrls = [];
// The cube flow.
let log = null; // MotionLog: every sample since the page started reading the sensors
let gyroSeen = false;
let noGyro = 0;
let redoing = false; // the next capture replaces the last position
let awaitingTurn = false; // a position was accepted: the cube must turn before the next capture
let resumed = false; // the session was resumed after a reload: the motion log starts at Continue

const status = $("#status");
function say(text) { status.textContent = text; }

function el(tag, text, attrs = {}) {
  const e = document.createElement(tag);
  if (text !== undefined && text !== null) e.textContent = text;
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  return e;
}

const list = (poses) => (poses.length ? poses.join(", ") : "none");

// --- problems with recovery text -------------------------------------------------------------

function showProblem(parts, announce) {
  const box = $("#problem");
  box.replaceChildren(...parts.map((p) => (typeof p === "string" ? document.createTextNode(p) : p)));
  box.hidden = false;
  say(announce);
  box.focus();
}

const uploadLink = (text = "upload a log instead") => el("a", text, { href: "/" });

function notSecure() {
  return !window.isSecureContext && !["localhost", "127.0.0.1", "[::1]"].includes(location.hostname);
}

function showInsecure() {
  $("#start-btn").hidden = true;
  const code = el("code", "trical serve --https");
  showProblem(["Motion sensors need HTTPS: run ", code, " and open the https address it prints. Or ",
    uploadLink(), " (a log recorded with a sensor app)."], "Motion sensors need HTTPS.");
}

function showDenied(state) {
  $("#start-btn").disabled = false;
  const p1 = el("p", `Motion access was not allowed (${state}), so the page cannot read the sensors.`);
  const p2 = el("p", "To allow it: reload this page (or close the tab and open it again), tap Start and "
    + "choose Allow. On iOS 12, turn on Settings › Safari › Motion & Orientation Access. If Safari no "
    + "longer asks, clear this site's data in Settings › Safari › Advanced › Website Data and reload.");
  const p3 = el("p", "Or ");
  p3.append(uploadLink(), ".");
  showProblem([p1, p2, p3], "Motion access was not allowed: see how to allow it.");
}

function showNoMotion() {
  $("#capture").hidden = true;
  $("#start").hidden = false;
  $("#start-btn").disabled = false;
  showProblem(["This browser sends no motion data (a desktop or a laptop has no motion sensors): ",
    uploadLink("upload a log instead"), ", recorded with a sensor app on the phone."],
  "This browser sends no motion data: upload a log instead.");
}

function showNoGyro() {
  stop();
  $("#capture").hidden = true;
  $("#start").hidden = false;
  $("#start-btn").disabled = false;
  const p1 = el("p", "This browser gives no gyroscope readings (its motion events have no rotationRate), and "
    + "the cube flow needs them: the page checks every turn with the gyroscope.");
  const p2 = el("p", "Try another browser on this phone (Chrome or Safari), or ");
  p2.append(el("a", "calibrate the accelerometer with six positions", { href: "/wizard?protocol=six" }),
    ", or record the cube sequence with a sensor app and upload it through the API (",
    el("a", "API documentation", { href: "/docs" }), ").");
  showProblem([p1, p2], "No gyroscope: the cube flow cannot run in this browser.");
}

// --- the pose list ---------------------------------------------------------------------------

function donePoses() {
  if (!session || cube) return [];
  return POSES.filter((p) => !session.remaining.includes(p));
}

function renderPoses(current = null) {
  if (cube) { renderCube(); return; }
  const done = new Set(donePoses());
  for (const li of document.querySelectorAll("#poses li")) {
    const pose = li.dataset.pose;
    let state = done.has(pose) ? "done" : "todo";
    if (machine && machine.redo.has(pose)) state = "redo";
    li.dataset.state = state;
    li.classList.toggle("current", pose === current);
    li.querySelector(".pose-state").textContent = { done: "captured ✓", todo: "to do", redo: "to redo" }[state];
    li.querySelector(".redo").hidden = state !== "done";
  }
}

// --- session ---------------------------------------------------------------------------------

function remember() { localStorage.setItem(storeKey, JSON.stringify({ id: session.id, token })); }

function adopt(s) {
  session = s;
  if (s.capture_s) captureS = s.capture_s;
  if (machine && !cube) machine.setDone(donePoses());
  renderPoses();
}

async function ensureSession() {
  if (session || creating) return;
  creating = true;
  try {
    const s = await createSession({ protocol, capture_s: captureS, device_id: null, label: null }, apiKey);
    token = s.token;
    adopt(s);
    remember();
    $("#key-box").hidden = true;
    $("#start-over").hidden = false;
    instruct(cube ? "Stand the cube in position 1 against the jig and let go."
      : `Put the phone down on one of its sides: ${list(session.remaining)}.`);
  } catch (err) {
    if (err.code === "unauthorized") {
      $("#key-box").hidden = false;
      $("#api-key").focus();
      instruct("This server needs an API key before it starts a session.");
      say(`An API key is needed: ${err.message}`);
    } else {
      instruct(`The session could not start: ${err.message}`);
      say(`The session could not start: ${err.message}`);
    }
  } finally {
    creating = false;
  }
}

async function resume() {
  let saved;
  try { saved = JSON.parse(localStorage.getItem(storeKey) || "null"); } catch { saved = null; }
  if (!saved || !saved.id || !saved.token) return;
  try {
    token = saved.token;
    adopt(await getSession(saved.id, saved.token));
  } catch (err) {
    token = null;
    if (err.code === "unauthorized" || err.code === "not_found") localStorage.removeItem(storeKey);
    say(`The saved calibration could not be resumed (${err.message}); starting a new one.`);
    return;
  }
  $("#start-over").hidden = false;
  const done = donePoses();
  if (session.calibration_id) {
    try {
      await showResult(await getCalibration(session.calibration_id, token));
      return;
    } catch (err) {
      say(`The saved result could not be read (${err.message}).`);
    }
  }
  $("#start-btn").textContent = "Continue";
  if (cube) { resumeCube(); return; }
  $("#capture").hidden = false;
  const text = `You have a calibration in progress: ${done.length} of 6 positions captured (${list(done)}); `
    + `remaining: ${list(session.remaining)}. Tap Continue to go on, or Start over.`;
  $("#resume").textContent = text;
  $("#resume").hidden = false;
  instruct("Tap Continue to read the motion sensors again.");
  say(text);
}

// --- motion ----------------------------------------------------------------------------------

// Must run straight from the tap: iOS grants motion access only to a user gesture.
function requestPermissions() {
  const DME = window.DeviceMotionEvent;
  if (!DME || typeof DME.requestPermission !== "function") return Promise.resolve("granted");
  const motion = DME.requestPermission();
  const DOE = window.DeviceOrientationEvent;
  const orientation = DOE && typeof DOE.requestPermission === "function"
    ? DOE.requestPermission().catch(() => "denied") : Promise.resolve("granted");
  return Promise.all([motion, orientation]).then(([m]) => m, (err) => `an error: ${err.message}`);
}

function onOrientation(event) { if (sign) sign.orientation(event.beta, event.gamma); }

function onMotion(event) {
  const raw = sampleFromMotionEvent(event);
  if (!raw) return;
  if (!gotMotion) {
    gotMotion = true;
    clearTimeout(noMotionTimer);
    $("#problem").hidden = true;
    if (!cube) ensureSession();
  }
  if (cube && !gyroSeen) { // the cube flow needs rotationRate: wait for it before starting a session
    if (raw.gyr) {
      gyroSeen = true;
      ensureSession();
    } else {
      noGyro += 1;
      if (noGyro >= NO_GYRO_SAMPLES) showNoGyro();
      return;
    }
  }
  const convention = sign.motion(raw.t, raw.acc);
  if (!convention) {
    instruct("Reading the sensors…");
    return;
  }
  // The cube's captures are joined into one recording by time, across reloads too: epoch ms
  // (event.timeStamp restarts with each page load).
  const t = cube ? performance.timeOrigin + raw.t : raw.t;
  if (lastT !== null && t <= lastT) return; // t_ms must increase
  lastT = t;
  const sample = { t, acc: toW3C(raw.acc, convention.convention), gyr: raw.gyr };
  if (cube) log.push(sample);
  if (!session) { renderLive(sample.acc, null, false); return; }
  const out = machine.push(sample);
  renderLive(sample.acc, out, out.event !== null);
  if (cube) showCube(out);
  else show(out);
  if (out.capture) (cube ? sendCubeCapture : sendCapture)(out.capture);
}

function listen() {
  if (listening) return;
  listening = true;
  sign = new SignDetector({ apple: isApplePlatform(navigator.userAgent, navigator.platform, navigator.maxTouchPoints) });
  if (cube) {
    // A cube may stand on an inclined plane: its up face is the nearest axis within the page's angle
    // (inside the server's).
    machine = new CaptureMachine(captureS * 1000, { maxAngleDeg: TABLES.cube.maxAngleDeg });
    log = new MotionLog();
    expectPosition(machine, nextPosition());
    // Resumed: the cube stands in the last captured position and must turn before the next capture.
    if (capturedCount() > 0 && !redoing) { machine.requireMove(true); awaitingTurn = true; }
  } else {
    machine = new CaptureMachine(captureS * 1000);
    machine.setDone(donePoses());
  }
  window.addEventListener("deviceorientation", onOrientation);
  window.addEventListener("devicemotion", onMotion);
}

async function onStart() {
  const asked = requestPermissions(); // first, while the tap's user activation lasts
  $("#start-btn").disabled = true;
  $("#problem").hidden = true;
  if (!window.DeviceMotionEvent) { showNoMotion(); return; }
  const state = await asked;
  if (state !== "granted") { showDenied(state); return; }
  listen();
  $("#start").hidden = true;
  $("#capture").hidden = false;
  $("#resume-pic").hidden = true;
  renderPoses();
  say("Reading the motion sensors…");
  instruct("Waiting for motion data…");
  if (!gotMotion) noMotionTimer = setTimeout(() => { if (!gotMotion) showNoMotion(); }, NO_MOTION_MS);
  $("#capture-h").focus();
}

// --- live view -------------------------------------------------------------------------------

function instruct(text) { $("#instruction").textContent = text; }

function renderLive(acc, out, force) {
  const now = performance.now();
  if (!force && now - lastLive < 100) return;
  lastLive = now;
  "xyz".split("").forEach((axis, i) => {
    const v = acc[i];
    $(`#num-${axis}`).textContent = `${v >= 0 ? "+" : "−"}${Math.abs(v).toFixed(2)}`;
    const frac = Math.max(-1, Math.min(1, v / STANDARD_GRAVITY)) / 2;
    const bar = $(`#bar-${axis}`);
    bar.style.left = `${50 + Math.min(0, frac) * 100}%`;
    bar.style.width = `${Math.abs(frac) * 100}%`;
  });
  if (!out) return;
  const dot = $("#still-dot");
  dot.className = `dot ${out.state === "capturing" ? "capturing" : out.still ? "still" : "moving"}`;
  let text = out.still ? `Still ${(out.stillMs / 1000).toFixed(1)} s` : "Moving";
  if (out.state === "capturing") text = `Capturing ${Math.round(out.progress * 100)} %`;
  $("#still-text").textContent = text;
  $("#progress").value = out.state === "capturing" ? out.progress : 0;
  const pic = $("#live-pose");
  const shown = out.still && out.angleDeg <= machine.o.maxAngleDeg ? out.pose : "";
  if (pic.dataset.pose !== shown) {
    pic.dataset.pose = shown;
    pic.innerHTML = shown ? poseSvg(shown, 72) : "";
  }
}

function show(out) {
  const { pose, state } = out;
  const remaining = machine.remaining();
  const name = pose ? `${pose} (${describePose(pose)})` : "";
  let text;
  switch (state) {
    case "waiting": text = "Reading the sensors…"; break;
    case "moving": text = `Put the phone down on one of its sides still to do: ${list(remaining)}.`; break;
    case "tilted": text = `The phone is tilted ${Math.round(out.angleDeg)}° away from ${pose}: rest it flat on one side.`; break;
    case "settling": text = `${name} recognised: keep still…`; break;
    case "capturing": text = `Capturing ${name}: keep still.`; break;
    case "sending": text = `Checking the capture of ${pose}…`; break;
    case "done": text = remaining.length ? `${pose} captured. Now turn the phone to: ${list(remaining)}.`
      : "All six positions captured."; break;
    case "refused": text = `${pose} is already captured. Remaining: ${list(remaining)}. `
      + `To capture ${pose} again, press its Redo button.`; break;
    case "retry": text = null; break; // the server's refusal stays on screen until the phone moves
    default: text = null;
  }
  if (text !== null) instruct(text);
  renderPoses(state === "moving" ? null : pose);
  if (out.event === "restarted") say("Moved during the capture: it restarts once the phone is still again.");
  const key = `${state} ${pose}`;
  if (key !== lastAnnounced && ["settling", "capturing", "refused", "tilted"].includes(state)) say(text);
  lastAnnounced = key;
}

// --- the cube flow ---------------------------------------------------------------------------

const capturedCount = () => (session ? session.captures.length : 0);
// The position the next capture is for: the last one again while redoing it.
const nextPosition = () => (redoing ? capturedCount() : Math.min(capturedCount() + 1, CUBE_POSITIONS));

function figure(box, k, turn, caption) {
  box.querySelector(".cube-pic").innerHTML = cubeSvg(k, { turn });
  box.querySelector("figcaption").textContent = caption;
}

function renderCube() {
  const n = capturedCount();
  const k = nextPosition();
  $("#capture-h").textContent = redoing ? `Redo position ${k} of ${CUBE_POSITIONS}` : `Position ${k} of ${CUBE_POSITIONS}`;
  if (k >= 2) {
    const { label, words } = turnInto(k);
    figure($("#cube-turn"), k - 1, label, `From position ${k - 1}: ${words}.`);
  } else {
    figure($("#cube-turn"), 1, null, "Start: screen (sensor z) up, the phone's x axis along the jig.");
  }
  figure($("#cube-target"), k, null, `Position ${k}: sensor ${upOf(k)} up.`);
  $("#cube-count").textContent = `${n} of ${CUBE_POSITIONS} positions captured`;
  $("#cube-count").dataset.captured = String(n);
  $("#cube-progress").value = n;
  const redo = $("#redo-last");
  redo.hidden = n === 0 || redoing;
  redo.textContent = `Redo position ${n}`;
  const hint = $("#redo-hint");
  hint.hidden = !(resumed && n >= 2 && !log?.ends.has(n - 1) && !redoing);
  hint.textContent = `After a reload, the page no longer has the turn into position ${n}: to redo it, put the `
    + `cube back in position ${n - 1} first, then press Redo and turn it into position ${n} again.`;
}

function showCube(out) {
  const k = nextPosition();
  const { state, pose } = out;
  const up = upOf(k);
  const turn = k >= 2 ? turnInto(k).words : null;
  let text;
  switch (state) {
    case "waiting": text = "Reading the sensors…"; break;
    case "moving": text = k >= 2 ? `Turning into position ${k}: ${turn}, then let go.` : "Stand the cube in position 1 and let go."; break;
    case "tilted": text = `The cube is tilted ${Math.round(out.angleDeg)}° away from ${pose} up: stand it on a face.`; break;
    case "refused": text = `Position ${k} needs sensor ${up} up; the cube has ${pose} up.`
      + (turn ? ` From position ${k - 1}: ${turn}.` : ""); break;
    case "settling": text = `Position ${k} recognised: keep still…`; break;
    case "capturing": text = `Capturing position ${k}: keep still.`; break;
    case "sending": text = `Checking position ${k} and the turn into it…`; break;
    case "retry": text = awaitingTurn && turn ? `Position ${k - 1} captured. Now ${turn}.` : null; break;
    default: text = null;
  }
  if (text !== null) instruct(text);
  if (out.event === "restarted") say("Moved during the capture: it restarts once the cube is still again.");
  const key = `${state} ${pose} ${k}`;
  if (key !== lastAnnounced && ["settling", "capturing", "refused", "tilted"].includes(state)) say(text);
  lastAnnounced = key;
}

function clearTurnAlert() {
  $("#turn-alert").hidden = true;
  $("#turn-alert").replaceChildren();
}

// The server refused the turn: its words, and the picture of the position to go back to with the
// turn to make from there. Recording goes on; the next move again runs from the last accepted end.
function showWrongTurn(message, k) {
  const { label } = turnInto(k);
  const box = $("#turn-alert");
  const pic = el("div", null, { class: "cube-pic" });
  pic.innerHTML = cubeSvg(k - 1, { turn: label });
  box.replaceChildren(el("p", message), el("p", `Put the cube back in position ${k - 1} as pictured, then make this turn:`), pic);
  box.hidden = false;
  say(""); // the alert announces itself (role=alert); nothing stale in the status line
  instruct(`Wrong turn into position ${k}: back to position ${k - 1}, then ${turnInto(k).words}.`);
}

async function sendCubeCapture(capture) {
  const k = nextPosition();
  const payload = {
    acc: capture.acc, t_ms: capture.t_ms, gyr: capture.gyr, unit: "m/s^2", gyr_unit: "deg/s",
    sign: sign.result, position: String(k), redo: redoing,
  };
  if (k >= 2) payload.motion = log.motion(capture.t_ms[0]);
  try {
    const answer = await postCapture(session.id, token, payload);
    log.accept(k, capture.t_ms[capture.t_ms.length - 1]);
    redoing = false;
    machine.resolve(true, capture.position);
    adopt(answer.session);
    clearTurnAlert();
    const n = capturedCount();
    if (n < CUBE_POSITIONS) {
      expectPosition(machine, n + 1);
      machine.requireMove(true); // the next position may have the same face up: wait for the turn
      awaitingTurn = true;
      renderCube();
      const text = `Position ${k} captured. Now ${turnInto(n + 1).words}.`;
      instruct(text);
      say(text);
    } else {
      instruct("All 24 positions captured: computing the calibration…");
      say("All 24 positions captured: computing the calibration…");
      await solve();
    }
  } catch (err) {
    machine.resolve(false, capture.position);
    awaitingTurn = false;
    if (err.code === "already_captured") {
      try { adopt(await getSession(session.id, token)); } catch { /* keep the old view */ }
    }
    if (err.code === "wrong_turn") {
      showWrongTurn(err.message, k);
    } else {
      const text = `The capture of position ${k} was refused: ${err.message}. Move the cube and put it down again.`;
      instruct(text);
      say(text);
    }
  }
}

function resumeCube() {
  resumed = true;
  const n = capturedCount();
  if (n >= CUBE_POSITIONS) { // complete but not solved (the solve failed): try again on Continue
    $("#resume").textContent = "All 24 positions are captured. Tap Continue to compute the calibration.";
    $("#resume").hidden = false;
    $("#start-btn").addEventListener("click", solve, { once: true });
    return;
  }
  const text = n === 0 ? "You have a cube calibration in progress with no position captured yet. "
    + "Stand the cube in position 1 and tap Continue."
    : `You have a cube calibration in progress: ${n} of ${CUBE_POSITIONS} positions captured. Put the cube back `
      + `in position ${n} (pictured), against the jig, then tap Continue: the recording of the next turn starts there.`;
  $("#resume").textContent = text;
  $("#resume").hidden = false;
  if (n) {
    $("#resume-pic").innerHTML = cubeSvg(n);
    $("#resume-pic").hidden = false;
  }
  renderCube();
  say(text);
}

function startRedoLast() {
  const n = capturedCount();
  if (!n) return;
  const last = log.samples.length ? log.samples[log.samples.length - 1].t : -Infinity;
  const known = log.redo(n, last);
  redoing = true;
  awaitingTurn = false;
  expectPosition(machine, n);
  machine.requireMove(!known && n >= 2); // from position n − 1 the cube must turn again
  clearTurnAlert();
  renderCube();
  const text = known || n === 1
    ? `Redo position ${n}: leave the cube in position ${n} (or put it back there); the new capture replaces the old one.`
    : `Redo position ${n}: the cube should now stand in position ${n - 1}; ${turnInto(n).words} into position ${n}.`;
  instruct(text);
  say(text);
}

// --- captures, solving -----------------------------------------------------------------------

async function sendCapture(capture) {
  const payload = {
    acc: capture.acc, t_ms: capture.t_ms, gyr: capture.gyr, unit: "m/s^2", gyr_unit: "deg/s",
    sign: sign.result, position: capture.position, redo: capture.redo,
  };
  try {
    const answer = await postCapture(session.id, token, payload);
    machine.resolve(true, capture.position);
    adopt(answer.session);
    const remaining = session.remaining;
    const text = remaining.length ? `${capture.position} captured. Remaining: ${list(remaining)}.`
      : "All six positions captured: computing the calibration…";
    instruct(text);
    say(text);
    if (!remaining.length) await solve();
  } catch (err) {
    machine.resolve(false, capture.position);
    if (err.code === "already_captured") {
      try { adopt(await getSession(session.id, token)); } catch { /* keep the old view */ }
    }
    const text = `The capture of ${capture.position} was refused: ${err.message}. Move the phone and put it down again.`;
    instruct(text);
    say(text);
  }
}

async function solve() {
  try {
    await showResult(await solveSession(session.id, token));
  } catch (err) {
    const text = `The calibration could not be computed: ${err.message}. Redo a position or start over.`;
    instruct(text);
    say(text);
  }
}

function fillMatrix(table, rows, halfWidths) {
  table.replaceChildren(...rows.map((row, i) => {
    const tr = el("tr");
    row.forEach((v, j) => tr.append(el("td", withInterval(v, halfWidths?.[i]?.[j], (x) => formatNumber(x)))));
    return tr;
  }));
}

async function showResult(cal) {
  stop();
  $("#start").hidden = true;
  $("#capture").hidden = true;
  $("#start-over").hidden = false;
  const result = $("#result");
  result.hidden = false;
  const ok = $("#result-ok");
  ok.className = cal.ok ? "ok" : "bad";
  ok.textContent = cal.ok ? `Calibration ${cal.id} passed its checks.` : `Calibration ${cal.id} failed its checks:`;
  $("#result-reasons").replaceChildren(...(cal.reasons || []).map((r) => el("li", r)));
  const warnings = cal.warnings || [];
  $("#result-warnings").replaceChildren(...(warnings.length ? warnings : ["none"]).map((w) => el("li", w)));
  if (cal.model.type === "cube") fillCubeModel(cal, cal.uncertainty || {});
  else fillSixModel(cal);
  $("#result-metrics").replaceChildren(...Object.entries(cal.metrics || {})
    .filter(([, v]) => v === null || typeof v !== "object") // the cube's lists stay in the JSON export
    .map(([k, v]) => {
      const tr = el("tr");
      tr.append(el("th", k, { scope: "row" }), el("td", formatNumber(v)));
      return tr;
    }));
  result.focus();
  say(cal.ok ? "Calibration done: it passed its checks. Downloads below." : "Calibration done, but it failed its checks.");
  await renderDownloads(cal.id);
}

// The affine model m = X a + y, and |m| before and after per pose.
function fillSixModel(cal) {
  const unc = cal.uncertainty || {};
  fillMatrix($("#result-X"), cal.model.X, unc.X);
  fillMatrix($("#result-y"), cal.model.y.map((v) => [v]), unc.y && unc.y.map((v) => [v]));
  const means = (cal.readings && cal.readings.length ? cal.readings.map((r) => ({ position: r.up, mean: r.mean }))
    : (session?.captures || [])).filter((c) => c.position);
  fillNorms(cal.model, means, cal.gravity || STANDARD_GRAVITY);
}

// |m| before and |a| after per position against g; `model` is {X, y} of m = X a + y.
function fillNorms(model, means, gravity) {
  const rows = normRows(model, means);
  $("#norm-chart").innerHTML = rows.length ? normChartSvg(rows, gravity) : "";
  $("#norm-table tbody").replaceChildren(...rows.map((r) => {
    const tr = el("tr");
    tr.append(el("th", r.position, { scope: "row" }), el("td", r.raw.toFixed(4)), el("td", r.calibrated.toFixed(4)));
    return tr;
  }));
}

// 003's model per sensor: S (with D and the misalignment when given) and b, each ± its 95 % half-width.
function fillCubeModel(cal, unc) {
  const units = { acc: cal.unit || "m/s²", gyr: (cal.units && cal.units.gyr) || "rad/s" };
  const parts = [];
  for (const [key, name] of [["acc", "Accelerometer"], ["gyr", "Gyroscope"]]) {
    const model = cal.model[key];
    if (!model) continue;
    const half = unc[key] || {};
    parts.push(el("h4", name));
    const row = el("div", null, { class: "row" });
    const items = [["S", "S (scale and cross-axis)", model.S, half.S]];
    if (key === "acc" && model.D) items.push(["D", "D (scale factors)", model.D.map((v) => [v]), half.D && half.D.map((v) => [v])]);
    if (key === "acc" && model.misalignment) items.push(["misalignment", "Misalignment", model.misalignment, half.misalignment]);
    items.push(["b", `b (${units[key]})`, model.b.map((v) => [v]), half.b && half.b.map((v) => [v])]);
    for (const [id, title, rows, halfRows] of items) {
      const table = el("table", null, { class: "matrix", id: `cube-${key}-${id}` });
      fillMatrix(table, rows, halfRows);
      const box = el("div");
      box.append(el("h5", title), table);
      row.append(box);
    }
    parts.push(row);
  }
  $("#cube-model").replaceChildren(...parts);
  // The accelerometer's raw = S f + b has the form of m = X a + y (003 eq. (1)).
  const acc = cal.model.acc;
  if (acc) fillNorms({ X: acc.S, y: acc.b }, cal.captures || [], cal.gravity || STANDARD_GRAVITY);
}

async function renderDownloads(id) {
  blobUrls.forEach((u) => URL.revokeObjectURL(u));
  blobUrls = [];
  const items = await Promise.all(formats.map(async ([key, name]) => {
    const li = el("li");
    try {
      const { blob, filename } = await fetchExport(id, key, token);
      const url = URL.createObjectURL(blob);
      blobUrls.push(url);
      li.append(el("a", name, { href: url, download: filename, "data-format": key }));
    } catch (err) {
      li.append(el("span", `${name}: ${err.message}`));
    }
    return li;
  }));
  $("#downloads").replaceChildren(...items);
  $("#downloads").dataset.ready = "true";
}

function stop() {
  window.removeEventListener("devicemotion", onMotion);
  window.removeEventListener("deviceorientation", onOrientation);
  clearTimeout(noMotionTimer);
  listening = false;
}

// --- controls --------------------------------------------------------------------------------

$("#start-btn").addEventListener("click", onStart);
$("#key-box").addEventListener("submit", (event) => {
  event.preventDefault();
  apiKey = $("#api-key").value.trim() || null;
  $("#key-box").hidden = true;
  say("Trying again with the API key…");
  ensureSession();
});
$("#start-over").addEventListener("click", () => {
  localStorage.removeItem(storeKey);
  blobUrls.forEach((u) => URL.revokeObjectURL(u));
  location.reload();
});
if (cube) {
  $("#redo-last").addEventListener("click", () => {
    // Not reading the sensors yet (a resumed session): this tap asks for them, as Continue would.
    if (!listening) onStart().then(() => { if (machine) startRedoLast(); });
    else startRedoLast();
  });
} else $("#poses").addEventListener("click", (event) => {
  const button = event.target.closest("button[data-redo]");
  if (!button) return;
  const pose = button.dataset.redo;
  // Not reading the sensors yet (a resumed session): this tap asks for them, as Continue would.
  if (!listening) onStart().then(() => { if (machine) markRedo(pose); });
  else markRedo(pose);
});

function markRedo(pose) {
  machine.requestRedo(pose);
  renderPoses();
  const text = `Redo ${pose}: put the phone ${describePose(pose)}; the new capture replaces the old one.`;
  instruct(text);
  say(text);
}

for (const span of document.querySelectorAll("[data-pic]")) span.innerHTML = poseSvg(span.dataset.pic);
if (notSecure()) showInsecure();
else resume();
