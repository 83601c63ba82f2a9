// The start page: the only module here that touches the DOM.
import { createCalibration, uploadRecording } from "./api.js";
import { columnSparkSvg, columnsField, headerColumns, logPlotSvg, tableColumns } from "./log_plot.js";
import { flightFields, showFlightLog } from "./flight_log.js";
import { formatNumber, parseReadings } from "./readings.js";
import { hideCalibration, showCalibration } from "./result_view.js";
import { showNotes } from "./notes.js";
import { TABLES } from "./tables.js";
import { $, cell, counted } from "./dom.js";


// A phone with motion sensors sees Start; a desktop sees the phone page's QR code and address and the
// upload (a desktop browser has DeviceMotionEvent too, but no touch screen and no motion).
const phone = "DeviceMotionEvent" in window && matchMedia("(pointer: coarse)").matches;
document.documentElement.dataset.device = phone ? "phone" : "desktop";
// A board needs the Web Serial API (or Web Bluetooth): elsewhere the card says which browsers have it.
const boardReach = "serial" in navigator || "bluetooth" in navigator;
$("#board-flows").hidden = !boardReach;
$("#board-no-serial").hidden = boardReach;
const status = $("#status");
let recordingId = null;
let lastUpload = null; // the form data of the upload on show, to read the file again with other units
let shown = null; // the calibration on show

function say(text) { status.textContent = text; }


function showResult(cal) {
  showCalibration(cal);
  // The calibration's own address: a reload, a bookmark or the history finds it again (/c/{id}).
  history.pushState({ calibration: cal.id }, "", `/c/${encodeURIComponent(cal.id)}`);
  shown = cal;
  $("#result").focus({ preventScroll: true });
  $("#result").scrollIntoView({ block: "start" }); // the verdict at the top of the screen
  say(`Calibration done. ${cal.verdict.words}`);
}

// --- upload: the log, its plot and still segments, then the calibration at once (method auto) ---

const ROLES = [["", "not used"], ["time_s", "time (s)"], ["time_ms", "time (ms)"], ["acc_x", "accelerometer x"],
  ["acc_y", "accelerometer y"], ["acc_z", "accelerometer z"], ["gyr_x", "gyroscope x"], ["gyr_y", "gyroscope y"],
  ["gyr_z", "gyroscope z"], ["mag_x", "magnetometer x"], ["mag_y", "magnetometer y"], ["mag_z", "magnetometer z"]];
const ROLE_WORDS = { ...Object.fromEntries(ROLES.filter(([role]) => role)), "-": "not used" };
// How to tell the sensors apart by what they read (app/io/readers/columns.py decides the same way).
const COLUMN_HINT = "At rest an accelerometer's three columns read about 1 g together (9.8 m/s²) and turn from "
  + "pose to pose; a gyroscope's read about 0 at every rest; a magnetometer's read the Earth's field (25–65 µT, "
  + "or counts) as it turns; a time column rises on every line.";
let action = 0; // the latest action: an older answer is never shown over a newer one

// A message next to the control it is about (and heard through the status region).
function note(sel, text, bad = false) {
  const p = $(sel);
  p.hidden = !text;
  p.textContent = text || "";
  p.classList.toggle("bad", bad);
  if (text) say(text);
}

// Nothing of an earlier upload or calibration stays on show.
function clearOutput() {
  shown = null;
  recordingId = null;
  $("#segments").hidden = true;
  $("#segments-table tbody").replaceChildren();
  $("#log-plot").replaceChildren();
  hideCalibration();
  if (location.pathname !== "/") history.replaceState(null, "", "/");
  $("#columns-map").hidden = true;
  $("#units").hidden = true;
  note("#upload-msg", "");
  note("#segments-msg", "");
  $("#segments-notes").hidden = true;
}

// The device the person named, so that the history lists its calibrations together.
function withDevice(payload) {
  const device = $("#log-device").value.trim();
  return device ? { ...payload, device_id: device } : payload;
}

async function calibrate(payload, doing, refused, where) {
  const mine = ++action;
  note(where, doing);
  try {
    const cal = await createCalibration(withDevice(payload));
    if (mine !== action) return;
    note(where, "");
    showResult(cal);
  } catch (err) {
    if (mine !== action) return;
    offerOptions(err.asks || []);
    note(where, `${refused}: ${err.message.replace(/\.$/, "")}.`, true);
  }
}

