// The lines a board prints over a serial port or a Bluetooth UART, read as readings (pure, no DOM).
//
// Formats, recognised from the first lines or chosen:
// - "raw": MotionCal's and Adafruit SensorLab's `Raw:ax,ay,az,gx,gy,gz,mx,my,mz`, nine integer counts
//   at MotionCal's fixed scales (the server's tables: 1/8192 g, 1/16 °/s, 0.1 µT a count);
// - "uni": their `Uni:` lines, the same nine values in m/s², rad/s and µT (Adafruit's Unified Sensor units);
// - "csv": a header line naming the columns as trical's log readers know them (ax, acc_x, aX (g), gX,
//   mag_x, Timestamp, time_ms …), then rows of numbers separated by commas, semicolons, tabs or spaces;
// - "bare": rows of 3, 6 or 9 numbers (accelerometer, then gyroscope, then magnetometer), optionally
//   after a leading time (4, 7 or 10 numbers).
// Lines end in CR, LF or CRLF. Lines that are not readings (boot text, a second header) are skipped and
// counted; the last of them is kept to show.
//
// A reading is {t (the board's time in ms, or null), acc, gyr, mag (arrays or null)} in the units of
// `units` (the line's own: `Raw:` counts are scaled here). The accelerometer's unit of csv and bare lines
// is decided later, from the data at rest (accUnitAtRest), as the log readers do: a header's "(g)" is
// often wrong.

import { TABLES } from "./tables.js";

const B = TABLES.board;
export const FORMAT_WORDS = {
  raw: "MotionCal Raw: lines (counts at MotionCal's scales)",
  uni: "Uni: lines (m/s², rad/s, µT)",
  csv: "CSV with a header line",
  bare: "numbers in columns",
};
export const UNIT_WORDS = { ...TABLES.unitWords, unknown: "unknown" }; // each unit in words (app/words.py)

// Splits a stream of text into lines at CR, LF or CRLF (a CRLF split across two chunks is one end).
export class LineSplitter {
  constructor() { this.rest = ""; this.afterCR = false; }

  push(text) {
    let s = text;
    if (this.afterCR && s.startsWith("\n")) s = s.slice(1);
    this.afterCR = false;
    const parts = (this.rest + s).split(/\r\n|\r|\n/);
    this.rest = parts.pop();
    if (this.rest === "" && s.endsWith("\r")) this.afterCR = true;
    return parts;
  }
}

const NUMBER = /^[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?$/;
const isNumber = (s) => NUMBER.test(s);

function splitFields(line) {
  const text = line.trim();
  for (const d of [",", ";", "\t"]) if (text.includes(d)) return text.split(d).map((f) => f.trim());
  return text.split(/\s+/);
}

function numbers(fields) {
  if (!fields.length || !fields.every(isNumber)) return null;
  return fields.map(Number);
}

// The column names of trical's log readers (app/io/readers/generic_csv.py), as patterns.
const AXIS = "[ _.\\-]?\\(?([xyz])\\)?(?:[ _]?axis)?";
const UNIT = "(?:\\s*[\\(\\[]([^\\)\\]]*)[\\)\\]])?";
const COLUMN = {
  acc: new RegExp(`^(?:acc|accel|accelerometer|acceleration|a)?${AXIS}${UNIT}$`),
  gyr: new RegExp(`^(?:gyr|gyro|gyroscope|g|angular[ _]velocity|rotation[ _]rate|w)${AXIS}${UNIT}$`),
  mag: new RegExp(`^(?:mag|magn|magnetometer|magnetic[ _]field|m|b)${AXIS}${UNIT}$`),
};
const TIME = /^(?:t|time|timestamp|times|elapsed|millis|micros)(?:[ _]?(s|sec|ms|us))?(?:\s*[([]([^)\]]*)[)\]])?$/;
const UNIT_ALIASES = { "m/s^2": "m/s^2", "m/s2": "m/s^2", "m/s²": "m/s^2", g: "g", "rad/s": "rad/s", "deg/s": "deg/s",
  "°/s": "deg/s", dps: "deg/s", ut: "uT", "µt": "uT", "μt": "uT", nt: "nT", raw: "raw", lsb: "raw", counts: "raw" };
const TIME_MS = { s: 1000, sec: 1000, ms: 1, us: 0.001, "µs": 0.001 };

function headerUnit(text, sensor) {
  if (!text) return null;
  const key = text.trim().toLowerCase().replace(/\s+/g, "");
  if (sensor === "mag" && ["g", "gauss", "ga"].includes(key)) return "gauss";
  return UNIT_ALIASES[key] || null;
}

