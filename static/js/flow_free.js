// The free-pose flow of the wizard (no DOM): the phone put down in any still pose, 12 or more, each at
// least 10° from the others; after each capture the server fits the triangular model (from 10 poses),
// reports the error to expect on new orientations and advises the next poses; the flow ends at the
// target or when the person taps Finish. Its steps as transitions on the wizard's state, and its calls.
import { getSession, postCapture } from "./api.js";
import { cue } from "./cues.js";
import { CaptureMachine, dot, norm } from "./motion.js";
import { sourcePoseWords } from "./poses.js";
import { TABLES } from "./tables.js";
import { FLOW_DEFAULTS, announce, instruct } from "./wizard_state.js";

const FREE = TABLES.free;
const COS_MIN = Math.cos((FREE.minAngleDeg * Math.PI) / 180);

export const poseCount = (state) => (state.session ? state.session.captures.length : 0);
export const progressOf = (state) => (state.session && state.session.progress) || null;
export const canFinish = (state) => poseCount(state) >= FREE.fitFrom;

const unitOf = (v) => { const n = norm(v); return [v[0] / n, v[1] / n, v[2] / n]; };

// The directions captured so far (unit vectors of the capture means).
export function coveredDirections(state) {
  return state.session ? state.session.captures.map((c) => unitOf(c.mean)) : [];
}

// True when `mean` points within the least angle of a pose already captured.
function taken(state, mean) {
  const u = unitOf(mean);
  return coveredDirections(state).some((c) => dot(c, u) > COS_MIN);
}

const nextWords = (state) => {
  const advice = progressOf(state)?.advice || [];
  return advice.length ? `Next: ${sourcePoseWords(advice[0].words)}.` : "";
};

function init(state) { state.free = { current: null }; }

function makeMachine(state) {
  // Any direction is a pose (no axis to be near); a direction already taken is refused.
  return new CaptureMachine(state.captureS * 1000,
    { maxAngleDeg: FREE.maxAngleDeg, isDone: (mean) => taken(state, mean) });
}

const firstInstruction = (state) => `Put the phone down in any still pose: flat, on an edge, leaning against `
  + `something. ${nextWords(state)}`;

function firstMotion(state, ctx) { ctx.ensureSession(); }

function show(state, out) {
  const { state: step } = out;
  const k = poseCount(state) + 1;
  let text;
  switch (step) {
    case "waiting": text = "Reading the sensors…"; break;
    case "moving": text = `Turn the phone to a new pose and let it rest. ${nextWords(state)}`; break;
    case "settling": text = `New direction for pose ${k}: keep still…`; break;
    case "capturing": text = `Capturing pose ${k}: keep still.`; break;
    case "sending": text = `Checking pose ${k}…`; break;
    case "done": text = `Pose ${k - 1} captured: turn the phone to a new pose. ${nextWords(state)}`; break;
    case "refused": text = `This direction is within ${FREE.minAngleDeg}° of a pose already captured: turn the `
      + `phone further. ${nextWords(state)}`; break;
    default: text = null;
  }
  if (text !== null) instruct(state, text);
  state.free.current = out.still ? out.mean : null;
  if (out.event === "restarted") {
    announce(state, "Moved during the capture: it restarts once the phone is still again.");
  }
  const key = `${step} ${k}`;
  if (key !== state.lastAnnounced && ["settling", "capturing", "refused"].includes(step)) announce(state, text);
  state.lastAnnounced = key;
}

async function send(state, capture, ctx) {
  const payload = {
    acc: capture.acc, t_ms: capture.t_ms, gyr: capture.gyr, unit: "m/s^2", gyr_unit: "deg/s",
    sign: state.sign.result, redo: false,
  };
  try {
    const answer = await postCapture(state.session.id, state.token, payload);
    state.machine.resolve(true, capture.position);
    ctx.adopt(answer.session);
    const progress = progressOf(state);
    const text = progress.target_reached ? `${progress.message}: computing the calibration…`
      : `${progress.message}. ${nextWords(state)}`;
    cue(progress.target_reached ? "finished" : "captured");
    instruct(state, text);
    announce(state, text);
    ctx.render();
    if (progress.target_reached) await ctx.solve();
  } catch (err) {
    state.machine.resolve(false, capture.position);
    cue("refused");
    try { ctx.adopt(await getSession(state.session.id, state.token)); } catch { /* keep the old view */ }
    const text = err.code === "pose_too_close" ? `Refused: ${err.message}.`
      : `The capture was refused: ${err.message}. Move the phone and put it down again.`;
    instruct(state, text);
    announce(state, text);
    ctx.render();
  }
}

function resume(state) {
  const progress = progressOf(state);
  const text = `You have a free calibration in progress: ${progress.message}. Tap Continue to go on, or Start over.`;
  state.view.resume = text;
  state.view.capture = true;
  instruct(state, "Tap Continue to read the motion sensors again.");
  announce(state, text);
}

export const freeFlow = { ...FLOW_DEFAULTS, init, makeMachine, firstInstruction, firstMotion, show, send, resume };

export default freeFlow; // the module the server's protocol table names (wizard.js imports it by that name)
