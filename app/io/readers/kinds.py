"""The kinds of file trical reads, by their names' suffixes: the one list that the page's file chooser offers
and that the refusal of a file of no known format names.

Each entry is a description and the suffixes such files carry. The readers recognise most formats by
their content (:data:`app.io.readers.DETECTORS`), not by the suffix; the suffixes are for the file
chooser and for the messages.
"""

from __future__ import annotations

FILE_KINDS = (
    (
        "CSV or text logs (a header row, or numbers from the first line; phone apps' and makers' exports)",
        (".csv", ".txt", ".tsv", ".log", ".dat"),
    ),
    ("JSON arrays of samples", (".json",)),
    ("zips: phyphox and Sensor Logger exports, or a zip of log files (one per pose, or one per sensor)", (".zip",)),
    ("PX4 ULog flight logs", (".ulg",)),
    ("ArduPilot DataFlash flight logs", (".bin",)),
    ("NumPy arrays", (".npy",)),
    ("Parquet tables", (".parquet", ".pq")),
    (
        "wearable device files (Axivity .cwa, ActiGraph .gt3x, GENEActiv .bin; with the optional actipy package)",
        (".cwa", ".gt3x"),
    ),
)
"""What trical reads: a description and the suffixes of such files."""

TEXT_SUFFIXES = (*FILE_KINDS[0][1], *FILE_KINDS[1][1])
"""Text files (CSV-like and JSON), known by their content whatever their name."""

ACCEPTED_SUFFIXES = tuple(dict.fromkeys(s for _, suffixes in FILE_KINDS for s in suffixes))
"""Every suffix of :data:`FILE_KINDS`, once: the page's file chooser offers these."""


NAMED_SUFFIXES = tuple(s for s in ACCEPTED_SUFFIXES if s not in TEXT_SUFFIXES)
"""Suffixes that name their file's kind (zips, arrays, flight and wearable logs): an upload keeps them."""


def formats_read() -> str:
    """The formats trical reads, in words, for a message refusing a file of no known format."""
    return "; ".join(f"{what} ({', '.join(suffixes)})" for what, suffixes in FILE_KINDS)
