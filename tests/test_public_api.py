"""The public packages: each name of ``__all__`` is there, and importing a package costs no numpy (its names
load on first use)."""

from __future__ import annotations

import importlib
import subprocess
import sys

import pytest

PACKAGES = ["tftools", "tftools.core", "tftools.sources", "tftools.analysis"]


@pytest.mark.parametrize("package", PACKAGES)
def test_every_public_name_is_there(package: str) -> None:
    module = importlib.import_module(package)
    assert module.__all__ and len(set(module.__all__)) == len(module.__all__)
    missing = [name for name in module.__all__ if getattr(module, name, None) is None]
    assert missing == []
    assert set(module.__all__) <= set(dir(module))


@pytest.mark.parametrize("package", PACKAGES)
def test_importing_a_package_costs_no_numpy(package: str) -> None:
    code = f"import sys, {package}; print('numpy' in sys.modules)"
    said = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert said.strip() == "False"
