"""A stored calibration's page and the history in WebKit (Safari's engine) at a phone's and a desktop's
width: the verdict, the file to use and every format read back from /c/{id}; the history's row, its
device filter and the device's latest calibration as one link."""

from __future__ import annotations

import httpx
import pytest

from app.calibration import CANONICAL_SIX

UPS = ([-1, 0, 0], [1, 0, 0], [0, -1, 0], [0, 1, 0], [0, 0, -1], [0, 0, 1])


def stored(url: str, device: str) -> dict:
    """A six-position calibration of slightly scaled readings, stored for `device` on a keyless server."""
    readings = [{"up": up, "mean": [9.80665 * 1.01 * v + 0.05 for v in vec]} for up, vec in zip(CANONICAL_SIX, UPS)]
    r = httpx.post(
        url + "/api/v1/calibrations",
        json={"method": "six_position", "readings": readings, "device_id": device},
        timeout=60,
    )
    assert r.status_code == 201, r.text
    return r.json()


@pytest.mark.parametrize("width", [390, 1280])
def test_a_calibration_s_page_and_the_history_read_in_webkit(webkit, server, width):
    cal = stored(server.url, f"wk-board-{width}")
    webkit.open(f"{server.url}/c/{cal['id']}", (width, 844))
    webkit.wait("document.querySelector('#downloads').dataset.ready === 'true'", 20, "the files of the calibration")
    assert webkit.text("#verdict-words") == cal["verdict"]["words"]
    assert f"wk-board-{width}" in webkit.text("#cal-meta")
    assert webkit.js("document.querySelectorAll('#downloads a').length") >= 4
    webkit.wait("!!document.querySelector('#correction-acc-M td')", 20, "the correction M, o in the details")
    assert not webkit.js("document.querySelector('#send').hidden")  # Send to my computer, offered
    assert webkit.js("document.querySelectorAll('#norm-chart svg circle').length") == 12
    assert not webkit.scrolls_sideways(), f"/c/{{id}} scrolls sideways at {width} px"
    webkit.shot(f"calibration_page_{width}")

    webkit.open(f"{server.url}/history?device=wk-board-{width}", (width, 844))
    webkit.wait(f"!!document.querySelector(\"#history-table tr[data-id='{cal['id']}']\")", 20, "the history's row")
    assert webkit.js("document.querySelectorAll('#history-table tbody tr').length") == 1
    assert webkit.js("document.querySelector('#history-device').value") == f"wk-board-{width}"
    assert (
        webkit.js("document.querySelector('#history-latest-link').getAttribute('href')")
        == f"/c/latest?device=wk-board-{width}"
    )
    assert not webkit.scrolls_sideways(), f"/history scrolls sideways at {width} px"
    webkit.shot(f"history_{width}")
    webkit.click("#history-latest-link")
    webkit.wait(
        "document.querySelector('#downloads') && document.querySelector('#downloads').dataset.ready === 'true'",
        20,
        "the device's latest calibration",
    )
    assert cal["id"] in webkit.text("#cal-meta")
    assert webkit.errors() == []
