// What this browser keeps to read its calibrations again (localStorage; nothing when it is off):
// the token of the wizard session that made each calibration (`trical.calibrations`: id → token;
// a session's calibration is readable with its token only), and the API key the person gave on a
// server with keys (`trical.apiKey`). The server scopes every read to the token's owner.

const CALS = "trical.calibrations";
const KEY = "trical.apiKey";

function load(name, fallback) {
  try { return JSON.parse(localStorage.getItem(name) || "null") ?? fallback; } catch { return fallback; }
}

function save(name, value) {
  try { localStorage.setItem(name, JSON.stringify(value)); } catch { /* private mode: no memory */ }
}

export function rememberToken(calibrationId, token) {
  if (!calibrationId || !token) return;
  save(CALS, { ...load(CALS, {}), [calibrationId]: token });
}

export function tokenFor(calibrationId) { return load(CALS, {})[calibrationId] || null; }

// Every session token kept, once each (a session makes one calibration, redone ones share it).
export function sessionTokens() {
  return [...new Set(Object.values(load(CALS, {})).filter((t) => t.startsWith("tks_")))];
}

// The calibrations opened through a short link (lnk_…), each readable alone until its link expires.
export function linkedCalibrations() { return Object.entries(load(CALS, {})).filter(([, t]) => t.startsWith("lnk_")); }

export function apiKey() { return load(KEY, null); }

export function rememberApiKey(key) { save(KEY, key); }

// The tokens to try for a calibration, most specific first; null (no token) last.
export function candidates(calibrationId = null) {
  const out = [];
  for (const t of [calibrationId && tokenFor(calibrationId), apiKey()]) if (t && !out.includes(t)) out.push(t);
  out.push(null);
  return out;
}
