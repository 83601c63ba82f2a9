// One result view, the same wherever a calibration is shown: the start page after an upload or a
// paste, and a stored calibration's own page /c/{id} (templates/_result.html). The verdict and "Use
// this calibration" (use_calibration.js), the plots (the compass's spheres, the noise's Allan
// deviation, the accelerometer's norms per reading), then the details: the model, the figures, the
// readings and the notes.
import { exportUrl } from "./api.js";
import { showCompasses } from "./compasses_view.js";
import { showCorrection } from "./correction_view.js";
import { fillFigures } from "./figures.js";
import { formatNumber } from "./readings.js";
import { showNotes } from "./notes.js";
import { normChartSvg } from "./result.js";
import { PLOTS, kindOf, magSpheres } from "./result_kinds.js";
import { offerSend } from "./send.js";
import { TABLES } from "./tables.js";
import { fetchDownloads, resetUse, showUse, showVerdict } from "./use_calibration.js";
import { $, cell } from "./dom.js";

let shown = null; // the calibration on show: an older one's files never land on a newer one

// |m| before and |a| after per position against g, as the wizard draws it, from the server's readings
// (result_kinds.js): six positions' labelled readings, a free session's poses, a cube's positions.
function showNorms(cal, rows) {
  $("#result-norms").hidden = !rows.length;
  $("#norm-chart").innerHTML = rows.length ? normChartSvg(rows, cal.gravity || TABLES.gravity) : "";
}

// The calibration `cal` (the API's body, with its verdict) on the page; its files are fetched with
// `token` (a wizard session's, or an API key; none on a server without keys).
export function showCalibration(cal, token = null) {
  $("#result").hidden = false;
  showVerdict(cal);
  $("#result-headline").textContent = cal.headline || "";
  const ok = $("#result-ok");
  ok.className = cal.ok ? "ok" : "bad";
  ok.textContent = cal.ok ? `Calibration ${cal.id} passed its checks.`
    : `Calibration ${cal.id} failed its checks: ${cal.reasons.join("; ")}`;
  const choice = $("#result-choice");
  choice.hidden = !cal.choice;
  // The server's words name the candidates by their method's key: each in the method table's words here.
  const named = Object.keys(cal.choice?.candidates || {});
  const words = (text) => (named.length ? text.replace(new RegExp(`\\b(?:${named.join("|")})\\b`, "g"),
    (key) => TABLES.methods[key] || key) : text);
  choice.textContent = cal.choice
    ? `Method: ${TABLES.methods[cal.choice.method] || cal.choice.method}, chosen because ${words(cal.choice.why)}.`
    : "";
  showNotes($("#result-warnings"), cal.warnings);
  const kind = kindOf(cal);
  $("#result-model").replaceChildren(...kind.model(cal));
  $("#result-model-h").textContent = kind.heading;
  showCorrection($("#result-correction"), cal, token, $("#result-fitted-note"));
  fillFigures($("#result-metrics"), cal);
  $("#result-mag-box").hidden = !kind.spheres;
  $("#result-mag").replaceChildren(...(kind.spheres ? magSpheres(cal) : []));
  showNorms(cal, []);
  const perReading = Boolean(cal.readings && cal.readings.length);
  $("#result-readings").hidden = !perReading;
  $("#result-readings-h").hidden = !perReading;
  // One file per pose: each reading names its file.
  const fromFiles = (cal.readings || []).some((r) => r.source);
  $("#result-readings .file-col").hidden = !fromFiles;
  $("#result-readings tbody").replaceChildren(...(cal.readings || []).map((r) => {
    const tr = document.createElement("tr");
    tr.append(cell("td", r.up ?? "—"), cell("td", formatNumber(r.norm_error_raw)),
      cell("td", formatNumber(r.norm_error)));
    if (fromFiles) tr.append(cell("td", r.source ?? "—"));
    return tr;
  }));
  // The figure the server draws for its kind (the noise's Allan deviation, a temperature calibration's
  // offset against temperature): one source, the export.
  for (const plot of PLOTS) {
    $(plot.box).hidden = plot !== kind.plot;
    if (plot === kind.plot) $(`${plot.box} img`).src = exportUrl(cal.id, plot.format);
    else $(`${plot.box} img`).removeAttribute("src");
    if (plot.caption) $(`${plot.box} figcaption`).textContent = plot === kind.plot ? plot.caption(cal) : "";
  }
  showCompasses(cal);
  shown = cal;
  offerSend(cal, token);
  resetUse(); // the files follow as they are fetched
  // The norms as soon as they are known (a cube's are the server's answer to …/apply), and before the
  // files are ready: #downloads[data-ready] means everything is on show.
  const norms = kind.norms(cal, token).catch(() => []).then((rows) => { if (shown === cal) showNorms(cal, rows); });
  Promise.all([fetchDownloads(cal, token), norms]).then(([downloads]) => {
    if (shown === cal) showUse(cal, downloads);
  });
}

// Nothing of an earlier calibration stays on show.
export function hideCalibration() {
  shown = null;
  $("#result").hidden = true;
  resetUse();
}
