"""Every corpus .db3's messages table read from its pages gives sqlite's rows, bit for bit: every topic's
whole, and every other topic cut to a header's bytes (where the page reader takes the file: not one with
a -wal file beside it, which sqlite reads)."""

from __future__ import annotations

import pytest

from tests.corpus.fetch import Recording
from tests.corpus.recordings import RECORDINGS, Corpus
from tests.sources.bag.test_db3_pages import from_pages, through_sqlite
from tftools.sources.bag.rosbag2.database import Database

DB3 = [r for r in RECORDINGS if r.meta.get("format") == "db3"]

pytest.importorskip("tftools.sources.bag.rosbag2._sqlite", reason="built without sqlite's headers")


@pytest.mark.parametrize("recording", DB3, ids=[r.id for r in DB3])
def test_pages_give_sqlites_rows(recording: Recording, corpus: Corpus) -> None:
    opened = corpus(recording)
    files = sorted(opened.glob("*.db3")) if opened.is_dir() else [opened]
    assert files
    for path in files:
        db = Database(path)
        try:
            topics = [int(row[0]) for row in db.rows("SELECT id FROM topics")]  # type: ignore[call-overload]
            if path.with_name(path.name + "-wal").exists():
                assert db.pages(64, 1 << 20, topics, (), 300) is None
                continue
            for headed in ([], topics[1::2]):
                expected = through_sqlite(db, topics, headed)
                assert from_pages(db, topics, headed) == expected
        finally:
            db.close()