// A header line as {columns: {t, acc: [i,j,k], gyr, mag}, units, timeMs}, or null when it names no
// accelerometer, gyroscope or magnetometer triple.
export function readHeader(line) {
  const names = splitFields(line).map((n) => n.replace(/^"|"$/g, "").trim().toLowerCase());
  if (names.some(isNumber)) return null;
  const columns = { t: null, acc: null, gyr: null, mag: null };
  const units = { acc: null, gyr: null, mag: null };
  let timeMs = null;
  const found = { acc: {}, gyr: {}, mag: {} };
  names.forEach((name, i) => {
    const time = TIME.exec(name);
    if (time && columns.t === null) {
      columns.t = i;
      const named = name === "millis" ? "ms" : name === "micros" ? "us" : "";
      const unit = (time[2] || time[1] || named || "").toLowerCase();
      timeMs = TIME_MS[unit] ?? null;
      return;
    }
    for (const sensor of ["acc", "gyr", "mag"]) {
      const m = COLUMN[sensor].exec(name);
      if (m && found[sensor][m[1]] === undefined) {
        found[sensor][m[1]] = i;
        units[sensor] = units[sensor] || headerUnit(m[2], sensor);
        return;
      }
    }
  });
  for (const sensor of ["acc", "gyr", "mag"]) {
    const f = found[sensor];
    if (["x", "y", "z"].every((a) => f[a] !== undefined)) columns[sensor] = [f.x, f.y, f.z];
  }
  if (!columns.acc && !columns.gyr && !columns.mag) return null;
  return { columns, units, timeMs, width: names.length };
}

// The format a line shows by itself: "raw", "uni", "csv" (a header), "bare" (numbers), or null.
export function sniff(line) {
  const text = line.trim();
  if (text.startsWith(B.raw.prefix)) return "raw";
  if (text.startsWith(B.uni.prefix)) return "uni";
  const values = numbers(splitFields(text));
  if (values && [3, 4, 6, 7, 9, 10].includes(values.length)) return "bare";
  if (readHeader(text)) return "csv";
  return null;
}

const scale = (v, k) => v.map((x) => x * k);
const G_TO_MS2 = TABLES.gravity;

// Reads one board's lines; `format` "auto" (from the first line that shows one) or one of FORMAT_WORDS.
export class BoardLines {
  constructor(format = "auto") {
    this.chosen = format;
    this.format = format === "auto" ? null : format;
    this.header = null;
    this.layout = null; // bare: {time, width}
    this.lines = 0;
    this.readings = 0;
    this.skipped = 0;
    this.lastSkipped = null;
    this.units = { acc: null, gyr: null, mag: null };
    this.headerUnits = null;
    this.timeMs = null; // ms per unit of the time column, once known
    this.timeSteps = [];
    this.candidate = null; // {format, width, line}: a first line waiting for the next to agree
    this.held = []; // lines of numbers read once the format is known
  }

  // Whether the lines carry the board's time (a time column of a CSV header, or a leading number).
  get hasTime() {
    if (this.format === "csv") return Boolean(this.header && this.header.columns.t !== null);
    return this.format === "bare" && Boolean(this.layout && this.layout.time);
  }

  skip(line) {
    if (line.trim() === "") return null; // blank lines are neither readings nor noise
    this.skipped += 1;
    this.lastSkipped = line.length > 120 ? `${line.slice(0, 120)}…` : line;
    return null;
  }

  // One line → the readings it completes: none (skipped, or held until the next line confirms the
  // format), one, or two (a held line of numbers and this one).
  push(line) {
    this.lines += 1;
    if (!this.format && !this.recognise(line)) return [];
    if (this.format === "csv" && !this.header) { // the header line: the columns, no reading
      this.header = readHeader(line.trim());
      if (!this.header) { this.skip(line); return []; }
      this.headerUnits = { ...this.header.units };
      this.units = { acc: null, gyr: this.header.units.gyr, mag: this.header.units.mag };
      this.timeMs = this.header.timeMs;
      return [];
    }
    const out = [];
    for (const held of this.held.splice(0)) {
      const r = this.read(held);
      if (r) { this.readings += 1; out.push(r); } else this.skip(held);
    }
    const reading = this.read(line);
    if (!reading) { this.skip(line); return out; }
    this.readings += 1;
    out.push(reading);
    return out;
  }

