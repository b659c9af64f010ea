"""The browser tests (test_console_browser.py) start chromium and runs: slow (`make quick`
leaves them out)."""

from __future__ import annotations

import pytest


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for item in items:
        if item.path.name == "test_console_browser.py":
            item.add_marker(pytest.mark.slow)
