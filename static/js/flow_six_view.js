// The six-position flow's render hooks (wizard.js calls them from its one render): the six poses'
// list (done, to do, redo), the next pose pictured before the phone is in one, and the affine model.
import { donePoses } from "./flow_six.js";
import { column, fillMatrix } from "./figures.js";
import { nextPose } from "./poses.js";
import { VIEW_DEFAULTS } from "./wizard_state.js";
import { $, setHidden, setText } from "./dom.js";

function capture(s) {
  const done = new Set(donePoses(s));
  for (const li of document.querySelectorAll("#poses li")) {
    const pose = li.dataset.pose;
    let shown = done.has(pose) ? "done" : "todo";
    if (s.machine && s.machine.redo.has(pose)) shown = "redo";
    if (li.dataset.state !== shown) li.dataset.state = shown;
    li.classList.toggle("current", pose === s.view.current);
    setText(li.querySelector(".pose-state"), { done: "done ✓", todo: "to do", redo: "redo" }[shown]);
    setHidden(li.querySelector(".redo"), shown !== "done");
  }
}

// Before the phone is in a pose, the next pose, large, in words: the person sees where to turn it before
// turning it (flow_six.js names the same pose in the instruction).
const next = (s) => (s.session ? nextPose(s.machine.remaining()) : null);

// The affine model m = X a + y, each ± its 95 % half-width.
function model(cal) {
  const unc = cal.uncertainty || {};
  fillMatrix($("#result-X"), cal.model.X, unc.X);
  fillMatrix($("#result-y"), column(cal.model.y), column(unc.y));
}

export const sixView = { ...VIEW_DEFAULTS, capture, next, model };

export default sixView; // the module the server's protocol table names (wizard.js imports it by that name)
