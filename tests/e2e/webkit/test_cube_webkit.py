"""The cube24 flow in WebKit as on an iPhone: 24 positions hands-free, each turn played at 60 Hz by
the page's own timer (a half sine of the rate about the turn's axis, 90° in all), white noise on
every sample as a phone's sensors have it, and Särkkä et al.'s model recovered from what was fed."""

from __future__ import annotations

import json

import numpy as np

from app.calibration.cube.protocols import CUBE24_ROTATIONS
from tests.cube_phone import X_ACC, Y_ACC
from tests.e2e.test_wizard_cube import COUNT, URL, reading, turn_axis_in_sensor_frame

ACC_SD = 0.01  # m/s², about 1 mg: an iPhone's accelerometer at rest
GYR_SD = 0.05  # deg/s


def test_the_24_positions_in_webkit_recover_the_accelerometer(webkit, server):
    webkit.open(server.url + URL)
    assert "in a fixed order" in webkit.text("#start")
    webkit.shot("cube_start")
    webkit.with_motion()
    webkit.noise(ACC_SD, GYR_SD, seed=24)
    webkit.set(reading(1), (0.0, 0.0, 0.0))
    webkit.tap_start()
    webkit.wait_for(COUNT.format(1), 30)
    for k in range(2, 25):
        label = CUBE24_ROTATIONS[k - 2]
        if k == 2:
            assert webkit.js("document.querySelector('#cube-turn svg').dataset.turn") == label
            webkit.shot("cube_turn_into_2")
        webkit.turn(turn_axis_in_sensor_frame(k - 1, label), 100.0 + 3.0 * (k % 11), reading(k))
        webkit.wait_for(COUNT.format(k), 30)
    webkit.wait_for("#downloads[data-ready=true]", 30)
    assert not webkit.scrolls_sideways()
    webkit.shot("cube_result")

    sent = webkit.captures()
    assert [c["position"] for c in sent] == [str(k) for k in range(1, 25)] and not any(c["redo"] for c in sent)
    assert all(c["sign"] == {"convention": "ios", "detected_from": "platform"} for c in sent)
    played = webkit.js("window.__phone.turns")
    assert len(played) == 23 and all(abs(t["angle"] - 90.0) < 0.5 for t in played), played

    doc = json.loads(webkit.download("json"))
    session = webkit.stored(server, "cube24")
    turns = [c["turn"] for c in session["captures"][1:]]
    assert [t["expected"] for t in turns] == list(CUBE24_ROTATIONS) and all(t["ok"] for t in turns)
    # The server integrates the page's gyroscope samples (Särkkä et al. eq. (2)): the 90° played, within
    # what sampling a half sine at 60 Hz (and its noise) leaves.
    seen = np.array([t["angle_deg"] for t in turns])
    assert np.all(np.abs(seen - 90.0) < 0.5), seen  # seen 89.96° to 90.05°
    # Each position's mean carries the noise over about a second at 60 Hz (0.01 / √60 ≈ 0.0013 m/s²).
    means = np.array([c["mean"] for c in session["captures"]])
    fed = np.array([reading(k) for k in range(1, 25)])
    assert np.abs(means - fed).max() < 6 * ACC_SD / np.sqrt(50)
    acc = doc["model"]["acc"]
    # S and b within a few times that noise over g (seen 3e-5 and 3e-4 m/s²)
    np.testing.assert_allclose(acc["S"], X_ACC, atol=5e-4)
    np.testing.assert_allclose(acc["b"], Y_ACC, atol=3e-3)
    full = webkit.stored(server, "cube24", f"/calibrations/{doc['id']}")
    assert webkit.text("#verdict-words") == full["verdict"]["words"]
    assert webkit.js("document.querySelectorAll('#norm-chart svg circle').length") == 48
    assert webkit.errors() == []
    print(
        f"\nWebKit cube24: turns seen {seen.min():.2f}° to {seen.max():.2f}°; "
        f"S − X up to {np.abs(np.array(acc['S']) - X_ACC).max():.5f}, b − y up to "
        f"{np.abs(np.array(acc['b']) - Y_ACC).max():.5f} m/s²; ok={doc['ok']}; {full['verdict']['words']}"
    )