  // The format from the first lines. Raw: and Uni: show theirs at once; a header or a line of numbers
  // is held until the next line agrees (a row as wide as the header, or as the numbers before it):
  // the first line after connecting is often the tail of one the board was printing.
  recognise(line) {
    let found = sniff(line);
    const held = this.candidate;
    // A row of numbers that no bare layout fits may still be one of a header's rows.
    if (!found && held && held.format === "csv" && numbers(splitFields(line.trim()))) found = "row";
    if (!found) {
      if (held) this.skip(held.line);
      this.candidate = null;
      this.skip(line);
      return false;
    }
    if (found === "raw" || found === "uni") {
      if (held) this.skip(held.line);
      this.candidate = null;
      this.format = found;
      return true;
    }
    const values = numbers(splitFields(line.trim()));
    const width = splitFields(line.trim()).length;
    if (held && values && width === held.width) {
      this.candidate = null;
      this.format = held.format;
      if (held.format === "csv") {
        this.header = readHeader(held.line.trim());
        this.headerUnits = { ...this.header.units };
        this.units = { acc: null, gyr: this.header.units.gyr, mag: this.header.units.mag };
        this.timeMs = this.header.timeMs;
      } else {
        this.held = [held.line];
      }
      return true;
    }
    if (held) this.skip(held.line);
    if (found === "row") { this.candidate = null; this.skip(line); return false; }
    this.candidate = { format: found, width, line };
    return false;
  }

  read(line) {
    const text = line.trim();
    if (this.format === "raw" || this.format === "uni") {
      const spec = B[this.format];
      if (!text.startsWith(spec.prefix)) return null;
      const values = numbers(splitFields(text.slice(spec.prefix.length)));
      if (!values || values.length !== spec.fields) return null;
      if (this.format === "raw") {
        this.units = { acc: "m/s^2", gyr: "deg/s", mag: "uT" };
        return { t: null, acc: scale(values.slice(0, 3), spec.acc_g_per_count * G_TO_MS2),
          gyr: scale(values.slice(3, 6), spec.gyr_dps_per_count),
          mag: scale(values.slice(6, 9), spec.mag_ut_per_count) };
      }
      this.units = { ...spec.units };
      return { t: null, acc: values.slice(0, 3), gyr: values.slice(3, 6), mag: values.slice(6, 9) };
    }
    if (this.format === "csv") {
      const values = numbers(splitFields(text));
      if (!values || values.length < this.header.width) return null;
      const c = this.header.columns;
      const pick = (idx) => (idx ? idx.map((i) => values[i]) : null);
      return { t: c.t === null ? null : this.time(values[c.t]), acc: pick(c.acc), gyr: pick(c.gyr), mag: pick(c.mag) };
    }
    const values = numbers(splitFields(text));
    if (!values) return null;
    if (!this.layout) {
      const n = values.length;
      if (![3, 4, 6, 7, 9, 10].includes(n)) return null;
      this.layout = { time: n % 3 === 1, width: n };
      this.units = { acc: null, gyr: null, mag: null };
    }
    if (values.length !== this.layout.width) return null;
    const v = this.layout.time ? values.slice(1) : values;
    const t = this.layout.time ? this.time(values[0]) : null;
    if (v.length === 3) return { t, acc: v, gyr: null, mag: null };
    return { t, acc: v.slice(0, 3), gyr: v.slice(3, 6), mag: v.length === 9 ? v.slice(6, 9) : null };
  }

  // The board's time in ms. Without a unit in the header: a time with decimals is in seconds; an
  // integer one in ms, or in µs when its steps are over 100 (no board prints readings 10 times a
  // second in ms and calls it a sensor log; micros() steps of a few thousand are common).
  time(value) {
    if (this.timeMs === null) {
      if (!Number.isInteger(value)) this.timeMs = 1000;
      else {
        if (this.timeLast !== undefined) this.timeSteps.push(value - this.timeLast);
        this.timeLast = value;
        if (this.timeSteps.length < 4) return null;
        const steps = [...this.timeSteps].sort((a, b) => a - b);
        this.timeMs = steps[steps.length >> 1] > 100 ? 0.001 : 1;
      }
    }
    return value * this.timeMs;
  }
}

// The accelerometer's unit from readings at rest (m/s², g), as the log readers decide it from the
// data: |a| near 9.8 is m/s², near 1 is g; anything else (counts of an unknown chip) is not decided.
export function accUnitAtRest(norm) {
  if (norm > 0.5 * G_TO_MS2 && norm < 1.5 * G_TO_MS2) return "m/s^2";
  if (norm > 0.5 && norm < 1.5) return "g";
  return null;
}

// The rates from the first burst end to the one nearest the middle and from there to the last agree within
// rateAgree: no end among them read late by a lagging reader (app.io.board.lines.StreamRate._halves_agree).
function halvesAgree(ends) {
  const middle = 0.5 * (ends[0][0] + ends[ends.length - 1][0]);
  const inner = ends.slice(1, -1);
  if (!inner.length) return false;
  const mid = inner.reduce((m, p) => (Math.abs(p[0] - middle) < Math.abs(m[0] - middle) ? p : m));
  const slope = (p, q) => (q[1] - p[1]) / (q[0] - p[0]);
  const a = slope(ends[0], mid), b = slope(mid, ends[ends.length - 1]);
  return Math.abs(a - b) <= B.rateAgree * 0.5 * (a + b);
}

