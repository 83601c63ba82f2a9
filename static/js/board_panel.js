// The board card of the wizard pages (templates/_board.html, _board_send.html): connect a board over
// USB or Bluetooth, see its readings arrive, and send a calibration back to it. The samples go to the
// page's own capture engine through onSample; this module only shows the board.
import { fetchExport, listCalibrations } from "./api.js";
import { BAUD_RATES, BoardPort, BoardSource, DEFAULT_BAUD, SILENCE_MS, hasBluetooth, hasSerial } from "./board.js";
import { FORMAT_WORDS, UNIT_WORDS } from "./board_lines.js";
import { formatNumber } from "./readings.js";
import { TABLES } from "./tables.js";
import { apiKey, sessionTokens } from "./tokens.js";
import { kindOf } from "./result_kinds.js";
import { preferSource } from "./use_calibration.js";
import { $, dateTimeWords, el } from "./dom.js";

const PLOT_MS = 5000;
const ACK_MS = 2000; // how long the board's reply to a packet is waited for
const DRAW_MS = 200;
const PACKET = TABLES.board.packet;


// The accelerometer's last seconds as three lines (x red, y green, z blue), an SVG string.
export function plotSvg(samples, gravity = TABLES.gravity) {
  const W = 300;
  const H = 100;
  if (samples.length < 2) {
    return `<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 ${W} ${H}" role="img" `
      + `aria-label="No readings yet"></svg>`;
  }
  const t1 = samples[samples.length - 1].t;
  const t0 = t1 - PLOT_MS;
  let top = gravity * 1.2;
  for (const s of samples) for (const v of s.acc) top = Math.max(top, Math.abs(v) * 1.05);
  const x = (t) => (((t - t0) / PLOT_MS) * W).toFixed(1);
  const y = (v) => ((H / 2) * (1 - v / top)).toFixed(1);
  const lines = ["#c62828", "#2e7d32", "#1565c0"].map((colour, i) => {
    const points = samples.map((s) => `${x(s.t)},${y(s.acc[i])}`).join(" ");
    return `<polyline points="${points}" fill="none" stroke="${colour}" stroke-width="1.5" />`;
  });
  return `<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 ${W} ${H}" role="img" `
    + `aria-label="The accelerometer's x, y and z over the last 5 seconds">`
    + `<line x1="0" y1="${H / 2}" x2="${W}" y2="${H / 2}" stroke="#bbb" />${lines.join("")}</svg>`;
}

// What a calibration carries of the packet's two parts: the accelerometer's (with the gyroscope's) offsets,
// and the compass's hard iron, soft iron and field, as the server's kind of it says (a compass calibration), or
// a model with a magnetometer's part (a cube's).
export function packetParts(cal) {
  const model = (cal && cal.model) || {};
  const parts = kindOf({ model }).packet;
  const compass = parts.includes("mag") || Object.keys(model).some((k) => k !== "type" && /mag/i.test(k));
  return { acc: parts.includes("acc"), compass };
}

// The packet's CRC-16, as app/io/exports/motioncal_packet.py computes it (the server's tables give its polynomial
// and start).
export function crc16(bytes, crc = PACKET.crc.start) {
  for (const byte of bytes) {
    crc ^= byte;
    for (let k = 0; k < 8; k += 1) crc = crc & 1 ? (crc >>> 1) ^ PACKET.crc.polynomial : crc >>> 1;
  }
  return crc;
}

// The packet `base` (the server's, for this calibration) with the compass floats of `compass` (the server's packet
// of a compass calibration) in place of its own, and the CRC made again over the result.
export function withCompass(base, compass) {
  const out = new Uint8Array(base);
  const [from, to] = PACKET.magFloats.map((i) => PACKET.signature.length + 4 * i);
  out.set(compass.subarray(from, to), from);
  const crc = crc16(out.subarray(0, PACKET.bytes - 2));
  out[PACKET.bytes - 2] = crc & 0xff;
  out[PACKET.bytes - 1] = crc >> 8;
  return out;
}

