// Motion data of the wizard (pure logic, no DOM): sign convention, stillness, pose, capture.
//
// Frame (W3C DeviceMotion): x right, y up along the screen, z out of the screen. Readings are
// specific force: at rest the axis pointing up reads +g. iOS Safari reports
// accelerationIncludingGravity with the opposite sign; SignDetector finds out which one a device
// follows and everything after it works in the W3C convention.
// The poses and thresholds come from the server's tables (tables.js).

import { TABLES } from "./tables.js";

export const POSES = TABLES.poses.order;
export const STANDARD_GRAVITY = TABLES.gravity;
const DEG = Math.PI / 180;

export function norm(v) { return Math.hypot(v[0], v[1], v[2]); }

export function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// The unit vector of a pose label: "+x" → [1, 0, 0].
export function poseVector(label) { return [...TABLES.poses.up[label]]; }

// The pose whose axis is closest to the direction of `acc`, and the angle between them (degrees).
export function nearestPose(acc) {
  const n = norm(acc);
  if (!(n > 0)) return { pose: null, angleDeg: 180 };
  let k = 0;
  for (let i = 1; i < 3; i += 1) if (Math.abs(acc[i]) > Math.abs(acc[k])) k = i;
  const cos = Math.min(1, Math.abs(acc[k]) / n);
  return { pose: (acc[k] >= 0 ? "+" : "-") + "xyz"[k], angleDeg: Math.acos(cos) / DEG };
}

// Unit specific force in the device frame predicted by a deviceorientation's beta and gamma
// (degrees), whatever sign the accelerometer uses: R = Rz(α) Rx(β) Ry(γ) (W3C Device Orientation),
// up in the device frame = Rᵀ e_z = (−cos β sin γ, sin β, cos β cos γ); α does not enter.
export function upFromOrientation(betaDeg, gammaDeg) {
  const b = betaDeg * DEG;
  const c = gammaDeg * DEG;
  return [-Math.cos(b) * Math.sin(c), Math.sin(b), Math.cos(b) * Math.cos(c)];
}

// iPhone, iPod, or iPad (an iPad may say "Macintosh" but has a touch screen).
export function isApplePlatform(userAgent, platform = "", maxTouchPoints = 0) {
  return /iPhone|iPad|iPod/.test(userAgent) || (platform === "MacIntel" && maxTouchPoints > 1);
}

// Which sign convention the device's accelerationIncludingGravity follows.
// From the data when deviceorientation events with numbers arrive: each motion sample whose
// direction agrees (or disagrees) with the orientation's predicted up vector within ~37° votes.
// Otherwise, after `waitMs` of motion data, from the platform; "default" is W3C off Apple devices.
export class SignDetector {
  constructor({ apple = false, waitMs = 1000, votesNeeded = 10, giveUpMs = 4000 } = {}) {
    this.apple = apple;
    this.waitMs = waitMs;
    this.votesNeeded = votesNeeded;
    this.giveUpMs = giveUpMs;
    this.up = null; // last predicted up vector from deviceorientation
    this.votes = { w3c: 0, ios: 0 };
    this.t0 = null;
    this.result = null; // {convention, detected_from}
  }

  orientation(beta, gamma) {
    if (Number.isFinite(beta) && Number.isFinite(gamma)) this.up = upFromOrientation(beta, gamma);
  }

  // Feed a raw sample; returns the decision once made (then it never changes).
  motion(tMs, acc) {
    if (this.result) return this.result;
    if (this.t0 === null) this.t0 = tMs;
    const n = norm(acc);
    if (this.up && n > 0.5 * STANDARD_GRAVITY && n < 1.5 * STANDARD_GRAVITY) {
      const c = dot(acc, this.up) / n;
      if (c > 0.8) this.votes.w3c += 1;
      else if (c < -0.8) this.votes.ios += 1;
    }
    const { w3c, ios } = this.votes;
    if (w3c + ios >= this.votesNeeded && w3c !== ios) {
      this.result = { convention: w3c > ios ? "w3c" : "ios", detected_from: "orientation" };
    } else if (tMs - this.t0 >= (this.up ? this.giveUpMs : this.waitMs)) {
      this.result = this.apple ? { convention: "ios", detected_from: "platform" }
        : { convention: "w3c", detected_from: "default" };
    }
    return this.result;
  }
}

