// A board on a serial port, as the Web Serial API shows it to a page, played by the page's own timer;
// injected by the tests with page.add_init_script before the page loads (as phone_shim.js is).
//
// - navigator.serial.requestPort() records whether it was called during a user activation (a click)
//   and resolves to a port (the chooser's answer); with window.__board.refuse set it rejects with a
//   NotFoundError, as Chromium does when the person closes the chooser;
// - port.open({baudRate}) records the rate; port.readable is a ReadableStream of Uint8Array chunks: the
//   lines the test queued with window.__board.play(lines, hz, eol, chunkMs) leave at `hz` lines a second
//   of the page's clock, gathered every 16 ms into one chunk (a USB serial port delivers bursts) or, with
//   `chunkMs`, every chunkMs (a USB-serial bridge's buffer, a loaded computer: 1000 → 1 s of lines at
//   once), each line ended by `eol` (CRLF unless given). Opened at another rate than window.__board.baud (115200 unless
//   set), the board's bytes arrive as a UART at the wrong rate makes them: the same count of bytes, each
//   one scrambled (XORed with 0x5A), the line ends left where they were;
// - port.writable is a WritableStream whose bytes are kept in window.__board.written;
// - port.close() is recorded; reading stops.
(() => {
  if (window.__board) return;
  const board = { baud: 115200, opened: [], requests: [], written: [], closed: 0, queue: [], hz: 100, sent: 0,
    refuse: false, reading: false };
  window.__board = board;
  board.play = (lines, hz, eol = "\r\n", chunkMs = 16) => {
    for (const line of lines) board.queue.push(line + eol);
    board.hz = hz;
    board.chunkMs = chunkMs;
  };
  board.pending = () => board.queue.length;
  const encoder = new TextEncoder();

  class SerialPort {
    constructor() { this.readable = null; this.writable = null; this.timer = null; }

    async open({ baudRate }) {
      board.opened.push(baudRate);
      let due = 0;
      let last = performance.now();
      let flushed = last;
      let text = "";
      const port = this;
      this.readable = new ReadableStream({
        start(controller) {
          port.timer = setInterval(() => {
            const now = performance.now();
            due += ((now - last) / 1000) * board.hz;
            last = now;
            while (due >= 1 && board.queue.length) { text += board.queue.shift(); due -= 1; board.sent += 1; }
            if (!board.queue.length) due = 0;
            if (!text || now - flushed < (board.chunkMs || 16) - 8) return;
            flushed = now;
            let bytes = encoder.encode(text);
            text = "";
            if (baudRate !== board.baud) bytes = bytes.map((b) => (b === 10 || b === 13 ? b : b ^ 0x5a));
            controller.enqueue(bytes);
          }, 16);
        },
        cancel() { clearInterval(port.timer); },
      });
      this.writable = new WritableStream({ write(chunk) { board.written.push(...chunk); } });
      board.reading = true;
    }

    async close() {
      clearInterval(this.timer);
      board.closed += 1;
      board.reading = false;
      this.readable = null;
      this.writable = null;
    }

    getInfo() { return { usbVendorId: 0x2341, usbProductId: 0x0043 }; }
  }

  const serial = {
    requestPort() {
      board.requests.push(navigator.userActivation ? navigator.userActivation.isActive : null);
      if (board.refuse) return Promise.reject(new DOMException("No port selected by the user.", "NotFoundError"));
      return Promise.resolve(new SerialPort());
    },
    getPorts: () => Promise.resolve([]),
  };
  Object.defineProperty(navigator, "serial", { value: serial, configurable: true });
})();

// A board over Bluetooth LE with the Nordic UART Service, as Web Bluetooth shows it:
// navigator.bluetooth.requestDevice({filters: [{services: [uuid]}]}) records the filter and whether it was
// called from a click; the device's GATT server gives the service, whose TX characteristic notifies the
// queued lines (at most 20 bytes a notification, the default MTU's payload, every 16 ms: as many as the
// rate allows) and whose RX characteristic keeps what is written (window.__board.bleWritten, one array a
// write).
(() => {
  const board = window.__board;
  board.bleRequests = [];
  board.bleWritten = [];
  const encoder = new TextEncoder();
  function characteristic(uuid) {
    const c = new EventTarget();
    c.uuid = uuid;
    c.startNotifications = async () => {
      let due = 0;
      let last = performance.now();
      let pending = new Uint8Array(0);
      c.timer = setInterval(() => {
        const now = performance.now();
        due += ((now - last) / 1000) * board.hz;
        last = now;
        let text = "";
        while (due >= 1 && board.queue.length) { text += board.queue.shift(); due -= 1; board.sent += 1; }
        if (!board.queue.length) due = 0;
        if (text) { const more = encoder.encode(text); const all = new Uint8Array(pending.length + more.length); all.set(pending); all.set(more, pending.length); pending = all; }
        while (pending.length) {
          const part = pending.slice(0, 20);
          pending = pending.slice(20);
          c.value = new DataView(part.buffer);
          c.dispatchEvent(new Event("characteristicvaluechanged"));
        }
      }, 16);
      return c;
    };
    c.writeValueWithResponse = async (bytes) => { board.bleWritten.push([...new Uint8Array(bytes.buffer || bytes)]); };
    return c;
  }
  const bluetooth = {
    requestDevice(options) {
      board.bleRequests.push({ options, click: navigator.userActivation ? navigator.userActivation.isActive : null });
      const uart = options.filters[0].services[0];
      const device = new EventTarget();
      device.name = "Feather nRF52840";
      device.gatt = {
        connected: false,
        async connect() { this.connected = true; return this; },
        disconnect() { this.connected = false; },
        async getPrimaryService(uuid) {
          if (uuid !== uart) throw new DOMException("No such service", "NotFoundError");
          const chars = {};
          return { async getCharacteristic(id) { chars[id] = chars[id] || characteristic(id); return chars[id]; } };
        },
      };
      return Promise.resolve(device);
    },
  };
  Object.defineProperty(navigator, "bluetooth", { value: bluetooth, configurable: true });
})();
