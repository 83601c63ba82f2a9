// The wizard page: reads the server's tables, imports the flow the server names for its protocol (flow_six.js,
// flow_cube.js or flow_free.js, each with its view's render hooks), owns the one state object
// (wizard_state.js) and the one render(state) that writes the DOM. The flows change the state and call
// the server; only render and the views' hooks it calls touch the page.
import { createSession, getCalibration, getSession, solveSession } from "./api.js";
import { SignDetector, STANDARD_GRAVITY, isApplePlatform, sampleFromMotionEvent, toW3C } from "./motion.js";
import { describePose, poseSvg } from "./poses.js";
import { SOURCE } from "./source.js";
import { BoardPanel } from "./board_panel.js";
import { STALL_MS, stallWords } from "./board.js";
import { adviceText, gyroBiasText } from "./result.js";
import { kindOf } from "./result_kinds.js";
import { cue, unlockCues } from "./cues.js";
import { fetchDownloads } from "./use_calibration.js";
import { offerSend } from "./send.js";
import { rememberToken } from "./tokens.js";
import { keepScreenOn, letScreenSleep } from "./wake_lock.js";
import { announce, deviceWords, instruct, newState, showResult } from "./wizard_state.js";
import { bindStartOver, newRendered, renderShared } from "./wizard_render.js";
import { $, el, setHidden, setText } from "./dom.js";

const WIZARD_URL = location.pathname + location.search; // before a result moves to /c/{id}
const root = $("#wizard");
const NO_MOTION_MS = 2000;
const EARLY_MS = 10_000; // a board's samples kept while its session is created

const state = newState({
  protocol: root.dataset.protocol,
  captureS: Number(root.dataset.captureS),
  device: SOURCE, // a board's page (source=board) reads the board from its first screen
});
// The protocol's flow (its steps on the state and its server calls) and its view (its render hooks): the
// modules its entry in the server's protocol table names (app/guided/capture_rules.py WIZARD_PROTOCOLS).
const [{ default: flow }, { default: view }] = await Promise.all([
  import(`./${root.dataset.flow}.js`),
  import(`./${root.dataset.flow}_view.js`),
]);
flow.init(state);
let noMotionTimer = null;

// --- rendering: the state onto the page --------------------------------------------------------

// render runs on every motion sample: it writes only what changed (dom.js's setText, setHidden).

const uploadLink = (text = "upload a log instead") => el("a", text, { href: "/" });

// Each problem with its recovery text: what the box shows, what the live region says, and what
// else on the page changes.
const PROBLEMS = {
  insecure: {
    parts: () => ["Motion sensors need HTTPS: on the computer that runs trical, scan the QR code of its start page ",
      "(", el("em", "Open on your phone"), "): it opens this page over HTTPS. Or ", uploadLink(),
      " (a log recorded with a sensor app)."],
    say: () => "Motion sensors need HTTPS.",
    apply: (v) => { v.startHidden = true; },
  },
  denied: {
    parts: (detail) => {
      const p3 = el("p", "Or ");
      p3.append(uploadLink(), ".");
      return [el("p", `Motion access was not allowed (${detail}), so the page cannot read the sensors.`),
        el("p", "To allow it: reload this page (or close the tab and open it again), tap Start and "
          + "choose Allow. On iOS 12, turn on Settings › Safari › Motion & Orientation Access. If Safari no "
          + "longer asks, clear this site's data in Settings › Safari › Advanced › Website Data and reload."),
      p3];
    },
    say: () => "Motion access was not allowed: see how to allow it.",
    apply: (v) => { v.startDisabled = false; },
  },
  noMotion: {
    parts: () => ["This browser sends no motion data (a desktop or a laptop has no motion sensors): ",
      uploadLink("upload a log instead"), ", recorded with a sensor app on the phone."],
    say: () => "This browser sends no motion data: upload a log instead.",
    apply: (v) => { v.capture = false; v.start = true; v.startDisabled = false; },
  },
  noGyro: {
    parts: () => {
      const p2 = el("p", "Try another browser on this phone (Chrome or Safari), or ");
      p2.append(el("a", "calibrate the accelerometer with six positions", { href: "/wizard?protocol=six" }),
        ", or record the cube sequence with a sensor app and upload it through the API (",
        el("a", "API documentation", { href: "/docs" }), ").");
      return [el("p", "This browser gives no gyroscope readings (its motion events have no rotationRate), and "
        + "the cube flow needs them: the page checks every turn with the gyroscope."), p2];
    },
    say: () => "No gyroscope: the cube flow cannot run in this browser.",
    apply: (v) => { v.capture = false; v.start = true; v.startDisabled = false; },
  },
};

