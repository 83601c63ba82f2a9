// The model in the form the person applies, f = M (m − o), per sensor (GET …/{id}/use, the server's
// correction: the exporters' M and o), then how the model as fitted relates to it, so that the
// numbers of the details, the JSON and the C header are the same numbers.
import { getUse } from "./api.js";
import { fillMatrix, column } from "./figures.js";
import { kindOf } from "./result_kinds.js";
import { TABLES } from "./tables.js";
import { el } from "./dom.js";

const UNIT_WORDS = TABLES.unitWords; // each unit in words (app/words.py)


function matrix(id, rows) {
  const table = el("table", null, { class: "matrix", id });
  fillMatrix(table, rows);
  return table;
}

// The correction of `cal` into `box` (read with `token`); the relation line into `fittedNote` when given.
export async function showCorrection(box, cal, token = null, fittedNote = null) {
  // how the model as fitted relates to the correction, by model type (the result classes' AS_FITTED)
  if (fittedNote) fittedNote.textContent = TABLES.asFitted[cal.model.type] || "";
  if (!kindOf(cal).correction) { box.replaceChildren(); box.hidden = true; return; }
  let use;
  try { use = await getUse(cal.id, token); } catch (err) {
    box.replaceChildren(el("p", `The correction could not be read: ${err.message}`, { class: "bad" }));
    return;
  }
  const parts = [el("h3", "The correction you apply: f = M (m − o)")];
  for (const [sensor, c] of Object.entries(use.corrections)) {
    const unitIn = UNIT_WORDS[c.input_unit] || c.input_unit || "";
    const unitOut = UNIT_WORDS[c.output_unit] || c.output_unit || "";
    const row = el("div", null, { class: "row" });
    const mBox = el("div", null,
      { class: "scroll", tabindex: "0", role: "region", "aria-label": `M of the ${sensor}` });
    mBox.append(el("h4", `M (${unitOut} per ${unitIn})`), matrix(`correction-${sensor}-M`, c.M));
    const oBox = el("div", null,
      { class: "scroll", tabindex: "0", role: "region", "aria-label": `o of the ${sensor}` });
    oBox.append(el("h4", `o (${unitIn})`), matrix(`correction-${sensor}-o`, column(c.o)));
    row.append(mBox, oBox);
    if (Object.keys(use.corrections).length > 1) parts.push(el("h4", TABLES.sensorWords[sensor] || sensor));
    parts.push(row);
  }
  parts.push(el("p", `The JSON file's correction and the C header's ${Object.values(use.functions).join(", ")} hold `
    + "these numbers.", { class: "hint" }));
  box.replaceChildren(...parts);
  box.hidden = false;
}
