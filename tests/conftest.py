"""What every test has: the hypothesis profile GPP_HYPOTHESIS names (tests.support.budget,
loaded before any test module builds its settings) and the fixture `gpp`, the command line run
in this process (tests.support.cli). The `slow` marker is declared in pyproject.toml."""

from __future__ import annotations

from tests.support.budget import load_profile

load_profile()

import pytest  # noqa: E402

from tests.support import cli  # noqa: E402


@pytest.fixture
def gpp() -> cli.Runner:
    """`gpp(*args, cwd=..., env=..., input=...)`: run a gpp command in this process; the result
    has `returncode`, `stdout` and `stderr`."""
    return cli.run
