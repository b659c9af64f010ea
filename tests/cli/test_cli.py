"""End-to-end tests of the `gpp` command, through its entry point in this process, and as a real
process where a process is what is tested: exit code 3, start-up imports, signals, pipes, the
console script."""

from __future__ import annotations

import itertools
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import gpp
from tests.support.cli import Result, run

GOOD = "number fluent x() { initially: () = 0; }\nprocedure main() {\n  x() = 1;\n}\n"
MISSING_SEMICOLON = "procedure main() {\n    x() = 1\n}\n"


def run_gpp(*args: str, cwd: Path, env: dict[str, str] | None = None) -> Result:
    return run(*args, cwd=cwd, env=env)


@pytest.fixture
def project(tmp_path: Path) -> Path:
    (tmp_path / "good.gpp").write_text(GOOD)
    (tmp_path / "bad.gpp").write_text(MISSING_SEMICOLON)
    return tmp_path


def test_version(tmp_path: Path) -> None:
    result = run_gpp("--version", cwd=tmp_path)
    assert result.returncode == 0
    assert result.stdout == f"gpp {gpp.__version__}\n"


def test_help_lists_check(tmp_path: Path) -> None:
    result = run_gpp("--help", cwd=tmp_path)
    assert result.returncode == 0
    assert "check" in result.stdout


def test_check_clean_file_exits_0(project: Path) -> None:
    result = run_gpp("check", "good.gpp", cwd=project)
    assert (result.returncode, result.stdout, result.stderr) == (0, "no problems found\n", "")


def test_check_file_with_errors_exits_1(project: Path) -> None:
    result = run_gpp("check", "bad.gpp", cwd=project)
    assert result.returncode == 1
    lines = result.stdout.splitlines()
    assert lines[0] == "error[E0011]: expected `;` after this statement"
    assert lines[1] == " --> bad.gpp:2:12"
    assert lines[-1] == "error: 1 error"


def test_check_orders_diagnostics_by_file_and_position(project: Path) -> None:
    (project / "worse.gpp").write_text("procedure main() {\n  a() = 1\n  b() = 2\n}\n")
    result = run_gpp("check", "worse.gpp", "bad.gpp", cwd=project)
    assert result.returncode == 1
    locations = [line.strip() for line in result.stdout.splitlines() if line.lstrip().startswith("-->")]
    assert locations == ["--> bad.gpp:2:12", "--> worse.gpp:2:10", "--> worse.gpp:3:10"]
    assert result.stdout.endswith("error: 3 errors\n")


def test_check_reports_missing_include(project: Path) -> None:
    (project / "inc.gpp").write_text('#include "nowhere.gpp"\nprocedure main() {\n}\n')
    result = run_gpp("check", "inc.gpp", cwd=project)
    assert result.returncode == 1
    assert " --> inc.gpp:1:10" in result.stdout


def test_json_output_points_right_after_the_previous_token(project: Path) -> None:
    result = run_gpp("check", "--format", "json", "bad.gpp", cwd=project)
    assert result.returncode == 1
    report = json.loads(result.stdout)
    assert report["version"] == 1
    assert report["summary"] == {"errors": 1, "warnings": 0}
    [item] = report["diagnostics"]
    assert item["code"] == "E0011"
    assert item["file"] == "bad.gpp"
    line_text = MISSING_SEMICOLON.splitlines()[1]
    assert (item["line"], item["column"]) == (2, line_text.index("1") + 2)
    assert item["offset"] == MISSING_SEMICOLON.index("1") + 1
    assert item["fix"]["edits"][0]["text"] == ";"


def test_json_output_for_a_clean_file(project: Path) -> None:
    result = run_gpp("check", "--format", "json", "good.gpp", cwd=project)
    assert result.returncode == 0
    assert json.loads(result.stdout)["diagnostics"] == []


def test_missing_file_is_a_usage_error(project: Path) -> None:
    result = run_gpp("check", "good.gpp", "missing.gpp", cwd=project)
    assert result.returncode == 2
    assert result.stderr == "error: cannot read 'missing.gpp': No such file or directory\n"
    assert result.stdout == ""


