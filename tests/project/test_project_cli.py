"""The command line for projects: configuration files (discovery, validation, `gpp config`),
folders in `gpp check`, the concise and GitHub formats, fixes in JSON/SARIF, `--fix` and
`--diff`, suppression comments, `gpp test` selection/parallelism/JUnit XML/exit codes,
`gpp explain --list` and `gpp new`.

Most tests run the typer app in-process (typer's CliRunner, with the working directory set to a
temporary project); `gpp new`, `gpp test -j` and `--fix` also run as real processes."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from typer.testing import CliRunner, Result

from gpp.check import check_text
from gpp.cli.app import app
from gpp.project.config import ConfigError, config_for, find_config_file, load_config, project_files
from tests.support import cli, disks

# Line 5 has a misspelled symbol with one close name (a safe fix); `idle` is unused.
AGENT = """\
symbol domain Room = {kitchen, hall}
action goto(Room r) {}
action idle() {}
procedure main() {
    goto(kitchn);
}
"""


def gpp(*args: str) -> Result:
    return CliRunner().invoke(app, list(args))


def gpp_process(*args: str, cwd: Path) -> cli.Result:
    return cli.run_process(*args, cwd=cwd)


def write(folder: Path, files: dict[str, str]) -> None:
    for name, text in files.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)


@pytest.fixture
def here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    return tmp_path


# ---------------------------------------------------------------- configuration files


def test_the_nearest_configuration_wins_and_gpp_toml_before_pyproject(tmp_path: Path) -> None:
    write(
        tmp_path,
        {
            "pyproject.toml": '[tool.gpp]\ninclude = ["top"]\n',
            "a/pyproject.toml": '[project]\nname = "not gpp"\n',  # no [tool.gpp]: passed over
            "a/b/gpp.toml": 'include = ["own"]\n',
            "a/b/pyproject.toml": '[tool.gpp]\ninclude = ["pyproject"]\n',
            "a/b/c/agent.gpp": "",
            "a/x.gpp": "",
        },
    )
    assert find_config_file(tmp_path / "a/b/c/agent.gpp") == tmp_path / "a/b/gpp.toml"
    assert config_for(tmp_path / "a/b/c/agent.gpp").include == (tmp_path / "a/b/own",)
    assert find_config_file(tmp_path / "a/x.gpp") == tmp_path / "pyproject.toml"
    config = config_for(tmp_path / "a")
    assert (config.include, config.table, config.root) == ((tmp_path / "top",), "tool.gpp", tmp_path)


def test_no_configuration_means_the_defaults(here: Path) -> None:
    config = config_for(here)
    assert (config.file, config.paths, config.include, config.disabled_lints()) == (None, (here,), (), [])


def config_error(tmp_path: Path, name: str, text: str) -> str:
    (tmp_path / name).write_text(text)
    with pytest.raises(ConfigError) as raised:
        load_config(tmp_path / name)
    d = raised.value.diagnostic
    return f"{d.span.line}:{d.span.col} {d.message} | {d.help}"


def test_unknown_keys_are_located_with_a_did_you_mean(tmp_path: Path) -> None:
    pyproject = '[project]\nname = "x"\n\n[tool.gpp]\nincude = ["lib"]\n'
    assert config_error(tmp_path, "pyproject.toml", pyproject) == (
        "5:1 unknown key `incude` in [tool.gpp] | did you mean `include`?"
    )
    assert config_error(tmp_path, "gpp.toml", '[lint]\nenable = ["all"]\ndisabel = ["unused"]\n') == (
        "3:1 unknown key `disabel` in [lint] | did you mean `disable`?"
    )
    assert config_error(tmp_path, "gpp.toml", "[tset]\ntimeout = 3\n") == (
        "1:2 unknown key `tset` in gpp.toml | did you mean `test`?"
    )


def test_values_of_the_wrong_type_are_located(tmp_path: Path) -> None:
    assert config_error(tmp_path, "gpp.toml", '[test]\ntimeout = "soon"\n') == (
        "2:1 `test.timeout` must be a number of seconds greater than 0 | None"
    )
    assert config_error(tmp_path, "gpp.toml", 'include = "lib"\n') == "1:1 `include` must be a list of strings | None"
    assert config_error(tmp_path, "gpp.toml", "lint = 3\n") == "1:1 `lint` must be a table | None"
    assert config_error(tmp_path, "gpp.toml", 'lint = { disable = ["unsued"] }\n') == (
        "1:1 `lint.disable`: unknown lint `unsued` | did you mean `unused`?"
    )
    assert config_error(tmp_path, "gpp.toml", 'lint.disable = ["E0101"]\n') == (
        "1:1 `lint.disable`: `E0101` is an error, not a lint | None"
    )


def test_a_bad_configuration_is_a_usage_error_shown_in_the_file(here: Path) -> None:
    write(here, {"gpp.toml": '[run]\nplatfrom = "sim"\n', "agent.gpp": AGENT})
    result = gpp("check")
    assert result.exit_code == 2
    assert result.stdout == ""
    assert result.stderr == (
        "error: unknown key `platfrom` in [run]\n"
        " --> gpp.toml:2:1\n"
        "  |\n"
        '2 | platfrom = "sim"\n'
        "  | ^^^^^^^^ unknown key\n"
        "  |\n"
        "  = note: the keys of [run]: `platform`, `world`, `timeout`, `time_limit` (docs/config.md)\n"
        "  = help: did you mean `platform`?\n"
        "\n"
    )


def test_gpp_config_shows_the_settings_and_where_they_come_from(here: Path) -> None:
    write(here, {"gpp.toml": 'include = ["lib"]\n[lint]\ndisable = ["unused"]\n[test]\ntimeout = 30\n'})
    result = gpp("config")
    assert result.exit_code == 0
    assert result.stdout == (
        "# settings from gpp.toml\n"
        f"# paths are relative to {here.resolve()}\n"
        "\n"
        'paths = ["."]                             # default\n'
        "exclude = []                              # default\n"
        'include = ["lib"]                         # from file\n'
        "\n"
        "[lint]\n"
        'enable = ["all"]                          # default\n'
        'disable = ["W0101"]                       # from file\n'
        "deny_warnings = false                     # default\n"
        "\n"
        "[run]\n"
        "# platform is not set                     # default\n"
        "# world is not set                        # default\n"
        "# timeout is not set                      # default\n"
        "# time_limit is not set                   # default\n"
        "\n"
        "[test]\n"
        'paths = ["tests/programs"]                # default\n'
        "timeout = 30                              # from file\n"
        "# time_limit is not set                   # default: none\n"
    )


# ---------------------------------------------------------------- projects in gpp check


def test_check_takes_folders_and_uses_the_configuration(here: Path) -> None:
    write(
        here,
        {
            "gpp.toml": 'include = ["lib"]\nexclude = ["scratch"]\n[lint]\ndisable = ["unused-variable"]\n',
            # A library is checked through the programs that include it (its procedures are used).
            "lib/robot.gpp": "action go(number speed) {}\nprocedure patrol() { go(1); }\n",
            "src/agent.gpp": '#include "robot.gpp"\nprocedure main() { patrol(); }\n',
            "src/.hidden/broken.gpp": "procedure main( {}\n",
            "scratch/broken.gpp": "procedure main( {}\n",
        },
    )
    assert [p.as_posix() for p in project_files([])] == ["lib/robot.gpp", "src/agent.gpp"]
    result = gpp("check", "--format", "concise")
    assert (result.exit_code, result.stdout) == (0, "All checks passed!\n")
    # The option adds to what the configuration turns off; without the include folder the
    # library is not found.
    assert gpp("check", "--format", "concise", "--allow", "unused", "src").exit_code == 0
    (here / "gpp.toml").write_text("")
    result = gpp("check", "--format", "concise", "src")
    assert result.stdout.splitlines()[0] == "src/agent.gpp:1:10: error[E0030] cannot find included file `robot.gpp`"


def test_a_library_is_linted_with_the_programs_that_include_it(here: Path) -> None:
    write(
        here,
        {
            "lib.gpp": (
                "action go() {}\n"
                "procedure patrol() { go(); }\n"
                "procedure dock() { go(); }\n"
                "procedure spin(number turns) { go(); }\n"
                "procedure never() { go(); }\n"
            ),
            "a.gpp": '#include "lib.gpp"\nprocedure main() { patrol(); spin(1); }\n',
            "b.gpp": '#include "lib.gpp"\nprocedure main() { patrol(); dock(); }\n',
        },
    )
    result = gpp("check", "--format", "concise")
    assert result.stdout == (
        "lib.gpp:4:23: warning[W0102] parameter `turns` of procedure `spin` is never used\n"
        "lib.gpp:5:11: warning[W0101] procedure `never` is never used\n"
        "Found 2 warnings.\n"
    )


def test_deny_warnings_from_the_configuration(here: Path) -> None:
    write(here, {"agent.gpp": AGENT.replace("kitchn", "kitchen"), "gpp.toml": "[lint]\ndeny_warnings = true\n"})
    assert gpp("check").exit_code == 1
    (here / "gpp.toml").write_text("")
    assert gpp("check").exit_code == 0


def test_gpp_run_takes_its_defaults_from_the_configuration(here: Path) -> None:
    write(
        here,
        {
            "gpp.toml": "[run]\ntime_limit = 5\n",
            "loop.gpp": "action step() { duration: [1, 1] }\nprocedure main() { while (true) step(); }\n",
        },
    )
    result = gpp("run", "--quiet", "loop.gpp")
    assert result.exit_code == 1
    assert "error[R0013]: the run reached its time limit of 5 s of platform time" in result.stdout
    assert "time               5.000 s platform" in result.stdout
    (here / "gpp.toml").write_text('[run]\nplatform = "nowhere"\n')
    result = gpp("run", "--quiet", "loop.gpp")
    assert result.exit_code == 2
    assert "nowhere" in result.stderr


def test_the_configured_world_is_used_on_the_sim(here: Path) -> None:
    example = (Path(__file__).resolve().parents[2] / "examples" / "rescue.gpp").read_text()
    program = "".join(line for line in example.splitlines(keepends=True) if not line.startswith("// world:"))
    write(here, {"rescue.gpp": program, "gpp.toml": '[run]\nplatform = "sim"\nworld = "rescue"\n'})
    result = gpp("run", "--quiet", "rescue.gpp")
    assert result.exit_code == 0, result.stdout
    assert result.stdout.splitlines()[0] == "rescue.gpp on sim: finished"
    # Without it the sim's default world (the blocksworld) has none of the rescue's services.
    (here / "gpp.toml").write_text('[run]\nplatform = "sim"\n')
    assert gpp("run", "--quiet", "rescue.gpp").exit_code == 1


# ---------------------------------------------------------------- output formats


def test_concise_format(here: Path) -> None:
    (here / "agent.gpp").write_text(AGENT)
    result = gpp("check", "--format", "concise", "agent.gpp")
    assert result.exit_code == 1
    assert result.stdout == (
        "agent.gpp:3:8: warning[W0101] action `idle` is never used\n"
        "agent.gpp:5:10: error[E0101] unknown name `kitchn` [*]\n"
        "Found 1 error and 1 warning.\n"
        "[*] 1 fixable with `gpp check --fix`.\n"
    )


def test_github_format(here: Path) -> None:
    (here / "agent.gpp").write_text(AGENT)
    result = gpp("check", "--format", "github", "agent.gpp")
    assert result.exit_code == 1
    assert result.stdout == (
        "::warning file=agent.gpp,line=3,col=8,endLine=3,endColumn=12,title=gpp (W0101)::action `idle` is never used\n"
        "::error file=agent.gpp,line=5,col=10,endLine=5,endColumn=16,title=gpp (E0101)::"
        "unknown name `kitchn`%0Ahelp: did you mean `kitchen`?\n"
    )


def test_did_you_mean_fixes_are_in_json_and_sarif(here: Path) -> None:
    (here / "agent.gpp").write_text(AGENT)
    report = json.loads(gpp("check", "--format", "json", "agent.gpp").stdout)
    [error] = [d for d in report["diagnostics"] if d["code"] == "E0101"]
    assert error["fix"] == {
        "message": "did you mean `kitchen`?",
        "applicability": "safe",
        "edits": [{"file": "agent.gpp", "line": 5, "column": 10, "end_line": 5, "end_column": 16, "text": "kitchen"}],
    }
    sarif = json.loads(gpp("check", "--format", "sarif", "agent.gpp").stdout)
    [result] = [r for r in sarif["runs"][0]["results"] if r["ruleId"] == "E0101"]
    assert result["fixes"] == [
        {
            "description": {"text": "did you mean `kitchen`?"},
            "artifactChanges": [
                {
                    "artifactLocation": {"uri": "agent.gpp", "uriBaseId": "%SRCROOT%"},
                    "replacements": [
                        {
                            "deletedRegion": {"startLine": 5, "startColumn": 10, "endLine": 5, "endColumn": 16},
                            "insertedContent": {"text": "kitchen"},
                        }
                    ],
                }
            ],
            "properties": {"applicability": "safe"},
        }
    ]


def test_a_guess_among_several_names_is_an_unsafe_fix() -> None:
    text = "symbol domain Room = {hall1, hall2, hall3}\naction go(Room r) {}\nprocedure main() { go(hall); }\n"
    [d] = check_text(text, lint=False).diagnostics
    assert d.help == "did you mean `hall3`, `hall2` or `hall1`?"  # best first, as difflib ranks them
    assert d.fix is not None and not d.fix.is_safe and d.fix.edits[0].text == "hall3"


def test_a_misspelled_keyword_gets_an_unsafe_fix() -> None:
    [d] = check_text("procedur main() {}\n", lint=False).diagnostics
    assert d.fix is not None and d.help == d.fix.message == "did you mean `procedure`?"
    [edit] = d.fix.edits
    assert (edit.span.start, edit.span.end, edit.text, d.fix.is_safe) == (0, 8, "procedure", False)


def test_a_fluent_used_without_parentheses_gets_a_safe_fix() -> None:
    text = "number fluent n() { initially: () = 0; }\nprocedure main() { n() = n + 1; }\n"
    [d] = check_text(text, lint=False).diagnostics
    assert d.code == "E0102" and d.fix is not None and d.fix.is_safe
    [edit] = d.fix.edits
    assert (edit.span.start, edit.span.end, edit.text) == (text.index("n + 1") + 1, text.index("n + 1") + 1, "()")


# ---------------------------------------------------------------- --fix and --diff

SEVERAL_FIXES = """\
symbol domain Room = {kitchen, hall}
action goto(Room r) {}
procedure main() {
    goto(kitchn)
    gotoo(hall);;
    // gpp: allow unused
    goto(hall);
}
"""
FIXED = """\
symbol domain Room = {kitchen, hall}
action goto(Room r) {}
procedure main() {
    goto(kitchen);
    goto(hall);
    goto(hall);
}
"""


def test_diff_shows_the_fixes_without_writing(here: Path) -> None:
    (here / "agent.gpp").write_text(SEVERAL_FIXES)
    result = gpp("check", "--diff")
    assert result.exit_code == 1
    assert result.stdout == (
        "--- a/agent.gpp\n"
        "+++ b/agent.gpp\n"
        "@@ -1,8 +1,7 @@\n"
        " symbol domain Room = {kitchen, hall}\n"
        " action goto(Room r) {}\n"
        " procedure main() {\n"
        "-    goto(kitchn)\n"
        "-    gotoo(hall);;\n"
        "-    // gpp: allow unused\n"
        "+    goto(kitchen);\n"
        "+    goto(hall);\n"
        "     goto(hall);\n"
        " }\n"
    )
    assert result.stderr == "would fix 5 problems (3 of them hidden by a syntax error) in 1 file\n"
    assert (here / "agent.gpp").read_text() == SEVERAL_FIXES
    assert gpp("check", "--diff", "--format", "json").exit_code == 2


def test_fix_writes_every_safe_fix_and_a_second_run_changes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "agent.gpp").write_text(SEVERAL_FIXES)
    (tmp_path / "other.gpp").write_text("procedure main() {}\n")
    result = gpp_process("check", "--fix", cwd=tmp_path)
    assert (result.returncode, result.stdout) == (
        0,
        "no problems found\nfixed 5 problems (3 of them hidden by a syntax error) in 1 file, 0 remaining\n",
    )
    assert (tmp_path / "agent.gpp").read_text() == FIXED
    assert sorted(p.name for p in tmp_path.iterdir()) == ["agent.gpp", "other.gpp"]  # no temporary file left
    again = gpp("check", "--fix")
    assert (again.exit_code, again.stdout) == (0, "no problems found\nnothing to fix, 0 problems remaining\n")
    assert (tmp_path / "agent.gpp").read_text() == FIXED
    assert gpp("check", "--diff").exit_code == 0


def test_fix_writes_nothing_when_a_file_cannot_be_written(tmp_path: Path) -> None:
    (tmp_path / "agent.gpp").write_text(SEVERAL_FIXES)
    with disks.immutable(tmp_path / "agent.gpp"):
        result = cli.run("check", "--fix", "agent.gpp", cwd=tmp_path)
    assert (result.returncode, result.stdout) == (2, "")
    assert result.stderr == "error: cannot write 'agent.gpp': it is read-only: no file was changed\n"
    assert (tmp_path / "agent.gpp").read_text() == SEVERAL_FIXES


def test_fix_on_a_full_disk_says_it_cannot_write_and_leaves_the_file(tmp_path: Path) -> None:
    with disks.full_disk(tmp_path / "disk", {"agent.gpp": SEVERAL_FIXES}) as disk:
        result = cli.run("check", "--fix", "agent.gpp", cwd=disk)
        assert result.returncode == 2
        assert result.stderr == ("error: cannot write 'agent.gpp': No space left on device (it was left as it was)\n")
        assert (disk / "agent.gpp").read_text() == SEVERAL_FIXES
        assert sorted(p.name for p in disk.iterdir()) == ["agent.gpp", "filler"]


def test_fix_reports_what_remains(here: Path) -> None:
    (here / "agent.gpp").write_text(AGENT.replace("goto(kitchn);", "goto(kitchn);\n    stay();"))
    result = gpp("check", "--fix", "--format", "concise")
    assert result.exit_code == 1
    assert result.stdout == (
        "agent.gpp:3:8: warning[W0101] action `idle` is never used\n"
        "agent.gpp:6:5: error[E0103] unknown action or procedure `stay`\n"
        "Found 1 error and 1 warning.\n"
        "fixed 1 problem in 1 file, 2 remaining\n"
    )


# ---------------------------------------------------------------- suppression comments


def problems(text: str) -> list[str]:
    return [f"{d.span.line}:{d.span.col} {d.code} {d.message}" for d in check_text(text).diagnostics]


def test_a_comment_at_the_end_of_a_line_allows_lints_on_that_line() -> None:
    text = "action idle() {} // gpp: allow unused\naction spare() {}\nprocedure main() {}\n"
    assert problems(text) == ["2:8 W0101 action `spare` is never used"]


def test_a_comment_above_a_declaration_allows_lints_in_all_of_it() -> None:
    text = (
        "procedure helper(number n) {}\n"
        "// gpp: allow W0102, unused -- kept for the next version\n"
        "procedure patrol(number a, number b) {\n"
        "    helper(1);\n"
        "}\n"
        "procedure main() { helper(2); }\n"
    )
    assert problems(text) == ["1:25 W0102 parameter `n` of procedure `helper` is never used"]


def test_a_file_comment_allows_lints_everywhere() -> None:
    text = "action idle() {}\naction spare() {}\nprocedure main() {}\n// gpp: allow-file unused\n"
    assert problems(text) == []


def test_a_comment_on_its_own_line_in_a_body_allows_lints_on_the_next_line() -> None:
    text = (
        "action go() {}\n"
        "procedure main() {\n"
        "    // gpp: allow online-nondeterminism\n"
        "    pick (bool b) go();\n"
        "    pick (bool c) go();\n"
        "    // gpp: allow\n"
        "}\n"
    )
    assert problems(text) == [
        "4:16 W0102 variable `b` is never used",
        "5:5 W0105 `pick` outside `solve` or `search` takes the first value that works now",
        "5:16 W0102 variable `c` is never used",
        "6:5 W0117 a suppression that names no lint",
    ]


def test_unused_and_invalid_suppressions_are_reported() -> None:
    text = "action go() {} // gpp: allow unused\nprocedure main() {\n    go(); // gpp: allow E0101, unsued\n}\n"
    assert problems(text) == [
        "1:30 W0116 unused suppression: no `unused` (W0101) to allow on this line",
        "3:25 W0117 `E0101` is an error: only lints can be allowed",
        "3:32 W0117 unknown lint `unsued` in a suppression",
    ]


def test_errors_are_not_suppressed() -> None:
    text = "procedure main() {\n    go(); // gpp: allow E0103\n}\n"
    assert problems(text) == [
        "2:5 E0103 unknown action or procedure `go`",
        "2:25 W0117 `E0103` is an error: only lints can be allowed",
    ]


def test_suppressions_of_lints_turned_off_are_not_reported_unused(here: Path) -> None:
    (here / "agent.gpp").write_text("action go() {} // gpp: allow unused\nprocedure main() { go(); }\n")
    assert gpp("check", "--format", "concise").stdout.startswith("agent.gpp:1:30: warning[W0116]")
    assert gpp("check", "--format", "concise", "--allow", "unused").stdout == "All checks passed!\n"
    assert gpp("check", "--format", "concise", "--no-lint").stdout == "All checks passed!\n"


def test_suppressions_hold_in_gpp_run(here: Path) -> None:
    (here / "agent.gpp").write_text("// gpp: allow-file unused\naction idle() {}\nprocedure main() {}\n")
    result = gpp("run", "--quiet", "agent.gpp")
    assert result.exit_code == 0
    assert "W0101" not in result.stdout


# ---------------------------------------------------------------- gpp test

PASSES = (
    "number fluent n() { initially: () = 0; }\nprocedure main() { n() = 1; }\nbool function postcond() = n() == 1\n"
)
FAILS = "number fluent n() { initially: () = 0; }\nprocedure main() { n() = 1; }\nbool function postcond() = n() == 2\n"


@pytest.fixture
def suite(here: Path) -> Path:
    write(
        here,
        {
            "tests/deliver_ok.gpp": PASSES,
            "tests/deliver_bad.gpp": FAILS,
            "tests/patrol_ok.gpp": PASSES,
            "tests/sub/broken.gpp": "procedure main() { nope(); }\n",
            "tests/sub/library.gpp": "action go() {}\n",
        },
    )
    return here


def last_line(result: Result) -> str:
    return result.stdout.strip().splitlines()[-1]


def test_k_selects_programs_by_name(suite: Path) -> None:
    result = gpp("test", "tests", "-k", "deliver and not bad")
    assert (result.exit_code, last_line(result)) == (0, "1 passed, 0 failed")
    result = gpp("test", "tests", "-k", "deliver or (sub and not library)")
    assert (result.exit_code, last_line(result)) == (1, "1 passed, 2 failed")


def test_exit_codes_are_pytests(suite: Path) -> None:
    assert gpp("test", "tests", "-k", "nothing_is_called_this").exit_code == 5
    assert gpp("test", "tests", "-k", "ok and").exit_code == 2
    (suite / "empty").mkdir()
    assert gpp("test", "empty").exit_code == 5


def test_x_stops_at_the_first_failure(suite: Path) -> None:
    result = gpp("test", "tests", "-x")
    assert result.exit_code == 1
    assert last_line(result) == "0 passed, 1 failed"  # deliver_bad.gpp comes first
    assert "patrol_ok" not in result.stdout


def test_junit_xml(suite: Path) -> None:
    result = gpp("test", "tests", "--junitxml", "out.xml")
    assert result.exit_code == 1
    root = ET.parse(suite / "out.xml").getroot()
    assert root.tag == "testsuites"
    [testsuite] = root
    assert (testsuite.tag, testsuite.get("name")) == ("testsuite", "gpp test")
    assert {k: testsuite.get(k) for k in ("tests", "failures", "errors", "skipped")} == {
        "tests": "5",
        "failures": "1",
        "errors": "1",
        "skipped": "1",
    }
    cases = {(c.get("classname"), c.get("name")): c for c in testsuite.iter("testcase")}
    assert sorted(cases) == [
        ("tests", "deliver_bad.gpp"),
        ("tests", "deliver_ok.gpp"),
        ("tests", "patrol_ok.gpp"),
        ("tests/sub", "broken.gpp"),
        ("tests/sub", "library.gpp"),
    ]
    assert all(float(c.get("time") or "x") >= 0 for c in cases.values())
    assert [child.tag for child in cases[("tests", "deliver_ok.gpp")]] == []
    [failure] = cases[("tests", "deliver_bad.gpp")]
    assert (failure.tag, failure.get("message")) == ("failure", "postcond() does not hold")
    [error] = cases[("tests/sub", "broken.gpp")]
    assert error.tag == "error"
    assert error.get("message") == "E0103 at tests/sub/broken.gpp:1:20: unknown action or procedure `nope`"
    assert (error.text or "").startswith("error[E0103]: unknown action or procedure `nope`\n")
    [skipped] = cases[("tests/sub", "library.gpp")]
    assert (skipped.tag, skipped.get("message")) == ("skipped", "no `procedure main()`")


@pytest.mark.slow
def test_configured_test_paths_and_parallel_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    write(
        tmp_path,
        {
            "gpp.toml": '[test]\npaths = ["checks"]\ntimeout = 30\n',
            "checks/a.gpp": PASSES,
            "checks/b.gpp": FAILS,
            "checks/c.gpp": PASSES,
        },
    )
    sequential = gpp("test")
    parallel = gpp_process("test", "-j", "2", cwd=tmp_path)
    assert (sequential.exit_code, parallel.returncode) == (1, 1)

    def rows(out: str) -> list[str]:
        return [
            line.split("│")[1].strip() + " " + line.split("│")[2].strip() for line in out.splitlines() if "│" in line
        ]

    assert rows(parallel.stdout) == rows(sequential.stdout)
    assert rows(parallel.stdout) == ["checks/a.gpp pass", "checks/b.gpp fail", "checks/c.gpp pass"]


def test_bad_jobs_and_output_are_usage_errors(suite: Path) -> None:
    assert gpp("test", "tests", "-j", "0").exit_code == 2
    assert gpp("test", "tests", "--junitxml", "missing/out.xml").exit_code == 2


# ---------------------------------------------------------------- explain --list, gpp new


def test_explain_list_lists_every_code(here: Path) -> None:
    from gpp.codes import CODES

    result = gpp("explain", "--list")
    assert result.exit_code == 0
    lines = result.stdout.splitlines()
    assert lines[0].split() == ["code", "severity", "name", "summary"]
    assert [line.split()[0] for line in lines[1:]] == list(CODES)
    assert lines[1].split()[:3] == ["E0001", "error", "unexpected-character"]
    assert any(line.split()[:3] == ["W0116", "lint", "unused-suppression"] for line in lines)
    assert any(line.split()[:3] == ["R0014", "warning", "plan-unfinished"] for line in lines)
    assert gpp("explain").exit_code == 2


@pytest.mark.slow
def test_gpp_new_makes_a_project_that_checks_and_tests_cleanly(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    made = gpp_process("new", "courier", cwd=tmp_path)
    assert made.returncode == 0, made.stderr
    project = tmp_path / "courier"
    assert sorted(p.relative_to(project).as_posix() for p in project.rglob("*") if p.is_file()) == [
        "README.md",
        "agent.gpp",
        "gpp.toml",
        "scenarios/delivery.toml",
        "src/robot.gpp",
        "tests/delivery.gpp",
    ]
    checked = gpp_process("check", cwd=project)
    assert (checked.returncode, checked.stdout) == (0, "no problems found\n")
    tested = gpp_process("test", "--junitxml", "out.xml", cwd=project)
    assert tested.returncode == 0, tested.stdout
    assert tested.stdout.strip().splitlines()[-1] == "1 passed, 0 failed"
    monkeypatch.chdir(project)
    ran = gpp("run", "--quiet", "agent.gpp")
    assert ran.exit_code == 0, ran.stdout + ran.stderr
    assert "postcond()         holds" in ran.stdout
    monkeypatch.chdir(tmp_path)
    again = gpp("new", "courier")
    assert again.exit_code == 2
    assert again.stderr == "error: 'courier' exists and is not empty; choose another name or remove it\n"


def test_gpp_new_dot_makes_the_project_in_the_working_directory_named_after_it(tmp_path: Path) -> None:
    folder = tmp_path / "courier"
    folder.mkdir()
    made = cli.run("new", ".", cwd=folder)
    assert made.returncode == 0, made.stderr
    assert made.stdout.startswith("created the project here with 6 files:\n")
    assert made.stdout.endswith("next: gpp check && gpp test\n")
    assert (folder / "agent.gpp").is_file() and (folder / "gpp.toml").is_file()
    assert "courier" in (folder / "README.md").read_text(encoding="utf-8")


def test_a_gpp_toml_with_a_byte_order_mark_is_read(tmp_path: Path) -> None:
    (tmp_path / "gpp.toml").write_bytes(b'\xef\xbb\xbf[lint]\ndisable = ["unused"]\n')
    assert load_config(tmp_path / "gpp.toml").disabled_lints() == ["W0101"]


def test_a_folder_named_gpp_toml_is_an_error_not_passed_over(tmp_path: Path) -> None:
    (tmp_path / "gpp.toml").mkdir()
    (tmp_path / "a.gpp").write_text("procedure main() { }\n")
    result = cli.run("check", "a.gpp", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.startswith("error: cannot read gpp.toml: it is a folder, not a file\n")
