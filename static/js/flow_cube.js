// The cube24 flow of the wizard (no DOM): the 24 positions in order, each turn checked by the server
// as it happens; its steps as transitions on the wizard's state, and its server calls.
import { getSession, postCapture } from "./api.js";
import { cue } from "./cues.js";
import { CaptureMachine } from "./motion.js";
import { CUBE_POSITIONS, MotionLog, expectPosition, turnInto, upOf } from "./cube.js";
import { TABLES } from "./tables.js";
import { announce, instruct } from "./wizard_state.js";

const NO_GYRO_SAMPLES = 10; // motion events without rotationRate before the cube flow gives up

export const capturedCount = (state) => (state.session ? state.session.captures.length : 0);
// The position the next capture is for: the last one again while redoing it.
export const nextPosition = (state) => (state.cube.redoing ? capturedCount(state)
  : Math.min(capturedCount(state) + 1, CUBE_POSITIONS));

function init(state) {
  state.cube = {
    log: null, // MotionLog: every sample since the page started reading the sensors
    gyroSeen: false,
    noGyro: 0,
    redoing: false, // the next capture replaces the last position
    awaitingTurn: false, // a position was accepted: the cube must turn before the next capture
    resumed: false, // the session was resumed after a reload: the motion log starts at Continue
  };
}

function makeMachine(state) {
  // A cube may stand on an inclined plane: its up face is the nearest axis within the page's angle,
  // inside the server's.
  const machine = new CaptureMachine(state.captureS * 1000, { maxAngleDeg: TABLES.cube24.maxAngleDeg });
  state.cube.log = new MotionLog();
  const cube = state.cube;
  expectPosition(machine, nextPosition(state));
  // Resumed: the cube stands in the last captured position and must turn before the next capture.
  if (capturedCount(state) > 0 && !cube.redoing) { machine.requireMove(true); cube.awaitingTurn = true; }
  return machine;
}

const firstInstruction = () => "Stand the cube in position 1 against the jig and let go.";

// The cube flow needs rotationRate: it waits for it before starting a session.
function gate(state, raw, ctx) {
  const cube = state.cube;
  if (cube.gyroSeen) return true;
  if (raw.gyr) {
    cube.gyroSeen = true;
    ctx.ensureSession();
    return true;
  }
  cube.noGyro += 1;
  if (cube.noGyro >= NO_GYRO_SAMPLES) {
    ctx.stop();
    ctx.problem("noGyro");
  }
  return false;
}

// The captures are joined into one recording by time, across reloads too: epoch ms
// (event.timeStamp restarts with each page load).
const sampleTime = (raw) => performance.timeOrigin + raw.t;

function record(state, sample) { state.cube.log.push(sample); }

function show(state, out) {
  const k = nextPosition(state);
  const { state: step, pose } = out;
  const up = upOf(k);
  const turn = k >= 2 ? turnInto(k).words : null;
  let text;
  switch (step) {
    case "waiting": text = "Reading the sensors…"; break;
    case "moving":
      text = k >= 2 ? `Turning into position ${k}: ${turn}, then let go.` : "Stand the cube in position 1 and let go.";
      break;
    case "tilted":
      text = `The cube is tilted ${Math.round(out.angleDeg)}° away from ${pose} up: stand it on a face.`;
      break;
    case "refused": text = `Position ${k} needs sensor ${up} up; the cube has ${pose} up.`
      + (turn ? ` From position ${k - 1}: ${turn}.` : ""); break;
    case "settling": text = `Position ${k} recognised: keep still…`; break;
    case "capturing": text = `Capturing position ${k}: keep still.`; break;
    case "sending": text = `Checking position ${k} and the turn into it…`; break;
    case "retry": text = state.cube.awaitingTurn && turn ? `Position ${k - 1} captured. Now ${turn}.` : null; break;
    default: text = null;
  }
  if (text !== null) instruct(state, text);
  if (out.event === "restarted") announce(state, "Moved during the capture: it restarts once the cube is still again.");
  const key = `${step} ${pose} ${k}`;
  if (key !== state.lastAnnounced && ["settling", "capturing", "refused", "tilted"].includes(step)) {
    announce(state, text);
  }
  state.lastAnnounced = key;
}

