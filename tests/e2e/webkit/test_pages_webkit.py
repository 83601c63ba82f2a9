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


@pytest.mark.parametrize("width", [390, 1280])
def test_the_board_card_in_a_browser_without_web_serial_offers_the_upload_and_the_terminal(webkit, server, width):
    """WebKit (Safari's engine) has neither the Web Serial API nor Web Bluetooth: on a computer the board
    card says which browsers read a board, and offers the upload and `trical capture` instead."""
    webkit.open(server.url + "/wizard?protocol=six&source=board", (width, 900))
    webkit.wait("!document.querySelector('#board').hidden", 5, "the board card on a board's page")
    assert webkit.js("'serial' in navigator") is False and webkit.js("'bluetooth' in navigator") is False
    assert webkit.js("document.querySelector('#board-connect').hidden")
    assert webkit.js("document.querySelector('#board-usb').hidden && document.querySelector('#board-ble').hidden")
    text = webkit.text("#board-none")
    assert "Chrome, Edge and Opera" in text and "not in Safari or Firefox" in text
    assert "trical capture PORT" in text
    assert webkit.js("document.querySelector('#board-none a').getAttribute('href')") == "/"
    assert webkit.text("#board-h") == "Connect the board"
    assert not webkit.scrolls_sideways(), f"the board card scrolls sideways at {width} px"
    webkit.shot(f"board_no_web_serial_{width}")
    assert webkit.errors() == []
