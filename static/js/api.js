// REST calls of the pages (no DOM here). Every failure becomes an Error whose message is the API's detail.

async function request(path, options = {}) {
  let response;
  try {
    response = await fetch(path, options);
  } catch (err) {
    throw new Error(`the server could not be reached (${err.message})`);
  }
  const text = await response.text();
  let body = null;
  try { body = text ? JSON.parse(text) : null; } catch { body = null; }
  if (!response.ok) {
    const detail = body && typeof body.detail === "string" ? body.detail : `HTTP ${response.status}`;
    throw new Error(detail);
  }
  return body;
}

export function uploadRecording(formData) {
  return request("/api/v1/recordings", { method: "POST", body: formData });
}

export function createCalibration(payload) {
  return request("/api/v1/calibrations", {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    body: JSON.stringify(payload),
  });
}

export function exportUrl(id, format) {
  return `/api/v1/calibrations/${encodeURIComponent(id)}/export?format=${encodeURIComponent(format)}`;
}
