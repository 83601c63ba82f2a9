"""Shared fixtures: seed tables (copied into tests/data) and a fresh application per test."""

from __future__ import annotations

import itertools
import os
import shutil
from pathlib import Path

import numpy as np
import pytest
from fastapi import FastAPI
from fastapi.testclient import TestClient

from app.config import Settings
from app.main import create_app
from app.store import open_store

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
test), for :func:`spread_long_tests`; weights, not bounds: no test asserts them."""

WAITING_TEST_SECONDS = {
    "test_examples.py::test_the_python_example_reads_a_board_and_calibrates_over_the_api": 58,
    "test_cli_capture.py::test_six_poses_captured_calibrated_and_sent": 35,
    "test_cli_capture.py::test_compass_records_a_turn_and_fits_the_hard_iron": 21,
    "test_cli_capture.py::test_noise_records_the_minutes_asked_at_rest": 15,
    "test_cli_capture.py::test_silence_is_said": 10,
    "test_cli_capture.py::test_ctrl_c_keeps_the_log_and_says_how_to_finish_it": 8,
}
"""The tests outside tests/e2e that mostly wait on real time (a simulated board's lines at 100 Hz, the minutes
a capture is asked to last), by their node id without parameters, with their real time (s) as measured here;
a few seconds of CPU each. Weights for :func:`spread_long_tests`, as above."""


def pytest_collection_modifyitems(config, items):
    """Every test under tests/e2e drives a real browser: marked `e2e` by its folder, so that
    `pytest -m "not e2e"` is the quick loop while developing."""
    for item in items:
        if E2E in Path(item.path).parents:
            item.add_marker(pytest.mark.e2e)


class SpreadLongTests:
    """Orders the selected tests for xdist's workers, once ``-m``'s deselection is done (hence ``trylast``)."""

    @pytest.hookimpl(trylast=True)
    def pytest_collection_modifyitems(self, config, items):
        spread_long_tests(items, int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1")), os.cpu_count() or 1)


def pytest_configure(config):
    config.pluginmanager.register(SpreadLongTests(), "trical-spread-long-tests")


def spread_long_tests(items: list, workers: int, cores: int) -> None:
    """Order the tests so that the workers start with the long ones that wait on real time, the longest first:
    the browser modules (`make test`) and the tests of :data:`WAITING_TEST_SECONDS`.

    pytest-xdist's work stealing hands worker k the k-th of ``workers`` consecutive slices of this order (each
    ``remaining // workers_left`` long), and an idle worker steals the back half of a busy one's queue. The
    browser modules (two thirds of `make test`'s time, a few long real-time flows each) were all in the first
    slice: the other workers stole its quick tests from the back and the long flows ran one after another on
    one worker. They are shared out by their measured time (the longest first, to the least loaded worker,
    a module kept whole for its server), each slice filled up with the other tests in their order.

    Without browser tests (`make check`) the rest is CPU work on every core: the waiting tests go to the
    workers beyond the cores only (one at least), which wait on them while the others keep the cores busy, and
    no longer start last (tests/test_examples.py, in the last slice by its name, was the run's tail)."""
    groups: dict[object, list] = {}
    weight: dict[object, float] = {}
    for item in items:
        path = Path(item.path)
        if E2E in path.parents:
            groups.setdefault(path, []).append(item)
            weight[path] = BROWSER_MODULE_SECONDS.get(path.relative_to(E2E).as_posix(), 5.0 * len(groups[path]))
            continue
        name = f"{path.relative_to(E2E.parent).as_posix()}::{getattr(item, 'originalname', item.name)}"
        if name in WAITING_TEST_SECONDS:
            groups[item.nodeid] = [item]
            weight[item.nodeid] = WAITING_TEST_SECONDS[name]
    browser = any(isinstance(key, Path) for key in groups)
    takers = workers if browser else min(workers, max(1, workers - cores))
    shares: list[list] = [[] for _ in range(max(workers, 1))]
    loads = [0.0] * len(shares)
    for key in sorted(groups, key=lambda k: weight[k], reverse=True):
        k = loads.index(min(loads[: max(takers, 1)]))
        shares[k] += groups[key]
        loads[k] += weight[key]
    placed = {id(item) for share in shares for item in share}
    order, rest = [], iter([item for item in items if id(item) not in placed])
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


@pytest.fixture(scope="session")
def migrated_database(tmp_path_factory) -> Path:
    """A SQLite file at the schema's head, migrated once a worker (the migrations themselves are tests/store's)."""
    folder = tmp_path_factory.mktemp("migrated")
    open_store(f"sqlite:///{folder / 'trical.db'}", folder / "files").engine.dispose()  # closed: its WAL checkpointed
    return folder / "trical.db"


@pytest.fixture
def settings(tmp_path, migrated_database) -> Settings:
    """The service's settings with its own SQLite file, a copy of :func:`migrated_database`: the store finds it at
    the head and migrates nothing (Alembic's run on an empty file cost each of 500 tests ~60 ms of CPU)."""
    shutil.copyfile(migrated_database, tmp_path / "trical.db")
    return make_settings(tmp_path)


@pytest.fixture(scope="session")
def application(tmp_path_factory, migrated_database) -> FastAPI:
    """The application, built once a worker (:func:`client` gives it each test's store): FastAPI builds every route's
    models on an application's first request, ~30 ms of CPU that an application built for each of 500 tests paid
    each time."""
    folder = tmp_path_factory.mktemp("application")
    shutil.copyfile(migrated_database, folder / "trical.db")
    app = create_app(make_settings(folder))
    app.state.store.engine.dispose()  # each test's store replaces it
    return app


@pytest.fixture
def client(settings, application):
    """The application with a store of its own (its own SQLite file, :func:`settings`), driven through TestClient:
    what ``create_app(settings)`` builds, as the settings differ from the application's in the database alone (the
    middleware's limits are the defaults in both; the assertion holds it)."""
    state = application.state
    assert settings.model_copy(update={"database_url": state.settings.database_url}) == state.settings
    state.settings, state.store = settings, open_store(settings.database_url, settings.recordings_dir)
    state.phone_door = state.listens_on = None
    try:
        with TestClient(application, raise_server_exceptions=False) as c:
            yield c
    finally:
        state.store.engine.dispose()
