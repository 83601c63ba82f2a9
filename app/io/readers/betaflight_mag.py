"""The Betaflight configurator's export of a compass tumble: a magnetometer characterization model (.json).

The configurator's Sensors tab guides a full tumble of the flight controller, fits an ellipsoid to
the compass samples it streamed, and its *export* button saves ``characterization_model_<date>.json``
(betaflight-configurator, ``src/js/utils/magModelExport.js`` ``buildCharacterizationModel`` and
``src/components/tabs/SensorsTab.vue`` ``exportFullCalModel``; schema
``https://betaflight.com/blackbox/mag-characterization-model/2.2``). The file holds the fit's result —
``ellipsoid_correction`` (``center``, ``soft_iron``, ``radius``, ``residual_rms``), ``hard_iron``,
``alignment``, ``geo_reference``, ``quality`` (with the ``sample_count``) and ``downstream_fusion`` — but
none of the samples: trical, which calibrates from samples, refuses it naming what it holds and what to
upload instead.

The configurator's other export of the tumble, ``calibration_samples_<time>.json`` (``"type":
"calibration_tumble"``), holds the samples themselves: each the flight controller's magnetometer ``x``,
``y``, ``z`` in the counts MSP reports, a ``timestamp`` in ms, and what the configurator drew with it (its
``roll``, ``pitch``, ``heading``, the quaternion ``qw`` … ``qz``, ``field_magnitude``, ``voxel_display``).
It is read as the compass's samples on their timestamps; the rest is named in a note.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

from ..errors import LogFormatError
from .json_samples import Samples
from .table import Sniff

NAME = "betaflight_mag"
SCHEMA = "mag-characterization-model"
"""The part of the export's ``$schema`` address that names it."""
MAX_BYTES = 4 << 20
"""The export is a few kilobytes; a larger file is not one."""


TUMBLE = re.compile(r'"type"\s*:\s*"calibration_tumble"')
"""The samples' export of a tumble names its type near its start."""
TUMBLE_COLUMNS = {"timestamp": "time_ms", "x": "mag_x", "y": "mag_y", "z": "mag_z"}
"""A tumble sample's fields read, and the columns they are read as."""
MAX_TUMBLE_BYTES = 64 << 20


def detect(s: Sniff) -> bool:
    """A JSON object whose ``$schema`` names Betaflight's magnetometer characterization model, or the configurator's
    export of a tumble's samples."""
    if s.is_zip or not s.text.lstrip().startswith("{"):
        return False
    return SCHEMA in s.text[:4096] or TUMBLE.search(s.text[:4096]) is not None


def read(path: Path, s: Sniff, *, name: str = "the file") -> Samples:
    """Read a tumble's samples as the compass's; refuse the characterization model: it holds the configurator's
    fit, not the samples trical calibrates from.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    s : Sniff
        Its head, which names a tumble's type.
    name : str
        How to call the file in messages.

    Returns
    -------
    Samples
        The tumble's magnetometer on its timestamps (``time_ms, mag_x, mag_y, mag_z``), for
        :func:`app.io.readers.read_log` to read as a CSV table; the log is named ``betaflight_mag``.

    Raises
    ------
    LogFormatError
        The characterization model (naming what it holds), or a tumble without samples or lacking a field.
    """
    if TUMBLE.search(s.text[:4096]):
        return _tumble(path, name)
    try:
        model = json.loads(path.read_bytes()[:MAX_BYTES].decode("utf-8-sig"))
    except (ValueError, UnicodeDecodeError):
        model = {}
    model = model if isinstance(model, dict) else {}
    version = model.get("version") or "?"
    held = ", ".join(k for k in model if not k.startswith("$")) or "the fit's result"
    count = (model.get("quality") or {}).get("sample_count") if isinstance(model.get("quality"), dict) else None
    raise LogFormatError(
        f"{name} is the Betaflight configurator's magnetometer characterization model (version {version}): it holds "
        f"the configurator's own fit of the compass tumble ({held}) but none of the "
        f"{count if count is not None else ''}{' ' if count is not None else ''}samples it was fitted to, and trical "
        "calibrates from samples. Record the tumble's magnetometer samples instead (time, x, y, z on each line, as "
        "CSV or a JSON array of samples) and upload those",
        status=422,
    )


def _tumble(path: Path, name: str) -> Samples:
    """The tumble's samples as a table of the magnetometer on its timestamps, read as any table is."""
    if path.stat().st_size > MAX_TUMBLE_BYTES:
        raise LogFormatError(f"{name} is a tumble export over {MAX_TUMBLE_BYTES >> 20} MiB: no tumble is that long")
    data = json.loads(path.read_bytes().decode("utf-8-sig"))
    samples = data.get("samples") if isinstance(data, dict) else None
    if not isinstance(samples, list) or not samples or not all(isinstance(x, dict) for x in samples):
        raise LogFormatError(
            f"{name} is the Betaflight configurator's tumble export but holds no samples: export the tumble again "
            "after turning the flight controller through every direction"
        )
    missing = [k for k in TUMBLE_COLUMNS if any(k not in x for x in samples)]
    if missing:
        raise LogFormatError(
            f"{name} is the Betaflight configurator's tumble export, but its samples lack {', '.join(missing)}: "
            "export the tumble again with this configurator, or upload the samples as CSV (time_ms, mag_x, mag_y, "
            "mag_z)"
        )
    left = sorted({k for x in samples for k in x} - set(TUMBLE_COLUMNS))
    rows = [[x[k] for k in TUMBLE_COLUMNS] for x in samples]
    note = (
        f"the Betaflight configurator's compass tumble: {len(samples)} samples of the flight controller's "
        "magnetometer (x, y, z as MSP reports them) on their timestamps"
        + (f"; not read: {', '.join(left)} (the configurator's attitude and drawing)" if left else "")
    )
    return Samples(list(TUMBLE_COLUMNS.values()), rows, note, format=NAME)