// A reading in the W3C convention.
export function toW3C(acc, convention) {
  return convention === "ios" ? [-acc[0], -acc[1], -acc[2]] : acc;
}

// Mean and largest per-axis standard deviation of samples [{acc}] in a window.
export function windowStats(samples) {
  const n = samples.length;
  const mean = [0, 0, 0];
  for (const s of samples) for (let i = 0; i < 3; i += 1) mean[i] += s.acc[i] / n;
  let spread = 0;
  for (let i = 0; i < 3; i += 1) {
    let v = 0;
    for (const s of samples) v += (s.acc[i] - mean[i]) ** 2;
    spread = Math.max(spread, Math.sqrt(v / n));
  }
  let gyr = null;
  const withGyr = samples.filter((s) => s.gyr);
  if (withGyr.length) gyr = withGyr.reduce((sum, s) => sum + norm(s.gyr), 0) / withGyr.length;
  return { mean, spread, gyr };
}

// windowMs: moving window of the mean and spread; holdMs: still in a valid pose this long before a
// capture starts; spreadLow/spreadHigh (m/s²): enter/leave "still" below/above (largest per-axis std
// over the window); gyrLow/gyrHigh (deg/s): the same for the mean |rotation rate| (the server refuses
// captures turning faster than gyrHigh); maxAngleDeg: the closest axis must be within this angle of
// the measured direction. Values: app/web/tables.py, from the server checks they stay inside.
// Optional isDone(mean): the free flow's test of a direction already captured (instead of the labels).
export const DEFAULTS = { ...TABLES.capture };

// The capture state machine. push() takes W3C samples {t (ms), acc [m/s²], gyr [deg/s] | null}
// and returns what the page should show: {state, pose, angleDeg, mean, spread, still, stillMs,
// progress, event, capture}. States: "waiting" (too little data), "moving", "tilted" (still, but no
// axis within maxAngleDeg), "settling" (still in a pose, counting holdMs), "capturing", "done"
// (this pose was just captured and the phone has not moved since), "refused" (an already captured
// pose), "sending" (a capture is out; push() ignores samples until resolve()), "retry" (the server
// refused the last capture; move the phone to try again).
// Events (once, on the transition): "started", "restarted" (moved during a capture), "captured",
// "refused".
export class CaptureMachine {
  constructor(captureMs, options = {}) {
    this.captureMs = captureMs;
    this.o = { ...DEFAULTS, ...options };
    this.done = new Set();
    this.redo = new Set();
    this.window = [];
    this.still = false;
    this.stillSince = null;
    this.pose = null;
    this.capturing = null; // {pose, samples}
    this.sending = false;
    this.justCaptured = null; // the pose captured last, until the phone moves
    this.needMove = false; // after a refusal by the server
    this.lastState = null;
  }

  setDone(poses) { this.done = new Set(poses); for (const p of poses) this.redo.delete(p); }

  remaining() { return POSES.filter((p) => !this.done.has(p) || this.redo.has(p)); }

  requestRedo(pose) {
    this.redo.add(pose);
    if (this.justCaptured === pose) this.justCaptured = null;
  }

  // After the page sent a capture: accepted → the pose is done; else the phone must move first.
  resolve(accepted, pose) {
    this.sending = false;
    if (accepted) {
      this.done.add(pose);
      this.redo.delete(pose);
      this.justCaptured = pose;
    } else {
      this.needMove = true;
    }
  }

  // Wait for the device to move before the next capture (on: after a cube position was accepted,
  // whose next position may have the same face up), or capture as soon as it is still (off).
  requireMove(on = true) {
    this.needMove = on;
    if (!on) this.justCaptured = null;
  }

  reset() {
    this.window = [];
    this.still = false;
    this.stillSince = null;
    this.capturing = null;
  }

