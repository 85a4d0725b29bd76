"""Shared fixtures."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from tests.oracle import cpp_core, unavailable_reason


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Every test of tests/live, and every *_live.py module, is marked ``live``."""
    tests = Path(__file__).parent
    for item in items:
        path = item.path.relative_to(tests)  # not the checkout's own path: it may hold a folder named live
        if path.parts[0] == "live" or path.stem.endswith("_live"):
            item.add_marker(pytest.mark.live)


@pytest.fixture(scope="session")
def tf2_available() -> None:
    """Skip unless the real tf2 can run; in CI it must (CI installs it)."""
    reason = unavailable_reason()
    if reason is not None:
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI must run the tf2 comparison, but {reason}")
        pytest.skip(reason)


@pytest.fixture(scope="session")
def tf2_cpp() -> None:
    """Skip unless ROS 1's tf2 core in C++ (``tests/oracle/tf2_core.cpp``) builds against Debian's libtf2."""
    program = cpp_core()
    if isinstance(program, str):
        pytest.skip(program)
