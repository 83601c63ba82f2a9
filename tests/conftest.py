"""Shared fixtures: seed tables (copied into tests/data) and a fresh application per test."""

from __future__ import annotations

import itertools
import os
from pathlib import Path

import numpy as np
import pytest
from fastapi.testclient import TestClient

from app.config import Settings
from app.main import create_app

DATA = Path(__file__).parent / "data"
E2E = Path(__file__).parent / "e2e"
WEBKIT = E2E / "webkit"


BROWSER_MODULE_SECONDS = {
    "test_layout.py": 275,
    "test_wizard_cube.py": 177,
    "test_wizard.py": 134,
    "test_wizard_free.py": 105,
    "test_result_page.py": 101,
    "webkit/test_cube_webkit.py": 100,
    "test_board.py": 92,
    "test_wizard_cues.py": 75,
    "test_start_page.py": 58,
    "test_wizard_compass.py": 45,
    "webkit/test_free_webkit.py": 38,
    "test_flight_compass_page.py": 33,
    "webkit/test_six_webkit.py": 31,
    "test_recording_decides.py": 31,
}
"""The browser modules' real time (s) as `pytest --durations=0` measured it here (a module not named: 5 s a
test), for :func:`spread_browser_tests`; weights, not bounds: no test asserts them."""


def pytest_collection_modifyitems(config, items):
    """Every test under tests/e2e drives a real browser: marked `e2e` by its folder, so that
    `pytest -m "not e2e"` is the quick loop while developing."""
    for item in items:
        if E2E in Path(item.path).parents:
            item.add_marker(pytest.mark.e2e)
    spread_browser_tests(items, int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1")))


def spread_browser_tests(items: list, workers: int) -> None:
    """Order the tests so that each of `make test`'s workers starts with its share of the browser tests, the
    longest module first.

    pytest-xdist's work stealing hands worker k the k-th of ``workers`` consecutive slices of this order (each
    ``remaining // workers_left`` long), and an idle worker steals the back half of a busy one's queue. The
    browser modules (two thirds of the suite's time, a few long real-time flows each) were all in the first
    slice: the other workers stole its quick tests from the back and the long flows ran one after another on
    one worker. They are shared out by their measured time (the longest first, to the least loaded worker,
    a module kept whole for its server), each slice filled up with the other tests in their order."""
    browser = [item for item in items if E2E in Path(item.path).parents]
    others = [item for item in items if E2E not in Path(item.path).parents]
    modules: dict[Path, list] = {}
    for item in browser:
        modules.setdefault(Path(item.path), []).append(item)

    def seconds(path: Path) -> float:
        return BROWSER_MODULE_SECONDS.get(path.relative_to(E2E).as_posix(), 5.0 * len(modules[path]))

    shares: list[list] = [[] for _ in range(max(workers, 1))]
    loads = [0.0] * len(shares)
    for path in sorted(modules, key=seconds, reverse=True):
        k = loads.index(min(loads))
        shares[k] += modules[path]
        loads[k] += seconds(path)
    order, rest = [], iter(others)
    for k, share in enumerate(shares):
        size = (len(items) - len(order)) // (len(shares) - k)
        order += share + list(itertools.islice(rest, max(0, size - len(share))))
    items[:] = order + list(rest)


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
