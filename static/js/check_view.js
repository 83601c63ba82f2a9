// What a check and a comparison of calibrations look like on a page (pure drawing: the server decides,
// app/calibration/check.py and compare.py): the verdict in words, each sensor's error now and a fresh
// calibration's with their intervals, what drifted; and two calibrations' differences, parameter by parameter,
// the real ones marked, with their effect as a tilt or a heading.
import { TABLES } from "./tables.js";
import { cell, el } from "./dom.js";

const fixed = (v, digits = 2) => (v == null ? "—" : Number(v).toFixed(digits));
const angle = (deg) => (deg == null ? "" : ` (${fixed(deg)}°)`);

function interval(figure) {
  if (!figure) return "—";
  const range = `95 % ${fixed(figure.low)}–${fixed(figure.high)}`;
  return `${fixed(figure.value)} ${figure.unit}, ${range}${angle(figure.value_deg)}`;
}

// The check's answer: its verdict first, then a block per sensor.
export function checkBlock(out) {
  const box = el("div", null, { class: "check-result", "data-verdict": out.verdict });
  box.append(el("p", `Verdict: ${TABLES.checkVerdicts[out.verdict] || out.verdict}.`, { class: "check-verdict" }));
  for (const s of out.sensors) {
    const words = TABLES.sensorWords[s.sensor] || s.sensor;
    box.append(el("h3", `${words}: ${TABLES.checkVerdicts[s.verdict] || s.verdict}`));
    const list = el("ul");
    if (s.current) list.append(el("li", `Now: ${interval(s.current)}`));
    if (s.fresh) list.append(el("li", `A fresh calibration: ${interval(s.fresh)}`));
    if (s.drifted.length) list.append(el("li", `Drifted: ${s.drifted.join(", ")}`));
    for (const reason of s.reasons) list.append(el("li", reason, { class: "hint" }));
    box.append(list);
  }
  return box;
}

// Two calibrations' differences: one table per sensor.
export function comparisonBlock(out) {
  const box = el("div", null, { class: "comparison" });
  for (const s of out.sensors) {
    const words = TABLES.sensorWords[s.sensor] || s.sensor;
    const effect = s.effect_deg == null ? ""
      : `, a ${s.effect_kind} off by up to ${fixed(s.effect_deg)}°`;
    box.append(el("h3", words), el("p", `At most ${fixed(s.effect, 3)} ${s.effect_unit} apart${effect}.`));
    const table = el("table", null, { class: "comparison-table" });
    const head = el("tr");
    for (const title of ["Parameter", "Difference", "95 % interval", "Real"]) {
      const th = cell("th", title);
      th.scope = "col";
      head.append(th);
    }
    table.append(el("thead"));
    table.tHead.append(head);
    const body = el("tbody");
    for (const d of s.differences) {
      const tr = el("tr", null, { "data-real": String(d.real) });
      const name = cell("th", d.axis ? `${d.parameter} ${d.axis}` : d.parameter);
      name.scope = "row";
      tr.append(name, cell("td", `${fixed(d.difference, 3)} ${d.unit}`),
        cell("td", d.half_width == null ? "none" : `± ${fixed(d.half_width, 3)}`),
        cell("td", d.real == null ? "—" : d.real ? "yes" : "no"));
      body.append(tr);
    }
    table.append(body);
    const region = el("div", null,
      { class: "scroll", tabindex: "0", role: "region", "aria-label": `${words}: differences` });
    region.append(table);
    box.append(region);
  }
  if (out.missing.length) {
    box.append(el("p", `Only one of them corrects: ${out.missing.join(", ")}.`, { class: "hint" }));
  }
  return box;
}
