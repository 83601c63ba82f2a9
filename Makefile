# trical — the two commands of the README: `make run` and `make test`.
PYTHON ?= python3
VENV ?= .venv
HOST ?= 127.0.0.1
PORT ?= 8000
BIN := $(VENV)/bin
CHROMIUM ?= /usr/bin/chromium
WEBKIT_DRIVER ?= /usr/bin/WebKitWebDriver
XVFB ?= /usr/bin/Xvfb

.PHONY: run test check quick-tests lint typecheck install install-test system-deps bench clean

# The service: a virtual environment, the package, and the server on $(HOST):$(PORT) with SQLite under ./var.
run: $(VENV)/.installed
	mkdir -p var
	HOST=$(HOST) PORT=$(PORT) $(BIN)/trical serve --host $(HOST) --port $(PORT)

# The whole suite, with the test extras and the browser the end-to-end tests drive, on $(TEST_WORKERS)
# workers (pytest-xdist): the browser tests mostly wait on real time (captures, servers, browsers), so
# three workers pay even on two cores; a worker that runs out of tests takes the others' pending ones
# (--dist worksteal), so the slowest browser walks do not leave one worker running alone at the end.
# Every test is bounded (pytest-timeout, pyproject.toml).
TEST_WORKERS ?= 3
# pytest keeps the test modules it rewrites (for its assertions) as bytecode beside them between runs; where the
# environment asks for no bytecode files (PYTHONDONTWRITEBYTECODE, as containers often set it) each worker
# rewrote and compiled them all again on every run, 8 s of CPU a worker.
KEEP_BYTECODE := PYTHONDONTWRITEBYTECODE=
test: system-deps $(VENV)/.installed-test lint typecheck
	$(KEEP_BYTECODE) $(BIN)/python -m pytest -n $(TEST_WORKERS) --dist worksteal

# The quick loop while developing: the static checks beside every test that needs no browser (`-m "not e2e"`:
# tests/e2e is marked so by tests/conftest.py) on the same workers, in parallel (make -j: the static checks' ten
# seconds overlap the workers' start); the browsers' tests are `make test`'s. Its tests are CPU work but for the
# few that wait on a simulated board in real time, which tests/conftest.py starts first on the worker beyond the
# two cores (spread_long_tests) while the other two keep them busy. It fails if any of the three fails.
check: system-deps $(VENV)/.installed-test
	$(MAKE) --no-print-directory -j3 lint typecheck quick-tests

# Its workers are CPU-bound on every core, so numpy's OpenBLAS (and OpenMP) run on one thread in each: a thread a
# core only spun waiting for the others. Measured here at rest, 1845 tests: 3:09 and 3:09 (329 s of CPU) with the
# default threads, 2:42 and 2:53 (279 s and 299 s) with one.
ONE_BLAS_THREAD := OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
quick-tests: $(VENV)/.installed-test
	$(KEEP_BYTECODE) $(ONE_BLAS_THREAD) $(BIN)/python -m pytest -n $(TEST_WORKERS) --dist worksteal -m "not e2e"

# The static checks, first in `make test`, each at zero findings: ruff's lint rules and its formatter's
# check on the whole repository (ruff pinned in the test extra, its settings in pyproject.toml), then
# mypy on app/, as pyproject.toml's [tool.mypy] sets it.
lint: $(VENV)/.installed-test
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .

typecheck: $(VENV)/.installed-test
	$(BIN)/mypy

install: $(VENV)/.installed
install-test: $(VENV)/.installed-test

$(VENV)/bin/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --upgrade pip

# The package in place, with the Allan sums' compiled loop built beside its source where a C compiler is
# (setup.py; without one the install goes on, and the sums run in numpy).
FUSED_LOOP := setup.py app/calibration/noise/allan_fused.pyx

$(VENV)/.installed: pyproject.toml $(FUSED_LOOP) | $(VENV)/bin/python
	$(BIN)/python -m pip install -e .
	touch $@

$(VENV)/.installed-test: pyproject.toml $(FUSED_LOOP) | $(VENV)/bin/python
	$(BIN)/python -m pip install -e '.[test]'
	touch $@ $(VENV)/.installed

# Debian's packages the tests drive for real: Chromium and WebKitGTK's WebKitWebDriver with its
# MiniBrowser under Xvfb (end-to-end tests in the two engines), PostgreSQL (storage tests), a Java
# runtime (actipy's wearable readers), and a C compiler for the compiled loop the tests check (installed
# before the package). Installed from the package registry when missing; no browser or server downloads.
system-deps:
	@missing=""; \
	command -v cc >/dev/null 2>&1 || missing="$$missing gcc libc6-dev"; \
	[ -x "$(CHROMIUM)" ] || missing="$$missing chromium"; \
	ls /usr/lib/postgresql/*/bin/initdb >/dev/null 2>&1 || missing="$$missing postgresql"; \
	command -v java >/dev/null 2>&1 || missing="$$missing default-jre-headless"; \
	[ -x "$(WEBKIT_DRIVER)" ] || missing="$$missing webkit2gtk-driver"; \
	[ -x "$(XVFB)" ] || missing="$$missing xvfb"; \
	if [ -n "$$missing" ]; then \
		echo "installing Debian's$$missing for the tests"; \
		SUDO=""; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
		$$SUDO apt-get update -q && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -q $$missing; \
	fi
	@test -x "$(CHROMIUM)" || { echo "chromium is missing at $(CHROMIUM) and could not be installed" >&2; exit 1; }
	@ls /usr/lib/postgresql/*/bin/initdb >/dev/null 2>&1 || { echo "postgresql could not be installed" >&2; exit 1; }
	@command -v java >/dev/null 2>&1 || { echo "java could not be installed" >&2; exit 1; }
	@test -x "$(WEBKIT_DRIVER)" || { echo "WebKitWebDriver is missing at $(WEBKIT_DRIVER) and could not be installed" >&2; exit 1; }
	@test -x "$(XVFB)" || { echo "Xvfb is missing at $(XVFB) and could not be installed" >&2; exit 1; }
	@command -v cc >/dev/null 2>&1 || { echo "a C compiler (cc) could not be installed" >&2; exit 1; }

bench: $(VENV)/.installed-test
	$(BIN)/python bench/api_latency.py

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache test-artifacts
