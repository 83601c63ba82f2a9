// The wizard page: reads the server's tables, picks the flow by protocol (flow_six.js, flow_cube.js),
// owns the one state object (wizard_state.js) and the one render(state) that writes the DOM. The
// flows change the state and call the server; only this module touches the page.
import { createSession, getCalibration, getSession, solveSession } from "./api.js";
import { SignDetector, STANDARD_GRAVITY, isApplePlatform, sampleFromMotionEvent, toW3C } from "./motion.js";
import { CUBE_POSITIONS, cubeSvg, turnInto, upOf } from "./cube.js";
import { describePose, nextPose, poseSvg, setDevice, shortPose } from "./poses.js";
import { BoardPanel } from "./board_panel.js";
import { showCorrection } from "./correction_view.js";
import { fillFigures } from "./figures.js";
import { formatNumber } from "./readings.js";
import { adviceText, gyroBiasText, normChartSvg, normRows, triangularAsAffine, withInterval } from "./result.js";
import { sphereSvg } from "./sphere.js";
import { cue, unlockCues } from "./cues.js";
import { fetchDownloads, showUse, showVerdict } from "./use_calibration.js";
import { offerSend } from "./send.js";
import { rememberToken } from "./tokens.js";
import { keepScreenOn, letScreenSleep } from "./wake_lock.js";
import { announce, instruct, newState } from "./wizard_state.js";
import { donePoses, sixFlow } from "./flow_six.js";
import { capturedCount, cubeFlow, nextPosition } from "./flow_cube.js";
import { canFinish, coveredDirections, freeFlow, poseCount, progressOf } from "./flow_free.js";
import { $, el } from "./dom.js";

const WIZARD_URL = location.pathname + location.search; // before a result moves to /c/{id}
const root = $("#wizard");
const NO_MOTION_MS = 2000;

const state = newState({
  protocol: root.dataset.protocol,
  captureS: Number(root.dataset.captureS),
});
const cube = state.protocol === "cube24";
const free = state.protocol === "free";
const flow = cube ? cubeFlow : free ? freeFlow : sixFlow;
flow.init(state);
let noMotionTimer = null;

// --- rendering: the state onto the page --------------------------------------------------------


// Writes only what changed: render runs on every motion sample.
function setText(node, text) { if (node.textContent !== text) node.textContent = text; }
function setHidden(node, hidden) { if (node.hidden !== hidden) node.hidden = hidden; }

const uploadLink = (text = "upload a log instead") => el("a", text, { href: "/" });

// Each problem with its recovery text: what the box shows, what the live region says, and what
// else on the page changes.
const PROBLEMS = {
  insecure: {
    parts: () => ["Motion sensors need HTTPS: run ", el("code", "trical serve --https"),
      " and open the https address it prints. Or ", uploadLink(), " (a log recorded with a sensor app)."],
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
          + "longer asks, clear this site's data in Settings › Safari › Advanced › Website Data and reload."), p3];
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

const rendered = { seq: 0, problem: null, turnAlert: null, calibration: null, downloads: null, resumePic: null,
  figures: {}, lastLive: 0, sphere: null };

