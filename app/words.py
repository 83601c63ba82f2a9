"""A message in the words of where it is read: the API's, the command line's or the page's.

Messages are written once, where the problem is found (app/io, app/workflows, the core), in the API's
words: a parameter is named as the API spells it. This module is the one place that says each parameter
in the other two places a person reads it (docs/conventions.md, "Messages in the words of where they are
read"): :data:`VOCABULARY` holds, per parameter, the command line's option and the page's control, and
:func:`render` rewrites a message for a reader. The API's error handler (app/api/errors.py) and the
routes render for the page when the request comes from it (the ``X-Trical-Client: page`` header the
page's ``static/js/api.js`` always sends); ``trical`` renders for the command line.

A message names a parameter in one of these forms, and only these are rewritten:

- an identifier with an underscore, bare: ``acc_unit``, ``sampling_rate_hz``;
- any parameter in code form: ```columns```, or with its value, ``chip=mpu6050-2g``, ``sign=-1``;
- a validation error's location, ``gravity: Input should be …``;
- ``method`` or ``chip`` followed by one of their values: ``method auto``, ``chip mpu6050-2g``;
- a plain word where :attr:`Term.word` says it is the parameter: ``chip`` (not ``chip's``), ``columns``
  before ``names``.

Any other plain English word (the unit, the sign, the columns of a file) is never taken for a parameter.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any, TypeVar

from app.calibration.shared.headlines import SENSOR_WORDS
from app.calibration.shared.plausible import UNIT_WORDS as PHYSICAL_UNIT_WORDS
from app.io.readers.chips import CHIPS
from app.methods import TABLE as METHOD_TABLE

READERS = ("api", "cli", "page")
"""Where a message is read."""

CLIENT_HEADER = "X-Trical-Client"
"""The request header that says who reads the answer; ``page`` from the pages' fetch wrapper."""

PAGE_HEADER = "X-Trical-Page"
"""The path of the page that sends the request (``/``, ``/wizard`` …), for words that differ by page."""

UNIT_WORDS = {**PHYSICAL_UNIT_WORDS, "raw": "counts"}
"""Each unit as a person reads it (the start page's unit menus show these): the core's words of the physical
units (app/calibration/shared/plausible.py), and counts."""

UNITS_CARD = "“Units, as the data show them”"
OPTIONS = "the upload's Options"
IMPORT_CARD = "“Bring in a calibration a device already holds”, on the history page"


@dataclass(frozen=True)
class Term:
    """One parameter of the API and how the command line and the page say it.

    ``cli`` is the option (``--unit``) or, for a parameter the command has no option for, words;
    None for ``--`` + the name with dashes. ``page`` names the page's control; ``page_value`` says the
    parameter with a value (``{value}``: the value in words); ``pages`` holds other words on a page
    whose control differs (by the page's path). ``values`` are words for its values, on the page and
    (``cli_values``) on the command line.
    """

    name: str
    page: str
    page_value: str | None = None
    cli: str | None = None
    pages: dict[str, str] = field(default_factory=dict)
    values: dict[str, str] = field(default_factory=dict)
    cli_values: dict[str, str] = field(default_factory=dict)
    word: str | None = None
    """For a plain word: where it names the parameter without code form (a regex after it, e.g.
    ``(?! names)``); None: only in code form."""

    @property
    def option(self) -> str:
        return self.cli or "--" + self.name.replace("_", "-")


def _unit_term(sensor: str, words: str, cli: str) -> Term:
    return Term(
        f"{sensor}_unit",
        f"the {words}'s unit menu (in {UNITS_CARD})",
        "{value} in the " + words + f"'s unit menu (in {UNITS_CARD})",
        cli=cli,
        values=UNIT_WORDS,
    )


_METHOD_PAGE = {method.name: method.page_words for method in METHOD_TABLE}
_METHOD_CLI = {method.name: f"trical {method.command}" for method in METHOD_TABLE if method.command != "calibrate"}
"""A method on the page and, for one with a command of its own, on the command line (the method table's)."""

