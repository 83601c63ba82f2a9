"""The presenters of the core's results (app/headlines.py, app/web/result_pages.py) key their tables by a result
class's name, so that a command loads only its own method's models: every name must be a class of the core's
registry or one of their bases, or its entry would never be used."""

from __future__ import annotations

import pytest

from app.calibration.registry import registered_classes
from app.headlines import HEADLINES, VERDICT_NOTES
from app.web.result_pages import PAGE_FACTS

CLASS_NAMES = {base.__name__ for cls in registered_classes() for base in cls.__mro__}


@pytest.mark.parametrize(
    ("table", "names"), [("HEADLINES", HEADLINES), ("VERDICT_NOTES", VERDICT_NOTES), ("PAGE_FACTS", PAGE_FACTS)]
)
def test_every_name_a_presenter_keys_is_a_result_class(table, names):
    assert set(names) <= CLASS_NAMES, (table, sorted(set(names) - CLASS_NAMES))


def test_a_misspelled_name_is_caught():
    assert "AffineCalibrations" not in CLASS_NAMES and "AffineCalibration" in CLASS_NAMES
