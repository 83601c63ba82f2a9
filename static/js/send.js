// "Send to my computer" on a result: a short link to the calibration (POST …/{id}/links, read with the
// token this page holds; it expires), handed to the Web Share API where the browser has it (a phone's
// share sheet: mail, a messenger, AirDrop), else shown as a QR code and an address to type.
import { createLink } from "./api.js";
import { $ } from "./dom.js";

let current = null; // {cal, token}: what the button sends

// The link's expiry as a date and a time in this browser's zone, named: "4 December 2026, 13:51 CET" (the other
// machine may be opened tomorrow, or in another zone; the API gives ISO 8601 in UTC).
export function until(iso) {
  const when = new Date(iso);
  const date = when.toLocaleDateString("en-GB", { day: "numeric", month: "long", year: "numeric" });
  const time = when.toLocaleTimeString("en-GB", { hour: "2-digit", minute: "2-digit", timeZoneName: "short" });
  return `${date}, ${time}`;
}

function say(text, bad = false) {
  const p = $("#send-msg");
  p.hidden = !text;
  p.textContent = text;
  p.classList.toggle("bad", bad);
}

function showFallback(link) {
  $("#send-qr").src = link.qr;
  $("#send-qr").alt = `QR code of ${link.url}`;
  $("#send-url").href = link.url;
  $("#send-url").textContent = link.url;
  $("#send-expires").textContent = `(it opens this calibration until ${until(link.expires_at)}).`;
  $("#send-box").hidden = false;
}

async function send() {
  if (!current) return;
  const { cal } = current;
  say("Making a link…");
  let link;
  try {
    link = await createLink(cal.id, current.token);
  } catch (err) {
    say(`No link could be made: ${err.message}.`, true);
    return;
  }
  say("");
  if (navigator.share) {
    const data = { title: `trical calibration ${cal.id}`, text: cal.verdict.words, url: link.url };
    if (!navigator.canShare || navigator.canShare(data)) {
      try {
        await navigator.share(data);
        say(`Sent: the link opens it until ${until(link.expires_at)}.`);
        return;
      } catch (err) {
        if (err.name === "AbortError") { say("Not sent. Tap again to share, or use the code below."); }
      }
    }
  }
  showFallback(link);
}

// Offer the button for `cal` (read with `token`); hidden for a calibration that offers no file.
export function offerSend(cal, token = null) {
  current = { cal, token };
  $("#send").hidden = !cal.verdict.apply;
  $("#send-box").hidden = true;
  say("");
}

const button = document.querySelector("#send-btn");
if (button) button.addEventListener("click", send);
