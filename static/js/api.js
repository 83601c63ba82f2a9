// REST calls of the pages (no DOM here). Every failure becomes an ApiError whose message is the
// API's detail, whose code is the API's error code (`wrong_turn`, `already_captured` …; null when
// the answer has none), whose asks are the parameters the detail asks for (`acc_unit`, `sampling_rate_hz` …:
// the page shows their controls) and whose status is the HTTP status (0 when the server could not be reached).
// Pages decide on the code, never on the message. Every request says it comes from a page
// (X-Trical-Client: page, and which page): the server then words its messages for the page, naming the
// page's controls rather than the API's parameters (app/words.py).

export class ApiError extends Error {
  constructor(message, status, code = null, asks = [], body = null) {
    super(message);
    this.status = status;
    this.code = code;
    this.asks = asks;
    this.body = body; // the whole answer (a columns_ambiguous refusal's candidates and preview)
  }
}

function bearer(token) { return token ? { Authorization: `Bearer ${token}` } : {}; }

async function send(path, { method = "GET", headers = {}, body } = {}) {
  try {
    const reader = { "X-Trical-Client": "page", "X-Trical-Page": location.pathname };
    return await fetch(path, { method, headers: { ...reader, ...headers }, body });
  } catch (err) {
    throw new ApiError(`the server could not be reached (${err.message})`, 0);
  }
}

async function failure(response) {
  let detail = `HTTP ${response.status}`;
  let code = null;
  let asks = [];
  let body = null;
  try {
    body = await response.json();
    if (body && typeof body.detail === "string") detail = body.detail;
    else if (body && Array.isArray(body.detail)) detail = body.detail.map((d) => d.msg || JSON.stringify(d)).join("; ");
    if (body && typeof body.code === "string") code = body.code;
    if (body && Array.isArray(body.asks)) asks = body.asks;
  } catch { /* not JSON: keep the status */ }
  return new ApiError(detail, response.status, code, asks, body);
}

async function request(path, options = {}) {
  const response = await send(path, options);
  if (!response.ok) throw await failure(response);
  const text = await response.text();
  try { return text ? JSON.parse(text) : null; } catch { return null; }
}

function json(method, payload, headers = {}) {
  return { method, headers: { "Content-Type": "application/json", ...headers }, body: JSON.stringify(payload) };
}

export function uploadRecording(formData, token = null) {
  return request("/api/v1/recordings", { method: "POST", body: formData, headers: bearer(token) });
}

// The calibration a device already holds, from its firmware's file (POST /api/v1/calibrations/import).
export function importCalibration(formData, token = null) {
  return request("/api/v1/calibrations/import", { method: "POST", body: formData, headers: bearer(token) });
}

export function createCalibration(payload) {
  return request("/api/v1/calibrations", json("POST", payload));
}

export function exportUrl(id, format) {
  return `/api/v1/calibrations/${encodeURIComponent(id)}/export?format=${encodeURIComponent(format)}`;
}

// A wizard session; `apiKey` only when the server has API keys (401 otherwise).
export function createSession(payload, apiKey = null) {
  return request("/api/v1/sessions", json("POST", payload, bearer(apiKey)));
}

const sessionPath = (id) => `/api/v1/sessions/${encodeURIComponent(id)}`;

export function getSession(id, token) {
  return request(sessionPath(id), { headers: bearer(token) });
}

export function postCapture(id, token, capture) {
  return request(`${sessionPath(id)}/captures`, json("POST", capture, bearer(token)));
}

export function solveSession(id, token) {
  return request(`${sessionPath(id)}/solve`, { method: "POST", headers: bearer(token) });
}

export function getCalibration(id, token) {
  return request(`/api/v1/calibrations/${encodeURIComponent(id)}`, { headers: bearer(token) });
}

// Samples calibrated by the server with a stored calibration (its correction of `sensor`): {samples, unit}.
export function applyCalibration(id, samples, sensor, token = null) {
  return request(`/api/v1/calibrations/${encodeURIComponent(id)}/apply`,
    json("POST", { samples, sensor }, bearer(token)));
}

// One export as {blob, filename}: fetched with the token, since a plain link cannot send it.
export async function fetchExport(id, format, token) {
  const response = await send(exportUrl(id, format), { headers: bearer(token) });
  if (!response.ok) throw await failure(response);
  const disposition = response.headers.get("Content-Disposition") || "";
  const match = /filename="([^"]+)"/.exec(disposition);
  return { blob: await response.blob(), filename: match ? match[1] : `${id}.${format}` };
}

// The calibrations the token (or no token) may read, newest first; `device` filters by device_id.
export function listCalibrations(token = null, device = null, limit = 100) {
  const query = new URLSearchParams({ limit: String(limit) });
  if (device) query.set("device_id", device);
  return request(`/api/v1/calibrations?${query}`, { headers: bearer(token) });
}

// The earlier calibrations of the same recording and method that `id` superseded, newest first.
export function listEarlier(id, token = null) {
  const query = new URLSearchParams({ superseded_by: id });
  return request(`/api/v1/calibrations?${query}`, { headers: bearer(token) });
}

// Paste-ready lines applying a calibration: {c, python, javascript, functions, scales}.
export function getUse(id, token = null) {
  return request(`/api/v1/calibrations/${encodeURIComponent(id)}/use`, { headers: bearer(token) });
}

// A short link that reads the calibration for a while: {code, url, qr, expires_at}.
export function createLink(id, token = null) {
  return request(`/api/v1/calibrations/${encodeURIComponent(id)}/links`, { method: "POST", headers: bearer(token) });
}

// What a link's code opens: {calibration_id, expires_at, token}.
export function openLink(code) {
  return request(`/api/v1/links/${encodeURIComponent(code)}`);
}

// A stored calibration checked on an uploaded recording: {verdict, reasons, sensors}.
export function checkCalibration(id, recordingId, token = null) {
  return request(`/api/v1/calibrations/${encodeURIComponent(id)}/check`,
    json("POST", { recording_id: recordingId }, bearer(token)));
}

// A stored compass calibration checked on a turn's readings as the device read them (the compass page's live turn).
export function checkTurn(id, mag, token = null) {
  return request(`/api/v1/calibrations/${encodeURIComponent(id)}/check`, json("POST", { mag }, bearer(token)));
}

// Two calibrations compared, `other` − `id`: {sensors: [{differences, effect, effect_deg, …}], missing}.
export function compareCalibrations(id, other, token = null) {
  const query = new URLSearchParams({ with: other });
  return request(`/api/v1/calibrations/${encodeURIComponent(id)}/compare?${query}`, { headers: bearer(token) });
}
