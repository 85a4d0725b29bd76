"""The corpus's recordings as manifest.json lists them, loaded once for every test module that picks from them."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from tests.corpus.fetch import Recording, load_manifest

ARCHIVES, RECORDINGS = load_manifest()
BY_ID = {r.id: r for r in RECORDINGS}
WITH_TF = [r for r in RECORDINGS if r.meta["frames"]]  # those with a tree to check

#: The ``corpus`` fixture's type: a recording's path to open (a skip while it awaits placement).
Corpus = Callable[[Recording], Path]
