"""Shared fixtures: seed tables (copied into tests/data) and a fresh application per test."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from fastapi.testclient import TestClient

from app.config import Settings
from app.main import create_app

DATA = Path(__file__).parent / "data"
E2E = Path(__file__).parent / "e2e"
WEBKIT = E2E / "webkit"


def pytest_collection_modifyitems(config, items):
    """Every test under tests/e2e drives a real browser: marked `e2e` by its folder, so that
    `pytest -m "not e2e"` is the quick loop while developing."""
    for item in items:
        if E2E in Path(item.path).parents:
            item.add_marker(pytest.mark.e2e)
    # The browser tests first, WebKit's before Chromium's: they are the longest (real-time flows), and
    # the workers of `make test` take tests in this order, so that none is left alone with a long one
    # at the end.
    items.sort(key=lambda item: 0 if WEBKIT in Path(item.path).parents else 1 if E2E in Path(item.path).parents else 2)


def seed_table(number: int) -> np.ndarray:
    """Rows of Georgieva et al. (ESGI'95) Table ``number`` (x, y, z in m/s²), as copied in tests/data."""
    return np.loadtxt(DATA / f"000_table{number}.csv", delimiter=",", skiprows=2)[:, 1:]


@pytest.fixture
def table1() -> np.ndarray:
    return seed_table(1)


@pytest.fixture
def table3() -> np.ndarray:
    return seed_table(3)


@pytest.fixture(scope="session")
def noise_three():
    """A noise calibration body of three sensors (tests/noise_bodies.py)."""
    from tests.noise_bodies import three_sensors_body

    return three_sensors_body()


@pytest.fixture(scope="session")
def noise_short():
    """A gyroscope noise body with null terms (tests/noise_bodies.py)."""
    from tests.noise_bodies import short_gyr_body

    return short_gyr_body()


def make_settings(tmp_path, **overrides) -> Settings:
    """The service's settings with its own SQLite file under ``tmp_path``."""
    return Settings(database_url=f"sqlite:///{tmp_path / 'trical.db'}", **overrides)


@pytest.fixture
def settings(tmp_path) -> Settings:
    return make_settings(tmp_path)


@pytest.fixture
def client(settings):
    """A fresh application with its own SQLite file, driven through TestClient."""
    with TestClient(create_app(settings), raise_server_exceptions=False) as c:
        yield c
