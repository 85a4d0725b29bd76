"""The corpus recordings' paths: skipped with the reason when missing, a failure in CI.

A recording placed in the shared folder (its manifest ``archive`` is ``{"shared": ...}``) is
optional until the CEO places it: while none of its files is there it skips with the reason, in
CI too. Once placed it is checked by sha256 like the others.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from tests.corpus.fetch import Recording, member_path, missing_members, root_of, shared_dir
from tests.corpus.recordings import Corpus


def _shared_copy(recording: Recording) -> Path | None:
    """Where the shared folder holds a byte-identical copy of a registry recording (its manifest's
    ``shared_copy``: ``open`` and ``members`` with the same sha256), all of it verified; else None."""
    copy = recording.meta.get("shared_copy")
    if recording.shared is not None or not copy or missing_members(shared_dir(), copy["members"]):
        return None
    return member_path(shared_dir(), copy["open"])


def _reason(recording: Recording) -> tuple[str, bool] | None:
    """Why ``recording`` cannot be used, and whether CI may skip for it; None when it can."""
    root = root_of(recording)
    missing = missing_members(root, recording.members)
    if not missing or _shared_copy(recording) is not None:
        return None
    if recording.shared is not None:
        where = root / recording.shared
        if not any(member_path(root, m).exists() for m in recording.members):
            return (
                f"corpus recording {recording.id} awaits placement in {where} "
                "(shared folder: $TFTOOLS_SHARED_DIR, default ../shared beside the repository)",
                True,
            )
        return f"corpus recording {recording.id} in {where} is altered or incomplete: {', '.join(missing)}", False
    return (
        f"corpus recording {recording.id} is not in {root} (missing or altered: {', '.join(missing)}); "
        "fetch it with: python -m tests.corpus.fetch",
        False,
    )


@pytest.fixture(scope="session")
def corpus() -> Corpus:
    """``corpus(recording) -> Path`` to open; skips (fails when ``CI=true``) if not fetched and verified."""
    checked: dict[str, tuple[str, bool] | None] = {}

    def path_of(recording: Recording) -> Path:
        if recording.id not in checked:
            checked[recording.id] = _reason(recording)
        found = checked[recording.id]
        if found is not None:
            reason, optional = found
            if os.environ.get("CI") == "true" and not optional:
                pytest.fail(f"CI must run the corpus tests, but {reason}")
            pytest.skip(reason)
        if missing_members(root_of(recording), recording.members):
            copy = _shared_copy(recording)
            assert copy is not None
            return copy
        return member_path(root_of(recording), recording.open)

    return path_of
