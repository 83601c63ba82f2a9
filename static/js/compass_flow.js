// The compass wizard's bookkeeping (pure, no DOM): the readings, a running estimate of the sensor's
// offset, and which of the 20 icosahedron faces (tables.js, from coverage.py) the field directions
// have reached.
//
// The face a reading falls in is that of its direction from the offset b (m − b), which the page
// does not know until the server has solved. Its running estimate is the centre of the sphere that
// fits the readings so far best in the algebraic sense, |m|² = 2 c·m + k, linear least squares in
// (c, k) (I. Kåsa, "A circle fitting procedure and its error analysis", IEEE Trans. Instrum. Meas.
// 25 (1976) 8–14): unlike the mid-point of each axis's extremes, it stays near b when only part of
// the sphere has been reached (a hemisphere already puts the extremes' mid-point half a radius off,
// and the readings near its rim then seem to point into the missing half). Soft iron, which makes
// the readings an ellipsoid, is ignored here: the faces are large (42° across) and the server
// counts the coverage again from the calibrated readings.

import { TABLES } from "./tables.js";
import { SOURCE } from "./source.js";

const C = TABLES.compass;
export const MIN_READINGS = C.minReadings;
export const COVERAGE_TO_SOLVE = C.coverageToSolve;
export const FACE_NAMES = C.faceNames;
export const FACE_WORDS = C.faceWords[SOURCE]; // the phone's sides or the board's

// Gauss–Jordan with partial pivoting on a small system; null when it is singular.
function solve(A, y) {
  const n = y.length;
  const a = A.map((row, i) => [...row, y[i]]);
  for (let col = 0; col < n; col += 1) {
    let piv = col;
    for (let r = col + 1; r < n; r += 1) if (Math.abs(a[r][col]) > Math.abs(a[piv][col])) piv = r;
    if (!(Math.abs(a[piv][col]) > 1e-12 * Math.abs(a[0][0] || 1))) return null;
    [a[col], a[piv]] = [a[piv], a[col]];
    for (let r = 0; r < n; r += 1) {
      if (r === col) continue;
      const f = a[r][col] / a[col][col];
      for (let c = col; c <= n; c += 1) a[r][c] -= f * a[col][c];
    }
  }
  return a.map((row, i) => row[n] / row[i]);
}

export function faceOf(v) {
  let best = 0;
  let bestDot = -Infinity;
  C.faceCentres.forEach((c, k) => {
    const d = c[0] * v[0] + c[1] * v[1] + c[2] * v[2];
    if (d > bestDot) { bestDot = d; best = k; }
  });
  return best;
}

export class CompassCoverage {
  constructor() {
    this.readings = [];
    this.ata = Array.from({ length: 4 }, () => [0, 0, 0, 0]); // normal equations of the sphere fit
    this.aty = [0, 0, 0, 0];
    this.min = [Infinity, Infinity, Infinity];
    this.max = [-Infinity, -Infinity, -Infinity];
  }

  // A reading in µT; false when it is not a number or repeats the last one (no new information).
  push(m) {
    if (!m.every(Number.isFinite)) return false;
    const last = this.readings[this.readings.length - 1];
    if (last && last[0] === m[0] && last[1] === m[1] && last[2] === m[2]) return false;
    this.readings.push(m);
    const row = [2 * m[0], 2 * m[1], 2 * m[2], 1];
    const y = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
    for (let i = 0; i < 4; i += 1) {
      this.aty[i] += row[i] * y;
      for (let j = 0; j < 4; j += 1) this.ata[i][j] += row[i] * row[j];
    }
    for (let i = 0; i < 3; i += 1) {
      this.min[i] = Math.min(this.min[i], m[i]);
      this.max[i] = Math.max(this.max[i], m[i]);
    }
    return true;
  }

  get count() { return this.readings.length; }

  // The running centre and radius, or null until the turn has gone far enough to fix them: ten
  // readings, and a spread on some axis of at least one radius (a cap about 60° across).
  centre() {
    if (this.count < 10) return null;
    const x = solve(this.ata, this.aty);
    if (!x) return null;
    const c = x.slice(0, 3);
    const r2 = x[3] + c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    if (!(r2 > 0)) return null;
    const radius = Math.sqrt(r2);
    const spread = Math.max(...this.max.map((v, i) => v - this.min[i]));
    return spread >= radius ? { c, radius } : null;
  }

  // {count, centre, radius, covered (20 booleans), coverage (0–1), missing (face indices),
  //  directions (unit-radius points m − c over the radius), current (the latest of them)}.
  status() {
    const fit = this.centre();
    const covered = FACE_NAMES.map(() => false);
    if (!fit) {
      return { count: this.count, centre: null, radius: null, covered, coverage: 0,
        missing: FACE_NAMES.map((_, k) => k), directions: [], current: null };
    }
    const { c, radius } = fit;
    const directions = this.readings.map(
      (m) => [(m[0] - c[0]) / radius, (m[1] - c[1]) / radius, (m[2] - c[2]) / radius]);
    for (const d of directions) covered[faceOf(d)] = true;
    const missing = covered.flatMap((on, k) => (on ? [] : [k]));
    return { count: this.count, centre: c, radius, covered,
      coverage: (covered.length - missing.length) / covered.length,
      missing, directions, current: directions[directions.length - 1] };
  }

  ready(status = this.status()) { return status.count >= MIN_READINGS && status.coverage >= COVERAGE_TO_SOLVE; }
}

// The missing faces in words: "screen, towards the top (+z+y)".
export function missingWords(missing) {
  return missing.map((k) => `${FACE_WORDS[k]} (${FACE_NAMES[k].replace(/-/g, "−")})`);
}