def test_a_directory_is_searched_for_programs(project: Path) -> None:
    result = run_gpp("check", "--format", "concise", ".", cwd=project)
    assert result.returncode == 1
    files = {line.split(":")[0] for line in result.stdout.splitlines() if ":" in line and not line.startswith("[")}
    assert files == {"bad.gpp"}


@pytest.mark.parametrize(
    "args",
    [["check", "--format", "xml", "good.gpp"], ["check", "--color", "sometimes", "good.gpp"], ["nope"]],
)
def test_bad_usage_exits_2(project: Path, args: list[str]) -> None:
    result = run_gpp(*args, cwd=project)
    assert result.returncode == 2
    assert "Traceback" not in result.stderr


def test_colour_follows_the_color_option(project: Path) -> None:
    assert "\x1b[" in run_gpp("check", "--color", "always", "bad.gpp", cwd=project).stdout
    assert "\x1b[" not in run_gpp("check", "--color", "never", "bad.gpp", cwd=project).stdout
    # auto: a pipe is not a terminal, and NO_COLOR wins over FORCE_COLOR.
    assert "\x1b[" not in run_gpp("check", "bad.gpp", cwd=project).stdout
    assert "\x1b[" in run_gpp("check", "bad.gpp", cwd=project, env={"FORCE_COLOR": "1"}).stdout
    assert "\x1b[" not in run_gpp("check", "bad.gpp", cwd=project, env={"NO_COLOR": "1", "FORCE_COLOR": "1"}).stdout


def test_coloured_and_plain_output_have_the_same_text(project: Path) -> None:
    import re

    coloured = run_gpp("check", "--color", "always", "bad.gpp", cwd=project).stdout
    plain = run_gpp("check", "--color", "never", "bad.gpp", cwd=project).stdout
    assert re.sub(r"\x1b\[[0-9;]*m", "", coloured) == plain


INTERNAL_ERROR_SCRIPT = """
import sys
import gpp.syntax.loader

def broken_load(*args, **kwargs):
    raise RuntimeError("boom")

gpp.syntax.loader.load = broken_load
from gpp.cli.main import main
main(sys.argv[1:])
"""


def test_internal_error_is_short_and_exits_3(project: Path) -> None:
    command = [sys.executable, "-c", INTERNAL_ERROR_SCRIPT, "check", "good.gpp"]
    env = {k: v for k, v in os.environ.items() if k != "GPP_DEBUG"}
    result = subprocess.run(command, cwd=project, env=env, capture_output=True, text=True, timeout=60)
    assert result.returncode == 3
    assert result.stderr.startswith("internal error: RuntimeError: boom\n")
    assert "GPP_DEBUG=1" in result.stderr
    assert "Traceback" not in result.stderr


def test_gpp_debug_shows_the_traceback(project: Path) -> None:
    command = [sys.executable, "-c", INTERNAL_ERROR_SCRIPT, "check", "good.gpp"]
    env = {**os.environ, "GPP_DEBUG": "1"}
    result = subprocess.run(command, cwd=project, env=env, capture_output=True, text=True, timeout=60)
    assert result.returncode not in (0, 3)
    assert "RuntimeError: boom" in result.stderr
    assert "Traceback" in result.stderr


# The command as `python -m gpp` runs it, and at its exit the names of the modules it imported.
LIST_MODULES = (
    "import atexit, sys\n"
    "atexit.register(lambda: sys.stderr.write('modules: ' + ' '.join(sorted(sys.modules)) + '\\n'))\n"
    "from gpp.cli.main import main\n"
    "main()\n"
)


def imported_modules(args: list[str], cwd: Path) -> set[str]:
    result = subprocess.run(
        [sys.executable, "-c", LIST_MODULES, *args], cwd=cwd, capture_output=True, text=True, timeout=60
    )
    assert result.returncode in (0, 1), result.stderr
    [line] = [line for line in result.stderr.splitlines() if line.startswith("modules: ")]
    return set(line.removeprefix("modules: ").split())


