"""A person's journey through the pages, from the start page to the file or packet that goes to the device: what
they do (each click, choice, typed field, file chosen or code scanned is one action) and the seconds it takes,
less the seconds the test spends looking (screenshots, axe, layout checks). The end-to-end tests of the three
journeys (a phone, a board, a drone's log) print it and keep it in test-artifacts/journey_<name>.txt."""

from __future__ import annotations

import re
import time
from contextlib import contextmanager

from tests.e2e.conftest import ARTIFACTS


class Journey:
    """The actions and seconds of one journey (``name``), from its construction."""

    def __init__(self, name: str):
        self.name = name
        self.actions: list[str] = []
        self.t0 = time.monotonic()
        self.aside = 0.0

    def act(self, what: str) -> None:
        """One thing the person does that the test does not do through :meth:`click`."""
        self.actions.append(what)

    def click(self, page, selector: str, what: str | None = None) -> None:
        self.act(what or selector)
        page.click(selector)

    @contextmanager
    def looking(self):
        """Seconds the test spends looking at the page, which are not the person's."""
        t = time.monotonic()
        try:
            yield
        finally:
            self.aside += time.monotonic() - t

    def seconds(self) -> float:
        return time.monotonic() - self.t0 - self.aside

    def report(self, end: str, person_s: float = 0.0, why: str = "") -> str:
        """Print and keep the journey's figures: its actions, its seconds on this machine to ``end``, and with
        ``person_s`` the seconds a person adds that the test does not wait (longer captures, turning the device)."""
        s = self.seconds()
        note = (
            f"{self.name}: {len(self.actions)} actions ({'; '.join(self.actions)}), {s:.1f} s from the start page "
            f"to {end}"
        )
        if person_s:
            note += f"; about {s + person_s:.0f} s for a person ({why})"
        print("\n" + note)
        ARTIFACTS.mkdir(exist_ok=True)
        slug = re.sub(r"[^a-z0-9]+", "_", self.name.lower()).strip("_")
        (ARTIFACTS / f"journey_{slug}.txt").write_text(note + "\n")
        return note