// One unit menu per sensor the file has, set to the unit trical read from the data (or "as the data show",
// sending none, for a file refused before its units were read), and the parts (app.io.readers.chips) that
// turn that sensor's counts into g, °/s or µT; the reader's warnings above.
function showUnits(rec) {
  const chips = (rec.read_with && rec.read_with.chip ? rec.read_with.chip.split(",") : []).map((c) => c.trim());
  const { units, chips: parts } = TABLES.units;
  const sensors = TABLES.sensorWords;
  $("#units-warnings").replaceChildren(...(rec.warnings || []).map((w) => cell("li", w)));
  $("#units-list").replaceChildren(...rec.channels.filter((s) => units[s]).flatMap((sensor) => {
    const unit = cell("label", `${sensors[sensor]} unit`);
    unit.htmlFor = `unit-${sensor}`;
    const menu = document.createElement("select");
    menu.id = `unit-${sensor}`;
    menu.dataset.sensor = sensor;
    if (!rec.units[sensor]) { const o = cell("option", "as the data show"); o.value = ""; menu.append(o); }
    menu.append(...units[sensor].map(([value, words]) => {
      const o = cell("option", words);
      o.value = value;
      return o;
    }));
    menu.value = rec.units[sensor] || "";
    unit.append(menu);
    const part = cell("label", `${sensors[sensor]} part, for counts`);
    part.htmlFor = `chip-${sensor}`;
    const chip = document.createElement("select");
    chip.id = `chip-${sensor}`;
    chip.dataset.sensor = sensor;
    const none = cell("option", "none");
    none.value = "";
    chip.append(none, ...parts[sensor].map(([name, words]) => {
      const o = cell("option", words);
      o.value = name;
      return o;
    }));
    chip.value = chips.find((c) => parts[sensor].some(([name]) => name === c)) || "";
    chip.addEventListener("change", () => { if (chip.value) menu.value = "raw"; });
    part.append(chip);
    return [unit, part];
  }));
  $("#units").hidden = false;
}

// The action of each calibration a recording supports (app/workflows/supports.py): the button that runs it (its
// data-runs, in the template: the compass's and the flight's read their place and instance), else a request of
// its method alone.
const runs = (method) => [...document.querySelectorAll("#segments button[data-runs]")]
  .find((b) => b.dataset.runs === method);
function runSupport(method) {
  const button = runs(method);
  if (button) button.click();
  else calibrate({ method, recording_id: recordingId }, "Calibrating…", "Calibration refused", "#segments-msg");
}

const calibrationWords = (method) => {
  const words = TABLES.calibrationWords[method] || method;
  return words[0].toUpperCase() + words.slice(1);
};

// What the recording holds and can do, said first: each calibration it supports with its reason and the button
// that runs it (the page's own, moved into its line; a flight's stays in the flight's card); one it cannot run yet
// says what it lacks, as a fact of the data (never in red), and nothing runs it unless the person asks.
function showSupports(rec) {
  const found = rec.supports || [];
  $("#supports").hidden = !found.length;
  const home = $("#support-buttons");
  for (const button of document.querySelectorAll("#segments button[data-runs]:not([data-shown-by])")) {
    button.hidden = true;
    home.append(button); // back where it waits, before this recording's lines are drawn
  }
  $("#supports-list").replaceChildren(...found.map((s) => {
    const li = cell("li", "");
    li.dataset.method = s.method;
    li.dataset.ready = String(s.ready);
    li.append(cell("strong", calibrationWords(s.method)), ` — ${s.why}. `);
    // Its own button, ready or not (the person may try what the data seem to lack: a refusal then says why);
    // one without a button of its own gets one where it is ready.
    const own = runs(s.method);
    if (own && !own.dataset.shownBy) {
      own.hidden = false;
      li.append(own);
    } else if (s.ready) {
      const go = cell("button", `Run ${TABLES.calibrationWords[s.method] || s.method}`);
      go.type = "button";
      go.className = "secondary";
      go.addEventListener("click", () => runSupport(s.method));
      li.append(go);
    }
    return li;
  }));
  return found.find((s) => s.ready) || null;
}

