// The six-position flow of the wizard (no DOM): poses in any order, recognised from the data; its
// steps as transitions on the wizard's state, and its server calls.
import { getSession, postCapture } from "./api.js";
import { cue } from "./cues.js";
import { CaptureMachine, POSES } from "./motion.js";
import { describePose, nextPose, shortPose } from "./poses.js";
import { FLOW_DEFAULTS, announce, instruct, list } from "./wizard_state.js";

export function donePoses(state) {
  if (!state.session) return [];
  return POSES.filter((p) => !state.session.remaining.includes(p));
}

function makeMachine(state) {
  const machine = new CaptureMachine(state.captureS * 1000);
  machine.setDone(donePoses(state));
  return machine;
}

function adopted(state) {
  if (state.machine) state.machine.setDone(donePoses(state));
}

const cap = (text) => text.charAt(0).toUpperCase() + text.slice(1);

// The next pose in words (its large picture beside it, wizard.js), any other side still to do allowed.
function nextWords(remaining) {
  const next = nextPose(remaining);
  if (!next) return "";
  return `Next: put the phone ${describePose(next)}${remaining.length > 1 ? " (or on any side still to do)" : ""}.`;
}

const codes = (remaining) => `Still to do: ${list(remaining)} (the axis pointing up).`;

const firstInstruction = (state) => nextWords(state.session.remaining);
const firstCode = (state) => codes(state.session.remaining);

function firstMotion(state, ctx) { ctx.ensureSession(); }

// What the machine's output means to the person, in the instruction and the live region.
function show(state, out) {
  const { pose, state: step } = out;
  const remaining = state.machine.remaining();
  const words = pose ? describePose(pose) : "";
  let text;
  let code = pose && step !== "moving" ? `${pose} up. ${codes(remaining)}` : codes(remaining);
  switch (step) {
    case "waiting": text = "Reading the sensors…"; break;
    case "moving": text = nextWords(remaining); break;
    case "tilted":
      text = `The phone is tilted ${Math.round(out.angleDeg)}° away from ${words}: rest it flat on that side.`;
      break;
    case "settling": text = `${cap(words)}: recognised, keep still…`; break;
    case "capturing": text = `Capturing ${words}: keep still.`; break;
    case "sending": text = `Checking the capture of ${words}…`; break;
    case "done":
      text = remaining.length ? `${cap(words)}: captured. ${nextWords(remaining)}` : "All six positions captured.";
      break;
    case "refused":
      text = `${cap(words)} is already captured. ${nextWords(remaining)} To capture it again, press its Redo button.`;
      code = `${pose} is already captured. ${codes(remaining)}`; break;
    case "retry": text = null; break; // the server's refusal stays on screen until the phone moves
    default: text = null;
  }
  if (text !== null) instruct(state, text, code);
  state.view.current = step === "moving" ? null : pose;
  if (out.event === "restarted") {
    announce(state, "Moved during the capture: it restarts once the phone is still again.");
  }
  const key = `${step} ${pose}`;
  if (key !== state.lastAnnounced && ["settling", "capturing", "refused", "tilted"].includes(step)) {
    announce(state, text);
  }
  state.lastAnnounced = key;
}

async function send(state, capture, ctx) {
  const payload = {
    acc: capture.acc, t_ms: capture.t_ms, gyr: capture.gyr, unit: "m/s^2", gyr_unit: "deg/s",
    sign: state.sign.result, position: capture.position, redo: capture.redo,
  };
  try {
    const answer = await postCapture(state.session.id, state.token, payload);
    state.machine.resolve(true, capture.position);
    ctx.adopt(answer.session);
    const remaining = state.session.remaining;
    cue(remaining.length ? "captured" : "finished"); // turn the phone now, or nothing more to do
    const text = remaining.length ? `${cap(describePose(capture.position))}: captured. ${nextWords(remaining)}`
      : "All six positions captured: computing the calibration…";
    instruct(state, text, remaining.length ? `${capture.position} captured. ${codes(remaining)}` : null);
    announce(state, text);
    ctx.render();
    if (!remaining.length) await ctx.solve();
  } catch (err) {
    state.machine.resolve(false, capture.position);
    cue("refused");
    if (err.code === "already_captured") {
      try { ctx.adopt(await getSession(state.session.id, state.token)); } catch { /* keep the old view */ }
    }
    const text = `The capture of ${describePose(capture.position)} was refused: ${err.message}. `
      + "Move the phone and put it down again.";
    instruct(state, text, `${capture.position} up.`);
    announce(state, text);
    ctx.render();
  }
}

function resume(state) {
  const done = donePoses(state);
  state.view.capture = true;
  const text = `You have a calibration in progress: ${done.length} of 6 positions captured `
    + `(${done.map(shortPose).join(", ")}); `
    + `remaining: ${state.session.remaining.map(shortPose).join(", ")}. Tap Continue to go on, or Start over.`;
  state.view.resume = text;
  instruct(state, "Tap Continue to read the motion sensors again.");
  announce(state, text);
}

function redo(state, pose) {
  state.machine.requestRedo(pose);
  state.view.current = null;
  const text = `Redo: put the phone ${describePose(pose)}; the new capture replaces the old one.`;
  instruct(state, text, `${pose} up.`);
  announce(state, text);
}

export const sixFlow = {
  ...FLOW_DEFAULTS, makeMachine, adopted, firstInstruction, firstCode, firstMotion, show, send, resume, redo,
};

export default sixFlow; // the module the server's protocol table names (wizard.js imports it by that name)
