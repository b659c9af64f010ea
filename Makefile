# The two set-up commands of the README: `make run` and `make test`.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: run test lint typecheck pytest browser bench clean

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

# The trace viewer's browser test (tests/test_traceview_browser.py) opens the page in Debian's
# chromium. As root with apt-get (CI, a fresh machine) it is installed when missing; otherwise
# the test is skipped and says why.
browser:
	@if command -v chromium >/dev/null 2>&1; then \
		:; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
		echo "installing Debian's chromium for the trace viewer's browser test"; \
		{ apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends chromium >/dev/null; } \
			|| echo "warning: could not install chromium: the browser test will be skipped"; \
	else \
		echo "note: chromium is missing and cannot be installed here (needs root and apt-get): the browser test will be skipped"; \
	fi

test: browser lint typecheck pytest

bench: $(VENV)/.installed
	$(BIN)/python bench/parse_speed.py
	$(BIN)/python bench/planner.py
	$(BIN)/python bench/sim.py

clean:
	rm -rf $(VENV) build dist .mypy_cache .pytest_cache .ruff_cache