function render(s) {
  const v = s.view;
  setHidden($("#start"), !v.start);
  setHidden($("#start-btn"), v.startHidden);
  if ($("#start-btn").disabled !== v.startDisabled) $("#start-btn").disabled = v.startDisabled;
  setText($("#start-btn"), v.startLabel);
  if (v.resume !== null) setText($("#resume"), v.resume);
  setHidden($("#resume"), v.resume === null);
  if (v.resumePic !== rendered.resumePic && v.resumePic !== null) $("#resume-pic").innerHTML = cubeSvg(v.resumePic);
  rendered.resumePic = v.resumePic;
  setHidden($("#resume-pic"), v.resumePic === null);
  renderProblem(v);
  setHidden($("#key-box"), !v.keyBox);
  setHidden($("#capture"), !v.capture);
  if (cube) renderCube(s);
  else if (free) renderFree(s);
  else renderPoses(s);
  setText($("#instruction"), v.instruction);
  setText($("#instruction-code"), v.instructionCode || "");
  setHidden($("#instruction-code"), !v.instructionCode);
  renderLive(s);
  setHidden($("#result"), !v.result);
  renderResult(s);
  renderDownloads(v);
  setHidden($("#start-over"), !v.startOver || v.askStartOver);
  setHidden($("#start-over-ask"), !(v.startOver && v.askStartOver));
  if (v.announcement.seq !== rendered.seq) {
    rendered.seq = v.announcement.seq;
    $("#status").textContent = v.announcement.text;
  }
  if (v.focus) {
    $(v.focus).focus();
    v.focus = null;
  }
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

function renderPoses(s) {
  const done = new Set(donePoses(s));
  for (const li of document.querySelectorAll("#poses li")) {
    const pose = li.dataset.pose;
    let shown = done.has(pose) ? "done" : "todo";
    if (s.machine && s.machine.redo.has(pose)) shown = "redo";
    if (li.dataset.state !== shown) li.dataset.state = shown;
    li.classList.toggle("current", pose === s.view.current);
    setText(li.querySelector(".pose-state"), { done: "done ✓", todo: "to do", redo: "redo" }[shown]);
    setHidden(li.querySelector(".redo"), shown !== "done");
  }
}

// The free flow: the sphere of directions covered and advised, the count, the advice in words, Finish.
function renderFree(s) {
  const progress = progressOf(s);
  const covered = coveredDirections(s);
  const advice = progress ? progress.advice : [];
  const current = s.free.current;
  const key = JSON.stringify([covered.length, advice.map((a) => a.up),
    current && current.map((v) => Math.round(v * 20))]); // redraw when the live direction moves ~3°
  if (rendered.sphere !== key) {
    rendered.sphere = key;
    $("#sphere").innerHTML = sphereSvg({ covered, advice: advice.map((a) => a.up), current });
  }
  const n = poseCount(s);
  const count = $("#free-count");
  setText(count, progress ? progress.message : "No pose captured yet.");
  if (count.dataset.count !== String(n)) count.dataset.count = String(n);
  const bar = $("#free-progress");
  bar.max = progress ? progress.target_poses : 12;
  if (bar.value !== Math.min(n, bar.max)) bar.value = Math.min(n, bar.max);
  const list = $("#free-advice");
  const words = advice.map((a) => a.words).join("|");
  if (list.dataset.words !== words) {
    list.dataset.words = words;
    list.replaceChildren(...advice.map((a) => el("li", a.words)));
  }
  const finish = $("#free-finish");
  const fitFrom = progress ? progress.fit_from : 10;
  if (finish.disabled !== !canFinish(s)) finish.disabled = !canFinish(s);
  setText(finish, canFinish(s) ? "Finish now" : `Finish (from ${fitFrom} poses)`);
}

function figure(box, k, turn, caption) {
  const key = `${k} ${turn}`;
  if (rendered.figures[box.id] !== key) {
    box.querySelector(".cube-pic").innerHTML = cubeSvg(k, { turn });
    rendered.figures[box.id] = key;
  }
  setText(box.querySelector("figcaption"), caption);
}

function renderCube(s) {
  const { redoing, resumed, log } = s.cube;
  const n = capturedCount(s);
  const k = nextPosition(s);
  setText($("#capture-h"), redoing ? `Redo position ${k} of ${CUBE_POSITIONS}` : `Position ${k} of ${CUBE_POSITIONS}`);
  if (k >= 2) {
    const { label, words } = turnInto(k);
    figure($("#cube-turn"), k - 1, label, `From position ${k - 1}: ${words}.`);
  } else {
    figure($("#cube-turn"), 1, null, "Start: screen (sensor z) up, the phone's x axis along the jig.");
  }
  figure($("#cube-target"), k, null, `Position ${k}: sensor ${upOf(k)} up.`);
  setText($("#cube-count"), `${n} of ${CUBE_POSITIONS} positions captured`);
  if ($("#cube-count").dataset.captured !== String(n)) $("#cube-count").dataset.captured = String(n);
  if ($("#cube-progress").value !== n) $("#cube-progress").value = n;
  $("#cube-row").querySelectorAll("li").forEach((li, i) => {
    const state = i < n ? "done" : i === n ? "current" : "todo";
    if (li.dataset.state !== state) li.dataset.state = state;
  });
  const redo = $("#redo-last");
  setHidden(redo, n === 0 || redoing);
  setText(redo, `Redo position ${n}`);
  const hint = $("#redo-hint");
  setHidden(hint, !(resumed && n >= 2 && !log?.ends.has(n - 1) && !redoing));
  setText(hint, `After a reload, the page no longer has the turn into position ${n}: to redo it, put the `
    + `cube back in position ${n - 1} first, then press Redo and turn it into position ${n} again.`);
  renderTurnAlert(s.view);
}

function renderTurnAlert(v) {
  const box = $("#turn-alert");
  if (v.turnAlert !== rendered.turnAlert) {
    rendered.turnAlert = v.turnAlert;
    if (v.turnAlert) {
      const { message, k } = v.turnAlert;
      const pic = el("div", null, { class: "cube-pic" });
      pic.innerHTML = cubeSvg(k - 1, { turn: turnInto(k).label });
      box.replaceChildren(el("p", message), el("p", `Put the cube back in position ${k - 1} as pictured, then make this turn:`), pic);
    } else {
      box.replaceChildren();
    }
  }
  setHidden(box, !v.turnAlert);
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
  // Before the phone is in a pose, the six flow's next pose, large, in words: the person sees where to
  // turn it before turning it (flow_six.js names the same pose in the instruction).
  const next = !seen && !cube && !free && s.session ? nextPose(s.machine.remaining()) : null;
  const shown = seen || (next ? `next ${next}` : "");
  if (pic.dataset.pose !== shown) {
    pic.dataset.pose = shown;
    pic.innerHTML = seen ? poseSvg(seen, 176) : next ? poseSvg(next, 176) : "";
    $("#live-pose-words").textContent = seen ? `Now: ${describePose(seen)}` : next ? `Next: ${describePose(next)}` : "";
  }
}

function fillMatrix(table, rows, halfWidths) {
  table.replaceChildren(...rows.map((row, i) => {
    const tr = el("tr");
    row.forEach((v, j) => tr.append(el("td", withInterval(v, halfWidths?.[i]?.[j], (x) => formatNumber(x)))));
    return tr;
  }));
}

function renderResult(s) {
  const cal = s.view.calibration;
  if (!cal || cal === rendered.calibration) return;
  rendered.calibration = cal;
  showVerdict(cal);
  $("#result-headline").textContent = cal.headline || "";
  const ok = $("#result-ok");
  ok.className = cal.ok ? "ok" : "bad";
  ok.textContent = cal.ok ? `Calibration ${cal.id} passed its checks.` : `Calibration ${cal.id} failed its checks:`;
  $("#result-reasons").replaceChildren(...(cal.reasons || []).map((r) => el("li", r)));
  const warnings = cal.warnings || [];
  $("#result-warnings").replaceChildren(...(warnings.length ? warnings : ["none"]).map((w) => el("li", w)));
  showCorrection($("#result-correction"), cal, s.token, $("#result-fitted-note"));
  if (cal.model.type === "cube") fillCubeModel(cal, cal.uncertainty || {});
  else if (cal.model.type === "triangular") fillTriangularModel(cal);
  else fillSixModel(cal, s.session);
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
  fillFigures($("#result-metrics"), { ...cal, metrics: Object.fromEntries(Object.entries(cal.metrics || {})
    .filter(([, v]) => v === null || typeof v !== "object")) }); // the cube's lists stay in the JSON export
}

// The affine model m = X a + y, and |m| before and after per pose.
function fillSixModel(cal, session) {
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

// Farago et al.'s triangular model a = K (m + o), each ± its 95 % half-width, and the norms per pose.
function fillTriangularModel(cal) {
  const unc = cal.uncertainty || {};
  // K is lower triangular: the zeros above its diagonal are exact, shown without an interval.
  fillMatrix($("#result-K"), cal.model.K, unc.K && unc.K.map((row, i) => row.map((v, j) => (j > i ? null : v))));
  fillMatrix($("#result-o"), cal.model.o.map((v) => [v]), unc.o && unc.o.map((v) => [v]));
  fillNorms(triangularAsAffine(cal.model), cal.captures || [], cal.gravity || STANDARD_GRAVITY);
}

// Särkkä et al.'s model per sensor: S (with D and the misalignment when given) and b, each ± its 95 % half-width.
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
  // The accelerometer's raw = S f + b has the form of m = X a + y (Särkkä et al. eq. (1)).
  const acc = cal.model.acc;
  if (acc) fillNorms({ X: acc.S, y: acc.b }, cal.captures || [], cal.gravity || STANDARD_GRAVITY);
}

function renderDownloads(v) {
  if (!v.downloads || v.downloads === rendered.downloads) return;
  rendered.downloads = v.downloads;
  showUse(v.calibration, v.downloads);
}

// --- transitions shared by the flows -----------------------------------------------------------

function showProblem(kind, detail = null) {
  const v = state.view;
  letScreenSleep(); // every problem stops the capture
  PROBLEMS[kind].apply(v);
  v.problem = { kind, detail };
  announce(state, PROBLEMS[kind].say(detail));
  v.focus = "#problem";
}

function remember() { localStorage.setItem(state.storeKey, JSON.stringify({ id: state.session.id, token: state.token })); }

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
    const created = await createSession({ protocol: state.protocol, capture_s: state.captureS, device_id: null,
      label: null, source: state.device }, state.apiKey);
    state.token = created.token;
    adopt(created);
    remember();
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
  v.start = false;
  v.capture = false;
  v.startOver = true;
  v.result = true;
  v.calibration = cal;
  v.focus = "#result";
  announce(state, `Calibration done. ${cal.verdict.words}`);
  render(state);
  // Its own address (/c/{id}): a reload, a bookmark or the history finds it again, with the session's
  // token kept for it (only that token reads it). The page stays: a board stays connected for Send.
  rememberToken(cal.id, state.token);
  offerSend(cal, state.token);
  history.pushState({ calibration: cal.id }, "", `/c/${encodeURIComponent(cal.id)}`);
  board.offer(cal, state.token);
  v.downloads = await fetchDownloads(cal, state.token);
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
    v.live = { acc: sample.acc, out: null, force: false };
    render(state);
    return;
  }
  const out = state.machine.push(sample);
  v.live = { acc: sample.acc, out, force: out.event !== null };
  flow.show(state, out);
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
  state.sign = new SignDetector({ apple: isApplePlatform(navigator.userAgent, navigator.platform, navigator.maxTouchPoints) });
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

