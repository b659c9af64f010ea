"""The programs the debugger's tests run, written into each test's folder (`write_programs`).

They live here, not as .gpp files of the repository, so that the repository-wide program tests
(formatting, the model's golden fingerprints) stay as they are."""

from __future__ import annotations

from pathlib import Path

PROGRAMS: dict[str, str] = {
    "blocked.gpp": """\
bool fluent door_open() {
initially:
    () = false;
}

action knock() {}

procedure wait_for_door() {
    test(door_open());
}

procedure main() {
    knock();
    wait_for_door();
}
""",
    "crash.gpp": """\
number fluent n() {
initially:
    () = 0;
}

action noop() {}

procedure main() {
    noop();
    n() = 10 / n();
}
""",
    "errands.gpp": """\
// The debugger's test agent: procedures with arguments, a loop, a list and a compound fluent.
symbol domain Room = {office, kitchen, lab}

compound Pose {
    number x,
    number y
}

Room fluent robot_at() {
initially:
    () = office;
}

number fluent cups(Room r) {
initially:
    (r) = 0;
    (kitchen) = 2;
    (lab) = 1;
}

number fluent carried() {
initially:
    () = 0;
}

list[Room] fluent visited() {
initially:
    () = list[Room] [];
}

Pose fluent pose() {
initially:
    () = Pose { x = 1, y = 2 };
}

action go(Room r) {
precondition:
    robot_at() != r
effect:
    robot_at() = r;
}

action pick_up() {
precondition:
    cups(robot_at()) > 0
effect:
    cups(robot_at()) = cups(robot_at()) - 1;
    carried() = carried() + 1;
}

procedure collect(Room r) {
    if (robot_at() != r)
        go(r);
    push_back(visited(), r);
    while (cups(r) > 0)
        pick_up();
}

procedure main(Room first, number rounds) {
    collect(first);

    collect(lab);
    pose().x = rounds;
    go(office);
}

bool function postcond() = carried() == 3
""",
    "failing.gpp": """\
// scenario: failing.toml
symbol domain Room = {office, lab}

Room fluent robot_at() {
initially:
    () = office;
}

action go(Room r) {
duration: [4, 4]
precondition:
    robot_at() != r
effect:
    robot_at() = r;
}

procedure main() {
    during (go(lab)) {
        test(true);
    }
    go(lab);
}
""",
    "failing.toml": """\
# The drive to the lab fails once.
[[action]]
match = "go(lab)"
outcome = "fail"
times = 1
""",
    "forever.gpp": """\
// Runs until it is paused or ended.
number fluent ticks() {
initially:
    () = 0;
}

action tick() {
effect:
    ticks() = ticks() + 1;
}

procedure main() {
    while (true)
        tick();
}
""",
    "noplan.gpp": """\
bool fluent done() {
initially:
    () = false;
}

action work() {
precondition:
    false
effect:
    done() = true;
}

number function reward() = if (done()) 10 else 0

procedure main() {
    solve(2, reward())
        work();
}
""",
    "planned.gpp": """\
// `solve` chooses `fast()`: the planner looks at `slow()` too, the run never executes it.
bool fluent done() {
initially:
    () = false;
}

number fluent cost() {
initially:
    () = 0;
}

action slow() {
effect:
    cost() = cost() + 5;
    done() = true;
}

action fast() {
effect:
    cost() = cost() + 1;
    done() = true;
}

action tidy() {}

number function reward() = if (done()) 10 - cost() else 0

procedure main() {
    solve(2, reward())
        choose {
            slow();
            { fast(); tidy(); }
        }
}
""",
    "unchecked.gpp": """\
procedure main() {
    undefined_action();
}
""",
}


def write_programs(folder: Path) -> None:
    for name, text in PROGRAMS.items():
        (folder / name).write_text(text, encoding="utf-8")


def tutorial_program(folder: Path, holding: str, name: str) -> Path:
    """The program of the tutorial (docs/tutorial.md) that holds `holding`, saved in `folder`
    as `name` with the tutorial's scenario files beside it."""
    from tests.test_docs import GPP, ROOT, write

    tutorial = ROOT / "docs" / "tutorial.md"
    (example,) = [e for e in GPP if e.page == tutorial and holding in e.text]
    return write(example, folder).rename(folder / name)
