// A board as the wizard's sensor source: the port (Web Serial or Web Bluetooth's Nordic UART), and
// the lines it prints turned into timed samples (no DOM here; board_panel.js shows them).
//
// The port is used as the Web Serial API specifies it, and nothing else: navigator.serial.requestPort()
// (from the person's click), port.open({baudRate}), port.readable's reader for the bytes in,
// port.writable's writer for the bytes out, port.close(). Over Bluetooth: the Nordic UART Service
// (the server's tables), whose TX characteristic notifies the lines and whose RX one takes writes.
//
// Times, on the page's clock (performance.now(), as a devicemotion event's): a board's own time
// column when its lines have one (in ms, shifted to the first reading's arrival, a reset of the
// board's clock rebased so that time goes on increasing); otherwise the board's rate counted over several
// seconds of arrivals (StreamRate, board_lines.js), each reading one interval of it after the one before,
// from the first chunk's arrival: lines that reach the page in bursts (a USB-serial bridge's buffer, a
// loaded computer) are neither motion nor a gap. Until the rate is decided the readings wait (the live
// view shows them at once). The rate shown is the board's: readings over the span of the board's time,
// or the counted one.

import { TABLES } from "./tables.js";
import { BoardLines, LineSplitter, StreamRate, accUnitAtRest, inWizardUnits } from "./board_lines.js";

const B = TABLES.board;
export const BAUD_RATES = B.baudRates;
export const DEFAULT_BAUD = B.defaultBaud;
export const SILENCE_MS = B.silenceS * 1000;
export const STALL_MS = B.stallS * 1000; // a capture without progress this long says what it waits for
const BLE_CHUNK = 20; // bytes a Bluetooth LE write carries at the default MTU

export const hasSerial = () => typeof navigator !== "undefined" && "serial" in navigator;
export const hasBluetooth = () => typeof navigator !== "undefined" && "bluetooth" in navigator;

// The port: bytes in as text (onText(chunk, arrivalMs)), bytes out (write), close.
export class BoardPort {
  constructor({ onText, onError }) {
    this.onText = onText;
    this.onError = onError;
    this.kind = null; // "usb" | "bluetooth"
    this.port = null;
    this.reader = null;
    this.rx = null;
    this.closing = false;
    this.decoder = new TextDecoder();
  }

  // Must be called straight from a click: requestPort() needs the person's gesture.
  async openSerial(baudRate) {
    const port = await navigator.serial.requestPort();
    await port.open({ baudRate });
    this.port = port;
    this.kind = "usb";
    this.baudRate = baudRate;
    this.readLoop();
  }

  async readLoop() {
    while (this.port && this.port.readable && !this.closing) {
      this.reader = this.port.readable.getReader();
      try {
        for (;;) {
          const { value, done } = await this.reader.read();
          if (done) break;
          if (value && value.length) this.onText(this.decoder.decode(value, { stream: true }), performance.now());
        }
      } catch (err) {
        if (!this.closing) this.onError(err);
        break;
      } finally {
        this.reader.releaseLock();
        this.reader = null;
      }
    }
  }

  async openBluetooth() {
    const uart = B.nordicUart;
    const device = await navigator.bluetooth.requestDevice({ filters: [{ services: [uart.service] }] });
    const server = await device.gatt.connect();
    const service = await server.getPrimaryService(uart.service);
    const tx = await service.getCharacteristic(uart.tx);
    this.rx = await service.getCharacteristic(uart.rx);
    tx.addEventListener("characteristicvaluechanged", (event) => {
      const view = event.target.value;
      this.onText(this.decoder.decode(new Uint8Array(view.buffer, view.byteOffset, view.byteLength), { stream: true }),
        performance.now());
    });
    await tx.startNotifications();
    device.addEventListener("gattserverdisconnected", () => {
      if (!this.closing) this.onError(new Error("the board disconnected"));
    });
    this.device = device;
    this.kind = "bluetooth";
  }

  async write(bytes) {
    if (this.kind === "bluetooth") {
      for (let i = 0; i < bytes.length; i += BLE_CHUNK) {
        const part = bytes.slice(i, i + BLE_CHUNK);
        if (this.rx.writeValueWithResponse) await this.rx.writeValueWithResponse(part);
        else await this.rx.writeValue(part);
      }
      return;
    }
    const writer = this.port.writable.getWriter();
    try {
      await writer.write(bytes);
    } finally {
      writer.releaseLock();
    }
  }

  async close() {
    this.closing = true;
    if (this.kind === "bluetooth") {
      if (this.device && this.device.gatt.connected) this.device.gatt.disconnect();
      return;
    }
    try { if (this.reader) await this.reader.cancel(); } catch { /* closed already */ }
    try { if (this.port) await this.port.close(); } catch { /* closed already */ }
  }
}

// The board's lines as samples in the wizard's units: {t (ms), acc (m/s²), gyr (°/s), mag (µT or as
// printed)}. onSample gets each one once the accelerometer's unit is known (or at once, for a board
// without one); onLive every reading, decided or not, for the live view.
export class BoardSource {
  constructor({ format = "auto", onSample = () => {}, onLive = () => {}, needAcc = true } = {}) {
    this.lines = new BoardLines(format);
    this.splitter = new LineSplitter();
    this.onSample = onSample;
    this.onLive = onLive;
    this.needAcc = needAcc;
    this.units = null; // {acc, gyr, mag} once decided
    this.unitProblem = null; // the norm at rest when it is neither g nor m/s²
    this.rest = []; // recent accelerometer readings, to decide the unit at rest
    this.firstArrival = null;
    this.stream = new StreamRate();
    this.waiting = []; // readings waiting for the rate (lines without the board's time)
    this.count = 0;
    this.boardFirst = null; // the first board time and the last, ms
    this.boardLast = null;
    this.offset = 0; // added to the board's time after it went back (a reset)
    this.lastT = null;
    this.lastChunk = null;
  }