function showSegments(rec) {
  // A turn of the magnetometer alone has no still segments to calibrate an accelerometer from.
  const still = rec.channels.includes("acc");
  // A flight log's compass takes the place and date from its GPS; the fields are there for a log without one
  // (or whose fix has no GPS time: the day is typed there).
  const flightCompass = Boolean(rec.flight && !(rec.flight.fix && rec.flight.fix.date)
    && rec.flight.instances.some((i) => i.sensor === "mag"));
  $("#compass-place").hidden = rec.flight ? !flightCompass : !rec.channels.includes("mag");
  if (!$("#place-date").value) $("#place-date").value = new Date().toISOString().slice(0, 10);
  $("#segments").hidden = false;
  $("#log-plot").innerHTML = rec.overview ? logPlotSvg(rec.overview, rec.segments, rec.sampling_rate_hz, {
    sensor: (TABLES.sensorWords[rec.overview.sensor] || TABLES.sensorWords.acc).toLowerCase(),
    unit: rec.overview.unit ? TABLES.unitWords[rec.overview.unit] || rec.overview.unit : "",
  }) : "";
  // Seconds, one decimal, always; a log without a sampling rate counts samples.
  const sec = (i) => (rec.sampling_rate_hz ? (i / rec.sampling_rate_hz).toFixed(1) : String(i));
  // A recording made of several files (one per pose): each segment names its file.
  const parts = rec.parts || [];
  $("#segments-table .file-col").hidden = !parts.length;
  $("#segments-table tbody").replaceChildren(...rec.segments.map((s) => {
    const tr = document.createElement("tr");
    tr.append(cell("td", String(s.index + 1)), cell("td", `${sec(s.start)}–${sec(s.end)}`), cell("td", s.up ?? "—"),
      cell("td", s.acc_mean.map((v) => formatNumber(v, 3)).join(", ")));
    if (parts.length) tr.append(cell("td", s.source ?? "—"));
    return tr;
  }));
  $("#segments-table").hidden = !still;
  const rate = rec.sampling_rate_hz
    ? `${formatNumber(rec.duration_s, 1)} s at ${formatNumber(rec.sampling_rate_hz, 1)} Hz`
    : `${rec.n_samples} samples (no time column)`;
  const files = parts.length ? ` of ${parts.length} files` : "";
  const names = rec.channels.map((c) => `the ${(TABLES.sensorWords[c] || c).toLowerCase()}`);
  const sensors = names.length > 1 ? `${names.slice(0, -1).join(", ")} and ${names.at(-1)}` : names.join("");
  const first = showSupports(rec);
  const segs = still ? `, with ${counted(rec.segments.length, "still segment")}` : "";
  const goal = $("#log-goal").value;
  const running = goal ? `${TABLES.calibrationWords[goal] || goal}, as you chose`
    : first && (TABLES.calibrationWords[first.method] || first.method);
  $("#supports-holds").textContent = `It holds ${sensors}: ${rate}${files}${segs}.`
    + (running ? ` Running ${running}.` : "");
  note("#segments-msg", running ? ""
    : "Nothing this recording supports is ready yet: each line above says what it lacks.");
  if (!running) offerOptions((rec.supports || []).flatMap((s) => s.asks || [])); // the options they ask for
  // What the reading of the files noticed (a file whose name contradicts its pose, one without a rest; which
  // file gave which sensor when they are one per sensor, merged onto one clock).
  const several = parts.length > 0 || $("#log-file").files.length > 1;
  showNotes($("#segments-notes"), several ? rec.notes : []);
}

const HEADER_HINT = "trical did not recognise this file's header. What does each column hold? Leave the others "
  + "as “not used”, then upload again.";

