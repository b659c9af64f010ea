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

# Development (and CI) installs the [ros] extra too, so that the ros2 platform's tests run
# against real ROS 2 nodes. Its wheels depend on lark-parser 0.12, which writes into the same
# `lark` package folder as lark 1.x (gpp's parser) and ships stubs that hide lark 1.x's types:
# it is removed and lark 1.x put back (gpp uses only rosidl_parser.definition, no lark).
$(VENV)/.installed-dev: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e '.[dev,ros]'
	$(BIN)/python -m pip uninstall -y -q lark-parser
	$(BIN)/python -m pip install -q --force-reinstall --no-deps 'lark>=1.3.1,<2'
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
