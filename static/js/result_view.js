// One result view, the same wherever a calibration is shown: the start page after an upload or a
// paste, and a stored calibration's own page /c/{id} (templates/_result.html). The verdict and "Use
// this calibration" (use_calibration.js), the plots (the compass's spheres, the noise's Allan
// deviation, the accelerometer's norms per reading), then the details: the model, the figures, the
// readings and the notes.
import { exportUrl } from "./api.js";
import { showCorrection } from "./correction_view.js";
import { fillFigures, pageWords } from "./figures.js";
import { magResultSvgs } from "./mag_sphere.js";
import { formatNumber } from "./readings.js";
import { normChartSvg, normRows, triangularAsAffine } from "./result.js";
import { offerSend } from "./send.js";
import { TABLES } from "./tables.js";
import { fetchDownloads, resetUse, showUse, showVerdict } from "./use_calibration.js";
import { $, cell } from "./dom.js";

let shown = null; // the calibration on show: an older one's files never land on a newer one


function fillMatrix(table, rows) {
  table.replaceChildren(...rows.map((row) => {
    const tr = document.createElement("tr");
    row.forEach((v) => tr.append(cell("td", formatNumber(v))));
    return tr;
  }));
}

const UNIT_WORDS = { "m/s^2": "m/s²", uT: "µT", raw: "counts", g: "g" };
const IN_INPUT_UNIT = new Set(["y", "o", "b", "s"]); // offsets and shifts: in the readings' unit
const ANGLES = new Set(["phi", "psi", "theta"]);

// Each parameter of the model as fitted (X and y, K and o, s, b and the angles…) as a small table
// #result-<name>, named with its unit.
function showModel(model, unit) {
  const title = (name) => (IN_INPUT_UNIT.has(name) && unit ? `${name} (${UNIT_WORDS[unit] || unit})`
    : ANGLES.has(name) ? `${name} (rad)` : name);
  $("#result-model").replaceChildren(...Object.entries(model).filter(([name]) => name !== "type").map(([name, value]) => {
    const box = document.createElement("div");
    if (value && typeof value === "object" && !Array.isArray(value)) { // a cube's sensors: one level down
      box.append(cell("h4", name));
      for (const [part, v] of Object.entries(value)) {
        if (!Array.isArray(v)) continue;
        const table = document.createElement("table");
        table.className = "matrix";
        table.id = `result-${name}-${part}`;
        fillMatrix(table, Array.isArray(v[0]) ? v : v.map((x) => [x]));
        box.append(cell("h5", part), table);
      }
      return box;
    }
    const table = document.createElement("table");
    table.className = "matrix";
    table.id = `result-${name}`;
    const rows = !Array.isArray(value) ? [[value]] : Array.isArray(value[0]) ? value : value.map((v) => [v]);
    fillMatrix(table, rows);
    box.append(cell("h4", title(name)), table);
    return box;
  }));
}

// A noise characterisation: per sensor, its noise terms per axis with their units (Kalibr's).
const NOISE_TERMS = [["noise_density", "noise density"], ["random_walk", "random walk"],
  ["bias_instability", "bias instability"], ["bias", "bias"]];

function showNoise(cal) {
  $("#result-model").replaceChildren(...Object.entries(cal.model).filter(([name]) => name !== "type").map(([sensor, m]) => {
    const box = document.createElement("div");
    const table = document.createElement("table");
    table.id = `result-noise-${sensor}`;
    const head = document.createElement("tr");
    head.append(cell("th", ""), ...["x", "y", "z"].map((a) => cell("th", a)), cell("th", "unit"));
    table.append(head);
    for (const [key, label] of NOISE_TERMS) {
      const tr = document.createElement("tr");
      tr.dataset.term = key;
      tr.append(cell("th", label), ...(m[key] || [null, null, null]).map((v) => cell("td", formatNumber(v, 8))),
        cell("td", m[`${key}_unit`] || m.unit || ""));
      table.append(tr);
    }
    box.append(cell("h4", TABLES.sensorWords[sensor] || sensor), table);
    return box;
  }));
}

// A compass calibration: the raw readings and the calibrated ones on the same sphere (mag_sphere.js).
function showMagSpheres(cal) {
  const mag = cal.model.type === "magnetometer";
  $("#result-mag-box").hidden = !mag;
  if (!mag) { $("#result-mag").replaceChildren(); return; }
  const svgs = magResultSvgs(cal);
  const fig = (svg, caption) => {
    const f = document.createElement("figure");
    f.className = "mag-fig";
    const pic = document.createElement("div");
    pic.innerHTML = svg;
    f.append(pic, cell("figcaption", caption));
    return f;
  };
  const legend = cell("p", "The sphere has the field's radius F; green faces: directions covered. Raw readings sit off it "
    + "(the hard iron b moves them, soft iron stretches them); calibrated ones lie on it.");
  legend.className = "hint legend";
  $("#result-mag").replaceChildren(fig(svgs.before, "Before: the raw readings m"), fig(svgs.after, "After: h = M (m − b)"), legend);
}

