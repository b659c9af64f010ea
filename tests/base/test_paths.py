"""gpp.base.paths.write_atomically: a file written in one step, with the permissions a user
expects of it."""

from __future__ import annotations

import os
import stat
from pathlib import Path

from gpp.base.paths import write_atomically


def test_a_new_file_gets_the_permissions_the_umask_gives(tmp_path: Path) -> None:
    old = os.umask(0o022)
    try:
        write_atomically(tmp_path / "run.mcap", b"data")
        os.umask(0o077)
        write_atomically(tmp_path / "private.html", "text")
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "run.mcap").stat().st_mode) == 0o644
    assert stat.S_IMODE((tmp_path / "private.html").stat().st_mode) == 0o600
    assert (tmp_path / "run.mcap").read_bytes() == b"data"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["private.html", "run.mcap"]  # no temporary left


def test_a_replaced_file_keeps_its_permissions(tmp_path: Path) -> None:
    target = tmp_path / "agent.gpp"
    target.write_text("old")
    target.chmod(0o640)
    write_atomically(target, "new")
    assert (target.read_text(), stat.S_IMODE(target.stat().st_mode)) == ("new", 0o640)
