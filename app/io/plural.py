"""A count with its noun in the number it takes: ``1 still reading``, ``6 still readings``."""

from __future__ import annotations


def counted(n: int, noun: str, plural: str | None = None) -> str:
    """``n`` and ``noun``, plural unless ``n`` is 1 (``plural``, else the noun with an s).

    >>> counted(1, "still reading"), counted(6, "still reading"), counted(2, "position(s)", "positions")
    ('1 still reading', '6 still readings', '2 positions')
    """
    return f"{n} {noun if n == 1 else (plural or noun + 's')}"