  get format() { return this.lines.format; }

  // Readings per second: the board's (see the module's comment), or null while too few.
  rate() {
    if (this.boardFirst !== null && this.boardLast > this.boardFirst && this.count > 2) {
      return (this.count - 1) / ((this.boardLast - this.boardFirst) / 1000);
    }
    return this.stream.rateHz;
  }

  text(chunk, now) {
    this.lastChunk = now;
    const readings = [];
    for (const line of this.splitter.push(chunk)) readings.push(...this.lines.push(line));
    if (!readings.length) return;
    const timed = this.lines.hasTime;
    readings.forEach((r, i) => {
      let t;
      if (timed) {
        if (r.t === null) return; // the time column's unit is not known yet
        if (this.lastT === null) this.offset = now - r.t; // on the page's clock from the first reading
        t = r.t + this.offset;
        if (this.lastT !== null && t <= this.lastT) { // the board restarted its clock
          this.offset += this.lastT - t + (this.step || 10);
          t = r.t + this.offset;
        }
        if (this.lastT !== null) this.step = t - this.lastT;
        if (this.boardFirst === null) this.boardFirst = t;
        this.boardLast = t;
      } else {
        this.waiting.push(r);
        return;
      }
      this.lastT = t;
      this.count += 1;
      this.take({ ...r, t });
    });
    if (this.firstArrival === null) this.firstArrival = now;
    if (timed) return;
    this.stream.arrive(readings.length, now / 1000);
    const rate = this.stream.rateHz;
    if (rate === null) { // the live view shows them at once, on their arrival
      for (const r of readings) this.onLive({ t: now, ...inWizardUnits(r, this.liveUnits()) }, r);
      return;
    }
    for (const r of this.waiting.splice(0)) {
      const t = this.lastT === null ? this.firstArrival : this.lastT + 1000 / rate;
      this.lastT = t;
      this.count += 1;
      this.take({ ...r, t });
    }
  }

  liveUnits() {
    const units = this.units || { ...this.lines.units, acc: this.lines.units.acc || "m/s^2" };
    return { ...units, gyr: units.gyr || "deg/s" };
  }

  take(r) {
    if (!this.units) this.decideUnits(r);
    const sample = { t: r.t, ...inWizardUnits(r, this.liveUnits()) };
    this.onLive(sample, r);
    if (this.units) this.onSample(sample);
  }

  // The accelerometer's unit from half a second at rest (Raw: and Uni: lines carry theirs); a
  // board without an accelerometer, or a flow that needs none, is decided at once.
  decideUnits(r) {
    const known = this.lines.units;
    const gyr = known.gyr || (r.gyr ? "deg/s" : null);
    if (known.acc || !r.acc || !this.needAcc) {
      this.units = { acc: known.acc || (r.acc ? "m/s^2" : null), gyr, mag: known.mag || (r.mag ? "unknown" : null) };
      return;
    }
    this.rest.push(r);
    while (this.rest.length && this.rest[0].t < r.t - 500) this.rest.shift();
    if (this.rest.length < 5 || r.t - this.rest[0].t < 400) return;
    const n = this.rest.length;
    const mean = [0, 1, 2].map((i) => this.rest.reduce((s, x) => s + x.acc[i], 0) / n);
    const norm = Math.hypot(...mean);
    const spread = Math.max(...[0, 1, 2].map(
      (i) => Math.sqrt(this.rest.reduce((s, x) => s + (x.acc[i] - mean[i]) ** 2, 0) / n)));
    if (!(spread < 0.02 * norm)) return; // not at rest
    const acc = accUnitAtRest(norm);
    if (!acc) { this.unitProblem = norm; return; }
    this.unitProblem = null;
    this.units = { acc, gyr, mag: known.mag || (r.mag ? "unknown" : null) };
  }
}

// What a board's capture that made no progress for STALL_MS waits for and what it sees, from the capture
// machine (motion.js) and its last output {still, spread, gyr, pose, angleDeg}: the poses asked, the
// stillness against the machine's thresholds, and what to do (the terminal's twin: app/cli/board.py).
const BOARD_POSES = TABLES.sources.board.poseShort;

export function stallWords(machine, out) {
  const o = machine.o || TABLES.capture;
  const left = typeof machine.remaining === "function" ? machine.remaining() : [];
  // A pose in the board's words, its code beside it (the board's page and `trical capture` name both).
  const named = (pose) => (BOARD_POSES[pose] ? `${BOARD_POSES[pose]} (${pose})` : pose);
  const asked = left.length ? `Waiting for ${left.map(named).join(" or ")}` : "Waiting for a new pose";
  let seen;
  if (!out.still) {
    const turning = out.gyr != null && out.gyr >= o.gyrLow && out.spread < o.spreadLow;
    seen = turning ? `the board turns: ${out.gyr.toFixed(1)} °/s > ${o.gyrLow}; hold it still in a pose asked`
      : `the board moves: spread ${out.spread.toFixed(2)} m/s² > ${o.spreadLow}; hold it still in a pose asked`;
  } else if (out.angleDeg > o.maxAngleDeg) {
    seen = `the board is still, ${Math.round(out.angleDeg)}° from ${named(out.pose)}; set it square on a side`;
  } else if (left.length && !left.includes(out.pose)) {
    seen = `the board is still, ${named(out.pose)}, captured already; turn it to a pose asked`;
  } else {
    seen = `the board is still, ${named(out.pose)}; keep it so`;
  }
  return `No capture for ${STALL_MS / 1000} s. ${asked}: ${seen}.`;
}
