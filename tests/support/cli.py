"""The `gpp` command for tests: `run` calls the entry point (gpp.cli.main.main) in this process,
`run_process` starts `python -m gpp` as a real process. Both take the same arguments and give
the same result (`returncode`, `stdout`, `stderr`, as subprocess.CompletedProcess has them).

In this process, `run` gives the command what a process would have: its own standard streams
(text, UTF-8, not a terminal; 80 columns unless `env` gives COLUMNS), the working directory
`cwd`, the environment without the colour and debug switches plus `env`. It puts back what a
command changes for the whole process: the streams, the working directory, the environment,
the SIGINT/SIGTERM/SIGALRM handlers, the unraisable hook, the recursion limit, and the root logger's handlers and level.

Use a real process only for what needs one: start-up (what a command imports), signals, exit
code 3 of an internal error, pipes, `python -m gpp` and the console script.
"""

from __future__ import annotations

import io
import logging
import os
import signal
import subprocess
import sys
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

# Switches of the user's environment that change what gpp writes: a test starts without them
# (and with 80 columns, as through a pipe, unless its `env` gives COLUMNS).
CLEARED = ("NO_COLOR", "FORCE_COLOR", "GPP_DEBUG", "COLUMNS")


@dataclass(frozen=True)
class Result:
    """What a `gpp` command did: its exit code and what it wrote (universal newlines)."""

    args: tuple[str, ...]
    returncode: int
    stdout: str
    stderr: str


class Runner(Protocol):
    """`run` or `run_process`."""

    def __call__(
        self, *args: str, cwd: Path | str | None = None, env: Mapping[str, str] | None = None, input: str | None = None
    ) -> Result: ...


def environment(env: Mapping[str, str] | None = None) -> dict[str, str]:
    """The environment of a command: this one without CLEARED, with `env` on top."""
    full = {k: v for k, v in os.environ.items() if k not in CLEARED}
    full.update(env or {})
    return full


def run(
    *args: str, cwd: Path | str | None = None, env: Mapping[str, str] | None = None, input: str | None = None
) -> Result:
    """Run `gpp *args` in this process (stdin reads `input`, empty when None)."""
    from gpp.cli.main import main

    streams = sys.stdin, sys.stdout, sys.stderr
    old_cwd = os.getcwd()
    old_environ = dict(os.environ)
    handlers = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM, signal.SIGALRM)}
    unraisable_hook = sys.unraisablehook
    recursion_limit = sys.getrecursionlimit()
    root = logging.getLogger()
    log_handlers, log_level = list(root.handlers), root.level
    out, err = _stream(), _stream()
    sys.stdin = io.TextIOWrapper(io.BytesIO((input or "").encode()), encoding="utf-8")
    sys.stdout, sys.stderr = out, err
    try:
        wanted = environment(env)  # from the environment as it is, before it is cleared
        os.environ.clear()
        os.environ.update(wanted)
        os.environ.setdefault("COLUMNS", "80")  # what a pipe gives: not the terminal pytest runs in
        if cwd is not None:
            os.chdir(cwd)
        try:
            main(list(args))
            code = 0
        except SystemExit as e:
            code = _exit_code(e.code, err)
    finally:
        sys.stdin, sys.stdout, sys.stderr = streams
        os.chdir(old_cwd)
        os.environ.clear()
        os.environ.update(old_environ)
        for sig, handler in handlers.items():
            signal.signal(sig, handler)
        sys.unraisablehook = unraisable_hook
        sys.setrecursionlimit(recursion_limit)
        root.handlers[:] = log_handlers
        root.setLevel(log_level)
    return Result(tuple(args), code, _text(out), _text(err))


def run_process(
    *args: str,
    cwd: Path | str | None = None,
    env: Mapping[str, str] | None = None,
    input: str | None = None,
    timeout: float = 120,
) -> Result:
    """Run `python -m gpp *args` as a real process."""
    done = subprocess.run(
        [sys.executable, "-m", "gpp", *args],
        cwd=cwd,
        env=environment(env),
        input=input,
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    return Result(tuple(args), done.returncode, done.stdout, done.stderr)


def _stream() -> io.TextIOWrapper:
    return io.TextIOWrapper(io.BytesIO(), encoding="utf-8", write_through=True)


def _text(stream: io.TextIOWrapper) -> str:
    stream.flush()
    buffer = stream.buffer
    assert isinstance(buffer, io.BytesIO)
    return buffer.getvalue().decode("utf-8").replace("\r\n", "\n").replace("\r", "\n")


def _exit_code(code: object, err: io.TextIOWrapper) -> int:
    """The exit status of `sys.exit(code)`, as the interpreter makes it."""
    if code is None:
        return 0
    if isinstance(code, int):
        return code
    print(code, file=err)
    return 1