// The server refused the turn: its words, and the picture of the position to go back to with the
// turn to make from there. Recording goes on; the next move again runs from the last accepted end.
function wrongTurn(state, message, k) {
  state.view.turnAlert = { message, k };
  announce(state, ""); // the alert announces itself (role=alert); nothing stale in the status line
  instruct(state, `Wrong turn into position ${k}: back to position ${k - 1}, then ${turnInto(k).words}.`);
}

async function send(state, capture, ctx) {
  const cube = state.cube;
  const k = nextPosition(state);
  const payload = {
    acc: capture.acc, t_ms: capture.t_ms, gyr: capture.gyr, unit: "m/s^2", gyr_unit: "deg/s",
    sign: state.sign.result, position: String(k), redo: cube.redoing,
  };
  if (k >= 2) payload.motion = cube.log.motion(capture.t_ms[0]);
  try {
    const answer = await postCapture(state.session.id, state.token, payload);
    cube.log.accept(k, capture.t_ms[capture.t_ms.length - 1]);
    cube.redoing = false;
    state.machine.resolve(true, capture.position);
    ctx.adopt(answer.session);
    state.view.turnAlert = null;
    const n = capturedCount(state);
    cue(n < CUBE_POSITIONS ? "captured" : "finished"); // turn the cube now, or nothing more to do
    if (n < CUBE_POSITIONS) {
      expectPosition(state.machine, n + 1);
      state.machine.requireMove(true); // the next position may have the same face up: wait for the turn
      cube.awaitingTurn = true;
      const text = `Position ${k} captured. Now ${turnInto(n + 1).words}.`;
      instruct(state, text);
      announce(state, text);
      ctx.render();
    } else {
      instruct(state, "All 24 positions captured: computing the calibration…");
      announce(state, "All 24 positions captured: computing the calibration…");
      ctx.render();
      await ctx.solve();
    }
  } catch (err) {
    state.machine.resolve(false, capture.position);
    cue("refused"); // a wrong turn too: the alert says which
    cube.awaitingTurn = false;
    if (err.code === "already_captured") {
      try { ctx.adopt(await getSession(state.session.id, state.token)); } catch { /* keep the old view */ }
    }
    if (err.code === "wrong_turn") {
      wrongTurn(state, err.message, k);
    } else {
      const text = `The capture of position ${k} was refused: ${err.message}. Move the cube and put it down again.`;
      instruct(state, text);
      announce(state, text);
    }
    ctx.render();
  }
}

function resume(state) {
  state.cube.resumed = true;
  const n = capturedCount(state);
  if (n >= CUBE_POSITIONS) { // complete but not solved (the solve failed): try again on Continue
    state.view.resume = "All 24 positions are captured. Tap Continue to compute the calibration.";
    state.solveOnContinue = true;
    return;
  }
  const text = n === 0 ? "You have a cube calibration in progress with no position captured yet. "
    + "Stand the cube in position 1 and tap Continue."
    : `You have a cube calibration in progress: ${n} of ${CUBE_POSITIONS} positions captured. Put the cube back `
      + `in position ${n} (pictured), against the jig, then tap Continue: the recording of the next turn starts there.`;
  state.view.resume = text;
  if (n) state.view.resumePic = n;
  announce(state, text);
}

// Redo the last position captured.
function redo(state) {
  const n = capturedCount(state);
  if (!n) return;
  const cube = state.cube;
  const { log } = cube;
  const last = log.samples.length ? log.samples[log.samples.length - 1].t : -Infinity;
  const known = log.redo(n, last);
  cube.redoing = true;
  cube.awaitingTurn = false;
  expectPosition(state.machine, n);
  state.machine.requireMove(!known && n >= 2); // from position n − 1 the cube must turn again
  state.view.turnAlert = null;
  const text = known || n === 1
    ? `Redo position ${n}: leave the cube in position ${n} (or put it back there); `
      + "the new capture replaces the old one."
    : `Redo position ${n}: the cube should now stand in position ${n - 1}; ${turnInto(n).words} into position ${n}.`;
  instruct(state, text);
  announce(state, text);
}

export const cubeFlow = {
  init,
  makeMachine,
  adopted() {},
  firstInstruction,
  firstMotion() {},
  gate,
  sampleTime,
  record,
  show,
  send,
  resume,
  redo,
};

export default cubeFlow; // the module the server's protocol table names (wizard.js imports it by that name)