// The device's latest compass calibration this browser can read ({cal, token}), or null: each owner's list
// (the API key or none, each wizard session's token) of that device, newest first, as the history reads them.
export async function latestCompass(device) {
  if (!device) return null;
  const owners = [...new Set([apiKey(), ...sessionTokens()])];
  const lists = await Promise.all(owners.map((token) => listCalibrations(token, device)
    .then(({ items }) => items.map((cal) => ({ cal, token }))).catch(() => [])));
  const found = lists.flat().filter(({ cal }) => cal.ok && !packetParts(cal).acc && packetParts(cal).compass);
  found.sort((a, b) => (a.cal.created_at < b.cal.created_at ? 1 : -1));
  return found[0] || null;
}

// "Copy the sketch": the file as served, on the clipboard; where the browser does not allow it (an http page on
// the LAN), the person is pointed to the file's link beside the button.
async function copySketch(button) {
  const msg = $("#sketch-msg");
  const name = button.dataset.url.split("/").pop();
  try {
    const text = await (await fetch(button.dataset.url)).text();
    await navigator.clipboard.writeText(text);
    msg.textContent = `${name} copied: paste it into a new sketch of the Arduino IDE.`;
  } catch {
    msg.textContent = `This browser did not let the page copy: open ${name} (the link beside the button) and copy it.`;
  }
  msg.hidden = false;
}

export class BoardPanel {
  // needAcc: the flow needs the accelerometer (its unit is checked at rest before samples flow);
  // onConnect(kind): the board is connected (from the click's promise); onSample(sample): a sample in
  // the wizard's units; onClose(reason): the port closed or failed.
  constructor({ needAcc = true, onConnect = () => {}, onSample = () => {}, onClose = () => {} } = {}) {
    this.needAcc = needAcc;
    this.onConnect = onConnect;
    this.onSample = onSample;
    this.onClose = onClose;
    this.port = null;
    this.source = null;
    this.recent = [];
    this.latest = null;
    this.drawnAt = 0;
    this.watch = null;
    this.openedAt = null;
    this.setup();
  }

  get connected() { return Boolean(this.port); }

  setup() {
    const card = $("#board");
    if (!card) return; // only a board's pages have the card (source=board); elsewhere it says why it cannot read one
    card.hidden = false;
    const usb = hasSerial();
    const ble = hasBluetooth();
    $("#board-usb").hidden = !usb;
    $("#board-ble").hidden = !ble;
    $("#board-none").hidden = usb || ble;
    $("#board-connect").hidden = !(usb || ble);
    const baud = $("#board-baud");
    if (!baud.options.length) {
      for (const rate of BAUD_RATES) baud.append(el("option", String(rate), { value: String(rate) }));
      baud.value = String(DEFAULT_BAUD);
    }
    $("#board-usb").addEventListener("click", () => this.connect("usb"));
    $("#board-ble").addEventListener("click", () => this.connect("bluetooth"));
    $("#board-close").addEventListener("click", () => this.close("You disconnected the board."));
    const send = $("#board-send");
    if (send) {  // two steps: what it replaces is confirmed before anything is written
      send.addEventListener("click", () => this.confirmSend(true));
      $("#board-send-cancel").addEventListener("click", () => this.confirmSend(false));
      $("#board-send-go").addEventListener("click", () => { this.confirmSend(false); this.send(); });
    }
    const include = $("#board-send-compass");
    if (include) include.addEventListener("change", () => this.describeSend());
    for (const button of document.querySelectorAll(".sketch-copy")) {
      button.addEventListener("click", () => copySketch(button));
    }
  }

  message(text) {
    const box = $("#board-msg");
    if (box.textContent !== (text || "")) box.textContent = text || "";
    box.hidden = !text;
  }

