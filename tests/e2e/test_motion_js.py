"""The wizard's pure motion logic (static/js/motion.js), run as the page runs it: imported by
real Chromium from the real server."""

from __future__ import annotations

import pytest

MODULE = "/static/js/motion.js"


@pytest.fixture
def js(page, server):
    page.goto(server.url + "/wizard")

    def run(body: str):
        return page.evaluate(f"async () => {{ const m = await import('{MODULE}'); {body} }}")

    return run


def test_pose_and_orientation_geometry(js):
    assert js("return m.nearestPose([0.3, -9.7, 0.2]).pose") == "-y"
    angle = js("return m.nearestPose([0, 9.80665 * Math.sin(Math.PI / 9), 9.80665 * Math.cos(Math.PI / 9)])")
    assert angle["pose"] == "+z" and angle["angleDeg"] == pytest.approx(20.0)
    # W3C Device Orientation: upright (beta 90°) puts +y up; gamma 90° (right edge down) puts −x up.
    assert js("return m.upFromOrientation(90, 0)") == pytest.approx([0, 1, 0], abs=1e-12)
    assert js("return m.upFromOrientation(0, 90)") == pytest.approx([-1, 0, 6.1e-17], abs=1e-12)
    assert js("return m.upFromOrientation(0, 0)") == pytest.approx([0, 0, 1])
    assert js("return m.isApplePlatform('Mozilla/5.0 (iPad; CPU OS 17_0)', 'iPad', 5)") is True
    assert js("return m.isApplePlatform('Mozilla/5.0 (Macintosh)', 'MacIntel', 5)") is True  # iPadOS desktop mode
    assert js("return m.isApplePlatform('Mozilla/5.0 (Linux; Android 14)', 'Linux armv8l', 5)") is False


def test_sign_detection(js):
    # Orientation says "upright"; the accelerometer says −g on y: the iOS convention, from the data.
    got = js("""const s = new m.SignDetector({apple: false});
      s.orientation(90, 0);
      let r = null; for (let i = 0; i < 10; i++) r = s.motion(i * 16, [0.1, -9.8, 0.2]);
      return r;""")
    assert got == {"convention": "ios", "detected_from": "orientation"}
    # No orientation: after a second of motion the platform decides; off Apple devices W3C is the default.
    got = js("""const a = new m.SignDetector({apple: true}), b = new m.SignDetector({apple: false});
      const r = [];
      for (const s of [a, b]) {
        r.push(s.motion(0, [0, 0, 9.8]), s.motion(999, [0, 0, 9.8]), s.motion(1000, [0, 0, 9.8]));
      }
      return r;""")
    assert got == [
        None,
        None,
        {"convention": "ios", "detected_from": "platform"},
        None,
        None,
        {"convention": "w3c", "detected_from": "default"},
    ]
    assert js("return m.toW3C([1, -2, 3], 'ios')") == [-1, 2, -3]


# Feed the machine 60 Hz samples: `segments` of (duration ms, mean acc, alternating ± noise per axis).
FEED = """
  const machine = new m.CaptureMachine(CAPTURE_MS);
  const outs = []; let t = 0, k = 0;
  for (const [ms, acc, noise] of SEGMENTS) {
    for (const end = t + ms; t < end; t += 1000 / 60, k++) {
      const s = k % 2 ? noise : -noise;
      outs.push(machine.push({t, acc: acc.map((v) => v + s), gyr: [0, 0, 0]}));
    }
  }
  return outs.map((o) => [o.state, o.event, o.capture && o.capture.t_ms.length,
                          o.capture && o.capture.t_ms[o.capture.t_ms.length - 1] - o.capture.t_ms[0]]);
"""


def feed(js, segments, capture_ms=1000):
    import json

    return js(FEED.replace("CAPTURE_MS", str(capture_ms)).replace("SEGMENTS", json.dumps(segments)))


def states(outs):
    collapsed = []
    for state, *_ in outs:
        if not collapsed or collapsed[-1] != state:
            collapsed.append(state)
    return collapsed


def test_still_hysteresis_and_capture(js):
    z = [0.0, 0.0, 9.8]
    # Still in +z: the capture starts ~1.5 s after the stillness began and lasts capture_s.
    outs = feed(js, [[4000, z, 0.0]])
    started = next(i for i, o in enumerate(outs) if o[1] == "started")
    assert 1.45 <= started / 60 <= 1.55
    captured = [o for o in outs if o[1] == "captured"]
    assert len(captured) == 1 and captured[0][3] >= 1000 and captured[0][2] >= 60
    assert states(outs) == ["waiting", "settling", "capturing", "sending"]
    # Spread between the two thresholds (0.1 < 0.15 < 0.25 m/s²): it never becomes still from moving...
    outs = feed(js, [[3000, z, 0.15]])
    assert set(states(outs)) == {"waiting", "moving"}
    # ...but once still it stays still through it (hysteresis), and the capture completes.
    outs = feed(js, [[1000, z, 0.0], [3000, z, 0.15]])
    assert sum(o[1] == "captured" for o in outs) == 1
    # Moving during the capture restarts it; the capture then starts over once still again.
    outs = feed(js, [[2000, z, 0.0], [300, z, 1.0], [4000, z, 0.0]])
    assert [o[1] for o in outs if o[1]] == ["started", "restarted", "started", "captured"]


def test_tilted_and_already_captured_poses(js):
    tilted = [0.0, 9.8 * 0.423, 9.8 * 0.906]  # 25° from +z
    assert "capturing" not in states(feed(js, [[4000, tilted, 0.0]]))
    assert states(feed(js, [[4000, tilted, 0.0]]))[-1] == "tilted"
    outs = js("""const c = new m.CaptureMachine(1000); c.setDone(['+z']);
      const r = []; for (let t = 0; t < 3000; t += 16) r.push(c.push({t, acc: [0, 0, 9.8], gyr: null}));
      c.requestRedo('+z');
      for (let t = 3000; t < 6000; t += 16) r.push(c.push({t, acc: [0, 0, 9.8], gyr: null}));
      return [r.map((o) => o.event).filter(Boolean), r.find((o) => o.capture).capture.redo, c.remaining()];""")
    assert outs == [["refused", "started", "captured"], True, ["-x", "+x", "-y", "+y", "-z", "+z"]]


def test_a_gap_in_the_data_does_not_refuse_the_same_pose_again(js):
    # Refused, then no sample for a second (the window empties: "waiting"), then the same pose again:
    # one refusal, one cue, for the one put-down.
    outs = js("""const c = new m.CaptureMachine(1000); c.setDone(['+z']);
      const r = []; for (let t = 0; t < 2000; t += 16) r.push(c.push({t, acc: [0, 0, 9.8], gyr: null}));
      for (let t = 3000; t < 5000; t += 16) r.push(c.push({t, acc: [0, 0, 9.8], gyr: null}));
      return [r.map((o) => o.event).filter(Boolean), [...new Set(r.map((o) => o.state))]];""")
    assert outs == [["refused"], ["waiting", "refused"]]
