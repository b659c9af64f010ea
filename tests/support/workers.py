"""Resources that parallel test workers (pytest-xdist, `-n auto`) must not share, taken from
the worker's number (PYTEST_XDIST_WORKER `gw0`, `gw1`, ...; none without xdist)."""

from __future__ import annotations

import os
import random


def worker() -> tuple[int, int]:
    """(this worker's number, how many workers there are): (0, 1) without xdist."""
    name = os.environ.get("PYTEST_XDIST_WORKER", "gw0")
    count = int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1"))
    return int(name.removeprefix("gw")), max(count, 1)


def ros_domain() -> int:
    """A ROS domain id (1-100) no other worker of this run uses: random among those that are
    this worker's number modulo the count of workers (random, so that two runs on one machine
    seldom meet either)."""
    number, count = worker()
    return random.choice([d for d in range(1, 101) if d % count == number % count])
