"""`gpp dap` driven by the official DebugClient of @vscode/debugadapter-testsupport (Node), as VS
Code drives it: editors/vscode/test/dap/scenario.test.js launches editors/vscode/test/dap/
collect.gpp, hits a breakpoint, steps over, in and out, reads the variables, evaluates (also an
expression that does not type-check) and stops at a conditional breakpoint (one whose condition
does not type-check is refused with the error's place); once on the dummy platform and once on
the sim.

The DebugClient is an npm package: it needs Node 20 or newer and `make vscode` (which `make
test` runs); without them the test is skipped and says which is missing.
"""

from __future__ import annotations

import pytest

from tests.support.node import GPP, needs_node, node

pytestmark = [needs_node, pytest.mark.slow]


@pytest.mark.parametrize("platform", ["dummy", "sim"])
def test_the_debugclient_launches_stops_steps_inspects_and_evaluates(platform: str) -> None:
    done = node("--test", "test/dap/scenario.test.js", env={"GPP_COMMAND": GPP, "GPP_PLATFORM": platform}, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "# pass 1" in done.stdout and "# fail 0" in done.stdout, done.stdout