  push(sample) {
    const o = this.o;
    this.window.push(sample);
    while (this.window.length && this.window[0].t < sample.t - o.windowMs) this.window.shift();
    const span = sample.t - this.window[0].t;
    const stats = windowStats(this.window);
    const { pose, angleDeg } = nearestPose(stats.mean);
    const out = { pose, angleDeg, mean: stats.mean, spread: stats.spread, gyr: stats.gyr, acc: sample.acc,
      still: false, stillMs: 0, progress: 0, event: null, capture: null, state: "waiting" };
    if (this.sending) return this.emit(out, "sending");
    if (span < 0.8 * o.windowMs) return this.emit(out, "waiting");

    const gyrOk = (limit) => stats.gyr === null || stats.gyr < limit;
    const wasStill = this.still;
    if (!this.still && stats.spread < o.spreadLow && gyrOk(o.gyrLow)) {
      this.still = true;
      this.stillSince = this.window[0].t; // the whole window was still
      this.pose = pose;
    } else if (this.still && (stats.spread > o.spreadHigh || !gyrOk(o.gyrHigh))) {
      this.still = false;
    }
    if (this.still && wasStill && pose !== this.pose) { // drifted into another pose without a jolt
      this.stillSince = sample.t;
      this.pose = pose;
    }
    out.still = this.still;

    if (!this.still) {
      this.justCaptured = null;
      this.needMove = false;
      if (this.capturing) {
        this.capturing = null;
        out.event = "restarted";
      }
      return this.emit(out, "moving");
    }
    out.stillMs = sample.t - this.stillSince;
    if (angleDeg > o.maxAngleDeg) {
      if (this.capturing) { this.capturing = null; out.event = "restarted"; }
      return this.emit(out, "tilted");
    }
    if (this.needMove) return this.emit(out, "retry");
    // A pose counts as done by its label, or (the free flow) when o.isDone(mean) says its direction is taken.
    const done = o.isDone ? o.isDone(stats.mean) : this.done.has(pose) && !this.redo.has(pose);
    if (done) {
      if (this.justCaptured === pose) return this.emit(out, "done");
      return this.emit(out, "refused");
    }
    if (this.capturing) {
      this.capturing.samples.push(sample);
      const elapsed = sample.t - this.capturing.samples[0].t;
      out.progress = Math.min(1, elapsed / this.captureMs);
      if (elapsed >= this.captureMs) {
        const samples = this.capturing.samples;
        this.capturing = null;
        this.sending = true;
        out.event = "captured";
        out.capture = {
          position: pose,
          redo: this.redo.has(pose),
          acc: samples.map((s) => s.acc),
          t_ms: samples.map((s) => s.t),
          gyr: samples.every((s) => s.gyr) ? samples.map((s) => s.gyr) : null,
        };
        return this.emit(out, "sending");
      }
      return this.emit(out, "capturing");
    }
    if (out.stillMs >= o.holdMs) {
      this.capturing = { pose, samples: [sample] };
      out.event = "started";
      return this.emit(out, "capturing");
    }
    return this.emit(out, "settling");
  }

  emit(out, state) {
    out.state = state;
    if (state === "refused" && this.lastState !== "refused") out.event = out.event || "refused";
    // A gap in the data ("waiting": too few samples in the window) is no new put-down: a pose refused
    // before it is not refused again after it (its cue would sound twice for the one pose).
    if (state !== "waiting") this.lastState = state;
    return out;
  }
}

// A devicemotion event as a raw sample, or null when it carries no numbers (desktops send one
// event of nulls). Time is event.timeStamp (ms); rotationRate's alpha, beta, gamma are the rates
// about x, y, z in deg/s (W3C Device Orientation and Motion; what Chromium reports).
export function sampleFromMotionEvent(event) {
  const a = event.accelerationIncludingGravity;
  if (!a || ![a.x, a.y, a.z].every(Number.isFinite)) return null;
  const r = event.rotationRate;
  const gyr = r && [r.alpha, r.beta, r.gamma].every(Number.isFinite) ? [r.alpha, r.beta, r.gamma] : null;
  return { t: event.timeStamp, acc: [a.x, a.y, a.z], gyr };
}
