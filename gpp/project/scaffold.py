"""`gpp new NAME`: a starter agent project that checks cleanly and whose test passes.

NAME/
  gpp.toml                 settings: include folder, test paths, time bounds
  README.md                what is where, the commands
  agent.gpp                the agent: `main()` and its `postcond()`
  src/robot.gpp            the robot: rooms, fluents, actions (included by agent and tests)
  scenarios/delivery.toml  outcomes and events for the dummy platform
  tests/delivery.gpp       a test program: a delivery despite a failed first attempt
"""

from __future__ import annotations

import re
from pathlib import Path

_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_.-]*")


class ScaffoldError(Exception):
    """The project cannot be created there (the message says why)."""


def _files(name: str) -> dict[str, str]:
    return {
        "gpp.toml": f"""\
# Settings of the gpp project `{name}` (`gpp config` shows them resolved; docs/config.md).
paths = ["."]            # what `gpp check` looks at
include = ["src"]        # `#include "robot.gpp"` finds src/robot.gpp

[lint]
disable = []             # lints not reported, by code or name

[run]
platform = "dummy"       # `gpp run agent.gpp` runs in virtual time
timeout = 600            # seconds of wall-clock time a run may take
# time_limit = 3600      # seconds of platform (mission) time; none unless set

[test]
paths = ["tests"]        # what `gpp test` runs
timeout = 60             # seconds of wall-clock time per program
# time_limit = 600       # seconds of platform (mission) time per program; none unless set
""",
        "README.md": f"""\
# {name}

A golog++ agent: a robot that fetches a parcel from the hall and delivers it to the office.

| file | what it is |
|---|---|
| `src/robot.gpp` | the robot: rooms, what it knows (fluents), what it can do (actions) |
| `agent.gpp` | the agent: `main()` and the `postcond()` that says it succeeded |
| `tests/delivery.gpp` | a test program: the delivery succeeds even when the first pick-up fails |
| `scenarios/delivery.toml` | what the dummy platform makes happen in that test |
| `gpp.toml` | the project's settings |

```
gpp check                 # every program of the project, with the lints
gpp run agent.gpp         # run the agent in virtual time
gpp test                  # run the programs in tests/ and check their postcond()
```
""",
        "src/robot.gpp": """\
// The robot: where it is, what it carries, and what it can do.

symbol domain Room = {hall, kitchen, office}

Room fluent robot_at() {
initially:
    () = hall;
}

bool fluent holding() {
initially:
    () = false;
}

bool fluent delivered() {
initially:
    () = false;
}

action go_to(Room r) {
duration: [2, 5]
effect:
    robot_at() = r;
}

action pick_up() {
precondition:
    !holding()
effect:
    holding() = true;
}

action put_down() {
precondition:
    holding()
effect:
    holding() = false;
    delivered() = robot_at() == office;
}

// Pick the parcel up, trying again as long as the pick-up fails.
procedure fetch(Room r) {
    go_to(r);
    while (!holding())
        pick_up();
}

procedure deliver(Room from, Room to) {
    fetch(from);
    go_to(to);
    put_down();
}
""",
        "agent.gpp": """\
// The agent: deliver the parcel from the hall to the office.
#include "robot.gpp"

procedure main() {
    deliver(hall, office);
}

bool function postcond() = delivered()
""",
        "scenarios/delivery.toml": """\
# The dummy platform's script for tests/delivery.gpp: times are seconds of virtual time.

[defaults]
duration = 3.0

# The first pick-up fails; the robot tries again.
[[action]]
match = "pick_up()"
outcome = "fail"
times = 1
""",
        "tests/delivery.gpp": """\
// scenario: ../scenarios/delivery.toml
// A delivery when the first pick-up fails: the robot tries again and still delivers.
#include "robot.gpp"

procedure main() {
    deliver(hall, office);
}

bool function postcond() = delivered() & robot_at() == office
""",
    }


def create_project(folder: Path) -> list[Path]:
    """Write a starter project into `folder` (created; it may exist if it is empty). Returns
    the files written; ScaffoldError when the folder is not empty or the name is unusable."""
    # The project is named after its folder (`gpp new .` names it after the working directory).
    name = folder.name or Path.cwd().joinpath(folder).resolve().name
    if not _NAME.fullmatch(name):
        raise ScaffoldError(f"'{name}' is not a usable project name (a letter, then letters, digits, `_`, `-` or `.`)")
    if folder.exists():
        if not folder.is_dir():
            raise ScaffoldError(f"'{folder}' exists and is not a folder")
        if any(folder.iterdir()):
            raise ScaffoldError(f"'{folder}' exists and is not empty; choose another name or remove it")
    written: list[Path] = []
    for relative, text in _files(name).items():
        path = folder / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        written.append(path)
    return written
