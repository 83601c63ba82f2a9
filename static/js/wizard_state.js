// The wizard's one state object (no DOM): what the session and the sensors are doing, and `view`,
// what the page shows. The flows change it; wizard.js's render(state) writes it to the page.

export function newState({ protocol, captureS, device = "phone" }) {
  return {
    protocol,
    captureS,
    device, // the page's source (source.js), "phone" or "board": the flows' words say "board" for a board
    board: null, // the board panel (board_panel.js) when a board is the source
    // A board's session resumes on a board's page.
    storeKey: `trical.wizard.${protocol}${device === "board" ? ".board" : ""}`,
    session: null, // the server's session object
    token: null,
    apiKey: null,
    machine: null, // CaptureMachine (motion.js)
    sign: null, // SignDetector (motion.js)
    listening: false,
    gotMotion: false,
    creating: false,
    lastT: null,
    early: [], // a board's samples before its session exists (wizard.js)
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
      norms: null, // [{position, raw, calibrated}]: its norms per position (result_kinds.js), once known
      downloads: null, // [{key, name, url, filename} | {name, error}]
    },
  };
}

// The flows speak of the phone; with a board as the source, of the board.
export function deviceWords(state, text) {
  if (state.device !== "board" || typeof text !== "string") return text;
  // (no Start on a board's page)
  return text.replace(/\bphone's\b/g, "board's").replace(/\bphone\b/g, "board").replace(/\bPhone\b/g, "Board")
    .replace(/\bTap Continue\b/g, "Connect the board").replace(/\btap Continue\b/g, "connect the board");
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

// A calibration to show: the result card in place of the others, its files and norms to follow.
export function showResult(state, cal) {
  const v = state.view;
  v.start = false;
  v.capture = false;
  v.startOver = true;
  v.result = true;
  v.calibration = cal;
  v.norms = null;
  v.downloads = null;
  v.focus = "#result";
  announce(state, `Calibration done. ${cal.verdict.words}`);
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

// The render hooks a flow's view (flow_six_view.js, flow_cube_view.js, flow_free_view.js, the compass's)
// has nothing of its own for. wizard.js's render calls them; only they and render write the page.
export const VIEW_DEFAULTS = {
  start() {}, // the flow's part of the start card
  capture() {}, // the flow's part of the capture card
  next: () => null, // the pose to picture before the phone is in one
  model() {}, // the model as fitted, in the result's details
  result() {}, // the flow's own parts of the result
  // The figures listed: the scalar metrics (a cube's lists stay in the JSON export).
  figures: (cal) => ({ ...cal, metrics: Object.fromEntries(Object.entries(cal.metrics || {})
    .filter(([, v]) => v === null || typeof v !== "object")) }),
  bind() {}, // the flow's own controls: (state, ctx)
};
