// What each kind of calibration shows: one entry per kind of body, keyed by its model's type
// (`cal.model.type`: affine, nonorthogonal, triangular, magnetometer, cube, noise, temperature). An entry
// says which uses and formats the result offers (app/web/uses.py through the page's tables), whether it
// has a correction to apply (GET …/{id}/use), the plot the server draws for it (an export), the heading
// and tables of its model, the compass's spheres, and its norms per position. The result view, the
// correction, "Use this calibration" and the wizard look a body's kind up once (kindOf) and read what to
// show from its entry: no module branches on a method or a model type.
import { applyCalibration } from "./api.js";
import { fillMatrix } from "./figures.js";
import { magResultSvgs } from "./mag_sphere.js";
import { formatNumber } from "./readings.js";
import { normRow } from "./result.js";
import { TABLES } from "./tables.js";
import { cell, el } from "./dom.js";

const UNIT_WORDS = TABLES.unitWords; // each unit in words (app/words.py)
const IN_INPUT_UNIT = new Set(["y", "o", "b", "s"]); // offsets and shifts: in the readings' unit
const ANGLES = new Set(["phi", "psi", "theta"]);

const asRows = (value) => (!Array.isArray(value) ? [[value]] : Array.isArray(value[0]) ? value : value.map((v) => [v]));

// Each parameter of the model as fitted (X and y, K and o, s, b and the angles…) as a small table
// #result-<name>, named with its unit; a cube's sensors one level down.
function modelTables(cal) {
  const unit = cal.unit;
  const title = (name) => (IN_INPUT_UNIT.has(name) && unit ? `${name} (${UNIT_WORDS[unit] || unit})`
    : ANGLES.has(name) ? `${name} (rad)` : name);
  return Object.entries(cal.model).filter(([name]) => name !== "type").map(([name, value]) => {
    const box = el("div");
    if (value && typeof value === "object" && !Array.isArray(value)) {
      box.append(cell("h4", name));
      for (const [part, v] of Object.entries(value)) {
        if (!Array.isArray(v)) continue;
        const table = el("table", null, { class: "matrix", id: `result-${name}-${part}` });
        fillMatrix(table, asRows(v));
        box.append(cell("h5", part), table);
      }
      return box;
    }
    const table = el("table", null, { class: "matrix", id: `result-${name}` });
    fillMatrix(table, asRows(value));
    box.append(cell("h4", title(name)), table);
    return box;
  });
}

// A noise characterisation: per sensor, its noise terms per axis with their units (Kalibr's).
export const NOISE_TERMS = [["noise_density", "noise density"], ["random_walk", "random walk"],
  ["bias_instability", "bias instability"], ["bias", "bias"]];

function noiseTables(cal) {
  return Object.entries(cal.model).filter(([name]) => name !== "type").map(([sensor, m]) => {
    const table = el("table", null, { id: `result-noise-${sensor}` });
    const head = el("tr");
    head.append(cell("th", ""), ...["x", "y", "z"].map((a) => cell("th", a)), cell("th", "unit"));
    table.append(head);
    for (const [key, label] of NOISE_TERMS) {
      const tr = el("tr");
      tr.dataset.term = key;
      tr.append(cell("th", label), ...(m[key] || [null, null, null]).map((v) => cell("td", formatNumber(v, 8))),
        cell("td", m[`${key}_unit`] || m.unit || ""));
      table.append(tr);
    }
    const box = el("div");
    box.append(cell("h4", TABLES.sensorWords[sensor] || sensor), table);
    return box;
  });
}

// A compass calibration: the raw readings and the calibrated ones on the same sphere (mag_sphere.js),
// with the legend; shared by the result view and the compass page.
export function magSpheres(cal) {
  const svgs = magResultSvgs(cal);
  const fig = (svg, caption) => {
    const f = el("figure", null, { class: "mag-fig" });
    const pic = el("div");
    pic.innerHTML = svg;
    f.append(pic, cell("figcaption", caption));
    return f;
  };
  return [fig(svgs.before, "Before: the raw readings m"), fig(svgs.after, "After: h = M (m − b)"),
    el("p", "The sphere has the field's radius F; green faces: directions covered. Raw readings sit off it "
      + "(the hard iron b moves them, soft iron stretches them); calibrated ones lie on it.", { class: "hint legend" })];
}

// The norms per position, |m| raw and |a| calibrated, from what the server says of each reading: the page
// applies no model. Each resolves to [{position, raw, calibrated}] ([] where the body has no positions).
const noNorms = () => Promise.resolve([]);

// Known orientations (six positions): each labelled reading's mean, and its calibrated vector as the
// server reports it, the expected vector a plus the residual X⁻¹(m − y) − a.
function readingNorms(cal) {
  return Promise.resolve((cal.readings || []).filter((r) => r.up && r.mean)
    .map((r) => normRow(r.up, r.mean, r.expected.map((a, i) => a + r.residual[i]))));
}

