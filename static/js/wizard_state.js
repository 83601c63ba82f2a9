// The wizard's one state object (no DOM): what the session and the sensors are doing, and `view`,
// what the page shows. The flows change it; wizard.js's render(state) writes it to the page.

export function newState({ protocol, captureS }) {
  return {
    protocol,
    captureS,
    device: "phone", // "board" once a board is the source: the flows' words say "board"
    board: null, // the board panel (board_panel.js) when a board is the source
    storeKey: `trical.wizard.${protocol}`,
    session: null, // the server's session object
    token: null,
    apiKey: null,
    machine: null, // CaptureMachine (motion.js)
    sign: null, // SignDetector (motion.js)
    listening: false,
    gotMotion: false,
    creating: false,
    lastT: null,
    lastAnnounced: "",
    solveOnContinue: false, // a complete session whose solve failed: Continue solves again
    view: {
      start: true, // the "Before you start" card
      startLabel: "Start",
      startDisabled: false,
      startHidden: false,
      capture: false, // the capture card
      keyBox: false,
      startOver: false,
      askStartOver: false, // Start over was tapped once: the page asks before it discards the session
      resume: null, // the resume text, or null
      resumePic: null, // the cube position pictured with the resume text, or null
      problem: null, // {kind, detail}: a new object each time a problem is shown
      instruction: "Waiting for motion data…",
      instructionCode: null, // the axis codes of the instruction, a grey note
      announcement: { text: "", seq: 0 }, // the live region; seq counts what was said
      focus: null, // a selector to focus once, at the next render
      live: null, // {acc, out, force}: the last sample for the live view
      current: null, // the six flow's pose in view
      turnAlert: null, // the cube flow's refused turn: {message, k}
      result: false,
      calibration: null, // the calibration shown
      downloads: null, // [{key, name, url, filename} | {name, error}]
    },
  };
}

// The flows speak of the phone; with a board as the source, of the board.
export function deviceWords(state, text) {
  if (state.device !== "board" || typeof text !== "string") return text;
  return text.replace(/\bphone's\b/g, "board's").replace(/\bphone\b/g, "board").replace(/\bPhone\b/g, "Board");
}

// Say `text` in the live region (again, even when it is the same words).
export function announce(state, text) {
  state.view.announcement = { text: deviceWords(state, text), seq: state.view.announcement.seq + 1 };
}

// The instruction in words; `code`, the axis codes it is about, only as a grey note under it.
export function instruct(state, text, code = null) {
  state.view.instruction = deviceWords(state, text);
  state.view.instructionCode = code;
}

export const list = (poses) => (poses.length ? poses.join(", ") : "none");

// What a flow (flow_six.js, flow_cube.js, flow_free.js) does at a step it has nothing of its own for.
export const FLOW_DEFAULTS = {
  init() {},
  adopted() {},
  firstMotion() {},
  gate: () => true,
  sampleTime: (raw) => raw.t, // ms of this page load
  record() {},
  redo() {},
};