# What `gpp check` must not import: its start-up time (bench/startup.py) is the time to import
# what it does import. typer converts its option values without pydantic (gpp.cli.coercion).
NOT_FOR_CHECK = {"pygls", "lsprotocol", "pymunk", "PIL", "hypothesis", "rich", "pydantic", "pygments", "rclpy"}
NOT_FOR_CHECK_IN_GPP = ("gpp.runtime", "gpp.planner", "gpp.platform", "gpp.run", "gpp.traceview", "lsp")
# But the platforms' static checks (gpp.platform.static), light until a program has something
# for them to check (tests/platform/ros2/test_ros2_static_checks.py).
FOR_STATIC_CHECKS = {
    "gpp.platform",
    "gpp.platform.options",
    "gpp.platform.static",
    "gpp.platform.ros2",
    "gpp.platform.ros2.static",
    "gpp.platform.ros2.names",
}
# Nor the modules of the other commands: the entry point builds the app with one command.
OTHER_COMMANDS = ("gpp.cli.run", "gpp.cli.trace", "gpp.cli.fmt", "gpp.cli.project", "gpp.cli.explain", "gpp.cli.lsp")


def unneeded(modules: set[str]) -> set[str]:
    return {
        m
        for m in modules
        if m.split(".")[0] in NOT_FOR_CHECK
        or (m.startswith(NOT_FOR_CHECK_IN_GPP) and m not in FOR_STATIC_CHECKS)
        or m == "lark"
        or m in OTHER_COMMANDS
    }


@pytest.mark.parametrize("args", [["check", "bad.gpp"], ["check", "good.gpp"], ["check", "--no-lint", "good.gpp"]])
def test_check_imports_only_what_it_needs(project: Path, args: list[str]) -> None:
    modules = imported_modules(args, project)
    assert {"gpp.syntax.parser", "gpp.model.typecheck", "gpp.cli.check", "typer"} <= modules  # the measurement works
    assert unneeded(modules) == set()


# What `gpp run` on the dummy must not import: the other platforms and what they need.
NOT_FOR_A_DUMMY_RUN = ("gpp.platform.sim", "gpp.platform.ros2", "pymunk", "PIL", "rclpy", "pydantic", "lsp", "pygls")


@pytest.mark.parametrize(
    ("header", "args"),
    [("", ["--platform", "dummy"]), ("", []), ("// scenario: s.toml\n", [])],
    ids=["named", "chosen", "with-directive"],
)
def test_a_dummy_run_imports_no_other_platform(project: Path, header: str, args: list[str]) -> None:
    (project / "s.toml").write_text("")
    (project / "run.gpp").write_text(header + GOOD)
    modules = imported_modules(["run", "-q", *args, "run.gpp"], project)
    assert {"gpp.platform.dummy", "gpp.runtime.executor", "gpp.cli.run"} <= modules  # the measurement works
    assert {m for m in modules if m.startswith(NOT_FOR_A_DUMMY_RUN)} == set()


def test_check_help_and_usage_errors(project: Path) -> None:
    helped = run_gpp("check", "--help", cwd=project)
    assert helped.returncode == 0
    assert "Usage: gpp check [OPTIONS] [PATH]..." in helped.stdout
    assert "--deny-warnings" in helped.stdout
    bad = run_gpp("check", "--format", "xml", "good.gpp", cwd=project)
    assert (bad.returncode, bad.stdout) == (2, "")
    assert "'xml' is not one of 'text', 'concise'," in bad.stderr
    negative = run_gpp("check", "--max-diagnostics", "-1", "good.gpp", cwd=project)
    assert (negative.returncode, negative.stderr) == (
        2,
        "error: --max-diagnostics takes a whole number of 0 or more, not -1\n",
    )
    assert "check" in run_gpp("--help", cwd=project).stdout


def command_descriptions(helped: str) -> dict[str, list[str]]:
    """The lines of each command's description in the Commands table of `gpp --help`."""
    table = helped[helped.index("Commands") :].splitlines()[1:]
    descriptions: dict[str, list[str]] = {}
    name = ""
    for row in table:
        if not row.startswith("│"):
            break
        cells = row.strip("│ ").split(None, 1) if not row.startswith("│  ") else ["", row.strip("│ ")]
        if cells[0]:
            name = cells[0]
        descriptions.setdefault(name, []).append(cells[-1].strip())
    return descriptions


