"""QR codes of an address, for a phone's camera: an SVG for the start page and a short link's."""

from __future__ import annotations

from functools import lru_cache


def _code(text: str):
    import segno

    # A full QR code, never a Micro QR code (phone cameras do not read those); M survives a glare.
    return segno.make_qr(text, error="m")


@lru_cache(maxsize=16)
def qr_svg_data_uri(text: str) -> str:
    """The QR code of `text` as an SVG ``data:`` URI for an ``<img src>``.

    Parameters
    ----------
    text : str
        What the code holds, usually a URL.

    Returns
    -------
    str
        ``data:image/svg+xml,...``, black on white with the standard quiet zone.
    """
    return _code(text).svg_data_uri(scale=4, dark="#000", light="#fff")
