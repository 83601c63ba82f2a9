// The free flow's render hooks (wizard.js calls them from its one render): the sphere of directions
// covered and advised, the count, the advice in words, Finish; and the triangular model.
import { canFinish, coveredDirections, poseCount, progressOf } from "./flow_free.js";
import { column, fillMatrix } from "./figures.js";
import { sourcePoseWords } from "./poses.js";
import { sphereSvg } from "./sphere.js";
import { WORDS } from "./source.js";
import { VIEW_DEFAULTS } from "./wizard_state.js";
import { $, el, setText } from "./dom.js";

let drawnSphere = null; // the key of the sphere drawn: redrawn only when it changes

function capture(s) {
  const progress = progressOf(s);
  const covered = coveredDirections(s);
  const advice = progress ? progress.advice : [];
  const current = s.free.current;
  const key = JSON.stringify([covered.length, advice.map((a) => a.up),
    current && current.map((v) => Math.round(v * 20))]); // redraw when the live direction moves ~3°
  if (drawnSphere !== key) {
    drawnSphere = key;
    $("#sphere").innerHTML = sphereSvg({ covered, advice: advice.map((a) => a.up), current, titles: WORDS.ups });
  }
  const n = poseCount(s);
  const count = $("#free-count");
  setText(count, progress ? progress.message : "No pose captured yet.");
  if (count.dataset.count !== String(n)) count.dataset.count = String(n);
  const bar = $("#free-progress");
  bar.max = progress ? progress.target_poses : 12;
  if (bar.value !== Math.min(n, bar.max)) bar.value = Math.min(n, bar.max);
  const list = $("#free-advice");
  const words = advice.map((a) => a.words).join("|");
  if (list.dataset.words !== words) {
    list.dataset.words = words;
    list.replaceChildren(...advice.map((a) => el("li", sourcePoseWords(a.words))));
  }
  const finish = $("#free-finish");
  const fitFrom = progress ? progress.fit_from : 10;
  if (finish.disabled !== !canFinish(s)) finish.disabled = !canFinish(s);
  setText(finish, canFinish(s) ? "Finish now" : `Finish (from ${fitFrom} poses)`);
}

// Farago et al.'s triangular model a = K (m + o), each ± its 95 % half-width.
function model(cal) {
  const unc = cal.uncertainty || {};
  // K is lower triangular: the zeros above its diagonal are exact, shown without an interval.
  fillMatrix($("#result-K"), cal.model.K, unc.K && unc.K.map((row, i) => row.map((v, j) => (j > i ? null : v))));
  fillMatrix($("#result-o"), column(cal.model.o), column(unc.o));
}

// Finish: the fit of the poses so far, from the least number of them.
function bind(state, ctx) {
  $("#free-finish").addEventListener("click", () => { if (canFinish(state)) ctx.solve(); });
}

export const freeView = { ...VIEW_DEFAULTS, capture, model, bind };

export default freeView; // the module the server's protocol table names (wizard.js imports it by that name)
