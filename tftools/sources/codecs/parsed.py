"""Messages parsed one by one in Python (JSON, and protobuf messages no template takes)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from tftools.core.arrays import Int64Array, UInt8Array
from tftools.sources.codecs.decoded import Decoded, DecodeError, FrameNames

_MIN_STAMP, _MAX_STAMP = -(2**63), 2**63 - 1


@dataclass
class Parsed:
    """One message's transforms (stamps in ns, values x y z qx qy qz qw)."""

    parents: list[str] = field(default_factory=list)
    children: list[str] = field(default_factory=list)
    stamps: list[int] = field(default_factory=list)
    values: list[tuple[float, ...]] = field(default_factory=list)


def one_by_one(
    raw: UInt8Array, starts: Int64Array, lengths: Int64Array, frames: FrameNames, parse: Callable[[bytes], Parsed]
) -> Decoded:
    """The payloads parsed one by one by ``parse`` (which raises ``DecodeError``)."""
    rows: list[tuple[int, int, int, int, tuple[float, ...]]] = []
    failures: list[tuple[int, str]] = []
    for number, (start, length) in enumerate(zip(starts.tolist(), lengths.tolist(), strict=True)):
        try:
            parsed = parse(raw[start : start + length].tobytes())
            if any(not _MIN_STAMP <= stamp <= _MAX_STAMP for stamp in parsed.stamps):
                raise DecodeError("a stamp beyond the int64 nanoseconds of ROS time")
        except DecodeError as e:
            failures.append((number, str(e)))
            continue
        ids = [(frames.intern(p), frames.intern(c)) for p, c in zip(parsed.parents, parsed.children, strict=True)]
        rows += [(number, *pair, s, v) for pair, s, v in zip(ids, parsed.stamps, parsed.values, strict=True)]
    if not rows:
        return Decoded.empty(failures)
    message, parent, child, stamp, values = zip(*rows, strict=True)
    return Decoded.of_values(
        np.array(message, np.int64),
        np.array(parent, np.int32),
        np.array(child, np.int32),
        np.array(stamp, np.int64),
        np.array(values, np.float64).reshape(-1, 7),
        failures,
    )
