// The compass page's render hooks (wizard_compass.js calls them from its render, through the wizard's
// shared render loop, wizard_render.js): the turn's coverage, its sphere and what is still missing; the
// result's summary, its spheres before and after, and the model h = M (m − b).
import { MIN_READINGS, missingWords } from "./compass_flow.js";
import { column, fillMatrix } from "./figures.js";
import { magSphereSvg } from "./mag_sphere.js";
import { formatNumber } from "./readings.js";
import { magSpheres } from "./result_kinds.js";
import { VIEW_DEFAULTS } from "./wizard_state.js";
import { $, setText } from "./dom.js";

const DRAWN_POINTS = 600; // the latest readings drawn
const pct = (v) => `${Math.round(100 * v)} %`;

let drawnStatus = null; // the coverage status drawn: the sphere is redrawn only with a new one

// The turn: the coverage of the last status drawn (the page draws at most every DRAW_MS), the message
// that stands in for the missing faces until the next draw, and Calibrate now.
function capture(s) {
  const c = s.compass;
  const st = c.status;
  if (st && st !== drawnStatus) {
    drawnStatus = st;
    const box = $("#compass-coverage");
    box.dataset.count = String(st.count);
    box.dataset.coverage = st.coverage.toFixed(2);
    const covered = st.covered.filter(Boolean).length;
    box.textContent = st.centre
      ? `Coverage ${pct(st.coverage)} (${covered} of ${st.covered.length} directions), ${st.count} readings.`
      : `${st.count} readings: keep turning, the sphere fills once the ${s.device} has turned a little.`;
    $("#compass-progress").value = st.coverage;
    $("#compass-sphere").innerHTML = magSphereSvg({ covered: st.covered, points: st.directions.slice(-DRAWN_POINTS),
      current: st.current, label: "Field directions reached" });
  }
  const words = st && st.centre ? missingWords(st.missing) : null;
  setText($("#compass-missing"), c.message !== null ? c.message : !words ? ""
    : words.length ? `Still missing: ${words.join("; ")}.` : "All directions covered.");
  const disabled = (st ? st.count : 0) < MIN_READINGS || c.solving;
  if ($("#compass-solve").disabled !== disabled) $("#compass-solve").disabled = disabled;
  if (c.whereText !== null) setText($("#compass-where-text"), c.whereText);
}

// The model h = M (m − b), each ± its 95 % half-width.
function model(cal) {
  const unc = cal.uncertainty || {};
  fillMatrix($("#result-M"), cal.model.M, unc.M, 4);
  fillMatrix($("#result-b"), column(cal.model.b), column(unc.b), 4);
}

// The field, the spread of |h| before and after, the error on new directions and the coverage, in one
// line; then the readings on the sphere before and after.
function result(cal) {
  const m = cal.metrics;
  const source = { given: "given", model: "IGRF model at your place", estimated: "estimated" }[m.field_source]
    || m.field_source;
  $("#result-summary").textContent = `Field ${formatNumber(m.field_ut, 1)} µT (${source}); spread of |h| `
    + `${formatNumber(m.norm_spread_raw_ut, 2)} µT before → ${formatNumber(m.norm_spread_ut, 2)} µT after; `
    + `error on new directions ${formatNumber(m.cv_error_ut, 2)} µT (raw ${formatNumber(m.raw_error_ut, 2)} µT); `
    + `coverage ${pct(m.coverage)} of ${m.count} readings.`;
  $("#result-mag").replaceChildren(...magSpheres(cal));
}

// Every figure, the faces still missing among them.
export const compassView = { ...VIEW_DEFAULTS, capture, model, result, figures: (cal) => cal };
