"""An LZ4 frame cut short (a ROS 1 bag's or an MCAP file's lz4 chunk in a file cut short): what its last block
holds up to the cut is read, exactly, where lz4 gives nothing of a block that is not whole."""

from __future__ import annotations

import random
from pathlib import Path

import lz4.frame
import pytest

from tests.sources.bag.damaged import copied, cut, rows
from tftools.sources.bag import unpack
from tftools.sources.bag.lz4_prefix import lz4_prefix

# An LZ4 frame cut inside its one block: the block's sequences before the cut are read (lz4 gives none).


def _lz4_frame(size: int) -> tuple[bytes, bytes]:
    """Text-like bytes (repeats and literals) and their LZ4 frame of one block, as roslz4 writes a chunk."""
    rng = random.Random(7)
    words = [bytes(rng.randrange(97, 123) for _ in range(rng.randrange(2, 9))) for _ in range(200)]
    data = b" ".join(rng.choice(words) for _ in range(size // 5))[:size]
    frame = lz4.frame.compress(data, block_size=lz4.frame.BLOCKSIZE_MAX4MB, content_checksum=True)
    return data, frame


@pytest.mark.parametrize("kept", [0.05, 0.3, 0.5, 0.9, 0.999])
def test_an_lz4_frame_cut_short_gives_the_exact_start_of_its_block(kept: float) -> None:
    data, frame = _lz4_frame(600_000)
    short = frame[: int(len(frame) * kept)]
    assert lz4.frame.LZ4FrameDecompressor().decompress(short) == b""  # what lz4 gives
    prefix = lz4_prefix(short, len(data))
    assert len(prefix) > len(data) * kept * 0.5
    assert bytes(prefix) == data[: len(prefix)]
    got = unpack.unpack("lz4", short, len(data))
    assert bytes(got.data) == bytes(prefix)
    assert got.loss == f"lz4 data cut short: {len(prefix)} of {len(data)} bytes"


def test_a_damaged_lz4_frame_is_not_decoded_past_its_damage() -> None:
    """Flipped bytes are not a cut: the frame is left to lz4 (which says what is wrong), not decoded past them."""
    data, frame = _lz4_frame(600_000)
    damaged = bytearray(frame)
    for i in range(len(frame) // 2, len(frame) // 2 + 64):
        damaged[i] ^= 0x5A
    got = unpack.unpack("lz4", bytes(damaged), len(data))
    assert got.loss and not got.loss.startswith("lz4 data cut short")


def test_lz4_prefix_stays_within_its_limit_and_its_input() -> None:
    data, frame = _lz4_frame(600_000)
    assert bytes(lz4_prefix(frame[: len(frame) // 2], 1000)) == data[:1000]
    assert lz4_prefix(b"not lz4 at all", 1000) == bytearray()
    for end in range(0, 40):  # cut inside the frame's header and its first sequences
        assert bytes(lz4_prefix(frame[:end], len(data))) == data[: len(lz4_prefix(frame[:end], len(data)))]


def test_a_real_lz4_bag_cut_in_its_one_chunk_reads_the_messages_before_the_cut(tmp_path: Path) -> None:
    """rosbagjs-example-lz4.bag is one lz4 chunk of 217 kB (743 kB of records, one LZ4 block): cut in half,
    it read 0 transforms ('no transforms could be read', exit 2) where its first ~1,900 are there."""
    bag = copied("rosbagjs-example-lz4.bag", tmp_path)
    whole, _ = rows(bag)
    cut(bag, bag.stat().st_size // 2)
    got, problems = rows(bag)
    assert len(got) > len(whole) // 2
    assert got == whole[: len(got)]  # every one read as it was, in order
    assert any("truncated after" in p for p in problems)
