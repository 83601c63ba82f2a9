"""The words of the other source on a wizard page: a board's page (``/wizard?…&source=board``) says
nothing of a phone, a phone's page nothing of a board. ``other_source_words(page, source)`` reads what a
person sees and hears of the page as it stands (its title, the visible text, the names of its visible
pictures and controls) and returns the other source's words found there.

The places a page names the other source on purpose are listed in ALLOWED: a phone's page links to
the same flow with a board (“Connect a board instead”), for a person who came to the wrong one; a
result's menu *I will use it with* lists every use of a calibration (app/web/uses.py), a phone app among
them, whichever source made it.
"""

from __future__ import annotations

import re

OTHER_WORDS = {
    "board": [r"phone", r"\bscreen", r"\bcase\b", r"motion access", r"motion data", r"earpiece", r"charging port"],
    "phone": [r"board", r"\bUSB\b", r"serial", r"\bbaud\b", r"silkscreen", r"component side"],
}
"""Per page source, the words of the other one (regular expressions, case-insensitive)."""

ALLOWED = {
    "phone": ["Calibrating a board that prints its readings? Connect a board instead."],
    "board": ["I will use it with a phone app"],
}
"""Sentences that name the other source on purpose, left out before the check."""

SEEN = """() => {
  const visible = (el) => {
    for (let e = el; e && e !== document.documentElement; e = e.parentElement) {
      if (e.hidden || getComputedStyle(e).display === "none"
          || getComputedStyle(e).visibility === "hidden") return false;
    }
    return true;
  };
  const names = [...document.querySelectorAll("[aria-label], [alt], [title]")].filter(visible)
    .map((el) => [el.getAttribute("aria-label"), el.getAttribute("alt"), el.getAttribute("title")]
      .filter(Boolean).join(" "));
  const svgText = [...document.querySelectorAll("svg text")].filter(visible).map((t) => t.textContent);
  return [document.title, document.body.innerText, ...names, ...svgText].join("\\n");
}"""


def other_source_words(page, source: str) -> list[str]:
    """The other source's words on the page as it stands, each with the text around it."""
    text = page.evaluate(SEEN)
    text = re.sub(r"\s+", " ", text)
    for sentence in ALLOWED[source]:
        text = text.replace(sentence, "")
    found = []
    for word in OTHER_WORDS[source]:
        for m in re.finditer(word, text, flags=re.I):
            found.append(f"{m.group(0)!r} in …{text[max(0, m.start() - 50) : m.end() + 50]}…")
    return found


def assert_only_its_words(page, source: str) -> None:
    """Fails, naming them, when the page shows the other source's words."""
    found = other_source_words(page, source)
    assert not found, f"a {source}'s page shows the other source's words:\n" + "\n".join(found)