VOCABULARY: dict[str, Term] = {
    t.name: t
    for t in (
        _unit_term("acc", SENSOR_WORDS["acc"], "--unit"),
        _unit_term("gyr", SENSOR_WORDS["gyr"], "--gyr-unit"),
        _unit_term("mag", SENSOR_WORDS["mag"], "--mag-unit"),
        Term(
            "lsb_per_g",
            f"the sensor's part menu (in {UNITS_CARD})",
            "an accelerometer part of {value} LSB per g (in its part menu, in " + UNITS_CARD + ")",
        ),
        Term(
            "chip",
            word=r"(?!'s)",
            page=f"the sensor's part menu (in {UNITS_CARD})",
            page_value="the part {value} (in its sensor's part menu, in " + UNITS_CARD + ")",
            values={name: chip.label for name, chip in CHIPS.items()},
        ),
        Term(
            "columns",
            word=r"(?= names\b)",
            page="“Which column is which?” (or the column names in " + OPTIONS + ")",
            page_value="the column names {value} (in " + OPTIONS + ", or “Which column is which?”)",
        ),
        Term(
            "sign",
            f"the Sign menu (in {OPTIONS})",
            "the Sign menu set to {value} (in " + OPTIONS + ")",
            values={"1": "keep the file's accelerations", "-1": "negate them"},
        ),
        Term(
            "sampling_rate_hz",
            f"the Sampling rate (Hz) (in {OPTIONS})",
            "a Sampling rate (Hz) of {value} (in " + OPTIONS + ")",
        ),
        Term("format", "a file named for its format (.csv, .zip, .ulg, .bin)", cli="--log-format"),
        Term("output_format", "the output's format", cli="--format"),
        Term("instance", "the “IMU read” menu", "IMU {value} in the “IMU read” menu"),
        Term("mag_instance", "the “Compass read” menu", "compass {value} in the “Compass read” menu"),
        Term(
            "latitude_deg",
            "the Latitude",
            "a Latitude of {value}°",
            pages={"/wizard": "your location (“Use my location for the reference field”)"},
        ),
        Term(
            "longitude_deg",
            "the Longitude",
            "a Longitude of {value}°",
            pages={"/wizard": "your location (“Use my location for the reference field”)"},
        ),
        Term("date", "the Date of the turn", pages={"/wizard": "today's date (the page sends it with your location)"}),
        Term("height_m", "the height (the page takes none: the latitude alone is used)"),
        Term(
            "field_ut",
            "the field's strength (µT)",
            "a field's strength of {value} µT",
            pages={"/wizard": "your location (“Use my location for the reference field”)"},
        ),
        Term("attitude", "the “Attitude from” menu", "{value} in the “Attitude from” menu"),
        Term(
            "window",
            "the “Part of the log fitted” menu",
            "{value} in the “Part of the log fitted” menu",
            values={"all": "every sample", "flying": "the flying part"},
        ),
        Term("from_s", "the From (s)", "a From (s) of {value}"),
        Term("to_s", "the To (s)", "a To (s) of {value}"),
        Term("gravity", "the Gravity (m/s²)", "a Gravity of {value} m/s²"),
        Term("unit", "the Unit menu", "{value} in the Unit menu", values=UNIT_WORDS),
        Term("method", "the kind of calibration", "{value}", values=_METHOD_PAGE, cli_values=_METHOD_CLI),
        Term("device_id", "the Device name", "the Device name {value}"),
        Term("recording_id", "an uploaded log", cli="the log file"),
        Term("readings", "the six readings", cli="the log file"),
        Term("means", "the still readings", cli="the log file"),
        Term("segments", "the still segments", cli="the log file"),
        Term("mag", "the magnetometer's readings", cli="the log file"),
        Term(
            "firmware",
            f"the Firmware menu (in {IMPORT_CARD})",
            "{value} in the Firmware menu (in " + IMPORT_CARD + ")",
        ),
        Term("file_base64", f"the File (in {IMPORT_CARD})", cli="the file"),
    )
}
"""Every parameter a message may name, and its words on the command line and on the page."""

_SPACED = {"method": tuple(_METHOD_PAGE), "chip": tuple(CHIPS)}
"""Parameters a message may name with a value after a space (``method auto``, ``chip mpu6050-2g``)."""

_VALUE = r"[^\s;)`]+?(?=[\s;)`]|[.,:](?:\s|$)|$)"
_NAMES = "|".join(sorted(map(re.escape, VOCABULARY), key=len, reverse=True))
_SPACED_RE = "|".join(
    rf"{name} `?(?:{'|'.join(sorted(map(re.escape, values), key=len, reverse=True))})(?:,[a-z0-9-]+)*`?(?![\w-])"
    for name, values in _SPACED.items()
)
TOKEN = re.compile(
    rf"(?P<spaced>\b(?:{_SPACED_RE}))"
    rf"|(?:the field )?`(?P<tick>{_NAMES})`"
    rf"|(?<![\w.\-])(?P<assign>{_NAMES})=(?P<value>{_VALUE})"
    rf"|(?:^|(?<=; ))(?P<loc>{_NAMES})(?P<path>(?:\[\d+\]|\.\w+)*): "
    rf"|(?<![\w.\-])(?P<bare>{'|'.join(n for n in _NAMES.split('|') if '_' in n)})(?![\w-])"
    + "".join(rf"|(?<![\w.\-`'])(?P<word_{t.name}>{t.name})(?![\w-]){t.word}" for t in VOCABULARY.values() if t.word)
)
"""A parameter named in a message, in one of the forms the module's docstring lists."""


