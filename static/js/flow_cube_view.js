// The cube24 flow's render hooks (wizard.js calls them from its one render): the position to reach and
// the turn into it, pictured; the row of 24 positions, the count, Redo; the refused turn; and Särkkä
// et al.'s model per sensor.
import { capturedCount, nextPosition } from "./flow_cube.js";
import { CUBE_POSITIONS, cubeSvg, turnInto, upOf } from "./cube.js";
import { column, fillMatrix } from "./figures.js";
import { TABLES } from "./tables.js";
import { VIEW_DEFAULTS } from "./wizard_state.js";
import { WORDS } from "./source.js";
import { $, el, setHidden, setText } from "./dom.js";

// What is drawn: pictures are redrawn only when they change.
const drawn = { figures: {}, turnAlert: null, resumePic: null };

function figure(box, k, turn, caption) {
  const key = `${k} ${turn}`;
  if (drawn.figures[box.id] !== key) {
    box.querySelector(".cube-pic").innerHTML = cubeSvg(k, { turn });
    drawn.figures[box.id] = key;
  }
  setText(box.querySelector("figcaption"), caption);
}

// A resumed session: the position to put the cube back in, pictured with the resume text.
function start(s) {
  const k = s.view.resumePic;
  if (k !== drawn.resumePic && k !== null) $("#resume-pic").innerHTML = cubeSvg(k);
  drawn.resumePic = k;
}

function capture(s) {
  const { redoing, resumed, log } = s.cube;
  const n = capturedCount(s);
  const k = nextPosition(s);
  setText($("#capture-h"), redoing ? `Redo position ${k} of ${CUBE_POSITIONS}` : `Position ${k} of ${CUBE_POSITIONS}`);
  if (k >= 2) {
    const { label, words } = turnInto(k);
    figure($("#cube-turn"), k - 1, label, `From position ${k - 1}: ${words}.`);
  } else {
    figure($("#cube-turn"), 1, null, `Start: ${WORDS.ups[0]} (sensor z), the ${WORDS.noun}'s x axis along the jig.`);
  }
  figure($("#cube-target"), k, null, `Position ${k}: sensor ${upOf(k)} up.`);
  setText($("#cube-count"), `${n} of ${CUBE_POSITIONS} positions captured`);
  if ($("#cube-count").dataset.captured !== String(n)) $("#cube-count").dataset.captured = String(n);
  if ($("#cube-progress").value !== n) $("#cube-progress").value = n;
  $("#cube-row").querySelectorAll("li").forEach((li, i) => {
    const state = i < n ? "done" : i === n ? "current" : "todo";
    if (li.dataset.state !== state) li.dataset.state = state;
  });
  const redo = $("#redo-last");
  setHidden(redo, n === 0 || redoing);
  setText(redo, `Redo position ${n}`);
  const hint = $("#redo-hint");
  setHidden(hint, !(resumed && n >= 2 && !log?.ends.has(n - 1) && !redoing));
  setText(hint, `After a reload, the page no longer has the turn into position ${n}: to redo it, put the `
    + `cube back in position ${n - 1} first, then press Redo and turn it into position ${n} again.`);
  turnAlert(s.view);
}

function turnAlert(v) {
  const box = $("#turn-alert");
  if (v.turnAlert !== drawn.turnAlert) {
    drawn.turnAlert = v.turnAlert;
    if (v.turnAlert) {
      const { message, k } = v.turnAlert;
      const pic = el("div", null, { class: "cube-pic" });
      pic.innerHTML = cubeSvg(k - 1, { turn: turnInto(k).label });
      box.replaceChildren(el("p", message),
        el("p", `Put the cube back in position ${k - 1} as pictured, then make this turn:`), pic);
    } else {
      box.replaceChildren();
    }
  }
  setHidden(box, !v.turnAlert);
}

// Särkkä et al.'s model per sensor: S (with D and the misalignment when given) and b, each ± its 95 % half-width.
function model(cal) {
  const unc = cal.uncertainty || {};
  const units = { acc: cal.unit || "m/s²", gyr: (cal.units && cal.units.gyr) || "rad/s" };
  const parts = [];
  // The accelerometer's D and misalignment are shown; the gyroscope's stay in the JSON export.
  for (const [key, factors] of [["acc", true], ["gyr", false]]) {
    const m = cal.model[key];
    if (!m) continue;
    const half = unc[key] || {};
    parts.push(el("h4", TABLES.sensorWords[key]));
    const row = el("div", null, { class: "row" });
    const items = [["S", "S (scale and cross-axis)", m.S, half.S]];
    if (factors && m.D) items.push(["D", "D (scale factors)", column(m.D), column(half.D)]);
    if (factors && m.misalignment) items.push(["misalignment", "Misalignment", m.misalignment, half.misalignment]);
    items.push(["b", `b (${units[key]})`, column(m.b), column(half.b)]);
    for (const [id, title, rows, halfRows] of items) {
      const table = el("table", null, { class: "matrix", id: `cube-${key}-${id}` });
      fillMatrix(table, rows, halfRows);
      const box = el("div");
      box.append(el("h5", title), table);
      row.append(box);
    }
    parts.push(row);
  }
  $("#cube-model").replaceChildren(...parts);
}

// No heading to change for a board: "Position k of 24" says it.
export const cubeView = { ...VIEW_DEFAULTS, start, capture, model };

export default cubeView; // the module the server's protocol table names (wizard.js imports it by that name)
