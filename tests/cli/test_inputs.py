"""Inputs that are not regular files: every command that reads a program or a trace refuses a
named pipe (reading it would wait for ever), a device (reading /dev/zero never ends) and a
symbolic link that loops, with one line and exit code 2, as a real process with a time limit."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from tests.support.cli import run_process

COMMANDS = [["check"], ["fmt"], ["run"], ["test"], ["trace", "summary"], ["trace", "html"]]


def make(kind: str, folder: Path) -> tuple[str, str]:
    """The path given to the command, and what the error says it is."""
    if kind == "fifo":
        os.mkfifo(folder / "agent.gpp")
        return "agent.gpp", "cannot read 'agent.gpp': it is a named pipe (FIFO), not a file"
    if kind == "device":
        return "/dev/zero", "cannot read '/dev/zero': it is a character device, not a file"
    (folder / "a.gpp").symlink_to("b.gpp")
    (folder / "b.gpp").symlink_to("a.gpp")
    return "a.gpp", "cannot read 'a.gpp': Too many levels of symbolic links"


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["fifo", "device", "loop"])
@pytest.mark.parametrize("command", COMMANDS, ids=" ".join)
def test_a_path_that_is_not_a_regular_file_is_refused(tmp_path: Path, command: list[str], kind: str) -> None:
    given, says = make(kind, tmp_path)
    result = run_process(*command, given, cwd=tmp_path, timeout=60)
    assert (result.returncode, result.stderr) == (2, f"error: {says}\n"), result.stdout