def _word(m: re.Match) -> str:
    """The parameter of a match named without a value."""
    return m["tick"] or m["bare"] or next(v for k, v in m.groupdict().items() if k.startswith("word_") and v)


def _value_words(term: Term, value: str, reader: str) -> str:
    table = term.cli_values if reader == "cli" else term.values
    return ",".join(table.get(v, v) for v in value.split(",")) if reader == "page" else table.get(value, value)


def _say(term: Term, value: str | None, reader: str, page: str | None) -> str:
    if reader == "cli":
        if value is None:
            return term.option
        if value in term.cli_values:
            return term.cli_values[value]
        return f"{term.option} {value}"
    words = term.pages.get(page or "", term.page)
    if value is None:
        return words
    if page in term.pages:
        return words
    return (term.page_value or words + " set to {value}").format(value=_value_words(term, value, reader))


def render(text: str, reader: str = "api", page: str | None = None) -> str:
    """``text`` (in the API's words) as ``reader`` reads it: ``api`` unchanged, ``cli`` with the command's
    options, ``page`` with the page's controls (those of the page at path ``page`` where they differ).

    >>> render("give chip or lsb_per_g for another scale, or acc_unit=raw to calibrate in counts", "cli")
    'give --chip or --lsb-per-g for another scale, or --unit raw to calibrate in counts'
    """
    if reader == "api" or not isinstance(text, str):
        return text

    said: set[str] = set()

    def one(m: re.Match) -> str:
        out = _one(m)
        said.add(out)
        return out

    def _one(m: re.Match) -> str:
        if m["spaced"]:
            name, _, value = m["spaced"].partition(" ")
            return _say(VOCABULARY[name], value.strip("`"), reader, page)
        if m["assign"]:
            return _say(VOCABULARY[m["assign"]], m["value"], reader, page)
        if m["loc"]:
            term = VOCABULARY[m["loc"]]
            if reader == "cli" and (m["path"] or not term.option.startswith("--")):
                return m[0]  # a request's inner field: the command has no option of its own for it
            return _say(term, None, reader, page) + ": "
        return _say(VOCABULARY[_word(m)], None, reader, page)

    out = TOKEN.sub(one, text)
    for words in said:  # "latitude_deg and longitude_deg" where one control gives both: said once
        once = re.escape(words)
        out = re.sub(rf"{once}(?:(?:,| and| or| /) {once}| \(or {once}\))+", words, out)
    for where in (f"in {UNITS_CARD}", f"in {OPTIONS}"):  # where the controls are: said once a message
        first = out.find(where) + len(where)
        if first >= len(where):
            out = out[:first] + re.sub(rf"(?: \({re.escape(where)}\)|, {re.escape(where)}(?=\)))", "", out[first:])
    return out[:1].upper() + out[1:] if reader == "page" and text[:1].isupper() else out


def named(text: str) -> list[str]:
    """The parameters a message (in the API's words) names, in order, once each."""
    found = []
    for m in TOKEN.finditer(text or ""):
        name = (m["spaced"] or "").partition(" ")[0] or m["assign"] or m["loc"] or _word(m)
        found.append(name)
    return list(dict.fromkeys(found))


def asked(text: str) -> list[str]:
    """The parameters a message asks for: those it names but ``method``, which a message names as what
    was asked of trical (``method noise needs …``), not as something to give."""
    return [name for name in named(text) if name != "method"]


MESSAGE_KEYS = ("detail", "warnings", "notes", "reasons", "words", "why", "headline", "cv_note", "note")
"""The keys of an answer whose strings are messages (the rest are data, never rewritten)."""


_Body = TypeVar("_Body")
"""An answer's type, which :func:`render_body` keeps."""


def render_body(body: _Body, reader: str = "api", page: str | None = None) -> _Body:
    """An answer (a dict of lists and dicts) with every message under :data:`MESSAGE_KEYS` rendered for
    ``reader``; the data are left as they are. ``api``: the body itself."""
    if reader == "api":
        return body

    def walk(node: Any, message: bool = False) -> Any:
        if isinstance(node, dict):
            return {k: walk(v, k in MESSAGE_KEYS) for k, v in node.items()}
        if isinstance(node, list):
            return [walk(v, message) for v in node]
        return render(node, reader, page) if message and isinstance(node, str) else node

    return walk(body)


def reader_of(headers) -> tuple[str, str | None]:
    """Who reads the answer to a request with ``headers``: (``page``, its path) from the page, else
    (``api``, None)."""
    if (headers.get(CLIENT_HEADER) or "").strip().lower() == "page":
        return "page", headers.get(PAGE_HEADER) or None
    return "api", None
