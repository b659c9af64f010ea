# The two set-up commands of the README: `make run` and `make test`.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: run test lint typecheck pytest bench clean

$(BIN)/python:
	$(PYTHON) -c 'import sys; assert sys.version_info >= (3, 11), "gpp needs Python 3.11 or newer"'
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip

$(VENV)/.installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e .
	touch $@

$(VENV)/.installed-dev: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e '.[dev]'
	touch $@ $(VENV)/.installed

# The blocksworld agent on the physics simulator; leaves an animation in run.gif.
run: $(VENV)/.installed
	$(BIN)/gpp run examples/blocksworld.gpp --platform sim --record run.gif

lint: $(VENV)/.installed-dev
	$(BIN)/ruff check gpp lsp tests bench
	$(BIN)/ruff format --check gpp lsp tests bench

typecheck: $(VENV)/.installed-dev
	$(BIN)/mypy --strict gpp lsp

pytest: $(VENV)/.installed-dev
	$(BIN)/pytest

test: lint typecheck pytest

bench: $(VENV)/.installed
	$(BIN)/python bench/parse_speed.py
	$(BIN)/python bench/planner.py
	$(BIN)/python bench/sim.py

clean:
	rm -rf $(VENV) build dist .mypy_cache .pytest_cache .ruff_cache
