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
"""

from __future__ import annotations

import json
from pathlib import Path

from ..errors import LogFormatError
from .table import Sniff

NAME = "betaflight_mag"
SCHEMA = "mag-characterization-model"
"""The part of the export's ``$schema`` address that names it."""
MAX_BYTES = 4 << 20
"""The export is a few kilobytes; a larger file is not one."""


def detect(s: Sniff) -> bool:
    """A JSON object whose ``$schema`` names Betaflight's magnetometer characterization model."""
    return not s.is_zip and s.text.lstrip().startswith("{") and SCHEMA in s.text[:4096]


def read(path: Path, s: Sniff, *, name: str = "the file", **_):
    """Refuse the export: it holds the configurator's fit, not the samples trical calibrates from."""
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