@pytest.mark.parametrize("columns", ["80", "100", "140"])
def test_help_reflows_descriptions_and_keeps_brackets(project: Path, columns: str) -> None:
    """Descriptions are filled greedily to the table's width (a docstring's line break is not
    a break in the help), and `[tool.gpp]` is shown, not taken for markup."""
    helped = run_gpp("--help", cwd=project, env={"COLUMNS": columns}).stdout
    descriptions = command_descriptions(helped)
    assert {"check", "new", "config", "run", "trace"} <= descriptions.keys()
    width = max(len(line) for lines in descriptions.values() for line in lines)
    for name, lines in descriptions.items():
        for line, following in itertools.pairwise(lines):
            assert len(line) + 1 + len(following.split()[0]) > width, (name, line, following)
    assert "[tool.gpp] table" in " ".join(descriptions["config"])
    assert "a robot library, a test program with its scenario" in " ".join(descriptions["new"])


@pytest.mark.parametrize("command", ["check", "run", "test", "fmt", "config", "new", "explain", "lsp"])
def test_help_shows_no_value_type_beside_a_flag(project: Path, command: str) -> None:
    helped = run_gpp(command, "--help", cwd=project, env={"COLUMNS": "100"}).stdout
    flags = [row for row in helped.splitlines() if "--help" in row or "--quiet" in row or "--fix" in row]
    assert flags, helped
    assert "<bool>" not in helped
    assert "<list[" not in helped
    assert "[[" not in helped.splitlines()[1]


def test_installed_console_script_runs(tmp_path: Path) -> None:
    script = Path(sys.executable).with_name("gpp")
    if not script.exists():
        pytest.skip("no gpp console script beside this interpreter")
    result = subprocess.run([str(script), "--version"], capture_output=True, text=True, timeout=60)
    assert (result.returncode, result.stdout) == (0, f"gpp {gpp.__version__}\n")


# ---------------------------------------------------------------- lint options

UNUSED_FLUENT = "number fluent spare() { initially: () = 0; }\nprocedure main() { }\n"


@pytest.fixture
def linted(project: Path) -> Path:
    (project / "warn.gpp").write_text(UNUSED_FLUENT)
    (project / "both.gpp").write_text(UNUSED_FLUENT + "procedure other() { nowhere(); }\n")
    return project


def test_warnings_alone_exit_0_and_are_counted(linted: Path) -> None:
    result = run_gpp("check", "warn.gpp", cwd=linted)
    assert result.returncode == 0
    assert result.stdout.splitlines()[0] == "warning[W0101]: fluent `spare` is never used"
    assert result.stdout.endswith("\nwarning: 1 warning\n")


def test_summary_counts_errors_and_warnings(linted: Path) -> None:
    result = run_gpp("check", "both.gpp", cwd=linted)
    assert result.returncode == 1
    assert result.stdout.endswith("\nerror: 1 error, 2 warnings\n")


def test_deny_warnings_turns_warnings_into_a_failure(linted: Path) -> None:
    assert run_gpp("check", "--deny-warnings", "warn.gpp", cwd=linted).returncode == 1
    assert run_gpp("check", "--deny-warnings", "good.gpp", cwd=linted).returncode == 0
    assert run_gpp("check", "--deny-warnings", "--allow", "unused", "warn.gpp", cwd=linted).returncode == 0


def test_no_lint_reports_errors_only(linted: Path) -> None:
    result = run_gpp("check", "--no-lint", "warn.gpp", cwd=linted)
    assert (result.returncode, result.stdout) == (0, "no problems found\n")
    both = run_gpp("check", "--no-lint", "both.gpp", cwd=linted)
    assert both.returncode == 1
    assert both.stdout.endswith("\nerror: 1 error\n")


@pytest.mark.parametrize("allowed", ["W0101", "unused", "UNUSED", "w0101"])
def test_allow_suppresses_a_lint(linted: Path, allowed: str) -> None:
    result = run_gpp("check", "--allow", allowed, "warn.gpp", cwd=linted)
    assert (result.returncode, result.stdout) == (0, "no problems found\n")


def test_allow_can_be_repeated(linted: Path) -> None:
    (linted / "two.gpp").write_text("number fluent f(number n) { initially: (1) = 0; }\nprocedure main() { }\n")
    assert "W0103" in run_gpp("check", "--allow", "unused", "two.gpp", cwd=linted).stdout
    result = run_gpp("check", "--allow", "unused", "--allow", "W0103", "two.gpp", cwd=linted)
    assert result.stdout == "no problems found\n"


