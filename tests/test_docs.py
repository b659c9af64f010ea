"""Every golog++ example in docs/ is checked (and run, where the docs say it runs), so the
user's guide cannot drift from the language gpp implements.

A fenced block's info string says what it is (docs/language.md, "About the examples"):

* ```gpp            a complete program: it checks without any diagnostic;
* ```gpp run        ... and runs to its end on its platform (the dummy platform, or the sim
                     for a program with a `// world:` line), with `postcond()` holding;
* ```gpp fragment   statements: checked inside `procedure main() { ... }`, without errors;
* ```gpp error=CODE a program that shows a mistake: checking it reports CODE;
* ```gpp test name=P a test program of a `gpp new` project, saved as P in a fresh one: it checks
                     cleanly and `gpp test` passes it with the project's own test;
* ```toml name=F    a file the programs of the same page can name (`// scenario: F`);
* `allow=CODE` after `gpp` or `gpp run`: that warning is expected (a lint the example shows).

Any other fenced block must not look like golog++ (a declaration or a procedure), so that no
example escapes the check by a missing tag.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import pytest

from gpp.check import check_paths, merged_diagnostics
from gpp.report.text import render_text
from gpp.run.runner import RunOptions, run_program
from gpp.runtime.executor import RunStatus

ROOT = Path(__file__).resolve().parent.parent
PAGES = sorted((ROOT / "docs").glob("*.md"))
# A fenced block, also indented (inside a list item): its indentation is removed.
FENCE = re.compile(r"^([ \t]*)```([^\n`]*)\n(.*?)^[ \t]*```[ \t]*$", re.MULTILINE | re.DOTALL)
LOOKS_LIKE_GOLOG = re.compile(r"^\s*(procedure \w+\(|\w+ fluent \w+\(|action \w+\(|#include )", re.MULTILINE)


@dataclass(frozen=True)
class Example:
    page: Path
    line: int
    info: str
    text: str

    @property
    def id(self) -> str:
        return f"{self.page.name}:{self.line}"


def examples() -> list[Example]:
    found = []
    for page in PAGES:
        source = page.read_text(encoding="utf-8")
        for m in FENCE.finditer(source):
            indent = len(m.group(1))
            text = "".join(line[indent:] if line[:indent].isspace() else line for line in m.group(3).splitlines(True))
            found.append(Example(page, source.count("\n", 0, m.start()) + 1, m.group(2).strip(), text))
    return found


EXAMPLES = examples()
GPP = [e for e in EXAMPLES if e.info.split(" ")[0] == "gpp"]
PROJECT_TESTS = [e for e in GPP if e.info.split(" ")[1:2] == ["test"]]


def test_the_guide_has_its_pages_and_checked_examples() -> None:
    names = {p.name for p in PAGES}
    assert {"tutorial.md", "language.md", "scenarios.md", "worlds.md", "platforms.md", "differences.md"} <= names
    assert len(GPP) >= 35
    assert any(e.info.startswith("gpp run") for e in GPP)
    assert any(e.info.startswith("gpp error=") for e in GPP)


@pytest.mark.parametrize("example", [e for e in EXAMPLES if e not in GPP], ids=lambda e: e.id)
def test_untagged_blocks_are_not_golog(example: Example) -> None:
    if example.info.startswith("toml"):
        return
    assert not LOOKS_LIKE_GOLOG.search(example.text), f"{example.id}: tag the golog++ example with ```gpp"


def write(example: Example, folder: Path) -> Path:
    """The program of an example in `folder`, with the named files of its page beside it."""
    for other in EXAMPLES:
        named = re.fullmatch(r"toml name=(\S+)", other.info)
        if other.page == example.page and named:
            (folder / named.group(1)).parent.mkdir(parents=True, exist_ok=True)
            (folder / named.group(1)).write_text(other.text, encoding="utf-8")
    text = example.text
    if example.info == "gpp fragment":
        text = "procedure main() {\n" + text + "}\n"
    path = folder / "example.gpp"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize("example", [e for e in GPP if e not in PROJECT_TESTS], ids=lambda e: e.id)
def test_the_example_does_what_the_guide_says(example: Example, tmp_path: Path) -> None:
    words = [w for w in example.info.split() if not w.startswith("allow=")]
    allowed = {w.removeprefix("allow=") for w in example.info.split() if w.startswith("allow=")}
    assert len(words) <= 2 and (len(words) == 1 or words[1] in ("run", "fragment") or words[1].startswith("error=")), (
        f"{example.id}: unknown tag ```{example.info}"
    )
    path = write(example, tmp_path)
    diagnostics = merged_diagnostics(check_paths([path]))
    shown = render_text(diagnostics)
    if words[-1].startswith("error="):
        code = words[-1].removeprefix("error=")
        assert code in {d.code for d in diagnostics}, f"{example.id}: expected {code}, got:\n{shown}"
        return
    if words[-1] == "fragment":
        assert not [d for d in diagnostics if d.is_error], f"{example.id}:\n{shown}"
        return
    assert [d for d in diagnostics if d.code not in allowed] == [], f"{example.id}:\n{shown}"
    assert {d.code for d in diagnostics} == allowed, f"{example.id}: allows a warning it does not have"
    if words[-1] == "run":
        outcome = run_program(path, RunOptions(timeout=600))
        assert outcome.result is not None, f"{example.id}: {render_text(outcome.diagnostics)}"
        assert outcome.result.status is RunStatus.FINISHED, f"{example.id}: {render_text(outcome.diagnostics)}"
        assert outcome.postcond is not False, f"{example.id}: postcond() does not hold"


def shown_session(page: Path, command: str) -> str:
    """The output a page shows for `$ command` (in an untagged block, up to the next `$ `)."""
    for e in EXAMPLES:
        if e.page == page and not e.info and f"$ {command}\n" in e.text:
            return e.text.split(f"$ {command}\n", 1)[1].split("\n$ ", 1)[0]
    raise AssertionError(f"{page.name} shows no `$ {command}`")


@pytest.mark.parametrize("example", PROJECT_TESTS, ids=lambda e: e.id)
def test_the_test_programs_of_the_guide_pass_in_a_new_project(example: Example, tmp_path: Path) -> None:
    from tests.support.cli import run as gpp

    created = gpp("new", "courier", cwd=tmp_path)
    assert created.returncode == 0, created.stderr
    assert created.stdout == shown_session(example.page, "gpp new courier")
    project = tmp_path / "courier"
    name = example.info.split("name=", 1)[1]
    program = write(example, project).rename(project / name)
    assert gpp("check", str(program), cwd=project).stdout == "no problems found\n"
    result = gpp("test", cwd=project)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.splitlines()[-1] == shown_session(example.page, "gpp test").splitlines()[-1]
    assert Path(name).name in result.stdout


def test_the_tutorials_look_at_a_run_shows_what_gpp_trace_prints(tmp_path: Path) -> None:
    from tests.support.cli import run as gpp

    tutorial = ROOT / "docs" / "tutorial.md"
    (fetch,) = [e for e in GPP if e.page == tutorial and "take_sample();" in e.text]
    write(fetch, tmp_path).rename(tmp_path / "fetch.gpp")
    assert gpp("run", "-q", "fetch.gpp", "--trace", "run.jsonl", cwd=tmp_path).returncode == 0
    summary = gpp("trace", "summary", "run.jsonl", cwd=tmp_path)
    assert summary.returncode == 0, summary.stderr
    # The header lines; the timeline's bars depend on the width of the terminal.
    shown = shown_session(tutorial, "gpp trace summary run.jsonl").splitlines()
    assert summary.stdout.splitlines()[:2] == shown[:2]
    assert gpp("trace", "html", "run.jsonl", "-o", "run.html", cwd=tmp_path).returncode == 0


@pytest.mark.parametrize("example", [e for e in EXAMPLES if e.info.startswith("toml name=")], ids=lambda e: e.id)
def test_the_scenario_and_world_files_of_the_guide_load(example: Example) -> None:
    import tomllib

    from gpp.platform.dummy import Scenario
    from gpp.platform.sim.world import World

    data = tomllib.loads(example.text)
    # A world on worlds.md, unless it has only the sections of a scenario (the sim takes both).
    if example.page.name == "worlds.md" and not set(data) <= {"defaults", "action", "exog", "exog_function"}:
        World.from_data(data)
    else:
        Scenario.from_data(data)


# ---------------------------------------------------------------- the README

README = ROOT / "README.md"
README_TEXT = README.read_text(encoding="utf-8")
# What differs between two runs of the same program: the wall-clock figures.
WALL = [
    (re.compile(r"\[(\d+) nodes, [\d.]+ s\]"), r"[\1 nodes, … s]"),
    (re.compile(r"[\d.]+ s wall \([^)]*real time\)"), "… s wall (…x real time)"),
]


def _wall_clock_out(text: str) -> str:
    for pattern, replacement in WALL:
        text = pattern.sub(replacement, text)
    return text


def test_the_readme_starts_with_the_two_set_up_commands() -> None:
    lines = README_TEXT.splitlines()
    assert lines[0].startswith("# ")
    first = next(i for i, line in enumerate(lines[1:], 1) if line.strip())
    assert lines[first] == "```", "the README starts with the set-up commands"
    end = lines.index("```", first + 1)
    commands = [line.split("#")[0].strip() for line in lines[first + 1 : end]]
    assert commands == ["make run", "make test"]
    makefile = (ROOT / "Makefile").read_text(encoding="utf-8")
    assert "\nrun:" in makefile and "\ntest:" in makefile


def test_the_readme_is_short_and_says_how_to_put_gpp_on_the_path() -> None:
    assert len(README_TEXT.splitlines()) <= 150
    assert "source .venv/bin/activate" in README_TEXT
    assert "(docs/differences.md)" in README_TEXT  # the differences from the original stay findable


def _slug(heading: str) -> str:
    """GitHub's anchor of a heading."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