// A free session's poses: each reading's mean and calibrated vector, named by the capture it came from
// (the session's captures are the readings fitted, in order).
function captureNorms(cal) {
  const readings = cal.readings || [];
  const captures = cal.captures || [];
  if (!captures.length || captures.length !== readings.length) return noNorms();
  return Promise.resolve(captures.map((c, i) => normRow(c.position, readings[i].mean, readings[i].calibrated)));
}

// A cube session's positions: the capture means, calibrated by the server with the accelerometer's
// correction (POST …/{id}/apply: S⁻¹(m − b), Särkkä et al., IEEE Sensors Journal 17(11) 2017, eq. (1)).
async function cubeNorms(cal, token) {
  const captures = (cal.captures || []).filter((c) => c.position && c.mean);
  if (!cal.model.acc || !captures.length) return [];
  const { samples } = await applyCalibration(cal.id, captures.map((c) => c.mean), "acc", token);
  return captures.map((c, i) => normRow(c.position, c.mean, samples[i]));
}

// A correction of a sensor: what every kind is unless its entry says otherwise.
const CORRECTION = {
  uses: "calibration", // the key of its uses in TABLES.uses
  formats: "formats", // the key of its export formats in TABLES.uses
  correction: true, // it has an f = M (m − o) to apply
  snippets: true, // paste-ready lines of its correction under its file
  plot: null, // {box, format}: the figure the server draws for it, an export
  heading: "The model as fitted",
  model: modelTables,
  spheres: false, // the compass's before and after
  norms: noNorms,
};

// A compass calibrated from a flight: what the picture does not say — the orientation found against the one the
// firmware has, the directions covered, the model chosen and how the raw readings were had.
const FIRMWARE_WORDS = { ardupilot: "ArduPilot", px4: "PX4" };
const STRUCTURE_WORDS = { offsets: "offsets (hard iron)", scale: "offsets and a scale per axis",
  soft_iron: "offsets and soft iron" };

export function flightCaption(cal) {
  const f = cal.flight || {};
  const near = f.rotation_nearest || {};
  const firmware = FIRMWARE_WORDS[f.firmware] || f.firmware || "the firmware";
  const number = f.firmware === "px4" ? near.px4 : near.ardupilot;
  const setting = f.firmware === "px4" ? "CAL_MAG_ROT" : "COMPASS_ORIENT";
  const orientation = f.orientation_agrees
    ? `Orientation: as ${firmware} has it (${near.name}), ${formatNumber(f.angle_left_deg, 1)}° left.`
    : `Orientation: the compass sits as ${near.name} (${setting} ${number ?? "—"}), not as ${firmware} has it; `
      + `${formatNumber(f.angle_left_deg, 1)}° left.`;
  const motor = f.motor ? `, with the motors' interference against the ${f.motor}` : ", without a motor term";
  const covered = cal.metrics && cal.metrics.coverage !== undefined
    ? ` Directions covered: ${Math.round(cal.metrics.coverage * 100)} %.` : "";
  const model = STRUCTURE_WORDS[f.structure] || f.structure || "—";
  return `${orientation}${covered} Model: ${model}${motor}. Compass ${f.instance ?? 0} of the log `
    + `(${f.generation || firmware}); ${f.raw_how || ""}.`;
}

export const KINDS = {
  affine: { ...CORRECTION, norms: readingNorms },
  nonorthogonal: CORRECTION,
  triangular: { ...CORRECTION, norms: captureNorms },
  cube: { ...CORRECTION, norms: cubeNorms },
  magnetometer: { ...CORRECTION, spheres: true },
  noise: { ...CORRECTION, uses: "noise", formats: "noiseFormats", correction: false, snippets: false, heading: "The noise terms",
    model: noiseTables, plot: { box: "#result-allan", format: "allan_svg" } },
  compass_flight: { ...CORRECTION, uses: "flightCompass", formats: "flightCompassFormats", snippets: false,
    // its numbers are in the frames of the firmware whose log it came from: that firmware's file, or the JSON
    usesFor: (cal, uses) => uses.filter((u) => u.format === "json" || u.key === cal.flight?.firmware),
    heading: "The compass's model, h = M (Q m − b − k p)",
    plot: { box: "#result-flight", format: "flight_svg", caption: flightCaption } },
  temperature: { ...CORRECTION, uses: "temperature", formats: "temperatureFormats", snippets: false,
    heading: "Each axis's offset polynomial", plot: { box: "#result-temperature", format: "temperature_svg" } },
};

// The entry of a calibration body: its model's type, else a correction's.
export const kindOf = (cal) => KINDS[cal.model?.type] || CORRECTION;

// Every plot a kind may show (the result view hides the others).
export const PLOTS = Object.values(KINDS).map((k) => k.plot).filter(Boolean);
