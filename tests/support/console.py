"""A `gpp run --console` in a real process for the console's tests: started on a free port of
loopback, its address read from the line it prints, its requests made with urllib."""

from __future__ import annotations

import json
import os
import queue
import subprocess
import sys
import threading
import urllib.error
import urllib.request
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
# Seconds a console may take to come up, a run to end: long, since a wait that holds ends at once.
WAIT = 60.0


class ConsoleRun:
    """`gpp run FILE --console 127.0.0.1:0 ARGS...` (with `--quiet`), in its own process."""

    def __init__(self, program: Path, *args: str, cwd: Path = ROOT, address: str = "127.0.0.1:0") -> None:
        env = {**os.environ, "PYTHONPATH": str(ROOT)}
        command = [sys.executable, "-m", "gpp", "run", str(program), "--quiet", "--console", address, *args]
        pipe = subprocess.PIPE
        self.process = subprocess.Popen(
            command, cwd=cwd, env=env, stdin=subprocess.DEVNULL, stdout=pipe, stderr=pipe, text=True
        )
        self._follow()

    def _follow(self) -> None:
        """Read what the process writes on stderr (in a thread), up to its console's address."""
        self.lines: queue.Queue[str | None] = queue.Queue()
        self.stderr: list[str] = []
        threading.Thread(target=self._read, daemon=True).start()
        self.url = self._url()

    def _read(self) -> None:
        assert self.process.stderr is not None
        for line in self.process.stderr:
            self.stderr.append(line)
            self.lines.put(line)
        self.lines.put(None)

    def _url(self) -> str:
        while True:
            line = self.lines.get(timeout=WAIT)
            if line is None:
                raise AssertionError("the console did not start:\n" + "".join(self.stderr))
            if line.startswith("console: http"):
                return line.split(" ", 1)[1].strip()

    @property
    def base(self) -> str:
        """The URL without its query (the token)."""
        return self.url.split("?", 1)[0]

    def request(self, path: str, body: Any = None, headers: dict[str, str] | None = None) -> tuple[int, Any]:
        """(status, JSON body) of a GET, or a POST when `body` is given."""
        data = None if body is None else json.dumps(body).encode()
        sent = {"Content-Type": "application/json"} if body is not None else {}
        sent.update(headers or {})
        req = urllib.request.Request(self.base + path, data=data, headers=sent)
        try:
            with urllib.request.urlopen(req, timeout=WAIT) as answer:
                return answer.status, json.loads(answer.read())
        except urllib.error.HTTPError as e:
            return e.code, json.loads(e.read())

    def finish(self) -> tuple[int, str]:
        """Wait for the run's end: (exit code, what it printed)."""
        out, _ = self.process.communicate(timeout=WAIT)
        return self.process.returncode, out

    def close(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
            self.process.communicate(timeout=WAIT)

    def state_when(self, holds: Any, what: str, path: str = "state") -> dict[str, Any]:
        """The console's view (at `path`) once `holds(view)` (looked at again and again, up to WAIT)."""
        import time

        deadline = time.monotonic() + WAIT
        while True:
            status, view = self.request(path)
            assert status == 200, view
            if holds(view):
                return dict(view)
            if time.monotonic() > deadline:
                raise AssertionError(f"the console never showed {what}: {view}")
            time.sleep(0.05)