  // From the click: the browser's chooser first (it needs the gesture), then the port.
  async connect(kind) {
    if (this.port) return;
    const baud = Number($("#board-baud").value);
    const port = new BoardPort({
      onText: (chunk, now) => this.text(chunk, now),
      onError: (err) => this.close(`The board stopped: ${err.message}.`),
    });
    this.message(null);
    // The source first: a port may hand over bytes it buffered as soon as it opens.
    this.source = new BoardSource({ format: $("#board-format").value, needAcc: this.needAcc,
      onLive: (sample) => this.live(sample), onSample: (sample) => this.onSample(sample) });
    this.recent = [];
    this.openedAt = performance.now();
    try {
      if (kind === "usb") await port.openSerial(baud);
      else await port.openBluetooth();
    } catch (err) {
      const chosen = err && err.name === "NotFoundError";
      this.message(chosen ? "No board was chosen: connect it, then choose it in the browser's list."
        : `The ${kind === "usb" ? "port" : "board"} could not be opened: ${err.message}. `
          + "Close the serial monitor or any other program using it, and try again.");
      this.source = null;
      return;
    }
    this.port = port;
    this.baud = baud;
    preferSource("board"); // a board's calibration goes into its sketch: the C header first (app/web/uses.py)
    this.openedAt = performance.now();
    $("#board-baud").disabled = true;
    $("#board-format").disabled = true;
    $("#board-usb").disabled = true;
    $("#board-ble").disabled = true;
    $("#board-live").hidden = false;
    $("#board-live").dataset.kind = kind;
    $("#board-what").textContent = kind === "usb" ? `Connected at ${baud} baud: waiting for lines…`
      : "Connected over Bluetooth: waiting for lines…";
    this.watch = setInterval(() => this.check(), 250);
    this.showSend();
    this.onConnect(kind);
  }

  text(chunk, now) {
    if (!this.source) return;
    this.source.text(chunk, now);
    if (this.port) this.check();
  }

  // The problems said next to the control: nothing arrives, lines that are not readings, a unit at rest
  // that is neither g nor m/s².
  check() {
    const s = this.source;
    if (!s) return;
    const now = performance.now();
    const quiet = now - (s.lastChunk ?? this.openedAt);
    const where = this.port.kind === "usb" ? `at ${this.baud} baud` : "over Bluetooth";
    if (quiet >= SILENCE_MS) {
      this.message(`Nothing arrives ${where}: check the rate and that the board prints readings.`);
    } else if (s.lines.readings === 0 && s.lines.skipped > 0 && now - this.openedAt >= SILENCE_MS) {
      this.message(`The lines arriving are not readings: the last one is “${s.lines.lastSkipped}”. `
        + "Check the baud rate, "
        + "and that the board prints Raw: or Uni: lines, CSV with a header line, or 3, 6 or 9 numbers a line.");
    } else if (s.unitProblem !== null && !s.units) {
      this.message(`At rest the accelerometer reads ${formatNumber(s.unitProblem, 4)}: neither g (about 1) nor m/s² `
        + "(about 9.8). Print the readings in g or m/s² (Uni: lines, or divide counts by the chip's counts per g).");
    } else {
      this.message(null);
    }
    this.draw(now);
  }

  live(sample) {
    this.latest = sample;
    if (sample.acc) {
      this.recent.push(sample);
      while (this.recent.length && this.recent[0].t < sample.t - PLOT_MS) this.recent.shift();
    }
  }