def test_allow_json_output_counts_only_what_is_reported(linted: Path) -> None:
    report = json.loads(run_gpp("check", "--format", "json", "--allow", "unused", "both.gpp", cwd=linted).stdout)
    assert report["summary"] == {"errors": 1, "warnings": 0}


@pytest.mark.parametrize(
    ("allowed", "message"),
    [
        ("unsed", "error: unknown lint `unsed`; did you mean `unused`?\n"),
        ("E0101", "error: `E0101` is an error, not a lint: only lints can be allowed\n"),
    ],
)
def test_allow_needs_a_lint(linted: Path, allowed: str, message: str) -> None:
    result = run_gpp("check", "--allow", allowed, "warn.gpp", cwd=linted)
    assert (result.returncode, result.stdout, result.stderr) == (2, "", message)


def test_list_lints_needs_no_files(tmp_path: Path) -> None:
    from gpp.codes import lints

    result = run_gpp("check", "--list-lints", cwd=tmp_path)
    assert result.returncode == 0
    lines = result.stdout.splitlines()
    assert lines[0].split() == ["code", "name", "summary"]
    assert [line.split()[:2] for line in lines[1:]] == [[c.code, c.name] for c in lints()]
    assert all(line.endswith(c.summary) for line, c in zip(lines[1:], lints(), strict=True))


def test_check_without_files_explains_itself(tmp_path: Path) -> None:
    result = run_gpp("check", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr == (
        "error: no .gpp files found in the project (the working directory); give .gpp files or folders, "
        "or --list-lints\n"
    )


def test_sarif_output_and_explain_do_not_import_heavy_packages(project: Path) -> None:
    heavy = {"pygls", "lsprotocol", "pymunk", "PIL", "hypothesis", "rich", "pydantic"}
    modules = imported_modules(["check", "--format", "sarif", "good.gpp"], project)
    assert "gpp.report.sarif" in modules
    assert unneeded(modules) == set()
    explain = imported_modules(["explain", "W0101"], project)
    assert "gpp.codes" in explain
    assert {m for m in explain if m.split(".")[0] in heavy or m.startswith("gpp.syntax")} == set()


# ---------------------------------------------------------------- platform flags


def test_the_platform_flags_come_from_the_platforms_declarations() -> None:
    from gpp.cli.run import platform_flags
    from gpp.platform.dummy import DummyPlatform
    from gpp.platform.options import BUILTIN
    from gpp.platform.sim import SimPlatform

    run_flags = [p.name for p in platform_flags(single_run=True)]
    assert run_flags == ["scenario", "seed", "random", "world", "record", "snapshot", "realtime"]
    assert [p.name for p in platform_flags(single_run=False)] == ["scenario", "seed", "random", "world"]
    for name, cls in (("dummy", DummyPlatform), ("sim", SimPlatform)):
        assert (cls.Options, cls.selected_by) == (BUILTIN[name].options, BUILTIN[name].selected_by)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ["run", "-q", "--world", "rescue", "good.gpp"],
            "error: --world is an option of platform sim, not of `dummy`\n",
        ),
        (
            ["run", "-q", "-p", "dummy", "--realtime", "good.gpp"],
            "error: --realtime is an option of platform sim, not of `dummy`\n",
        ),
        (
            ["run", "-q", "-p", "sim", "--random", "good.gpp"],
            "error: --random is an option of platform dummy, not of `sim`\n",
        ),
        (
            ["test", "-p", "sim", "--random", "good.gpp"],
            "error: --random is an option of platform dummy, not of `sim`\n",
        ),
        (
            ["test", "-p", "dummy", "--world", "rescue", "good.gpp"],
            "error: --world is an option of platform sim, not of `dummy`\n",
        ),
    ],
)
def test_a_flag_the_platform_does_not_take_is_a_usage_error(
    project: Path, monkeypatch: pytest.MonkeyPatch, args: list[str], message: str
) -> None:
    from typer.testing import CliRunner

    from gpp.cli.app import app

    monkeypatch.chdir(project)
    result = CliRunner().invoke(app, args)
    assert (result.exit_code, result.stdout, result.stderr) == (2, "", message)


# ---------------------------------------------------------------- signals

