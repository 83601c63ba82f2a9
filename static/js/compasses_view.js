// A flight log's compasses side by side in its result (app/workflows/flight_compasses.py): each compass's heading
// error before and after, how it is mounted, the power's pull, whether it agrees with the first compass as the
// firmware's pre-arm check asks, and the one thing to do with it; the pairs' figures below.

import { formatNumber } from "./readings.js";
import { $, cell } from "./dom.js";

const HEADS = ["Compass", "Heading error (firmware's → trical's)", "Mounted", "Pull of the power",
  "Agrees with the first", "What to do"];

const degrees = (v) => (v === null || v === undefined ? "—" : `${formatNumber(v, 1)}°`);

function mounted(row) {
  if (!row.orientation) return "not found";
  const left = row.orientation_left_deg;
  if (left === null || left <= 5) return row.orientation;
  return `${row.orientation}, ${formatNumber(left, 0)}° left (unresolved)`;
}

function pulled(row) {
  const p = row.pull;
  if (!p) return "—";
  const sure = p.determined ? "" : " (not determined)";
  const top = `${formatNumber(p.at_top_deg, 0)}° at the top ${row.power_kind}`;
  return `${formatNumber(p.per_unit, 2)} ${p.unit}: ${top}${sure}`;
}

const AGREES = { true: "yes", false: "no: inconsistent", null: "— (the first)" };

export function showCompasses(cal) {
  const flight = cal.flight || {};
  const rows = flight.compasses || [];
  $("#result-compasses").hidden = !rows.length;
  $("#result-compasses-table tbody").replaceChildren(...rows.map((row) => {
    const tr = document.createElement("tr");
    const asked = row.instance === flight.instance ? " (this result)" : "";
    tr.append(cell("td", `${row.instance}${asked}`),
      cell("td", `${degrees(row.before_deg)} → ${degrees(row.after_deg)}`),
      cell("td", row.measures ? mounted(row) : "does not measure"), cell("td", pulled(row)),
      cell("td", AGREES[String(row.consistent ?? null)]), cell("td", row.action));
    [...tr.cells].forEach((td, k) => { td.dataset.label = HEADS[k]; });
    return tr;
  }));
  $("#result-compasses-checks").textContent = (flight.consistency || []).map((c) =>
    `Compass ${c.pair[1]} against ${c.pair[0]}: ${formatNumber(c.xyz_angle_deg, 0)}° apart, `
    + `${formatNumber(c.xy_angle_deg, 0)}° horizontally, ${formatNumber(c.xy_length_diff_ut, 1)} µT horizontal `
    + `difference (${c.consistent ? "within" : "beyond"} ArduPilot's pre-arm limits: 90°, 60°, 20 µT).`).join(" ");
}