const rendered = { ...newRendered(), problem: null, lastLive: 0 };

function render(s) {
  const v = s.view;
  setHidden($("#start"), !v.start);
  const startBtn = $("#start-btn"); // a phone's page only: a board's starts when it connects
  if (startBtn) {
    setHidden(startBtn, v.startHidden);
    if (startBtn.disabled !== v.startDisabled) startBtn.disabled = v.startDisabled;
    setText(startBtn, v.startLabel);
  }
  if (v.resume !== null) setText($("#resume"), v.resume);
  setHidden($("#resume"), v.resume === null);
  view.start(s);
  setHidden($("#resume-pic"), v.resumePic === null);
  setHidden($("#device-name-box"), Boolean(s.session)); // named once, when the session starts
  renderProblem(v);
  setHidden($("#key-box"), !v.keyBox);
  setHidden($("#capture"), !v.capture);
  view.capture(s);
  setText($("#instruction"), v.instruction);
  setText($("#instruction-code"), v.instructionCode || "");
  setHidden($("#instruction-code"), !v.instructionCode);
  renderLive(s);
  renderShared(s, rendered, hooks);
}

function renderProblem(v) {
  const box = $("#problem");
  if (v.problem && v.problem !== rendered.problem) {
    const parts = PROBLEMS[v.problem.kind].parts(v.problem.detail);
    box.replaceChildren(...parts.map((p) => (typeof p === "string" ? document.createTextNode(p) : p)));
  }
  rendered.problem = v.problem;
  setHidden(box, !v.problem);
}

// The live view: the gravity bars, the stillness and the pose seen, at most every 100 ms.
function renderLive(s) {
  const live = s.view.live;
  s.view.live = null;
  if (!live) return;
  const { acc, out, force } = live;
  const now = performance.now();
  if (!force && now - rendered.lastLive < 100) return;
  rendered.lastLive = now;
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
  const seen = out.still && out.angleDeg <= s.machine.o.maxAngleDeg ? out.pose : "";
  // Before the phone is in a pose, the flow's next pose (six: the next side), large, in words.
  const next = seen ? null : view.next(s);
  const shown = seen || (next ? `next ${next}` : "");
  if (pic.dataset.pose !== shown) {
    pic.dataset.pose = shown;
    pic.innerHTML = seen ? poseSvg(seen, 176) : next ? poseSvg(next, 176) : "";
    $("#live-pose-words").textContent = seen ? `Now: ${describePose(seen)}` : next ? `Next: ${describePose(next)}` : "";
  }
}

// How a session ended, beside the flow's own parts of the result: the free flow's finish and advice, the
// gyroscope's bias over the still captures (each hidden where the body has none).
function sessionEnd(cal) {
  const finishLine = $("#result-finish");
  setHidden(finishLine, !cal.finish);
  if (cal.finish) {
    finishLine.textContent = `${cal.finish.text[0].toUpperCase()}${cal.finish.text.slice(1)}.`;
    finishLine.dataset.reason = cal.finish.reason;
  }
  const gyroLine = $("#result-gyro");
  setHidden(gyroLine, !cal.gyroscope_bias);
  gyroLine.textContent = cal.gyroscope_bias ? gyroBiasText(cal.gyroscope_bias) : "";
  setHidden($("#result-advice-box"), !(cal.advice && cal.advice.length));
  $("#result-advice").replaceChildren(...(cal.advice || []).map((a) => el("li", adviceText(a))));
}

