"""Checks of paths a command will write, made before any work starts."""

from __future__ import annotations

import os
import stat
import tempfile
from collections.abc import Iterable
from pathlib import Path

_KINDS = {
    stat.S_IFIFO: "a named pipe (FIFO)",
    stat.S_IFCHR: "a character device",
    stat.S_IFBLK: "a block device",
    stat.S_IFSOCK: "a socket",
    stat.S_IFDIR: "a folder",
}


def input_problem(path: Path, *, folder: bool = False) -> str | None:
    """Why `path` cannot be read as a program or data file (missing, a link that loops, not a
    regular file: reading a FIFO would wait for ever, a device would never end), or None. A
    folder is fine where `folder` is."""
    try:
        mode = os.stat(path).st_mode
    except OSError as e:
        return f"cannot read '{path}': {e.strerror or e}"
    if stat.S_ISREG(mode) or (folder and stat.S_ISDIR(mode)):
        return None
    return f"cannot read '{path}': it is {_KINDS.get(stat.S_IFMT(mode), 'not a regular file')}, not a file"


def output_problem(path: Path) -> str | None:
    """Why `path` cannot be written as a file (a folder, or in a folder that does not exist),
    or None when it can."""
    if path.is_dir():
        return f"'{path}' is a folder, not a file"
    parent = path.parent
    if not parent.is_dir():
        return f"the folder '{parent}' does not exist"
    return None


def overwritten_input(output: Path, inputs: Iterable[tuple[Path, str]]) -> str | None:
    """What writing `output` would overwrite of the `inputs` (each a path and what it is: "the
    program", "the scenario file"), as "'agent.gpp' is the program", or None. The same file
    under another name (a link, `./x`, an absolute path) counts."""
    if not output.is_file():
        return None
    for path, what in inputs:
        try:
            if os.path.samefile(output, path):
                return f"'{output}' is {what}"
        except OSError:
            continue
    return None


def write_problem(path: Path) -> str | None:
    """Why `write_atomically` could not replace the existing file `path` (it is read-only, or
    its folder takes no new file), or None: checked for every file before any is written."""
    if not os.access(path, os.W_OK):
        return f"cannot write '{path}': it is read-only"
    try:
        fd, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
        os.close(fd)
        os.unlink(temporary)
    except OSError as e:
        return f"cannot write '{path}': {e.strerror or e}"
    return None


def write_atomically(path: Path, data: str | bytes) -> None:
    """Write the file in one step: to a temporary file beside it, then renamed over it (keeping
    the permissions of the file it replaces; a new file gets those `open` would give it, as the
    umask allows), so a reader never sees half a file. Text is written as UTF-8 with its line
    endings as they are."""
    fd, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as out:
            out.write(data.encode("utf-8") if isinstance(data, str) else data)
        os.chmod(temporary, path.stat().st_mode & 0o7777 if path.exists() else 0o666 & ~_umask())
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


def _umask() -> int:
    """The process's umask (read by setting it, and setting it back)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask
