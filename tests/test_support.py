"""The tests' own helpers (tests/support): the in-process command line gives what a process
gives and puts back what a command changes; hypothesis budgets follow the profile; parallel
workers get ROS domains of their own."""

from __future__ import annotations

import logging
import os
import signal
import sys
from pathlib import Path

import pytest
from hypothesis import settings

from gpp import __version__
from tests.support import cli
from tests.support.budget import CI_EXAMPLES, PROFILES, examples
from tests.support.workers import ros_domain

BAD = "procedure main() {\n    x() = 1\n}\n"


def test_the_runner_captures_output_and_exit_code(gpp: cli.Runner, tmp_path: Path) -> None:
    assert gpp("--version") == cli.Result(("--version",), 0, f"gpp {__version__}\n", "")
    (tmp_path / "bad.gpp").write_text(BAD)
    result = gpp("check", "bad.gpp", cwd=tmp_path)
    assert result.returncode == 1
    assert result.stdout.startswith("error[E0011]: expected `;` after this statement\n")
    missing = gpp("check", "missing.gpp", cwd=tmp_path)
    assert (missing.returncode, missing.stdout) == (2, "")
    assert "missing.gpp" in missing.stderr


def test_the_runner_reads_input_and_takes_the_environment(gpp: cli.Runner, tmp_path: Path) -> None:
    formatted = gpp("fmt", "-", input="procedure main() {a();}\n", cwd=tmp_path)
    assert (formatted.returncode, formatted.stdout) == (0, "procedure main() {\n    a();\n}\n")
    (tmp_path / "bad.gpp").write_text(BAD)
    assert "\x1b[" not in gpp("check", "bad.gpp", cwd=tmp_path).stdout
    assert "\x1b[" in gpp("check", "bad.gpp", cwd=tmp_path, env={"FORCE_COLOR": "1"}).stdout


def test_the_runner_keeps_the_environment_but_its_switches(monkeypatch: pytest.MonkeyPatch) -> None:
    """In this process, the command sees the test's environment (a ROS domain, HOME, ...) less
    the switches that change what gpp writes, with `env` on top."""
    import gpp.cli.main

    seen: dict[str, str | None] = {}

    def main(args: list[str]) -> None:
        seen.update({k: os.environ.get(k) for k in ("GPP_KEPT", "GPP_DEBUG", "COLUMNS", "GPP_GIVEN")})

    monkeypatch.setenv("GPP_KEPT", "kept")
    monkeypatch.setenv("GPP_DEBUG", "1")
    monkeypatch.setenv("COLUMNS", "133")
    monkeypatch.setattr(gpp.cli.main, "main", main)
    assert cli.run("anything", env={"GPP_GIVEN": "given"}).returncode == 0
    assert seen == {"GPP_KEPT": "kept", "GPP_DEBUG": None, "COLUMNS": "80", "GPP_GIVEN": "given"}


def process_state() -> tuple[object, ...]:
    """What a command may change for the whole process: the working directory, the environment,
    the signal handlers, the recursion limit, the standard streams, the root logger's handlers."""
    return (
        os.getcwd(),
        dict(os.environ),
        signal.getsignal(signal.SIGINT),
        signal.getsignal(signal.SIGTERM),
        sys.getrecursionlimit(),
        (sys.stdin, sys.stdout, sys.stderr),
        list(logging.getLogger().handlers),
    )


def test_the_runner_puts_back_what_a_command_changes(
    gpp: cli.Runner, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("GPP_DEBUG", "1")  # cleared for the command, back afterwards
    (tmp_path / "agent.gpp").write_text("action a() { }\nprocedure main() { a(); }\n")
    before = process_state()
    result = gpp("run", "-q", "agent.gpp", cwd=tmp_path)  # sets SIGTERM and the recursion limit
    assert result.returncode == 0, result.stdout + result.stderr
    after = process_state()
    assert after == before


@pytest.mark.slow
def test_the_runner_gives_what_a_process_gives(gpp: cli.Runner, tmp_path: Path) -> None:
    (tmp_path / "bad.gpp").write_text(BAD)
    for args in (["check", "bad.gpp"], ["check", "--format", "json", "bad.gpp"], ["explain", "E0011"]):
        assert gpp(*args, cwd=tmp_path) == cli.run_process(*args, cwd=tmp_path)


def test_budgets_scale_with_the_profile() -> None:
    loaded = settings.default.max_examples
    assert loaded in PROFILES.values()
    assert examples(CI_EXAMPLES) == loaded
    assert examples(10 * CI_EXAMPLES) == 10 * loaded
    assert examples(1) == 1  # never none
    assert PROFILES["dev"] * 10 == PROFILES["ci"] == CI_EXAMPLES


def test_each_worker_has_ros_domains_of_its_own(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PYTEST_XDIST_WORKER_COUNT", "3")
    seen: list[set[int]] = []
    for worker in ("gw0", "gw1", "gw2"):
        monkeypatch.setenv("PYTEST_XDIST_WORKER", worker)
        seen.append({ros_domain() for _ in range(200)})
    assert all(domains and min(domains) >= 1 and max(domains) <= 100 for domains in seen)
    assert not (seen[0] & seen[1] or seen[0] & seen[2] or seen[1] & seen[2])