const hooks = { ...view, result(cal, s) { sessionEnd(cal); view.result(cal, s); } };

// --- transitions shared by the flows -----------------------------------------------------------

function showProblem(kind, detail = null) {
  const v = state.view;
  letScreenSleep(); // every problem stops the capture
  PROBLEMS[kind].apply(v);
  v.problem = { kind, detail };
  announce(state, PROBLEMS[kind].say(detail));
  v.focus = "#problem";
}

function remember() {
  localStorage.setItem(state.storeKey, JSON.stringify({ id: state.session.id, token: state.token }));
}

function adopt(session) {
  state.session = session;
  if (session.capture_s) state.captureS = session.capture_s;
  flow.adopted(state);
  state.view.current = null;
}

async function ensureSession() {
  if (state.session || state.creating) return;
  state.creating = true;
  const v = state.view;
  try {
    const created = await createSession({ protocol: state.protocol, capture_s: state.captureS,
      device_id: $("#device-name").value.trim() || null, label: null, source: state.device }, state.apiKey);
    state.token = created.token;
    adopt(created);
    remember();
    for (const sample of state.early.splice(0)) if (state.machine) capture(sample);
    v.keyBox = false;
    v.startOver = true;
    instruct(state, flow.firstInstruction(state), flow.firstCode ? flow.firstCode(state) : null);
  } catch (err) {
    if (err.code === "unauthorized") {
      v.keyBox = true;
      v.focus = "#api-key";
      instruct(state, "This server needs an API key before it starts a session.");
      announce(state, `An API key is needed: ${err.message}`);
    } else {
      instruct(state, `The session could not start: ${err.message}`);
      announce(state, `The session could not start: ${err.message}`);
    }
  } finally {
    state.creating = false;
  }
  render(state);
}

async function resume() {
  let saved;
  try { saved = JSON.parse(localStorage.getItem(state.storeKey) || "null"); } catch { saved = null; }
  if (!saved || !saved.id || !saved.token) return;
  try {
    state.token = saved.token;
    adopt(await getSession(saved.id, saved.token));
  } catch (err) {
    state.token = null;
    if (err.code === "unauthorized" || err.code === "not_found") localStorage.removeItem(state.storeKey);
    announce(state, `The saved calibration could not be resumed (${err.message}); starting a new one.`);
    render(state);
    return;
  }
  state.view.startOver = true;
  if (state.session.calibration_id) {
    try {
      await finish(await getCalibration(state.session.calibration_id, state.token));
      return;
    } catch (err) {
      announce(state, `The saved result could not be read (${err.message}).`);
    }
  }
  state.view.startLabel = "Continue";
  flow.resume(state);
  state.view.resume = deviceWords(state, state.view.resume); // a board's page: connect it to go on
  render(state);
}

async function solve() {
  try {
    await finish(await solveSession(state.session.id, state.token));
  } catch (err) {
    const text = `The calibration could not be computed: ${err.message}. Redo a position or start over.`;
    instruct(state, text);
    announce(state, text);
    render(state);
  }
}

// The result of the session, then its downloads (fetched with the token: a plain link cannot send it).
async function finish(cal) {
  stop();
  letScreenSleep();
  const v = state.view;
  showResult(state, cal);
  render(state);
  // Its own address (/c/{id}): a reload, a bookmark or the history finds it again, with the session's
  // token kept for it (only that token reads it). The page stays: a board stays connected for Send.
  rememberToken(cal.id, state.token);
  offerSend(cal, state.token);
  history.pushState({ calibration: cal.id }, "", `/c/${encodeURIComponent(cal.id)}`);
  board.offer(cal, state.token);
  // The norms per position as soon as the server's figures are in (a cube's: …/apply), the files after
  // them: #downloads[data-ready] means the whole result is on show.
  const norms = kindOf(cal).norms(cal, state.token).catch(() => []).then((rows) => { v.norms = rows; render(state); });
  const [downloads] = await Promise.all([fetchDownloads(cal, state.token), norms]);
  v.downloads = downloads;
  render(state);
}

