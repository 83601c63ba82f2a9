"""The six-position flow in WebKit as on an iPhone: iOS's permission prompt from the tap, iOS's sign of
accelerationIncludingGravity detected from the platform, hands-free captures, and the stored
calibration equal to the closed form on what the page was given."""

from __future__ import annotations

import json

import numpy as np

from app.calibration import fit_six_position
from tests.e2e.test_wizard import CAPTURED, POSES, G, reading

ORDER = ["+z", "-y", "+x", "-z", "-x", "+y"]  # shuffled
GYRO_DEG_S = [0.3, -0.2, 0.1]  # a gyroscope bias at rest


def test_six_poses_in_webkit_as_on_an_iphone(webkit, server):
    webkit.open(server.url + "/wizard?protocol=six&capture_s=1")
    assert "flat, steady table" in webkit.text("#start")
    assert not webkit.scrolls_sideways()
    webkit.shot("six_start")
    webkit.with_motion()
    webkit.set(reading(ORDER[0]), GYRO_DEG_S)
    # The page's own frames note that the capture's progress showed: a 1 s capture can be over between two
    # of the test's polls through WebDriver on a loaded machine.
    webkit.js(
        "(() => { window.__sawProgress = false; const watch = () => { if (document.querySelector('#progress')"
        ".value > 0) window.__sawProgress = true; else requestAnimationFrame(watch); }; watch(); })()"
    )
    webkit.tap_start()  # motion access asked once, from the tap
    for k, label in enumerate(ORDER):
        if k:
            webkit.set(reading(label))
        if k == 0:
            webkit.wait("window.__sawProgress", 10, "the first capture's progress")
            if webkit.js("document.querySelector('#progress').value > 0"):
                webkit.shot("six_capturing_first_pose")
        webkit.wait_for(CAPTURED.format(label))
        webkit.shot(f"six_captured_{k + 1}_{label}")
    webkit.wait_for("#downloads[data-ready=true]")
    assert not webkit.scrolls_sideways()
    webkit.shot("six_result")

    # iOS's sign, from the platform (the user agent), and the raw samples in order.
    sent = webkit.captures()
    assert [c["position"] for c in sent] == ORDER
    for c in sent:
        assert c["sign"] == {"convention": "ios", "detected_from": "platform"}
        assert c["redo"] is False and c["unit"] == "m/s^2" and c["gyr_unit"] == "deg/s"
        assert len(c["acc"]) >= 10 and np.all(np.diff(c["t_ms"]) > 0) and len(c["gyr"]) == len(c["acc"])
        assert c["t_ms"][-1] - c["t_ms"][0] >= 1000
        # turned back into the W3C sign by the page: exactly the reading, negated twice
        np.testing.assert_array_equal(np.array(c["acc"]), np.tile(reading(c["position"]), (len(c["acc"]), 1)))

    # The closed form of Georgieva et al. section 3.3.1 on the readings, as the page's JSON download.
    expected = fit_six_position(np.array([reading(label) for label in POSES]), POSES, gravity=G)
    doc = json.loads(webkit.download("json"))
    np.testing.assert_allclose(np.array(doc["model"]["X"]), expected.X, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(np.array(doc["model"]["y"]), expected.y, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(doc["gyroscope"]["bias"], np.radians(GYRO_DEG_S), rtol=1e-12)
    assert webkit.text("#result-gyro").startswith("Gyroscope bias: 0.300, -0.200, 0.100 °/s")

    # The verdict first, the file for a phone app under it, every format below.
    full = webkit.stored(server, "six", f"/calibrations/{doc['id']}")
    assert webkit.text("#verdict-words") == full["verdict"]["words"]
    # six poses, twelve unknowns: no pose is left to test on, and the verdict says on what it stands
    assert full["verdict"]["words"].startswith("Apply it: error on the 6 poses fitted ")
    assert webkit.js("document.querySelector('#use-file').dataset.format") == "json"
    names = webkit.js("[...document.querySelectorAll('#downloads a')].map(a => a.textContent)")
    assert names == ["JSON", "C header", "ArduPilot", "PX4", "Betaflight", "INAV", "YAML", "CSV"]
    rows = webkit.js("[...document.querySelectorAll('#norm-table tbody tr')].map(r => r.cells[0].textContent)")
    assert rows == POSES
    assert webkit.js("document.querySelectorAll('#norm-chart svg circle').length") == 12
    assert webkit.errors() == []
    # Hands-free in WebKit as on iOS 16.4+: the browser's own wake lock, granted from the Start tap, and
    # a tone for each capture's start and end (the last one the long "finished"); no navigator.vibrate
    # (as on iOS), and nothing breaks for it.
    assert webkit.js("window.__phone.wakeLocks") == ["screen: granted"]
    assert webkit.js("window.__phone.tones") == [523, 880] * 5 + [523, 660]
    assert webkit.js("navigator.vibrate === undefined")

    for width in (1280,):  # the phone's 390 px is checked above; WebKitGTK's window is at least 334 px
        webkit.resize(width, 800)
        assert not webkit.scrolls_sideways(), f"the result scrolls sideways at {width} px"
        webkit.shot(f"six_result_{width}")


def test_a_repeated_pose_is_refused_aloud_and_redo_replaces_it_in_webkit(webkit, server):
    webkit.open(server.url + "/wizard?capture_s=1")
    webkit.with_motion()
    webkit.set(reading("+z"), (0.0, 0.0, 0.0))
    webkit.tap_start()
    webkit.wait_for(CAPTURED.format("+z"))
    webkit.set((3.0, 3.0, 8.8))  # picked up and tilted...
    webkit.wait("document.querySelector('#still-text').textContent === 'Moving'", 5, "the move")
    webkit.set(reading("+z"))  # ...and put down screen up again
    webkit.wait(
        "document.querySelector('#instruction').textContent.includes('Flat, screen up is already captured')",
        10,
        "the refusal of the repeat",
    )
    assert "Flat, screen up is already captured" in webkit.text("#status")  # announced to a screen reader
    webkit.shot("six_repeat_refused")
    assert webkit.js("window.__phone.tones") == [523, 880, 220]  # start, captured, refused
    assert len(webkit.captures()) == 1
    webkit.click('#poses button[data-redo="+z"]')
    webkit.wait(
        "document.querySelectorAll('#poses li[data-state=done]').length === 1 && window.__phone.captures.length === 2",
        20,
        "the redo of +z",
    )
    assert [c["redo"] for c in webkit.captures()] == [False, True]
    assert webkit.errors() == []
