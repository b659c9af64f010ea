"""The debugger's tests: each gets a folder with the test programs and a `gpp dap` session."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.dap.programs import write_programs
from tests.support.dap_client import DapClient, dap_session


@pytest.fixture
def programs(tmp_path: Path) -> Path:
    write_programs(tmp_path)
    return tmp_path


@pytest.fixture
def dap(programs: Path) -> Iterator[DapClient]:
    with dap_session(cwd=programs) as client:
        yield client
