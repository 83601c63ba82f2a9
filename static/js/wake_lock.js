// Keeps the screen on while a session runs (no DOM besides the document's visibility): the phone
// lies on the table for minutes with nobody touching it, and a screen that dims or locks stops
// the motion events. Best effort: without the Screen Wake Lock API, or when the browser refuses
// (low battery, no permission), the screen simply follows its own timeout.
//
// The browser drops the lock whenever the page is hidden (another tab, the screen switched off);
// it is asked for again when the page is visible again, as long as the session runs.

let wanted = false;
let sentinel = null; // the WakeLockSentinel held, or null
let asking = false;

function release(lock) {
  try { Promise.resolve(lock.release()).catch(() => {}); } catch { /* already released */ }
}

async function acquire() {
  if (!wanted || asking || (sentinel && !sentinel.released) || document.visibilityState !== "visible") return;
  const api = navigator.wakeLock;
  if (!api || typeof api.request !== "function") return;
  asking = true;
  try {
    const got = await api.request("screen");
    if (wanted) sentinel = got;
    else release(got); // the session ended while the browser was deciding
  } catch { /* refused: the screen keeps its own timeout */ }
  asking = false;
}

// From the Start tap (and again on every later Start or Continue: nothing happens while it is held).
export function keepScreenOn() {
  wanted = true;
  acquire();
}

// The session is over (its result shows) or discarded.
export function letScreenSleep() {
  wanted = false;
  const held = sentinel;
  sentinel = null;
  if (held && !held.released) release(held);
}

document.addEventListener("visibilitychange", () => {
  if (document.visibilityState === "visible") acquire();
});
