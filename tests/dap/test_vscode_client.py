"""`gpp dap` driven by the official DebugClient of @vscode/debugadapter-testsupport (Node), as VS
Code drives it: editors/vscode/test/dap/scenario.test.js launches COLLECT below, hits a
breakpoint, steps over, in and out, reads the variables, evaluates (also an
expression that does not type-check) and stops at a conditional breakpoint (one whose condition
does not type-check is refused with the error's place); once on the dummy platform and once on
the sim.

The DebugClient is an npm package: it needs Node 20 or newer and `make vscode` (which `make
test` runs); without them the test is skipped and says which is missing.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.support.node import GPP, needs_node, node

pytestmark = [needs_node, pytest.mark.slow]

# The agent the scenario debugs (it finds the lines by their text): it collects the cups of two
# rooms. On the sim (world blocksworld) its actions, which have no mapping, succeed after a
# second as on the dummy platform.
COLLECT = """\
symbol domain Room = {office, kitchen, lab}

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
    while (cups(r) > 0)
        pick_up();
}

procedure main() {
    go(kitchen);
    collect(kitchen);
    collect(lab);
    go(office);
}

bool function postcond() = carried() == 3 & robot_at() == office
"""


@pytest.mark.parametrize("platform", ["dummy", "sim"])
def test_the_debugclient_launches_stops_steps_inspects_and_evaluates(platform: str, tmp_path: Path) -> None:
    program = tmp_path / "collect.gpp"
    program.write_text(COLLECT, encoding="utf-8")
    env = {"GPP_COMMAND": GPP, "GPP_PLATFORM": platform, "GPP_PROGRAM": str(program)}
    done = node("--test", "test/dap/scenario.test.js", env=env, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "# pass 1" in done.stdout and "# fail 0" in done.stdout, done.stdout
