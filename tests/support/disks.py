"""Files that cannot be written, made for real: an immutable file (`chattr +i`, which even
root cannot replace) and a full disk (a small tmpfs filled to the last byte). Each skips the
test, saying why, where the machine does not allow it (they need root)."""

from __future__ import annotations

import contextlib
import shutil
import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest


@contextlib.contextmanager
def immutable(path: Path) -> Iterator[Path]:
    """`path` (an existing file) made immutable for the block."""
    if subprocess.run(["chattr", "+i", str(path)], capture_output=True, check=False).returncode != 0:
        pytest.skip("chattr +i is not possible here (needs root and a file system with attributes)")
    try:
        yield path
    finally:
        subprocess.run(["chattr", "-i", str(path)], check=False)


@contextlib.contextmanager
def full_disk(folder: Path, files: dict[str, str], free: int = 0) -> Iterator[Path]:
    """`folder` as a 64 KiB file system holding `files` (name: text), then filled by a file
    named `filler` up to the last byte, or up to `free` bytes before it."""
    folder.mkdir()
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(folder)], capture_output=True)
    if mounted.returncode != 0:
        pytest.skip(f"cannot mount a small tmpfs here (needs root): {mounted.stderr.decode().strip()}")
    try:
        for name, text in files.items():
            (folder / name).write_text(text, encoding="utf-8")
        with (folder / "filler").open("wb", buffering=0) as filler:
            if free:
                filler.write(b"x" * (shutil.disk_usage(folder).free - free))
            else:
                for size in (1024, 1):
                    with contextlib.suppress(OSError):
                        while True:
                            filler.write(b"x" * size)
        yield folder
    finally:
        subprocess.run(["umount", str(folder)], check=False)
