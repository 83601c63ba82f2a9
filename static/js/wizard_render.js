// The render loop the wizard pages share (wizard.js: six, cube24, free; wizard_compass.js: the compass;
// the noise page, wizard_noise.js, its files and live region):
// the state's view (wizard_state.js) onto what every wizard page has — the result's shell (verdict,
// headline, checks, notes, the correction, the figures), its norms per position, its files, Start over,
// the live region and the focus. What a flow draws of its own comes from its view's hooks (`view`:
// model, result), called from here; each page's render draws its own cards, then calls renderShared.
import { showCorrection } from "./correction_view.js";
import { fillFigures } from "./figures.js";
import { showNotes } from "./notes.js";
import { normChartSvg } from "./result.js";
import { STANDARD_GRAVITY } from "./motion.js";
import { resetUse, showUse, showVerdict } from "./use_calibration.js";
import { $, el, setHidden } from "./dom.js";

// What render last wrote, so that it writes only what changed (render runs on every sample).
export function newRendered() {
  return { seq: 0, calibration: null, norms: null, downloads: null };
}

function renderResult(s, rendered, view) {
  const cal = s.view.calibration;
  if (!cal || cal === rendered.calibration) return;
  rendered.calibration = cal;
  resetUse(); // an earlier result's files go; this one's follow as they are fetched
  showVerdict(cal);
  $("#result-headline").textContent = cal.headline || "";
  const ok = $("#result-ok");
  ok.className = cal.ok ? "ok" : "bad";
  ok.textContent = cal.ok ? `Calibration ${cal.id} passed its checks.` : `Calibration ${cal.id} failed its checks:`;
  $("#result-reasons").replaceChildren(...(cal.reasons || []).map((r) => el("li", r)));
  showNotes($("#result-warnings"), cal.warnings);
  showCorrection($("#result-correction"), cal, s.token, $("#result-fitted-note"));
  view.model(cal, s);
  view.result(cal, s);
  fillFigures($("#result-metrics"), view.figures(cal));
}

// |m| before and |a| after per position against g, from the server's readings (result_kinds.js).
function renderNorms(s, rendered) {
  const { calibration: cal, norms: rows } = s.view;
  if (!rows || rows === rendered.norms) return;
  rendered.norms = rows;
  $("#norm-chart").innerHTML = rows.length ? normChartSvg(rows, cal.gravity || STANDARD_GRAVITY) : "";
  $("#norm-table tbody").replaceChildren(...rows.map((r) => {
    const tr = el("tr");
    tr.append(el("th", r.position, { scope: "row" }), el("td", r.raw.toFixed(4)), el("td", r.calibrated.toFixed(4)));
    return tr;
  }));
}

// The result's files once fetched ("Use this calibration" and every format).
export function renderDownloads(v, rendered) {
  if (!v.downloads || v.downloads === rendered.downloads) return;
  rendered.downloads = v.downloads;
  showUse(v.calibration, v.downloads);
}

// The shared part of a wizard page's render: after the page's own cards, before the focus moves.
export function renderShared(s, rendered, view) {
  const v = s.view;
  setHidden($("#result"), !v.result);
  renderResult(s, rendered, view);
  renderNorms(s, rendered);
  renderDownloads(v, rendered);
  setHidden($("#start-over"), !v.startOver || v.askStartOver);
  setHidden($("#start-over-ask"), !(v.startOver && v.askStartOver));
  renderVoice(v, rendered);
}

// What the live region says (again, when the same words are said again), then the focus, once.
export function renderVoice(v, rendered) {
  if (v.announcement.seq !== rendered.seq) {
    rendered.seq = v.announcement.seq;
    $("#status").textContent = v.announcement.text;
  }
  if (v.focus) {
    $(v.focus).focus();
    v.focus = null;
  }
}

// Start over in two taps: the first asks in place, where the thumb already is, and Keep it goes back;
// the second (Yes) calls startAfresh. The page's render shows the question (state.view.askStartOver).
export function bindStartOver(state, render, startAfresh) {
  const ask = (yes) => {
    state.view.askStartOver = yes;
    state.view.focus = yes ? "#start-over-no" : "#start-over";
    render(state);
  };
  $("#start-over").addEventListener("click", () => ask(true));
  $("#start-over-no").addEventListener("click", () => ask(false));
  $("#start-over-yes").addEventListener("click", startAfresh);
}