// --- motion ------------------------------------------------------------------------------------

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

function onOrientation(event) { if (state.sign) state.sign.orientation(event.beta, event.gamma); }

function onMotion(event) {
  const raw = sampleFromMotionEvent(event);
  if (raw) onSample(raw);
}

// The seam of the two sources: a raw sample {t (ms, the page's clock), acc (m/s²), gyr (°/s) | null}
// from the phone's devicemotion events or from a board's lines (board.js), into the one capture engine.
function onSample(raw) {
  const v = state.view;
  if (!state.gotMotion) {
    state.gotMotion = true;
    clearTimeout(noMotionTimer);
    v.problem = null;
    flow.firstMotion(state, ctx);
  }
  if (!flow.gate(state, raw, ctx)) { render(state); return; }
  const convention = state.sign.motion(raw.t, raw.acc);
  if (!convention) {
    instruct(state, "Reading the sensors…");
    render(state);
    return;
  }
  const t = flow.sampleTime(raw);
  if (state.lastT !== null && t <= state.lastT) return; // t_ms must increase
  state.lastT = t;
  const sample = { t, acc: toW3C(raw.acc, convention.convention), gyr: raw.gyr };
  flow.record(state, sample);
  if (!state.session) {
    // A board's lines come in bursts, and the first wait for its rate to be counted: what it printed
    // while the session was being created goes to the capture engine once it is.
    if (state.device === "board") {
      state.early.push(sample);
      while (state.early[0].t < t - EARLY_MS) state.early.shift();
    }
    v.live = { acc: sample.acc, out: null, force: false };
    render(state);
    return;
  }
  capture(sample);
}

// One sample into the capture engine, and what it says to the person.
function capture(sample) {
  const v = state.view;
  const out = state.machine.push(sample);
  v.live = { acc: sample.acc, out, force: out.event !== null };
  flow.show(state, out);
  if (state.device === "board") stalled(out);
  // The machine's own events as cues, the same in every flow: a capture has begun (again, after a
  // move); a pose is refused before anything is sent (six: already captured; cube24: the wrong face
  // up; free: too near a direction captured). The flows cue what the server answers (send).
  if (out.event === "started") cue("start");
  else if (out.event === "refused") cue("refused");
  render(state);
  if (out.capture) flow.send(state, out.capture, ctx);
}

function listen() {
  if (state.listening) return;
  if (state.device === "board") { listenBoard(); return; }
  state.listening = true;
  state.sign = new SignDetector({
    apple: isApplePlatform(navigator.userAgent, navigator.platform, navigator.maxTouchPoints),
  });
  state.machine = flow.makeMachine(state);
  window.addEventListener("deviceorientation", onOrientation);
  window.addEventListener("devicemotion", onMotion);
}

function stop() {
  window.removeEventListener("devicemotion", onMotion);
  window.removeEventListener("deviceorientation", onOrientation);
  clearTimeout(noMotionTimer);
  state.listening = false;
}

async function onStart() {
  const asked = requestPermissions(); // first, while the tap's user activation lasts
  unlockCues(); // sound needs a tap too
  keepScreenOn(); // the phone lies untouched for minutes
  const v = state.view;
  v.startDisabled = true;
  v.problem = null;
  render(state);
  if (!window.DeviceMotionEvent) { showProblem("noMotion"); render(state); return; }
  const answer = await asked;
  if (answer !== "granted") { showProblem("denied", answer); render(state); return; }
  listen();
  v.start = false;
  v.capture = true;
  v.resumePic = null;
  v.current = null;
  announce(state, "Reading the motion sensors…");
  instruct(state, "Waiting for motion data…");
  if (!state.gotMotion) {
    noMotionTimer = setTimeout(() => {
      if (!state.gotMotion) { showProblem("noMotion"); render(state); }
    }, NO_MOTION_MS);
  }
  v.focus = "#capture-h";
  render(state);
}

// --- a board ------------------------------------------------------------------------------------