// The board's samples go where the phone's go (onSample), read while the flow listens.
function listenBoard() {
  state.listening = true;
  state.sign = new SignDetector({ waitMs: 0 }); // a board reads +g on the axis pointing up: the W3C sign
  state.machine = flow.makeMachine(state);
}

// Connected: the board is the source from now on; the flow starts (or goes on) at once.
function startBoard() {
  if (state.device !== "board") {
    state.device = "board";
    setDevice("board");
    for (const span of document.querySelectorAll("[data-pic]")) span.innerHTML = poseSvg(span.dataset.pic, null);
    for (const words of document.querySelectorAll("[data-words]")) words.textContent = shortPose(words.dataset.words);
    for (const li of document.querySelectorAll("#poses li")) { // the words a screen reader says, a board's
      const pose = li.dataset.pose;
      li.querySelector(".pose-text .sr-only").textContent = ` ${describePose(pose)}`;
      li.querySelector(".redo").setAttribute("aria-label", `Redo ${pose} (${describePose(pose)})`);
    }
    $("#live-pose").dataset.pose = ""; // redrawn as a board at the next sample
    if (!cube) setText($("#capture-h"), free ? "Rest the board in any pose" : "Rest the board on one side");
    setText($("h1"), "Calibrate this board");
    document.title = "Calibrate this board — trical";
  }
  if (state.listening && !state.board) stop(); // the phone's events (none come on a computer) make way
  state.board = board;
  unlockCues();
  const v = state.view;
  v.problem = null;
  if (!state.listening) listenBoard();
  if (v.result) { render(state); return; } // a finished session: the board stays connected for Send
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

// --- controls ----------------------------------------------------------------------------------

function redo(arg) {
  // Not reading the sensors yet (a resumed session): this tap asks for them, as Continue would.
  const go = () => { if (state.machine) { flow.redo(state, arg); render(state); } };
  if (!state.listening && state.device === "board" && board.connected) { startBoard(); go(); }
  else if (!state.listening) onStart().then(go);
  else go();
}

$("#start-btn").addEventListener("click", () => {
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
// Start over in two taps (the session is lost): the first asks in place, where the thumb already is;
// the capture goes on meanwhile, and Keep it goes back to it.
function askStartOver(ask) {
  state.view.askStartOver = ask;
  state.view.focus = ask ? "#start-over-no" : "#start-over";
  render(state);
}
$("#start-over").addEventListener("click", () => askStartOver(true));
$("#start-over-no").addEventListener("click", () => askStartOver(false));
$("#start-over-yes").addEventListener("click", () => {
  letScreenSleep();
  localStorage.removeItem(state.storeKey);
  location.assign(WIZARD_URL); // the wizard afresh, not the result's own address (/c/{id})
});
if (free) $("#free-finish").addEventListener("click", () => { if (canFinish(state)) solve(); });
$("#capture").addEventListener("click", (event) => {
  const button = event.target.closest("#redo-last, button[data-redo]");
  if (button) redo(button.dataset.redo);
});

for (const span of document.querySelectorAll("[data-pic]")) span.innerHTML = poseSvg(span.dataset.pic, null);
const local = ["localhost", "127.0.0.1", "[::1]"].includes(location.hostname);
if (!window.isSecureContext && !local) {
  showProblem("insecure");
  render(state);
} else resume();
