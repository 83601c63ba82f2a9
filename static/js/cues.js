// Short sound and vibration cues for hands-off capturing (no DOM): the phone lies on the table while
// the person watches from a distance. Both are best effort: a browser without the Vibration API or
// Web Audio (iOS has no navigator.vibrate) simply stays silent.
//
// The kinds: "start" (a capture has begun: keep still), "captured" (it is done: turn the phone now),
// "refused" (this pose is not taken: turn it elsewhere), "finished" (nothing more to capture). Each
// has its own pitch and length and its own vibration pattern, so they are told apart unseen: a short
// short tick to start, a bright beep to turn, a long low tone to refuse, a long mid tone at the end.
const TONES = { start: [523, 0.06], captured: [880, 0.12], refused: [220, 0.25], finished: [660, 0.35] };
const BUZZ = { start: 30, captured: 80, refused: [60, 80, 60], finished: [120, 60, 120] };
let audio = null;

// Call from a tap: browsers let a page make sound only after a user gesture.
export function unlockCues() {
  try {
    const Ctx = window.AudioContext || window.webkitAudioContext;
    if (!audio && Ctx) audio = new Ctx();
    if (audio && audio.state === "suspended") audio.resume();
  } catch { audio = null; }
}

export function cue(kind) {
  try { if (navigator.vibrate) navigator.vibrate(BUZZ[kind]); } catch { /* no vibration */ }
  if (!audio || audio.state !== "running") return;
  const [hz, seconds] = TONES[kind];
  const osc = audio.createOscillator();
  const gain = audio.createGain();
  osc.frequency.value = hz;
  gain.gain.setValueAtTime(0.15, audio.currentTime);
  gain.gain.exponentialRampToValueAtTime(0.001, audio.currentTime + seconds);
  osc.connect(gain).connect(audio.destination);
  osc.start();
  osc.stop(audio.currentTime + seconds);
}