// A board's capture that makes no progress (no capture started or done) for STALL_MS says, in the
// instruction, what it waits for and what it sees against the capture's thresholds, until it goes on.
function stalled(out) {
  const now = performance.now();
  if (out.event === "started" || out.capture || state.progressAt == null) state.progressAt = now;
  if (now - state.progressAt < STALL_MS) return;
  instruct(state, stallWords(state.machine, out));
}

// The board's samples go where the phone's go (onSample), read while the flow listens.
function listenBoard() {
  state.listening = true;
  state.sign = new SignDetector({ waitMs: 0 }); // a board reads +g on the axis pointing up: the W3C sign
  state.machine = flow.makeMachine(state);
}

// Connected: the board is the source from now on; the flow starts (or goes on) at once.
function startBoard() {
  state.board = board;
  state.progressAt = null; // the wait without progress counts from the first sample
  unlockCues();
  const v = state.view;
  v.problem = null;
  if (!state.listening) listenBoard();
  if (v.result) { render(state); return; } // a finished session: the board stays connected for Send
  if (state.solveOnContinue) { state.solveOnContinue = false; solve(); } // a complete session whose solve failed
  v.start = false;
  v.capture = true;
  v.resumePic = null;
  v.current = null;
  instruct(state, state.session ? flow.firstInstruction(state) : "Waiting for the board's readings…",
    state.session && flow.firstCode ? flow.firstCode(state) : null);
  announce(state, "The board is connected: its readings are the sensor now.");
  v.focus = "#capture-h";
  render(state);
}

function boardSample(sample) {
  if (state.device !== "board" || !state.listening || !sample.acc) return;
  onSample({ t: sample.t, acc: sample.acc, gyr: sample.gyr });
}

function boardClosed(why) {
  if (state.device !== "board" || state.view.result) return;
  state.listening = false;
  state.board = null;
  instruct(state, `${why} Connect it again to go on.`);
  announce(state, why);
  render(state);
}

const board = new BoardPanel({ needAcc: true, onConnect: startBoard, onSample: boardSample, onClose: boardClosed });

// What the flows may do besides changing the state.
const ctx = { render: () => render(state), solve, stop, adopt, ensureSession, problem: (kind) => showProblem(kind) };
view.bind(state, ctx);

// --- controls ----------------------------------------------------------------------------------

function redo(arg) {
  // Not reading the sensors yet (a resumed session): this tap asks for them, as Continue would.
  const go = () => { if (state.machine) { flow.redo(state, arg); render(state); } };
  if (!state.listening && state.device === "board" && board.connected) { startBoard(); go(); }
  else if (!state.listening && state.device === "board") {
    instruct(state, "Connect the board first (above).");
    render(state);
  }
  else if (!state.listening) onStart().then(go);
  else go();
}

if (SOURCE === "phone") $("#start-btn").addEventListener("click", () => {
  onStart();
  if (state.solveOnContinue) { // a complete session whose solve failed: Continue solves again
    state.solveOnContinue = false;
    solve();
  }
});
$("#key-box").addEventListener("submit", (event) => {
  event.preventDefault();
  state.apiKey = $("#api-key").value.trim() || null;
  state.view.keyBox = false;
  announce(state, "Trying again with the API key…");
  render(state);
  ensureSession();
});
// Start over (the session is lost; the capture goes on while the page asks).
bindStartOver(state, render, () => {
  letScreenSleep();
  localStorage.removeItem(state.storeKey);
  location.assign(WIZARD_URL); // the wizard afresh, not the result's own address (/c/{id})
});
$("#capture").addEventListener("click", (event) => {
  const button = event.target.closest("#redo-last, button[data-redo]");
  if (button) redo(button.dataset.redo);
});

for (const span of document.querySelectorAll("[data-pic]")) span.innerHTML = poseSvg(span.dataset.pic, null);
const local = ["localhost", "127.0.0.1", "[::1]"].includes(location.hostname);
if (SOURCE === "phone" && !window.isSecureContext && !local) { // a board's page: the board card says what it can read
  showProblem("insecure");
  render(state);
} else resume().finally(() => render(state)); // Start (or Continue) comes alive once the page knows which
