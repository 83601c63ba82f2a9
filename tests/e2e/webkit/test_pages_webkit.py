"""What WebKit shows where iOS has no sensor or no phone page: the compass flow without a Magnetometer
(Safari has none) and the start page."""

from __future__ import annotations

import pytest


def test_the_compass_flow_says_safari_has_no_magnetometer(webkit, server):
    webkit.open(server.url + "/wizard?protocol=compass")
    webkit.wait("!document.querySelector('#compass-none').hidden", 5, "the no-magnetometer card")
    assert webkit.js("document.querySelector('#compass-start').hidden")
    text = webkit.text("#compass-none")
    assert "Safari and Firefox do not have it" in text and "phyphox" in text
    assert webkit.js("document.querySelector('#compass-upload-link').getAttribute('href')") == "/"
    assert not webkit.scrolls_sideways()
    webkit.shot("compass_no_magnetometer")
    assert webkit.js("window.__phone === undefined")  # nothing injected: what the page itself did


@pytest.mark.parametrize("width", [390, 1280])
def test_the_start_page_reads_in_webkit(webkit, server, width):
    webkit.open(server.url + "/", (width, 844))
    assert "Calibrate" in webkit.text("h1, h2")
    assert not webkit.scrolls_sideways(), f"/ scrolls sideways at {width} px"
    webkit.shot(f"start_page_{width}")
