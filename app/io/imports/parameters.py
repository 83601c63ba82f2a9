"""Parameter files as text: names and values, whatever the ground station wrote.

* Mission Planner's ``.param``: ``NAME,VALUE`` a line;
* MAVProxy's and ArduPilot's ``.parm``: ``NAME VALUE`` (spaces or a tab), ``#`` comments;
* QGroundControl's ``.params``: ``vehicle<TAB>component<TAB>NAME<TAB>VALUE<TAB>type``, ``#`` comments;
* PX4's shell: ``param set NAME VALUE`` (what trical's own ``px4`` export writes).
"""

from __future__ import annotations

import re

NAME = re.compile(r"^[A-Z][A-Z0-9_]*$")

QGC_VERSION = re.compile(r"^#\s*Version:\s*(\S+)")
"""QGroundControl's header names the firmware's version (``# Version: 1.12.3 dev``)."""


def parse(text: str) -> tuple[dict[str, float], str, str | None]:
    """The parameters of a parameter file, the kind of file and the version its header states.

    Returns
    -------
    (dict, str, str or None)
        Name → value (the last of a name), the file's kind in words, the version (or None). Lines that are
        not a parameter (comments, blank lines, a value that is not a number) are left out.
    """
    params: dict[str, float] = {}
    kinds: dict[str, int] = {}
    version = None
    for raw in text.splitlines():
        line = raw.strip()
        if not line:
            continue
        if line.startswith("#"):
            found = QGC_VERSION.match(line)
            if found:
                version = found.group(1)
            continue
        line = line.split("#", 1)[0].strip()
        parts = line.split("\t")
        if len(parts) >= 4 and parts[0].strip().isdigit() and parts[1].strip().isdigit():
            kind, name, value = "QGroundControl .params", parts[2].strip(), parts[3].strip()
        elif line.startswith("param set "):
            fields = line.split()
            if len(fields) < 4:
                continue
            kind, name, value = "PX4 param set lines", fields[2], fields[3]
        elif "," in line:
            name, _, value = (p.strip() for p in line.partition(","))
            kind = "Mission Planner .param"
        else:
            fields = line.split()
            if len(fields) < 2:
                continue
            kind, name, value = "MAVProxy .parm", fields[0], fields[1]
        if not NAME.match(name):
            continue
        try:
            params[name] = float(value)
        except ValueError:
            continue
        kinds[kind] = kinds.get(kind, 0) + 1
    kind = max(kinds, key=lambda k: kinds[k]) if kinds else ""
    return params, kind, version
