"""Messages a live source received, decoded together by the bulk decoder bags use: each keeps its publisher,
topic and receive time; a message that is not well-formed is told apart and gives nothing."""

from __future__ import annotations

import numpy as np

from tftools.core.transform import Transform
from tftools.sources.codecs import cdr, ros1
from tftools.sources.codecs.decoded import BulkDecoder, TransformEncoder
from tftools.sources.live.received import Received, decode_received


def _message(encode: TransformEncoder, *edges: tuple[str, str, int, float]) -> bytes:
    return encode([Transform((x, 0.0, 0.0), stamp=stamp, frame_id=p, child_frame_id=c) for p, c, stamp, x in edges])


def _arrivals(encode: TransformEncoder) -> list[Received]:
    return [
        Received("/tf", _message(encode, ("odom", "base", 7, 1.0), ("base", "arm", 8, 2.0)), "/driver", 50),
        Received("/tf", _message(encode, ("map", "odom", 9, 3.0))[:-5], "/broken", 40),  # cut short
        Received("/tf_static", _message(encode, ("base", "laser", 0, 4.0)), "/state", 30),
        Received("/tf", _message(encode), "/driver", 60),  # well-formed, no transform
        Received("/tf", _message(encode, ("odom", "base", 10, 5.0)), "/driver", 70),
    ]


def _rows(decode: BulkDecoder, encode: TransformEncoder) -> None:
    messages = _arrivals(encode)
    arrivals = decode_received(decode, messages)
    batch = arrivals.batch
    names = batch.frame_names
    assert [(names[p], names[c]) for p, c in zip(batch.parent, batch.child, strict=True)] == [
        ("odom", "base"),
        ("base", "arm"),
        ("base", "laser"),
        ("odom", "base"),
    ]
    assert batch.stamp.tolist() == [7, 8, 0, 10] and batch.translation[:, 0].tolist() == [1.0, 2.0, 4.0, 5.0]
    assert [batch.authorities[a] for a in batch.authority] == ["/driver", "/driver", "/state", "/driver"]
    assert batch.authorities == ["/driver", "/state"]  # not the unreadable message's publisher
    assert batch.static.tolist() == [False, False, True, False]
    assert batch.record_time.tolist() == [50, 50, 30, 70]
    assert arrivals.readable == 4
    assert [(m.authority, m.topic) for m, _ in arrivals.unreadable] == [("/broken", "/tf")]
    sent = arrivals.sent  # those that held a transform, in record order, with their first stamp
    assert sent.record_time.tolist() == [30, 50, 70] and sent.stamp.tolist() == [0, 7, 10]
    assert [sent.authorities[a] for a in sent.authority] == ["/state", "/driver", "/driver"]
    assert sent.static.tolist() == [True, False, False]
    one_by_one = [decode_received(decode, [m]).batch for m in messages]
    assert np.array_equal(np.concatenate([b.rotation for b in one_by_one]), batch.rotation)


def test_cdr_messages_decode_together_as_one_by_one() -> None:
    _rows(cdr.decode_tf, cdr.encode_tf_message)


def test_ros1_messages_decode_together_as_one_by_one() -> None:
    _rows(ros1.decode_tf, ros1.encode_tf_message)


def test_nothing_received_is_nothing_decoded() -> None:
    arrivals = decode_received(cdr.decode_tf, [])
    assert not len(arrivals.batch) and not len(arrivals.sent) and arrivals.readable == 0 and not arrivals.unreadable
