"""TFMessages of ROS1 and CDR decoded in bulk (native/wire_module.cpp, native/tf_wire.hpp)."""

from tftools.core.arrays import BoolArray, FloatArray, Int32Array, Int64Array, UInt8Array

#: A wire: (CDR encapsulation or -1, big endian, origin, align, seq, signed_sec, nul, exact), as ``wire.Wire``.
WireFields = tuple[int, bool, int, int, bool, bool, bool, bool]

#: What ``decode_transforms`` gives.
Columns = tuple[
    Int64Array, Int64Array, FloatArray, FloatArray, Int32Array, Int32Array, Int64Array, Int64Array, Int64Array
]

def decode_transforms(
    raw: UInt8Array, starts: Int64Array, lengths: Int64Array, wires: list[WireFields], counted: bool
) -> Columns:
    """The payloads ``raw[starts[i] : starts[i] + lengths[i]]`` read field by field, each in its wire
    (the one, or the one its CDR encapsulation names; a count of transforms first where ``counted``):
    of the well-formed messages, each row's message, stamp (ns), translation (N, 3), rotation (N, 4) (each
    contiguous, as the core takes them) and parent and child
    as ids among the names; each distinct name's start and length in ``raw`` (a CDR NUL left out);
    of the messages not well-formed or in none of the wires, (K, 4): each one, why (``wire.Reason``),
    the offset in it and the figure the reason tells."""

class Decoding:
    """``decode_transforms`` on a thread of its own, started at once (the GIL not held there); the arrays
    are held until it is done."""

    def __init__(
        self, raw: UInt8Array, starts: Int64Array, lengths: Int64Array, wires: list[WireFields], counted: bool
    ) -> None: ...
    def result(self) -> Columns:
        """What ``decode_transforms`` would have given, once the thread is done (the GIL let go while waiting);
        once only."""

def match_records(
    raw: UInt8Array,
    offsets: Int64Array,
    limits: Int64Array,
    cuts: BoolArray,
    header: bytes,
    conn_at: int,
    time_at: int,
) -> tuple[BoolArray, Int64Array, Int64Array, Int64Array, Int64Array]:
    """Which ROS1 records at ``offsets`` of ``raw`` have a header laid out as ``header`` (its length, and its
    bytes after it; conn's 4 at ``conn_at`` and time's 8 at ``time_at`` may differ) and end within their
    ``limits`` (or, ``cuts``, were read only that far: their payload ends there); of those, their conn,
    record time (ns), payload start and payload end."""

def per_row(
    messages: Int64Array,
    rows: Int64Array,
    times: Int64Array,
    channel_of: Int32Array,
    static_of: BoolArray,
    authority_of: Int32Array,
) -> tuple[Int64Array, BoolArray, Int32Array]:
    """Of ``rows[i]`` rows of each message ``messages[i]``, in order: each row's message's record time, and
    its message's channel's ``static_of`` and ``authority_of``."""
