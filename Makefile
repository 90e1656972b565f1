# One way to build and check: the README, CI (.ci/run) and developers use these targets.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
BAGS   ?= ../shared/data/bags
STAMP  := $(VENV)/.installed-stamp
# Compiled bytecode is kept even where the environment says not to write it (this workplace sets
# PYTHONDONTWRITEBYTECODE=1): every test process and every process of the stacks the tests start imports the
# product's own packages, which pip installs editable (no .pyc); compiling them from source again costs each
# process about 0.45 s of CPU (2.40 against 1.96 s to import a plotting worker), hundreds of times in `make test`.
export PYTHONDONTWRITEBYTECODE :=
PACKAGES := shared/pyproject.toml kit/pyproject.toml gateway/pyproject.toml services/bag_store/pyproject.toml services/analysis/pyproject.toml services/plotting/pyproject.toml lab/pyproject.toml cli/pyproject.toml

.PHONY: install run stack test lint typecheck pytest browser bench bench-fleet bench-quick docs-images lock clean

$(STAMP): requirements.lock $(PACKAGES)
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --disable-pip-version-check --upgrade pip
	$(PY) -m pip install --quiet --disable-pip-version-check -r requirements.lock
	touch $(STAMP)

NODE_STAMP := node_modules/.package-lock.json
CHROMIUM ?= /usr/bin/chromium

# The web console's tools from npm (package-lock.json records versions and hashes, no addresses): uPlot,
# whose dist files are vendored in kit/bagmcp_kit/web/static/vendor, and axe-core for the browser tests.
$(NODE_STAMP): package.json package-lock.json
	command -v npm >/dev/null || (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq npm)
	npm ci --no-audit --no-fund --loglevel=error

install: $(STAMP) $(NODE_STAMP)  ## create .venv with pinned dependencies and the bagmcp command (and node_modules)

browser:  ## Debian's Chromium for the browser tests (apt-get install when missing; never a browser download)
	@test -x $(CHROMIUM) || (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium)
	@$(CHROMIUM) --version 2>/dev/null | head -1

HOST ?= 127.0.0.1
PORT ?= 8000

run: install  ## serve the bags under BAGS over MCP at http://HOST:PORT/mcp (embedded, no Docker)
	$(VENV)/bin/bagmcp serve --bags $(BAGS) --host $(HOST) --port $(PORT)

stack: install  ## the distributed stack as local processes (redis, S3, bag-store, worker, gateway)
	deploy/stack/run.sh

lint: install
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .

typecheck: install
	$(VENV)/bin/mypy

# pytest-xdist's own file order (files with the most tests first) is kept: collection order, integration first,
# was tried on 2026-11-28 and ran the corpus uploads (test_fleet_on_recorded_corpus) before the session-stack
# files that name their uploads (test_stack_range_reads), which then found the corpus's twins under those names.
pytest: install browser  ## every test on two processes, a file per process at a time (its servers start once)
	$(PY) -m pytest -n 2 --dist loadfile $(PYTEST_ARGS)

unit: install  ## the tests that start no server, on two processes (pytest-xdist): 50-58 s on a recent 2-core EPYC, 1 min 46 s on a 2 GHz first-generation one (README: Development)
	$(PY) -m pytest -m 'not integration' -n 2 $(PYTEST_ARGS)

test: lint typecheck browser pytest  ## everything CI checks (the browser tests included)

bench: install  ## on demand, not in CI: every tool as MCP calls (embedded, stack) on ~2 GB bags; writes BENCHMARKS.md
	$(PY) -m bench $(BENCH_ARGS)

bench-fleet: install  ## questions across 500 generated short bags, embedded and stack (writes BENCHMARKS.fleet.md)
	$(PY) -m bench.fleet $(BENCH_ARGS)

bench-quick: install  ## the benchmark's small version (about ten minutes; writes .bench/BENCHMARKS.quick.md)
	$(PY) -m bench --quick $(BENCH_ARGS)

docs-images: install  ## regenerate docs/images/*.png: one example of each plot kind, from generated bags
	PYTHONPATH=. $(PY) docs/images/make_images.py

lock:  ## re-pin requirements.lock from requirements.in (needs uv in .venv)
	$(VENV)/bin/uv pip compile --quiet --no-header --python-version 3.11 requirements.in -o requirements.lock

clean:
	rm -rf $(VENV) node_modules .pytest_cache .mypy_cache .ruff_cache
