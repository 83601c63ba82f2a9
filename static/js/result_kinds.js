// What each kind of calibration shows. The server says it, by model type (`cal.model.type`), in the page's
// tables (TABLES.kinds: the result classes' page facts, app/web/result_pages.py PageFacts): which set of uses
// and formats the result offers (app/web/uses.py), whether it has a correction to apply (GET …/{id}/use), the
// plot the server draws for it (an export), the heading of its model, and which drawing draws its model, its
// norms per position and its plot's caption. This module keeps only the drawings, named by what they draw.
// The result view, the correction, "Use this calibration" and the wizard look a body's kind up once (kindOf)
// and read what to show from it: no module branches on a method or a model type.
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

// A noise characterisation: per sensor, its noise terms per axis with their units (Kalibr's), the rows the
// server's kind names (app/calibration/noise/characterise.py TERM_WORDS); a table wider than a phone scrolls in its
// box.
function noiseTables(cal) {
  const { terms } = kindOf(cal);
  return Object.entries(cal.model).filter(([name]) => name !== "type").map(([sensor, m]) => {
    const table = el("table", null, { id: `result-noise-${sensor}` });
    const head = el("tr");
    head.append(cell("th", ""), ...["x", "y", "z"].map((a) => cell("th", a)), cell("th", "unit"));
    table.append(head);
    for (const [key, label] of terms) {
      const tr = el("tr");
      tr.dataset.term = key;
      tr.append(cell("th", label), ...(m[key] || [null, null, null]).map((v) => cell("td", formatNumber(v, 8))),
        cell("td", m[`${key}_unit`] || m.unit || ""));
      table.append(tr);
    }
    const scroll = el("div", null, { class: "scroll", tabindex: "0" });
    scroll.append(table);
    const box = el("div");
    box.append(cell("h4", TABLES.sensorWords[sensor] || sensor), scroll);
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
      + "(the hard iron b moves them, soft iron stretches them); calibrated ones lie on it.",
    { class: "hint legend" })];
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

// The drawings, by the names the server's kinds give them.
const MODELS = { parameters: modelTables, noiseTerms: noiseTables };
const NORMS = { readings: readingNorms, captures: captureNorms, positions: cubeNorms };
const CAPTIONS = { flight: flightCaption };

// A flight's compass calibration: its numbers are in the frames of the firmware whose log it came from, so it
// offers that firmware's file, or the JSON.
const firmwareUses = (cal, uses) => uses.filter((u) => u.format === "json" || u.key === cal.flight?.firmware);

// A kind as the page uses it: the server's facts, with the drawings they name.
function pageKind(facts) {
  return {
    ...facts,
    model: MODELS[facts.model],
    norms: NORMS[facts.norms] || noNorms,
    usesFor: facts.firmware_uses ? firmwareUses : null,
    plot: facts.plot ? { box: facts.box, format: facts.plot, caption: CAPTIONS[facts.caption] || null } : null,
  };
}

const KINDS = Object.fromEntries(Object.entries(TABLES.kinds).map(([type, facts]) => [type, pageKind(facts)]));

// The entry of a calibration body: its model's type's, else a correction's (the server's kind "").
export const kindOf = (cal) => KINDS[cal.model?.type] || KINDS[""];

// Every plot a kind may show (the result view hides the others).
export const PLOTS = Object.values(KINDS).map((k) => k.plot).filter(Boolean);
