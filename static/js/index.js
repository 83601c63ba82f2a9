// The start page: the only module here that touches the DOM.
import { createCalibration, exportUrl, uploadRecording } from "./api.js";
import { magResultSvgs } from "./mag_sphere.js";
import { formatNumber, parseReadings } from "./readings.js";

const $ = (sel) => document.querySelector(sel);
const status = $("#status");
let recordingId = null;

function say(text) { status.textContent = text; }

function cell(tag, text) { const el = document.createElement(tag); el.textContent = text; return el; }

function fillMatrix(table, rows) {
  table.replaceChildren(...rows.map((row) => {
    const tr = document.createElement("tr");
    row.forEach((v) => tr.append(cell("td", formatNumber(v))));
    return tr;
  }));
}

// Each parameter of the model (X and y, K and o, s, b and the angles…) as a small table #result-<name>.
function showModel(model) {
  $("#result-model").replaceChildren(...Object.entries(model).filter(([name]) => name !== "type").map(([name, value]) => {
    const box = document.createElement("div");
    const table = document.createElement("table");
    table.className = "matrix";
    table.id = `result-${name}`;
    const rows = !Array.isArray(value) ? [[value]] : Array.isArray(value[0]) ? value : value.map((v) => [v]);
    fillMatrix(table, rows);
    box.append(cell("h3", name), table);
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
    box.append(cell("h3", sensor), table);
    return box;
  }));
}

function showResult(cal) {
  $("#result").hidden = false;
  $("#result-headline").textContent = cal.headline || "";
  const ok = $("#result-ok");
  ok.className = cal.ok ? "ok" : "bad";
  ok.textContent = cal.ok ? `Calibration ${cal.id} passed its checks.` : `Calibration ${cal.id} failed its checks: ${cal.reasons.join("; ")}`;
  const choice = $("#result-choice");
  choice.hidden = !cal.choice;
  choice.textContent = cal.choice ? `Method ${cal.choice.method}: ${cal.choice.why}.` : "";
  $("#result-warnings").replaceChildren(...cal.warnings.map((w) => cell("li", w)));
  if (cal.method === "noise") showNoise(cal);
  else showModel(cal.model);
  const metrics = $("#result-metrics");
  // A noise result's metrics are per sensor: one level is flattened (gyr.adev_min …).
  const flat = Object.entries(cal.metrics).flatMap(([k, v]) => (v && typeof v === "object" && !Array.isArray(v)
    ? Object.entries(v).map(([k2, v2]) => [`${k}.${k2}`, v2]) : [[k, v]]));
  metrics.replaceChildren(...flat.map(([k, v]) => {
    const tr = document.createElement("tr");
    const shown = Array.isArray(v) ? v.map((x) => formatNumber(x, 4)).join(", ") : formatNumber(v);
    tr.append(cell("th", k), cell("td", shown));
    tr.firstChild.scope = "row";
    return tr;
  }));
  showMagSpheres(cal);
  const perReading = Boolean(cal.readings && cal.readings.length);
  $("#result-readings").hidden = !perReading;
  $("#result-readings-h").hidden = !perReading;
  $("#result-readings tbody").replaceChildren(...(cal.readings || []).map((r) => {
    const tr = document.createElement("tr");
    tr.append(cell("td", r.up ?? "—"), cell("td", formatNumber(r.norm_error_raw)), cell("td", formatNumber(r.norm_error)));
    return tr;
  }));
  // A noise characterisation's Allan deviation: the server draws it (the allan_svg export), one source.
  const allan = $("#result-allan");
  allan.hidden = cal.method !== "noise";
  if (cal.method === "noise") $("#result-allan img").src = exportUrl(cal.id, "allan_svg");
  else $("#result-allan img").removeAttribute("src");
  const list = $("#downloads");
  const formats = JSON.parse(cal.method === "noise" ? list.dataset.noiseFormats : list.dataset.formats);
  list.replaceChildren(...formats.map(([key, name]) => {
    const li = document.createElement("li");
    const a = cell("a", name);
    a.href = exportUrl(cal.id, key);
    a.setAttribute("download", "");
    li.append(a);
    return li;
  }));
  $("#result").focus();
  say(cal.ok ? "Calibration done." : "Calibration done, but it failed its checks.");
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

$("#upload-form").addEventListener("submit", async (event) => {
  event.preventDefault();
  const data = new FormData(event.target);
  for (const key of ["sampling_rate_hz", "acc_unit", "columns", "sign"]) if (!data.get(key)) data.delete(key);
  say("Uploading…");
  try {
    const rec = await uploadRecording(data);
    recordingId = rec.id;
    // A turn of the magnetometer alone has no still segments to calibrate an accelerometer from.
    $("#compass-recording").hidden = !rec.channels.includes("mag");
    $("#calibrate-recording").hidden = !rec.channels.includes("acc");
    $("#segments").hidden = false;
    $("#segments-table tbody").replaceChildren(...rec.segments.map((s) => {
      const tr = document.createElement("tr");
      tr.append(cell("td", String(s.index)), cell("td", `${s.start}–${s.end}`), cell("td", s.up ?? "—"),
        cell("td", s.acc_mean.map((v) => formatNumber(v, 3)).join(", ")));
      return tr;
    }));
    const still = rec.channels.includes("acc");
    $("#segments-h").hidden = !still;
    $("#segments-table").hidden = !still;
    const rate = `${rec.n_samples} samples at ${formatNumber(rec.sampling_rate_hz, 1)} Hz`;
    say(still ? `Found ${rec.segments.length} still segments in ${rate}.`
      : `Read the magnetometer alone: ${rate}. Calibrate the compass below.`);
  } catch (err) {
    say(`Upload refused: ${err.message}`);
  }
});

$("#calibrate-recording").addEventListener("click", async () => {
  say("Calibrating…");
  try {
    showResult(await createCalibration({ method: "auto", recording_id: recordingId }));
  } catch (err) {
    say(`Calibration refused: ${err.message}`);
  }
});

$("#noise-recording").addEventListener("click", async () => {
  say("Computing the Allan deviation…");
  try {
    showResult(await createCalibration({ method: "noise", recording_id: recordingId }));
  } catch (err) {
    say(`Noise characterisation refused: ${err.message}`);
  }
});

$("#compass-recording").addEventListener("click", async () => {
  say("Calibrating the compass…");
  try {
    showResult(await createCalibration({ method: "magnetometer", recording_id: recordingId }));
  } catch (err) {
    say(`Compass calibration refused: ${err.message}`);
  }
});

$("#fill").addEventListener("click", () => {
  try {
    for (const { up, mean } of parseReadings($("#paste").value)) {
      const row = document.querySelector(`#readings-table tr[data-up="${up}"]`);
      row.querySelectorAll("input").forEach((input, i) => { input.value = String(mean[i]); });
    }
    say("Table filled from the pasted lines.");
  } catch (err) {
    say(`Could not read the pasted lines: ${err.message}`);
  }
});

$("#readings-form").addEventListener("submit", async (event) => {
  event.preventDefault();
  const readings = [...document.querySelectorAll("#readings-table tbody tr")].map((tr) => ({
    up: tr.dataset.up,
    mean: [...tr.querySelectorAll("input")].map((input) => Number(input.value)),
  }));
  const payload = { method: "six_position", readings, unit: $("#r-unit").value };
  const g = $("#r-gravity").value;
  if (g) payload.gravity = Number(g);
  say("Calibrating…");
  try {
    showResult(await createCalibration(payload));
  } catch (err) {
    say(`Calibration refused: ${err.message}`);
  }
});