ENDLESS = "number fluent n() { initially: () = 0; }\nprocedure main() { while (true) n() = n() + 1; }\n"
MESSAGES = {signal.SIGINT: "interrupted", signal.SIGTERM: "terminated (SIGTERM)"}


def _catches_sigterm(pid: int) -> bool:
    """Whether the process handles SIGTERM (/proc/PID/status: its mask of caught signals)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    caught = next(line.split()[1] for line in status.splitlines() if line.startswith("SigCgt:"))
    return bool(int(caught, 16) & (1 << (signal.SIGTERM - 1)))


def _interrupt(project: Path, signum: int, delay: float | None) -> tuple[subprocess.Popen[str], str, str, Path]:
    """Start an endless `gpp run` with a trace and send it the signal `delay` seconds after its
    entry point installed its handlers (None: once the run has stepped)."""
    (project / "endless.gpp").write_text(ENDLESS)
    trace = project / "endless.jsonl"
    env = {k: v for k, v in os.environ.items() if k not in ("NO_COLOR", "FORCE_COLOR", "GPP_DEBUG")}
    process = subprocess.Popen(
        [sys.executable, "-m", "gpp", "run", "-q", "--trace", str(trace), "endless.gpp"],
        cwd=project,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        deadline = time.monotonic() + 60
        while not _catches_sigterm(process.pid):
            assert process.poll() is None and time.monotonic() < deadline, "no handler installed"
            time.sleep(0.001)
        if delay is None:
            while not (trace.exists() and '"event": "assign"' in trace.read_text()):
                assert process.poll() is None and time.monotonic() < deadline, "the run does not step"
                time.sleep(0.01)
        else:
            time.sleep(delay)
        process.send_signal(signum)
        out, err = process.communicate(timeout=60)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    return process, out, err, trace


@pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="reads /proc/PID/status")
@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
@pytest.mark.parametrize("delay", [0.0, 0.02, 0.05, 0.1, 0.2, None], ids=lambda d: "running" if d is None else f"{d}s")
def test_a_signal_at_any_moment_ends_the_process_in_one_way(project: Path, signum: int, delay: float | None) -> None:
    process, _, err, trace = _interrupt(project, signum, delay)
    assert (process.returncode, err) == (128 + signum, MESSAGES[signal.Signals(signum)] + "\n")
    if trace.exists():  # the run opened its trace: it ends with its one finish record
        records = [json.loads(line) for line in trace.read_text().splitlines()]
        assert records[0]["event"] == "header"
        assert [r["event"] for r in records].count("finish") == 1
        assert records[-1]["event"] == "finish" and records[-1]["status"] == "interrupted"
        assert records[-2] == {**records[-2], "event": "error", "message": MESSAGES[signal.Signals(signum)]}
    if delay is None:
        assert trace.exists()


DROPPED = """
import signal, time, weakref
from gpp.base import signals
signals.install()
class Thing: ...
thing = Thing()
# Python drops an exception raised in a weak reference's callback (the import system runs
# one after every import): the signal's handler raises the interruption there.
ref = weakref.ref(thing, lambda _: signal.raise_signal(signal.SIGTERM))
try:
    del thing
    time.sleep(5)
    print("went on")
except signals.Terminated:
    print("raised again")
"""


@pytest.mark.skipif(not hasattr(signal, "setitimer"), reason="raised again by SIGALRM")
def test_an_interruption_python_drops_is_raised_again(tmp_path: Path) -> None:
    result = subprocess.run([sys.executable, "-c", DROPPED], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert (result.returncode, result.stdout, result.stderr) == (0, "raised again\n", "")


# ---------------------------------------------------------------- pipes


def test_a_reader_that_goes_away_ends_the_output_quietly(project: Path) -> None:
    (project / "many.gpp").write_text("procedure main() {\n" + "    x() = 1\n" * 5000 + "}\n")
    process = subprocess.Popen(
        [sys.executable, "-m", "gpp", "check", "--max-diagnostics", "0", "many.gpp"],
        cwd=project,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    assert process.stdout is not None and process.stderr is not None
    process.stdout.read(100)
    process.stdout.close()  # as `gpp check ... | head -c 100`
    err = process.stderr.read().decode()
    assert process.wait(timeout=60) == 1
    assert err == ""
