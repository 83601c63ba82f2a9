// A flight controller's log on the upload page (PX4 ULog, ArduPilot DataFlash): fills its section with the sensor
// instances it holds (app.io.flight.instances, the recording's `flight`), the IMU and compass read, the
// temperature over the log, and whether the range allows a temperature calibration; the plot itself is a pure
// function.

import { formatNumber } from "./readings.js";
import { TABLES } from "./tables.js";
import { $, cell } from "./dom.js";

// The sensors' words: app/calibration/shared/headlines.py.
const sensorWords = (sensor) => (TABLES.sensorWords[sensor] || sensor).toLowerCase();
const TEMPERATURE_SPAN_C = TABLES.flightLog.temperatureMinSpanC; // the temperature method's least span (its gate), °C

const celsius = (v) => Number(v).toFixed(1); // temperatures alike in the table, the caption and the plot

// The decimals a span of temperature needs to show (0.02 °C, not 0.0 °C): one, or as many as its first digit.
export function spanDecimals(span) {
  return span >= 0.1 || !(span > 0) ? 1 : Math.min(3, Math.ceil(-Math.log10(span)));
}


function esc(text) {
  return String(text).replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" }[c]));
}

// The temperature over the log as a small SVG line (each overview bin's mean), or "" without one.
export function temperaturePlotSvg(overview) {
  const temps = overview && overview.temperature_c;
  const t = overview && (overview.t_s ?? overview.start);
  if (!temps || !t || !temps.some((v) => v !== null)) return "";
  const W = 320, H = 90, LEFT = 34, RIGHT = 6, TOP = 10, BOTTOM = 20;
  const values = temps.filter((v) => v !== null);
  const lo = Math.min(...values), hi = Math.max(...values);
  const pad = (hi - lo) * 0.1 || 0.5;
  const end = t[t.length - 1] || 1;
  const x = (sec) => LEFT + (sec / end) * (W - LEFT - RIGHT);
  const y = (v) => TOP + (1 - (v - (lo - pad)) / (hi - lo + 2 * pad)) * (H - TOP - BOTTOM);
  const points = temps.map((v, i) => (v === null ? null : `${x(t[i]).toFixed(1)},${y(v).toFixed(1)}`)).filter(Boolean);
  const unit = overview.t_s ? "s" : "samples";
  return `<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 ${W} ${H}" role="img" `
    + `aria-label="${esc(`The sensor's temperature over the log, ${celsius(lo)} to ${celsius(hi)} °C`)}">`
    + `<polyline points="${points.join(" ")}" fill="none" stroke="#c62828" stroke-width="1.5" />`
    + `<text x="2" y="${y(hi) + 4}" font-size="10">${esc(celsius(hi))}</text>`
    + `<text x="2" y="${y(lo) + 4}" font-size="10">${esc(celsius(lo))}</text>`
    + `<text x="${W - RIGHT}" y="${H - 4}" font-size="10" text-anchor="end">`
    + `${esc(`${formatNumber(end, 0)} ${unit}`)}</text>`
    + `<text x="${LEFT}" y="${H - 4}" font-size="10">°C</text></svg>`;
}

// A cell whose name may wrap after each underscore ("sensor_/combined"), its text unchanged.
function breakable(words) {
  const td = cell("td");
  String(words).split("_").forEach((part, k, all) => {
    td.append(part + (k < all.length - 1 ? "_" : ""));
    if (k < all.length - 1) td.append(document.createElement("wbr"));
  });
  return td;
}

function option(value, words, chosen) {
  const o = cell("option", words);
  o.value = String(value);
  o.selected = chosen;
  return o;
}

// Fill the flight section from a recording; hidden for any other log. Returns whether it is one.
export function showFlightLog(rec) {
  const box = $("#flight");
  const flight = rec.flight;
  box.hidden = !flight;
  if (!flight) return false;
  const heads = [...document.querySelectorAll("#flight-table thead th")].map((th) => th.textContent);
  const rows = flight.instances.map((i) => {
    const tr = document.createElement("tr");
    const range = i.temperature_min_c === null || i.temperature_min_c === undefined ? "—"
      : `${celsius(i.temperature_min_c)}–${celsius(i.temperature_max_c)}`;
    const device = i.device ? `${i.device.bus_type} ${i.device.bus}, address ${i.device.address}` : "—";
    tr.append(cell("td", sensorWords(i.sensor)), cell("td", String(i.instance)), breakable(i.source),
      cell("td", String(i.n_samples)), cell("td", i.sampling_rate_hz ? formatNumber(i.sampling_rate_hz, 1) : "—"),
      cell("td", range), cell("td", device));
    // Each cell named by its column, for a phone's block of lines (the table's header is hidden there).
    [...tr.cells].forEach((td, k) => { td.dataset.label = heads[k]; });
    return tr;
  });
  $("#flight-table tbody").replaceChildren(...rows);
  const imus = flight.instances.filter((i) => i.sensor === "acc");
  const mags = flight.instances.filter((i) => i.sensor === "mag");
  const chosenImu = flight.imu || {};
  $("#flight-imu").replaceChildren(...imus.map((i) => option(i.source === "sensor_combined" ? "" : i.instance,
    `${i.source} ${i.instance}`, i.instance === chosenImu.instance && i.source === chosenImu.source)));
  $("#flight-mag").replaceChildren(...mags.map((i) => option(i.instance, `${i.source} ${i.instance}`,
    flight.mag && i.instance === flight.mag.instance)));
  $("#flight-imu-label").hidden = !imus.length;
  $("#flight-mag-label").hidden = !mags.length;
  $("#flight-compass-box").hidden = !mags.length;
  $("#flight-compass-msg").textContent = "";
  $("#flight-temp-plot").innerHTML = temperaturePlotSvg(rec.overview);
  const temp = rec.temperature_c;
  const span = temp && temp.min !== null ? temp.max - temp.min : null;
  const digits = spanDecimals(span); // a small span with the digits that show it, its ends alike
  $("#flight-temp").textContent = !imus.length
    ? "The log holds no IMU samples: its compass is read alone (log the IMU for the other calibrations)."
    : span === null
    ? "The IMU read logs no temperature."
    : `The IMU read went from ${Number(temp.min).toFixed(digits)} to ${Number(temp.max).toFixed(digits)} °C`
      + (span >= TEMPERATURE_SPAN_C ? ": enough for a temperature calibration."
        : ` (a span of ${span.toFixed(digits)} °C): a temperature calibration needs ${TEMPERATURE_SPAN_C} °C `
          + "or more — log a cold start, the board left still while it warms up.");
  return true; // the temperature's button: in what the recording supports (index.js), where it is ready
}

// The upload's form fields for the sensors chosen in the flight section.
export function flightFields() {
  const fields = {};
  const imu = $("#flight-imu").value;
  if (imu !== "" && !$("#flight-imu-label").hidden) fields.instance = imu;
  if (!$("#flight-mag-label").hidden && $("#flight-mag").value !== "") fields.mag_instance = $("#flight-mag").value;
  return fields;
}