@pytest.mark.parametrize("page", [README, *PAGES], ids=lambda p: p.name)
def test_the_links_between_the_pages_resolve(page: Path) -> None:
    text = page.read_text(encoding="utf-8")
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"[a-z]+:", target):
            continue  # a web address
        file, _, anchor = target.partition("#")
        path = (page.parent / file).resolve() if file else page
        assert path.exists(), f"{page.name}: a link to {target}, which does not exist"
        if anchor and path.suffix == ".md":
            headings = re.findall(r"^#+ (.*)$", path.read_text(encoding="utf-8"), re.MULTILINE)
            assert anchor in {_slug(h) for h in headings}, f"{page.name}: no heading for the anchor of {target}"


def test_the_readme_agent_checks_runs_and_prints_what_the_readme_shows(tmp_path: Path) -> None:
    from tests.support.cli import run as gpp

    (agent,) = [m.group(3) for m in FENCE.finditer(README_TEXT) if m.group(2).strip() == "gpp"]
    name = re.match(r"// (\S+\.gpp)", agent)
    assert name is not None, "the README's agent starts with a comment naming its file"
    (tmp_path / name.group(1)).write_text(agent, encoding="utf-8")
    (session,) = [m.group(3) for m in FENCE.finditer(README_TEXT) if m.group(3).startswith("$ gpp check")]
    shown = re.split(r"^\$ (.*)\n", session, flags=re.MULTILINE)[1:]
    commands = shown[0::2]
    assert commands == [f"gpp check {name.group(1)}", f"gpp run {name.group(1)}"]
    for command, output in zip(commands, shown[1::2], strict=True):
        result = gpp(*command.split()[1:], cwd=tmp_path)
        assert result.returncode == 0, result.stdout + result.stderr
        assert _wall_clock_out(result.stdout + result.stderr) == _wall_clock_out(output), command


def test_the_tutorial_goes_from_a_first_agent_to_a_tested_project() -> None:
    text = (ROOT / "docs" / "tutorial.md").read_text(encoding="utf-8")
    chapters = re.findall(r"^## \d+\. (.*)$", text, re.MULTILINE)
    assert len(chapters) == 8
    assert "failures" in chapters[5] and "project" in chapters[6] and "run" in chapters[7]
    # Each chapter has a program that the docs test checks (chapter 8 runs chapter 6's).
    sections = re.split(r"^## \d+\. .*$", text, flags=re.MULTILINE)[1:8]
    assert all("```gpp" in section for section in sections)
    # Chapter 3 says how the scenario's result reaches the sensing function.
    assert "answers with that result" in sections[2]
