"""Every golog++ example in docs/ is checked (and run, where the docs say it runs), so the
user's guide cannot drift from the language gpp implements.

A fenced block's info string says what it is (docs/language.md, "About the examples"):

* ```gpp            a complete program: it checks without any diagnostic;
* ```gpp run        ... and runs to its end on its platform (the dummy platform, or the sim
                     for a program with a `// world:` line), with `postcond()` holding;
* ```gpp fragment   statements: checked inside `procedure main() { ... }`, without errors;
* ```gpp error=CODE a program that shows a mistake: checking it reports CODE;
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
            (folder / named.group(1)).write_text(other.text, encoding="utf-8")
    text = example.text
    if example.info == "gpp fragment":
        text = "procedure main() {\n" + text + "}\n"
    path = folder / "example.gpp"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize("example", GPP, ids=lambda e: e.id)
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
