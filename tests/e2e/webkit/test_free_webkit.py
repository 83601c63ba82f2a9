"""The free-pose flow in WebKit as on an iPhone: poses anywhere, one too close refused, the flow ending
at its target, and Farago et al.'s model equal to the fit of what the page was given."""

from __future__ import annotations

import numpy as np
import pytest

from app.workflows.still import calibrate_unknown
from tests.e2e.test_wizard import G
from tests.e2e.test_wizard_free import UPS, reading


def put_down(webkit, k: int) -> None:
    webkit.set(reading(UPS[k]))
    webkit.wait_for(f'#free-count[data-count="{k + 1}"]')


def test_free_poses_in_webkit_until_the_target(webkit, server):
    webkit.open(server.url + "/wizard?protocol=free&capture_s=1")
    assert "12 or more still poses" in webkit.text("#start")
    webkit.with_motion()
    webkit.set(reading(UPS[0]), (0.0, 0.0, 0.0))
    webkit.tap_start()
    webkit.wait_for('#free-count[data-count="1"]')
    put_down(webkit, 1)
    # Back at pose 2, after a move: refused in the page, nothing sent.
    webkit.set((1.0, 2.0, 9.0))
    webkit.wait("document.querySelector('#still-text').textContent === 'Moving'", 5, "the move")
    webkit.set(reading(UPS[1]))
    webkit.wait(
        "document.querySelector('#instruction').textContent.includes('within 10° of a pose already captured')",
        10,
        "the refusal of a pose too close",
    )
    webkit.shot("free_too_close")
    assert len(webkit.captures()) == 2
    for k in range(2, 11):
        put_down(webkit, k)
    assert webkit.js("document.querySelectorAll('#sphere circle.covered').length") == 11
    webkit.shot("free_eleven_poses")
    webkit.set(reading(UPS[11]))  # the twelfth: the readings carry no noise, the 2 mg target is met
    webkit.wait_for("#downloads[data-ready=true]", 30)
    assert webkit.text("#result-finish").startswith("Target reached: ")
    assert not webkit.scrolls_sideways()
    webkit.shot("free_result")

    session = webkit.stored(server, "free")
    cal = webkit.stored(server, "free", f"/calibrations/{session['calibration_id']}")
    assert cal["finish"]["reason"] == "target" and cal["finish"]["poses"] == 12
    result, _ = calibrate_unknown("triangular", np.array([reading(u) for u in UPS[:12]]), unit="m/s^2", gravity=G)
    np.testing.assert_allclose(cal["model"]["K"], result.K, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(cal["model"]["o"], result.o, rtol=1e-9, atol=1e-12)
    assert cal["metrics"]["cv_error_mg"] == pytest.approx(result.metrics["cv_error_mg"], rel=1e-6, abs=1e-9)
    assert webkit.text("#verdict-words") == cal["verdict"]["words"]
    assert all(c["sign"] == {"convention": "ios", "detected_from": "platform"} for c in webkit.captures())
    assert webkit.errors() == []