  draw(now) {
    const s = this.source;
    if (!s || now - this.drawnAt < DRAW_MS) return;
    this.drawnAt = now;
    const box = $("#board-live");
    const rate = s.rate();
    box.dataset.format = s.format || "";
    box.dataset.readings = String(s.lines.readings);
    box.dataset.skipped = String(s.lines.skipped);
    box.dataset.rate = rate === null ? "" : rate.toFixed(2);
    box.dataset.accUnit = s.units ? s.units.acc || "" : "";
    if (!s.format) return;
    const units = s.units || s.lines.units;
    const said = [FORMAT_WORDS[s.format]];
    const accUnit = s.units ? s.units.acc : s.lines.units.acc;
    if (this.latest && this.latest.acc) {
      const how = s.lines.units.acc ? "" : " (from its reading at rest)";
      said.push(accUnit ? `accelerometer in ${UNIT_WORDS[accUnit]}${how}`
        : "accelerometer: keep the board still to check its unit");
    }
    if (this.latest && this.latest.gyr) {
      said.push(`gyroscope in ${UNIT_WORDS[units.gyr || "deg/s"]}${s.lines.units.gyr ? "" : " (assumed)"}`);
    }
    if (this.latest && this.latest.mag) {
      said.push(units.mag && units.mag !== "unknown" ? `magnetometer in ${UNIT_WORDS[units.mag]}`
        : "magnetometer in the unit it prints (no unit named)");
    }
    said.push(rate === null ? "measuring the rate" : `${rate.toFixed(1)} readings/s`);
    $("#board-what").textContent = `${said.join("; ")}.`;
    const rows = [];
    const shown = { acc: ["acc", "m/s²"], gyr: ["gyr", "°/s"], mag: ["mag", UNIT_WORDS[units.mag] || ""] };
    for (const [key, [name, unit]] of Object.entries(shown)) {
      const v = this.latest && this.latest[key];
      if (!v) continue;
      const tr = el("tr");
      tr.append(el("th", `${name}${unit && unit !== "unknown" ? ` (${unit})` : ""}`, { scope: "row" }),
        ...v.map((x) => el("td", formatNumber(x, 4))));
      rows.push(tr);
    }
    $("#board-numbers tbody").replaceChildren(...rows);
    $("#board-plot").innerHTML = plotSvg(this.recent);
    $(".board-plot-fig").hidden = !this.recent.length; // a board without an accelerometer: no plot
    const skipped = s.lines.skipped;
    $("#board-counts").textContent = `${s.lines.readings} readings`
      + (skipped ? `; ${skipped} lines that are not readings skipped (the last: “${s.lines.lastSkipped}”).` : ".");
  }

  async close(why) {
    const port = this.port;
    if (!port) return;
    this.port = null;
    clearInterval(this.watch);
    await port.close();
    this.source = null;
    $("#board-live").hidden = true;
    for (const id of ["#board-baud", "#board-format", "#board-usb", "#board-ble"]) $(id).disabled = false;
    this.message(why);
    this.showSend();
    this.onClose(why);
  }

  // --- send a calibration back ----------------------------------------------------------------

  // The calibration a Send would write, with the token that reads its export.
  // An accelerometer's calibration looks for the same device's latest compass calibration to send with it.
  offer(calibration, token = null) {
    this.calibration = calibration;
    this.token = token;
    this.compass = null;
    this.showSend();
    const box = $("#board-send-box");
    if (!box) return;
    const parts = packetParts(calibration);
    box.dataset.compass = "";
    this.describeSend();
    if (!parts.acc || parts.compass) return;
    latestCompass(calibration.device_id).then((found) => {
      if (this.calibration !== calibration) return;
      this.compass = found;
      $("#board-send-compass").checked = Boolean(found); // checked by default when there is one
      box.dataset.compass = found ? found.cal.id : "none";
      this.describeSend();
    });
  }

  // What the packet will replace on the board, and where each part comes from.
  describeSend() {
    const cal = this.calibration;
    if (!cal || !$("#board-send-box")) return;
    const parts = packetParts(cal);
    const device = cal.device_id;
    const found = this.compass;
    const included = Boolean(found) && $("#board-send-compass").checked;
    $("#board-send-compass-box").hidden = !found;
    if (found) {
      $("#board-send-compass-words").textContent = `Include the compass calibration of ${device} from `
        + `${dateTimeWords(found.cal.created_at)} (its hard iron, soft iron and field), so that the board keeps it.`;
    }
    const reset = `no hard iron, an identity soft iron and ${PACKET.defaultFieldUt} µT`;
    let words;
    if (parts.acc && parts.compass) {
      words = "From this calibration: the accelerometer's and gyroscope's offsets, and the compass's hard iron, "
        + "soft iron and field.";
    } else if (parts.acc && included) {
      words = "From this calibration: the accelerometer's and gyroscope's offsets. From the compass calibration of "
        + `${dateTimeWords(found.cal.created_at)}: the compass's hard iron, soft iron and field.`;
    } else if (parts.acc && !found && this.latest && !this.latest.mag) {
      // A board whose lines carry no magnetometer (an MPU-6050), and no compass calibration of it stored: the
      // packet's compass part changes nothing on it.
      words = "From this calibration: the accelerometer's and gyroscope's offsets. This board prints no "
        + "magnetometer, so the packet's compass part (no hard iron, an identity soft iron) concerns nothing on it.";
    } else if (parts.acc) {
      const why = found ? "" : device ? ` (no compass calibration of ${device} in your calibrations)`
        : " (this calibration names no device, so none of its compass calibrations can be found)";
      words = "From this calibration: the accelerometer's and gyroscope's offsets. The board's compass calibration "
        + `will be reset${why}: ${reset}. Calibrate the compass afterwards, or send its calibration again.`;
    } else {
      words = "From this calibration: the compass's hard iron, soft iron and field. The board's accelerometer and "
        + "gyroscope offsets will be reset to zero (a compass calibration has none): calibrate the accelerometer "
        + "afterwards and send that, with this compass calibration included.";
    }
    $("#board-send-parts").textContent = words;
  }