// The board's rate from live lines without a time column: readings counted over their arrival, the twin
// of app/io/board/lines.py's StreamRate on the same constants (the server's tables). Each chunk is a point
// (arrival, readings so far); a burst ends at a point whose next chunk comes after at least half the
// longest step (a read that splits a burst brings its parts closer together), and when it ends every
// line printed until then has arrived. The rate is the readings counted between the end of the first
// burst and the end of the latest over the time between them, decided once those ends span rateMinS and
// rateSteps times the longest step of the last rateWindowS of arrivals (bursts of 1–2 s: after 3–4 bursts) and
// the rates over the span's halves agree (halvesAgree), else once the arrivals fill the window; or once the
// arrivals after the window's longest pause so decide alone, spanning rateSteps times that pause (a short
// pause is not waited out); then kept
// up to date. Never the step of one burst's arrival.
export class StreamRate {
  constructor(minS = B.rateMinS, steps = B.rateSteps, windowS = B.rateWindowS) {
    this.minS = minS;
    this.steps = steps;
    this.windowS = windowS;
    this.count = 0;
    this.longest = 0;
    this.points = []; // until decided: every arrival
    this.first = null; // [t, count] at the end of the first burst, once decided
    this.end = null; // and of the latest
    this.last = null; // [t, count] of the latest arrival
  }

  // A chunk bringing `readings` readings arrived at `t` (seconds, any origin).
  arrive(readings, t) {
    if (readings <= 0) return;
    this.count += readings;
    if (this.first !== null) { // decided: the latest burst's end moves on
      const step = t - this.last[0];
      this.longest = Math.max(this.longest, step);
      if (step >= 0.5 * this.longest) this.end = this.last;
    }
    this.last = [t, this.count];
    if (this.first === null) {
      this.points.push(this.last);
      // The longest step among the last windowS of arrivals: a pause of the reader is forgotten once it has left.
      this.points = this.points.filter((p) => p[0] >= t - this.windowS);
      const gaps = this.points.slice(1).map((p, i) => p[0] - this.points[i][0]);
      this.longest = Math.max(0, ...gaps);
      let decided = this.ends(this.points, gaps, t - this.points[0][0]);
      if (decided === null && gaps.length > 1) {
        // The arrivals since the window's longest pause (a page busy drawing as the board connected, a
        // host's hiccup) decide alone once they span what the whole window needs and their halves agree:
        // a short pause is not waited out for the whole window.
        const after = gaps.indexOf(this.longest) + 1;
        decided = this.ends(this.points.slice(after), gaps.slice(after), null, this.longest);
      }
      if (decided !== null) {
        [this.first, this.end, this.longest] = decided;
        this.points = [];
      }
    }
  }

  // The first and the latest burst end of `points` (`gaps` apart) and their longest step, if they decide the
  // rate: the ends span the needed time (for their longest step, or the `pause` before them) and the halves
  // agree, or (`full`: the arrivals' age) fill the window; else null.
  ends(points, gaps, full, pause = 0) {
    const longest = Math.max(0, ...gaps);
    const ends = points.filter((p, i) => i < gaps.length && gaps[i] >= 0.5 * longest);
    const needed = Math.max(this.minS, this.steps * Math.max(longest, pause));
    if (ends.length < 2 || ends[ends.length - 1][0] - ends[0][0] < needed) return null;
    if (halvesAgree(ends) || (full !== null && full >= this.windowS - longest)) {
      return [ends[0], ends[ends.length - 1], longest];
    }
    return null;
  }

  get neededS() { return Math.max(this.minS, this.steps * this.longest); }

  get spanS() { return this.first === null ? 0 : this.end[0] - this.first[0]; }

  // Readings per second, or null while undecided.
  get rateHz() {
    if (this.first === null) return null;
    return (this.end[1] - this.first[1]) / (this.end[0] - this.first[0]);
  }
}

// Converts a reading to the wizard's units: acc m/s², gyr °/s, mag µT (or as they are when unknown).
const GYR_TO_DEG_S = { "deg/s": 1, "rad/s": 180 / Math.PI };
const MAG_TO_UT = { uT: 1, nT: 0.001, gauss: 100 };
export function inWizardUnits(reading, units) {
  const acc = reading.acc && (units.acc === "g" ? scale(reading.acc, G_TO_MS2) : reading.acc);
  const gyr = reading.gyr && scale(reading.gyr, GYR_TO_DEG_S[units.gyr] ?? 1);
  const mag = reading.mag && scale(reading.mag, MAG_TO_UT[units.mag] ?? 1);
  return { acc, gyr, mag };
}
