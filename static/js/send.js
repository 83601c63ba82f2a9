// "Send to my computer" on a result: a short link to the calibration (POST …/{id}/links, read with the
// token this page holds; it expires), handed to the Web Share API where the browser has it (a phone's
// share sheet: mail, a messenger, AirDrop), else shown as a QR code and an address to type.
import { createLink } from "./api.js";
import { $, dateTimeWords } from "./dom.js";

let current = null; // {cal, token}: what the button sends

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
  $("#send-expires").textContent = `(it opens this calibration until ${dateTimeWords(link.expires_at)}).`;
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
        say(`Sent: the link opens it until ${dateTimeWords(link.expires_at)}.`);
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
