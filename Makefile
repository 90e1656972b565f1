# One way to build and check: the README, CI (.ci/run) and developers use these targets.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
BAGS   ?= ../shared/data/bags
STAMP  := $(VENV)/.installed-stamp
PACKAGES := shared/pyproject.toml gateway/pyproject.toml

.PHONY: install run test lint typecheck pytest lock clean

$(STAMP): requirements.lock $(PACKAGES)
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --disable-pip-version-check --upgrade pip
	$(PY) -m pip install --quiet --disable-pip-version-check -r requirements.lock
	touch $(STAMP)

install: $(STAMP)  ## create .venv with pinned dependencies and the bagmcp command

run: install  ## summarize every bag under BAGS (the embedded server replaces this)
	@for bag in $(BAGS)/*/*; do $(VENV)/bin/bagmcp info "$$bag" || true; echo; done

lint: install
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .

typecheck: install
	$(VENV)/bin/mypy

pytest: install
	$(PY) -m pytest $(PYTEST_ARGS)

test: lint typecheck pytest  ## everything CI checks

lock:  ## re-pin requirements.lock from requirements.in (needs uv in .venv)
	$(VENV)/bin/uv pip compile --quiet --no-header --python-version 3.11 requirements.in -o requirements.lock

clean:
	rm -rf $(VENV) .pytest_cache .mypy_cache .ruff_cache
