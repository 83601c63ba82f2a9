// The phone's motion sensors played by the page's own timer, injected by the test before it taps
// Start: for a WebKit that has none (WebKitGTK's MiniBrowser), and in Chromium for the flows whose
// turns must not depend on the test process keeping time (a stall of a loaded machine would stretch
// or cut a turn fed from outside). It plays what a phone's browser gives a page, and observes what
// the page does:
//
// - window.DeviceMotionEvent, a subclass of Event with accelerationIncludingGravity (m/s², in iOS's
//   sign by default: at rest the axis pointing up reads -g; in the W3C sign, up reads +g, when
//   window.__phoneSign is 1 before the shim runs), rotationRate (deg/s: alpha, beta, gamma about
//   x, y, z) and interval (s), as the W3C Device Orientation and Motion draft and Apple describe it;
// - DeviceMotionEvent.requestPermission, iOS 13's: it records whether it was called during a user
//   activation (a tap) and grants;
// - a "devicemotion" event every 16 ms of the page's clock (60 Hz, as an iPhone delivers; a timer
//   that fires late dispatches the samples it owes, each with its own timeStamp), with
//   the readings the test sets through window.__phone.set(acc, gyr); a turn through
//   window.__phone.turn(axis, peakDegS, thenAcc) is played by the timer itself: a half sine of the
//   rate about `axis` (sensor frame) sampled at each event's time, 90° in all, so that a stall of the
//   test process cannot stretch or cut it; window.__phone.noise(accSd, gyrSd, seed) adds white noise
//   to every sample (m/s², deg/s) from a seeded generator (mulberry32 with Box–Muller), so that a
//   run is repeatable;
// - the capture requests the page sends (fetch observed, not altered), the files it offers for
//   download (URL.createObjectURL observed: the page's CSP rightly keeps blob: out of connect-src, so
//   the test reads the Blob itself), the tones it starts (AudioContext.prototype.createOscillator
//   wrapped, the real oscillator still made and played), its wake-lock requests (passed on to the
//   browser's own navigator.wakeLock when it has one) and any error it raises.
(() => {
  if (window.__phone) return;
  const phone = {
    acc: [0, 0, 9.80665], gyr: [0, 0, 0], permissionCalls: [], captures: [], errors: [], events: 0, turns: [],
    tones: [], wakeLocks: [], audioStates: [], turning: null, accSd: 0, gyrSd: 0, random: null,
  };
  window.__phone = phone;

  class DeviceMotionEvent extends Event {
    constructor(type, init = {}) {
      super(type, init);
      this.acceleration = init.acceleration ?? null;
      this.accelerationIncludingGravity = init.accelerationIncludingGravity ?? null;
      this.rotationRate = init.rotationRate ?? null;
      this.interval = init.interval ?? 0.016;
    }
  }
  DeviceMotionEvent.requestPermission = () => {
    phone.permissionCalls.push(navigator.userActivation ? navigator.userActivation.isActive : null);
    return Promise.resolve("granted");
  };
  window.DeviceMotionEvent = DeviceMotionEvent;

  // The test's readings are in the W3C sign (up reads +g); iOS reports the opposite.
  const sign = window.__phoneSign === 1 ? 1 : -1;
  phone.set = (acc, gyr) => {
    phone.acc = acc.map((v) => sign * v);
    if (gyr) phone.gyr = gyr.slice();
  };
  phone.turn = (axis, peakDegS, thenAcc) => {
    const seconds = (90 * Math.PI) / (2 * peakDegS); // ∫ peak sin(π t / T) dt = 2 peak T / π = 90°
    phone.turning = { axis, peakDegS, ms: seconds * 1000, t0: phone.clock, thenAcc, angle: 0, last: null };
  };

  phone.noise = (accSd, gyrSd, seed) => {
    let a = seed >>> 0;
    const uniform = () => { // mulberry32
      a = (a + 0x6d2b79f5) >>> 0;
      let t = a;
      t = Math.imul(t ^ (t >>> 15), t | 1);
      t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
      return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
    };
    phone.random = () => Math.sqrt(-2 * Math.log(1 - uniform())) * Math.cos(2 * Math.PI * uniform());
    phone.accSd = accSd;
    phone.gyrSd = gyrSd;
  };
  const noisy = (v, sd) => (sd > 0 ? v.map((x) => x + sd * phone.random()) : v);

  function rates(now) {
    const turn = phone.turning;
    if (!turn) return phone.gyr;
    const t = now - turn.t0;
    if (t >= turn.ms) { // done: at rest in the new position
      phone.turns.push({ ms: t, angle: turn.angle });
      phone.turning = null;
      phone.gyr = [0, 0, 0];
      phone.set(turn.thenAcc);
      return phone.gyr;
    }
    const rate = turn.peakDegS * Math.sin((Math.PI * t) / turn.ms);
    if (turn.last) turn.angle += ((now - turn.last.t) / 1000) * (rate + turn.last.rate) / 2;
    turn.last = { t: now, rate };
    return turn.axis.map((a) => a * rate);
  }

  // The sensor's clock: a sample every 16 ms of the page's time, each event stamped with its own time.
  // The timer that dispatches them fires late when a loaded machine stalls the page; it then
  // dispatches every sample it owes at once, as a browser delivers the samples queued while its page
  // was busy, so that a turn is sampled alike however late the timer runs (at most 4.8 s are owed).
  const PERIOD_MS = 16;
  const MAX_OWED = 300;
  phone.clock = performance.now();
  function sample(t) {
    const event = new DeviceMotionEvent("devicemotion", {});
    Object.defineProperty(event, "timeStamp", { value: t });
    const w = noisy(rates(t), phone.gyrSd);
    const f = noisy(phone.acc, phone.accSd);
    event.accelerationIncludingGravity = { x: f[0], y: f[1], z: f[2] };
    event.acceleration = { x: 0, y: 0, z: 0 };
    event.rotationRate = { alpha: w[0], beta: w[1], gamma: w[2] };
    phone.events += 1;
    window.dispatchEvent(event);
  }
  setInterval(() => {
    let owed = Math.floor((performance.now() - phone.clock) / PERIOD_MS);
    if (owed > MAX_OWED) {
      phone.clock += (owed - MAX_OWED) * PERIOD_MS;
      owed = MAX_OWED;
    }
    for (let i = 0; i < owed; i += 1) {
      phone.clock += PERIOD_MS;
      sample(phone.clock);
    }
  }, PERIOD_MS);

  const fetchOriginal = window.fetch.bind(window);
  window.fetch = (input, init = {}) => {
    const url = typeof input === "string" ? input : input.url;
    if (url.endsWith("/captures") && typeof init.body === "string") phone.captures.push(JSON.parse(init.body));
    return fetchOriginal(input, init);
  };
  const blobs = new Map();
  const createObjectURL = URL.createObjectURL.bind(URL);
  URL.createObjectURL = (blob) => {
    const url = createObjectURL(blob);
    blobs.set(url, blob);
    return url;
  };
  phone.blobText = (url) => (blobs.has(url) ? blobs.get(url).text() : Promise.resolve(`no Blob behind ${url}`));
  const Audio = window.AudioContext || window.webkitAudioContext;
  if (Audio) {
    const createOscillator = Audio.prototype.createOscillator;
    Audio.prototype.createOscillator = function () {
      const osc = createOscillator.call(this);
      const start = osc.start;
      osc.start = function (...args) { phone.tones.push(osc.frequency.value); return start.apply(this, args); };
      return osc;
    };
  }
  if (navigator.wakeLock && typeof navigator.wakeLock.request === "function") {
    const request = navigator.wakeLock.request.bind(navigator.wakeLock);
    navigator.wakeLock.request = (type) => request(type).then(
      (sentinel) => { phone.wakeLocks.push(`${type}: granted`); return sentinel; },
      (err) => { phone.wakeLocks.push(`${type}: ${err.name}`); throw err; });
  }
  phone.hasWakeLock = Boolean(navigator.wakeLock);
  window.addEventListener("error", (event) => phone.errors.push(String(event.message)));
  window.addEventListener("unhandledrejection", (event) => phone.errors.push(`unhandled: ${event.reason}`));
  const consoleError = console.error.bind(console);
  console.error = (...args) => { phone.errors.push(args.map(String).join(" ")); consoleError(...args); };
})();
