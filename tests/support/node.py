"""Node for the tests of the VS Code extension (editors/vscode) and of `gpp dap` through the
official DebugClient: where the extension and its npm packages are, whether they can run here,
and a Node script run in the extension's folder.

The npm packages come from `make vscode` (run by `make test`), at the versions of
editors/vscode/package-lock.json; without Node 20 or without the packages, the tests that need
them are skipped and say which and how to get it.
"""

from __future__ import annotations

import functools
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXTENSION = ROOT / "editors" / "vscode"
NODE_MODULES = EXTENSION / "node_modules"
NODE = shutil.which("node")
# The gpp of this Python (the extension and the DebugClient start `gpp lsp` and `gpp dap`).
GPP = str(Path(sys.executable).with_name("gpp"))


def _node_major() -> int | None:
    if NODE is None:
        return None
    done = subprocess.run([NODE, "-p", "process.versions.node"], capture_output=True, text=True, timeout=60)
    return int(done.stdout.split(".")[0]) if done.returncode == 0 else None


_WHAT = "the Node tests (the VS Code extension, the DebugClient driving gpp dap)"


@functools.cache
def why_not() -> str | None:
    """Why the Node tests cannot run here (None when they can)."""
    major = _node_major()
    if major is None:
        return f"Node is not installed: {_WHAT} need Node 20 or newer and `make vscode`"
    if major < 20:
        return f"Node {major} is too old: {_WHAT} need Node 20 or newer (@vscode/vsce 3)"
    if not (NODE_MODULES / ".package-lock.json").is_file():
        return f"the npm packages of editors/vscode are not installed: {_WHAT} need them, `make vscode` installs them"
    return None


needs_node = pytest.mark.skipif(why_not() is not None, reason=str(why_not()))


def node(*args: str, timeout: float = 120, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    """Run Node with these arguments in editors/vscode, where the npm packages resolve; the
    environment gets PYTHONPATH to this checkout, so that `gpp` runs its code."""
    assert NODE is not None
    full_env = {**os.environ, "PYTHONPATH": str(ROOT), **(env or {})}
    return subprocess.run([NODE, *args], cwd=EXTENSION, env=full_env, capture_output=True, text=True, timeout=timeout)


def npm_tool(name: str) -> str:
    """The path of a command an npm package of the extension installs (node_modules/.bin)."""
    return str(NODE_MODULES / ".bin" / name)