// |m| before and |a| after per position against g, as the wizard draws it: an affine model's readings
// (six positions, known orientations) or a session's captures (free poses: the triangular model as
// m = X a + y; a cube's accelerometer, raw = S f + b).
function showNorms(cal) {
  let model = null;
  let means = [];
  if (cal.model.type === "affine") {
    model = cal.model;
    means = (cal.readings || []).filter((r) => r.up && r.mean).map((r) => ({ position: r.up, mean: r.mean }));
  } else if (cal.model.type === "triangular" && cal.captures) {
    model = triangularAsAffine(cal.model);
    means = cal.captures;
  } else if (cal.model.type === "cube" && cal.model.acc && cal.captures) {
    model = { X: cal.model.acc.S, y: cal.model.acc.b };
    means = cal.captures;
  }
  means = means.filter((c) => c.position && c.mean);
  $("#result-norms").hidden = !(model && means.length);
  $("#norm-chart").innerHTML = model && means.length ? normChartSvg(normRows(model, means), cal.gravity || TABLES.gravity) : "";
}

// The calibration `cal` (the API's body, with its verdict) on the page; its files are fetched with
// `token` (a wizard session's, or an API key; none on a server without keys).
export function showCalibration(cal, token = null) {
  $("#result").hidden = false;
  showVerdict(cal);
  $("#result-headline").textContent = cal.headline || "";
  const ok = $("#result-ok");
  ok.className = cal.ok ? "ok" : "bad";
  ok.textContent = cal.ok ? `Calibration ${cal.id} passed its checks.` : `Calibration ${cal.id} failed its checks: ${cal.reasons.join("; ")}`;
  const choice = $("#result-choice");
  choice.hidden = !cal.choice;
  // The server's words name methods by key: each in words here.
  const words = (text) => text.replace(/\b[a-z]+(?:_[a-z]+)+\b|\b(?:triangular|nonorthogonal|autocal|orientations)\b/g,
    (key) => TABLES.methods[key] || key);
  choice.textContent = cal.choice ? `Method: ${TABLES.methods[cal.choice.method] || cal.choice.method}, ${words(cal.choice.why)}.` : "";
  $("#result-warnings").replaceChildren(...cal.warnings.map((w) => cell("li", pageWords(w))));
  if (cal.method === "noise") showNoise(cal);
  else showModel(cal.model, cal.unit);
  $("#result-model-h").textContent = { noise: "The noise terms", temperature: "Each axis's offset polynomial" }[cal.method]
    || "The model as fitted";
  showCorrection($("#result-correction"), cal, token, $("#result-fitted-note"));
  fillFigures($("#result-metrics"), cal);
  showMagSpheres(cal);
  showNorms(cal);
  const perReading = Boolean(cal.readings && cal.readings.length);
  $("#result-readings").hidden = !perReading;
  $("#result-readings-h").hidden = !perReading;
  // One file per pose: each reading names its file.
  const fromFiles = (cal.readings || []).some((r) => r.source);
  $("#result-readings .file-col").hidden = !fromFiles;
  $("#result-readings tbody").replaceChildren(...(cal.readings || []).map((r) => {
    const tr = document.createElement("tr");
    tr.append(cell("td", r.up ?? "—"), cell("td", formatNumber(r.norm_error_raw)), cell("td", formatNumber(r.norm_error)));
    if (fromFiles) tr.append(cell("td", r.source ?? "—"));
    return tr;
  }));
  // A noise characterisation's Allan deviation: the server draws it (the allan_svg export), one source.
  const allan = $("#result-allan");
  allan.hidden = cal.method !== "noise";
  if (cal.method === "noise") $("#result-allan img").src = exportUrl(cal.id, "allan_svg");
  else $("#result-allan img").removeAttribute("src");
  // A temperature calibration's offset against temperature: the server draws it too (temperature_svg).
  const drift = $("#result-temperature");
  drift.hidden = cal.method !== "temperature";
  if (cal.method === "temperature") $("#result-temperature img").src = exportUrl(cal.id, "temperature_svg");
  else $("#result-temperature img").removeAttribute("src");
  shown = cal;
  offerSend(cal, token);
  resetUse(); // the files follow as they are fetched
  fetchDownloads(cal, token).then((downloads) => { if (shown === cal) showUse(cal, downloads); });
}

// Nothing of an earlier calibration stays on show.
export function hideCalibration() {
  shown = null;
  $("#result").hidden = true;
  resetUse();
}