// The file's header was not recognised: a control per column to say what it holds.
async function offerColumnMap(file) {
  const head = await file.slice(0, 4096).text();
  if (/^\s*[[{]/.test(head)) return false; // JSON: its keys are its columns, and the refusal says what it holds
  const names = headerColumns(head.split(/\r?\n/)[0] || "");
  if (names.length < 2 || names.every((n) => Number.isFinite(Number(n)))) return false; // no header to map
  $("#columns-map-list").dataset.mode = "map";
  $("#columns-map-hint").textContent = `${HEADER_HINT} ${COLUMN_HINT}`;
  $("#columns-map-list").replaceChildren(...names.map((name, i) => {
    const label = cell("label", name);
    label.htmlFor = `map-${i}`;
    const select = document.createElement("select");
    select.id = `map-${i}`;
    select.dataset.column = name;
    select.append(...ROLES.map(([role, words]) => { const o = cell("option", words); o.value = role; return o; }));
    label.append(select);
    return label;
  }));
  $("#columns-map").hidden = false;
  return true;
}

// The data let the columns be read more than one way: each reading as a choice, over the first lines
// and a small plot of each column; the one chosen is sent as `columns`.
async function offerCandidates(answer, file, several = false) {
  const columns = tableColumns(await file.slice(0, 65536).text());
  const list = $("#columns-map-list");
  list.dataset.mode = "candidates";
  const preview = cell("pre", (answer.preview || []).join("\n"));
  preview.className = "columns-preview";
  const plots = document.createElement("div");
  plots.className = "columns-plots";
  // Each column on its own scale, its range under it, and what the reading chosen makes of it: the sensor's
  // axis and the units it may be in (whole numbers: counts). What it reads tells the sensor (COLUMN_HINT).
  const captions = columns.map((values, i) => {
    const fig = document.createElement("figure");
    fig.innerHTML = columnSparkSvg(values);
    const caption = cell("figcaption", "");
    fig.append(caption);
    plots.append(fig);
    return (role) => {
      const finite = values.filter(Number.isFinite);
      const range = finite.length ? `${formatNumber(Math.min(...finite), 3)} to ${formatNumber(Math.max(...finite), 3)}`
        : "";
      const sensor = (role || "").split("_")[0];
      const whole = finite.length && finite.every(Number.isInteger);
      const units = whole ? ["counts"]
        : (TABLES.units.units[sensor] || []).filter(([u]) => u !== "raw").map(([, w]) => w);
      const what = role && role !== "-" ? `, ${ROLE_WORDS[role] || role}` : "";
      caption.textContent = `column ${i + 1}${what}: ${range}${units.length ? ` (${units.join(" or ")})` : ""}`;
    };
  });
  const describe = (value) => value.split(",").forEach((role, k) => captions[k]?.(role));
  const choices = (answer.candidates || []).map((c, i) => {
    const label = document.createElement("label");
    label.className = "columns-choice";
    const radio = document.createElement("input");
    radio.type = "radio";
    radio.name = "columns-candidate";
    radio.value = c.columns;
    radio.checked = i === 0;
    radio.addEventListener("change", () => describe(c.columns));
    const columns = c.columns.split(",").map((n, k) => `${k + 1}: ${ROLE_WORDS[n] || n}`).join(", ");
    label.append(radio, ` ${c.sensors} — ${columns}`);
    return label;
  });
  list.replaceChildren(preview, plots, ...choices);
  describe(answer.candidates?.[0]?.columns || "");
  list.dataset.file = several ? file.name : "";
  const which = several ? `The columns of ${file.name} (one of the files)` : "The columns of this file";
  $("#columns-map-hint").textContent = `${which} can be read more than one way. Which do they `
    + `hold? Its first lines and a plot of each column are below. ${COLUMN_HINT} Choose, then upload again.`;
  $("#columns-map").hidden = false;
}

// The columns chosen so far for each of several files uploaded together (one choice per file), sent as
// `columns` NAME=COLUMNS;NAME=COLUMNS (app.io.readers.columns_of_file).
let fileColumns = {};
const perFileColumns = () => Object.entries(fileColumns).map(([name, cols]) => `${name}=${cols}`).join(";");

async function upload(data) {
  clearOutput();
  const mine = ++action;
  note("#upload-msg", "Uploading…");
  let rec;
  try {
    rec = await uploadRecording(data);
  } catch (err) {
    if (mine !== action) return;
    const files = data.getAll("file");
    const asked = files.find((f) => f.name === err.body?.file) || files[0];
    const several = files.length > 1;
    if (err.code === "columns_ambiguous" && (several ? !(asked.name in fileColumns) : !data.get("columns"))) {
      await offerCandidates(err.body || {}, asked, several);
      note("#upload-msg", several ? `Say which column is which in ${asked.name}, below.`
        : "Say which column is which, below.");
      return;
    }
    const mapped = err.code === "unreadable_log" && err.asks.includes("columns") && !data.get("columns")
      && await offerColumnMap(data.get("file"));
    if (!mapped) offerControls(err.asks, data);
    note("#upload-msg", mapped ? "Say which column is which, below." : `Upload refused: ${err.message}`, !mapped);
    return;
  }
  if (mine !== action) return;
  note("#upload-msg", "");
  recordingId = rec.id;
  lastUpload = data;
  // A flight controller's log states its units (the menus would be refused): its sensors instead.
  if (!showFlightLog(rec)) showUnits(rec);
  showSegments(rec);
  // The calibration the person chose, else the first the recording supports that is ready; nothing else is tried.
  const goal = $("#log-goal").value;
  const first = goal ? { method: goal } : (rec.supports || []).find((s) => s.ready);
  if (first) runSupport(first.method);
}

// A refusal that asks for a unit, a part or an option of the upload: their controls, to read the file again.
const UNIT_ASKS = ["acc_unit", "gyr_unit", "mag_unit", "chip", "lsb_per_g"];
const OPTION_ASKS = { sampling_rate_hz: "#opt-rate", columns: "#opt-columns", sign: "#opt-sign" };
function offerControls(asks, data) {
  if (asks.some((a) => UNIT_ASKS.includes(a))) {
    lastUpload = data;
    showUnits({ channels: Object.keys(TABLES.units.units), units: {}, warnings: [], read_with: null });
  }
  offerOptions(asks);
}

// The upload's options a refusal asks for (a sampling rate for the noise …), open to read the file again.
function offerOptions(asks) {
  const options = asks.filter((a) => a in OPTION_ASKS);
  for (const a of options) $(OPTION_ASKS[a]).hidden = false;
  if (options.length) { $("#options").hidden = false; $("#options").open = true; }
}

function uploadData() {
  const data = new FormData($("#upload-form"));
  for (const key of ["sampling_rate_hz", "columns", "sign"]) if (!data.get(key)) data.delete(key);
  return data;
}

// The upload's options, each only when it applies to the file chosen (its first line read here): the rate
// when no column names a time, the column names when the file has no header row, the sign when the
// header is iOS Core Motion's (its sign is read from it, app/io/readers/ios_sign.py) or absent.
const TIME_NAME = new RegExp("^(?:t|time|timestamp|times|elapsed|seconds_elapsed|time_elapsed|millis|micros)"
  + "(?:[ _]?(?:s|sec|ms|us|ns))?(?:\\s*[([].*[)\\]])?$", "i");
const CORE_MOTION = /acceleration[xyz]\(g\)|useracceleration|gravity[ _]?[xyz]/i;
function optionsFor(firstLine) {
  const names = headerColumns(firstLine);
  const header = names.length > 0 && !names.every((n) => /^[+-]?(\d+\.?\d*|\.\d+)(e[+-]?\d+)?$/i.test(n));
  return { rate: !header || !names.some((n) => TIME_NAME.test(n.trim())), columns: !header,
    sign: !header || names.some((n) => CORE_MOTION.test(n)) };
}

async function showOptions() {
  const file = $("#log-file").files[0];
  let apply = { rate: false, columns: false, sign: false };
  if (file && /\.(ulg|bin)$/i.test(file.name)) {
    // a flight controller's log states its rate, units and columns: nothing to give
  } else if (file && /\.json$/i.test(file.name)) {
    // a JSON array of samples: its keys name the columns (app/io/readers/json_samples.py); the rate is asked
    // for unless a key names a time
    const head = await file.slice(0, 4096).text();
    const timeKey = [...head.matchAll(/"([^"]{1,40})"\s*:/g)].some((m) => TIME_NAME.test(m[1]));
    apply = { rate: !timeKey, columns: false, sign: false };
  } else if (file && !/\.zip$/i.test(file.name)) {
    const head = await file.slice(0, 4096).text();
    const first = head.split(/\r\n|\r|\n/).find((line) => line.trim() && !line.trim().startsWith("#")) || "";
    apply = optionsFor(first);
  } else if (file) apply = { rate: true, columns: false, sign: false };
  $("#opt-rate").hidden = !apply.rate;
  $("#opt-columns").hidden = !apply.columns;
  $("#opt-sign").hidden = !apply.sign;
  const words = [apply.rate && "sampling rate", apply.columns && "column names", apply.sign && "sign"].filter(Boolean);
  $("#options-summary").textContent = `Options: ${words.join(", ")}`;
  $("#options").hidden = !words.length;
  for (const [key, input] of [["rate", "#log-rate"], ["columns", "#log-columns"], ["sign", "#log-sign"]]) {
    if (!apply[key]) $(input).value = ""; // an option that does not apply is not sent
  }
}
$("#log-file").addEventListener("change", showOptions);
// The drone's door: its first step is the log itself, chosen with the upload's own file chooser.
$("#drone-log").addEventListener("click", () => {
  $("#upload-form").scrollIntoView();
  $("#log-file").click();
});

// What the person may ask of any recording (the method table's methods that read one), in the page's words.
$("#log-goal").append(...TABLES.recordingMethods.map((method) => {
  const o = cell("option", TABLES.calibrationWords[method] || method);
  o.value = method;
  return o;
}));

$("#upload-form").addEventListener("submit", (event) => {
  event.preventDefault();
  fileColumns = {}; // a new upload: no file's columns chosen yet
  upload(uploadData());
});

$("#columns-map-go").addEventListener("click", () => {
  const data = uploadData();
  if ($("#columns-map-list").dataset.mode === "candidates") {
    const chosen = document.querySelector("#columns-map-list input[name=columns-candidate]:checked");
    if (!chosen) return;
    const file = $("#columns-map-list").dataset.file;
    if (file) fileColumns[file] = chosen.value; // one of several files: its choice beside the others'
    data.set("columns", file ? perFileColumns() : chosen.value);
  } else {
    const mapping = Object.fromEntries([...document.querySelectorAll("#columns-map-list select")]
      .map((s) => [s.dataset.column, s.value]));
    data.set("columns", columnsField(mapping));
  }
  upload(data);
});

// The same file (and columns) again, with the unit or the part chosen for each sensor: a part sends
// its chip and no unit (the chip says the readings are counts).
$("#units-go").addEventListener("click", () => {
  if (!lastUpload) return;
  const data = new FormData();
  for (const [key, value] of lastUpload.entries()) {
    if (!["acc_unit", "gyr_unit", "mag_unit", "chip"].includes(key)) data.append(key, value);
  }
  const chips = [];
  for (const menu of document.querySelectorAll("#units-list select[id^=unit-]")) {
    const chip = $(`#chip-${menu.dataset.sensor}`).value;
    if (chip) chips.push(chip);
    else if (menu.value) data.set(`${menu.dataset.sensor}_unit`, menu.value);
  }
  if (chips.length) data.set("chip", chips.join(","));
  upload(data);
});

$("#calibrate-recording").addEventListener("click", () => calibrate({ method: "auto", recording_id: recordingId },
  "Calibrating…", "Calibration refused", "#segments-msg"));

$("#noise-recording").addEventListener("click", () => calibrate({ method: "noise", recording_id: recordingId },
  "Computing the Allan deviation…", "Noise characterisation refused", "#segments-msg"));

// The same flight log again, reading the IMU and the compass chosen.
$("#flight-go").addEventListener("click", () => {
  if (!lastUpload) return;
  const data = new FormData();
  for (const [key, value] of lastUpload.entries()) {
    if (!["instance", "mag_instance"].includes(key)) data.append(key, value);
  }
  for (const [key, value] of Object.entries(flightFields())) data.set(key, value);
  upload(data);
});

// A flight's compass: the place and date of the log's GPS fix, or those typed (the field's strength is not
// used: the model's field is turned by the attitude, its direction as much as its strength).
$("#flight-compass").addEventListener("click", () => {
  let place;
  try { place = compassPlace(); } catch (err) {
    note("#flight-compass-msg", `Not calibrated: ${err.message}.`, true);
    return;
  }
  delete place.field_ut;
  // A log whose fix has no GPS time: the day typed under Where and when, with the fix's place.
  if (!place.date && !$("#compass-place").hidden && $("#place-date").value) place.date = $("#place-date").value;
  // The attitude judged by and the part of the log fitted: the flying part by default, the seconds typed, if any.
  const part = { window: $("#flight-window").value };
  if ($("#flight-attitude").value) part.attitude = $("#flight-attitude").value;
  for (const [key, id] of [["from_s", "#flight-from"], ["to_s", "#flight-to"]]) {
    if ($(id).value !== "") part[key] = Number($(id).value);
  }
  calibrate(
    { method: "compass_flight", recording_id: recordingId, mag_instance: Number($("#flight-mag").value), ...place,
      ...part },
    "Fitting the compass against the flight's attitude and the Earth's field…", "Compass calibration refused",
    "#flight-compass-msg");
});

$("#temperature-recording").addEventListener("click", () => calibrate(
  { method: "temperature", recording_id: recordingId },
  "Fitting the offsets against temperature…", "Temperature calibration refused", "#segments-msg"));

// The compass's place and date (the IGRF field there, app/geomag.py) or the field's strength, as the
// request's latitude_deg, longitude_deg, date and field_ut; a half-given place is named, not sent.
function compassPlace() {
  const number = (sel) => ($(sel).value.trim() === "" ? null : Number($(sel).value));
  const lat = number("#place-lat");
  const lon = number("#place-lon");
  const field = number("#place-field");
  const out = {};
  if ((lat === null) !== (lon === null)) throw new Error("give both the latitude and the longitude, or neither");
  if (lat !== null) {
    if (!(Math.abs(lat) <= 90)) throw new Error("the latitude is from −90° (south pole) to 90° (north pole)");
    if (!(Math.abs(lon) <= 180)) throw new Error("the longitude is from −180° to 180°, east positive");
    Object.assign(out, { latitude_deg: lat, longitude_deg: lon });
    if ($("#place-date").value) out.date = $("#place-date").value;
  }
  if (field !== null) {
    if (!(field > 0 && field <= 1000)) {
      throw new Error("the field's strength is in µT, between 0 and 1000 (the Earth's: 22–67 µT)");
    }
    out.field_ut = field;
  }
  return out;
}

$("#compass-recording").addEventListener("click", () => {
  let place;
  try { place = compassPlace(); } catch (err) {
    note("#place-msg", `Not calibrated: ${err.message}.`, true);
    return;
  }
  note("#place-msg", "");
  calibrate({ method: "magnetometer", recording_id: recordingId, ...place },
    "Calibrating the compass…", "Compass calibration refused", "#segments-msg");
});

// Use my location: the Geolocation API, where the browser has it and the person allows it.
$("#place-here").addEventListener("click", () => {
  if (!navigator.geolocation) {
    note("#place-msg", "This browser gives no location: type the latitude and longitude.", true);
    return;
  }
  note("#place-msg", "Asking this browser for its location…");
  navigator.geolocation.getCurrentPosition((pos) => {
    $("#place-lat").value = pos.coords.latitude.toFixed(4);
    $("#place-lon").value = pos.coords.longitude.toFixed(4);
    if (!$("#place-date").value) $("#place-date").value = new Date().toISOString().slice(0, 10);
    note("#place-msg", `Location ${pos.coords.latitude.toFixed(2)}°, ${pos.coords.longitude.toFixed(2)}°: `
      + "if the turn was made elsewhere, type its place instead.");
  }, (err) => note("#place-msg", `No location (${err.message || "refused"}): type the latitude and longitude.`, true),
  { timeout: 15000, maximumAge: 600000 });
});

$("#fill").addEventListener("click", () => {
  try {
    for (const { up, mean } of parseReadings($("#paste").value)) {
      const row = document.querySelector(`#readings-table tr[data-up="${up}"]`);
      row.querySelectorAll("input").forEach((input, i) => { input.value = String(mean[i]); });
    }
    note("#fill-msg", "Table filled from the pasted lines.");
  } catch (err) {
    note("#fill-msg", `Could not read the pasted lines: ${err.message}`, true);
  }
});

$("#readings-form").addEventListener("submit", (event) => {
  event.preventDefault();
  const readings = [...document.querySelectorAll("#readings-table tbody tr")].map((tr) => ({
    up: tr.dataset.up,
    mean: [...tr.querySelectorAll("input")].map((input) => Number(input.value)),
  }));
  const payload = { method: "six_position", readings, unit: $("#r-unit").value };
  const g = $("#r-gravity").value;
  if (g) payload.gravity = Number(g);
  $("#result").hidden = true;
  calibrate(payload, "Calibrating…", "Calibration refused", "#paste-msg");
});
