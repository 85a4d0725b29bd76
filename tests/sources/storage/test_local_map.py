"""A local file's map lets go of the pages read from it (``FileSource.release``), and of those the kernel
mapped beside them."""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

from tftools.sources.storage.source import FileSource


def _resident_kib(path: Path) -> int:
    """This process's resident KiB of its maps of ``path`` (Linux's smaps)."""
    total, inside = 0, False
    for line in Path("/proc/self/smaps").read_text().splitlines():
        if re.match(r"[0-9a-f]+-[0-9a-f]+ ", line):
            inside = line.rstrip().endswith(str(path))
        elif inside and line.startswith("Rss:"):
            total += int(line.split()[1])
    return total


@pytest.mark.skipif(not Path("/proc/self/smaps").exists(), reason="Linux's smaps tells what a map holds")
def test_a_released_range_leaves_no_page_of_the_map_resident(tmp_path: Path) -> None:
    """A ROS1 bag's chunk headers are read through the map and each chunk let go once read; the kernel maps up
    to 64 KiB of cached pages around each page faulted in (its fault-around), and those beside the range let go
    stayed: a 4 h .bag replay's map held 13 MB at its peak against 4 MB for 1.3 h (issue 41)."""
    path = tmp_path / "chunks.bin"
    data = os.urandom(4 << 20)
    with path.open("wb", buffering=0) as file:  # a page at a time, as a recorder writes: the page cache holds
        for at in range(0, len(data), 4096):  # it in small pages (written at once, in one large folio mapped whole)
            file.write(data[at : at + 4096])
    source = FileSource(path)
    buf = source.buffer()
    for start in range(100_000, 4_000_000, 300_000):  # a chunk's header read, then the chunk let go
        assert bytes(buf[start : start + 1]) == data[start : start + 1]
        source.release(start, start + 5_000)
    assert _resident_kib(path) == 0
    source.close()