  showSend() {
    const box = $("#board-send-box");
    if (!box) return;
    box.hidden = !(this.port && this.calibration);
    $("#board-send").disabled = !this.port;
  }

  confirmSend(asking) {
    $("#board-send-confirm").hidden = !asking;
    $("#board-send").hidden = asking;
    if (asking) $("#board-send-go").focus();
  }

  // What the board printed in reply within ACK_MS of the packet: a line that is not a reading (Adafruit's
  // calibration sketch prints none; others acknowledge), or null.
  async acknowledgement(before) {
    await new Promise((done) => setTimeout(done, ACK_MS));
    const lines = this.source && this.source.lines;
    return lines && lines.skipped > before ? lines.lastSkipped : null;
  }

  // MotionCal's packet from the API (GET …/export?format=motioncal), written to the port as it came.
  async send() {
    const msg = $("#board-send-msg");
    if (!this.port || !this.calibration) return;
    msg.textContent = "Sending…";
    const found = this.compass && $("#board-send-compass").checked ? this.compass : null;
    const packet = async (id, token) => new Uint8Array(
      await (await fetchExport(id, "motioncal", token)).blob.arrayBuffer());
    const whole = (b) => b.length === PACKET.bytes && b[0] === PACKET.signature[0] && b[1] === PACKET.signature[1];
    let bytes;
    let compass = null;
    try {
      bytes = await packet(this.calibration.id, this.token);
    } catch (err) {
      msg.textContent = `The packet could not be made: ${err.message}.`;
      return;
    }
    try {
      if (found) compass = await packet(found.cal.id, found.token);
    } catch (err) {
      msg.textContent = `The compass calibration of ${dateTimeWords(found.cal.created_at)} cannot go in the packet: `
        + `${err.message}. Nothing was sent: untick it to send this calibration alone `
        + "(the board's compass is then reset).";
      return;
    }
    for (const b of [bytes, compass]) {
      if (b && !whole(b)) {
        msg.textContent = `The server's answer is not MotionCal's ${PACKET.bytes}-byte packet `
          + `(${b.length} bytes): nothing was sent.`;
        return;
      }
    }
    if (compass) bytes = withCompass(bytes, compass);
    const before = this.source && this.source.lines ? this.source.lines.skipped : 0;
    try {
      await this.port.write(bytes);
    } catch (err) {
      msg.textContent = `The board could not be written to: ${err.message}.`;
      return;
    }
    msg.dataset.sent = String(bytes.length);
    msg.dataset.compass = found ? found.cal.id : "";
    const withWhat = found ? `, with the compass calibration of ${dateTimeWords(found.cal.created_at)}` : "";
    const sent = `Sent MotionCal's ${bytes.length}-byte packet to the board${withWhat}.`;
    msg.textContent = `${sent} Waiting for the board's reply…`;
    const reply = await this.acknowledgement(before);
    msg.dataset.ack = reply === null ? "none" : "line";
    msg.textContent = reply === null
      ? `${sent} The board printed no reply within ${ACK_MS / 1000} s: Adafruit's Sensor Calibration library checks `
        + "the CRC and stores the packet without a word, so its readings from now on show whether it took it."
      : `${sent} The board replied: “${reply}”.`;
  }
}
