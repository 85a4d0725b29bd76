"""Damaged copies of the corpus's real recordings, made where a test asks (never in the corpus)."""

from __future__ import annotations

import dataclasses
import random
import shutil
import sqlite3
from collections.abc import Callable
from contextlib import closing
from pathlib import Path
from typing import Any

import pytest

from tests.corpus import variants
from tests.corpus.fetch import shared_dir
from tests.sources.bag.reading import read_contents
from tests.sources.ros2_helpers import batch_rows

TOPICS = ("/tf", "/tf_static")


def copied(name: str, into: Path) -> Path:
    """A copy in ``into`` of the corpus recording ``name`` (a file or a bag directory, links followed)."""
    original = shared_dir() / "corpus" / name
    if not original.exists():
        pytest.skip(f"{name} is not in {original.parent}")
    target = into / original.name
    if original.is_dir():
        shutil.copytree(original, target)
    else:
        shutil.copyfile(original, target)
    for path in [target, *target.rglob("*")]:
        path.chmod(0o755 if path.is_dir() else 0o644)
    return target


def overwritten(path: Path, share: float, seed: int = 43, length: int = 16) -> None:
    """``length`` bytes from ``share`` of the file overwritten with seeded noise."""
    data = bytearray(path.read_bytes())
    start = int(len(data) * share)
    rng = random.Random(seed)
    data[start : start + length] = bytes(rng.randrange(256) for _ in range(length))
    path.write_bytes(bytes(data))


def zeroed_pages(db3: Path, share: float, length: int = 1 << 16) -> None:
    """``length`` bytes of whole pages zeroed from ``share`` of a .db3 (its pages are 4 KiB)."""
    data = bytearray(db3.read_bytes())
    at = int(len(data) * share) // 4096 * 4096
    data[at : at + length] = bytes(length)
    db3.write_bytes(bytes(data))


def cut(path: Path, size: int) -> None:
    with path.open("r+b") as f:
        f.truncate(size)


def rows(path: Path) -> tuple[list[tuple[Any, ...]], list[str]]:
    contents = read_contents([path], TOPICS)
    return batch_rows(contents.transforms), contents.problems


def record_time_moved(path: Path, to: Callable[[int], int], topic: str = "/tf") -> int:
    """The middle message on ``topic`` of a .bag, .mcap or .db3 file recorded at ``to(its record time)`` instead,
    the file written again in place (a .db3 changed in its row); returns the time it was recorded at."""
    if path.suffix == ".db3":
        with closing(sqlite3.connect(path)) as db, db:
            rows = db.execute(
                "SELECT m.id, m.timestamp FROM messages m JOIN topics t ON m.topic_id = t.id WHERE t.name = ? "
                "ORDER BY m.timestamp",
                (topic,),
            ).fetchall()
            row, time = rows[len(rows) // 2]
            db.execute("UPDATE messages SET timestamp = ? WHERE id = ?", (to(time), row))
        return int(time)
    if path.suffix == ".mcap":
        return _mcap_record_time_moved(path, to, topic)
    contents = variants.read(path)
    on_topic = [i for i, (k, _, _) in enumerate(contents.messages) if contents.connections[k].topic == topic]
    moved = list(contents.messages)
    key, time, raw = moved[on_topic[len(on_topic) // 2]]
    moved[on_topic[len(on_topic) // 2]] = (key, to(time), raw)
    written = variants.write_ros1(path.with_name("moved.bag"), dataclasses.replace(contents, messages=moved))
    written.replace(path)
    return time


def _mcap_record_time_moved(path: Path, to: Callable[[int], int], topic: str) -> int:
    from mcap.reader import make_reader
    from mcap.writer import Writer

    with path.open("rb") as f:
        reader = make_reader(f)
        header, summary = reader.get_header(), reader.get_summary()
        assert summary is not None
        messages = [(c, m) for _, c, m in reader.iter_messages(log_time_order=False)]
    on_topic = [i for i, (c, _) in enumerate(messages) if c.topic == topic]
    middle = on_topic[len(on_topic) // 2]
    time = messages[middle][1].log_time
    with path.open("wb") as out:
        writer = Writer(out)
        writer.start(profile=header.profile, library=header.library)
        schemas = {s.id: writer.register_schema(s.name, s.encoding, s.data) for s in summary.schemas.values()}
        channels = {
            c.id: writer.register_channel(c.topic, c.message_encoding, schemas.get(c.schema_id, 0), c.metadata)
            for c in summary.channels.values()
        }
        for i, (channel, message) in enumerate(messages):
            at = to(time) if i == middle else message.log_time
            writer.add_message(channels[channel.id], at, message.data, message.publish_time, message.sequence)
        writer.finish()
    return int(time)
