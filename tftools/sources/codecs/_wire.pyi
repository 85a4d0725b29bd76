"""TFMessages of ROS1 and CDR decoded in bulk (native/wire_module.cpp, native/tf_wire.hpp)."""

from tftools.core.arrays import FloatArray, Int32Array, Int64Array, UInt8Array

def decode_transforms(
    raw: UInt8Array,
    starts: Int64Array,
    lengths: Int64Array,
    big_endian: bool,
    origin: int,
    align: int,
    seq: bool,
    signed_sec: bool,
    nul: bool,
    exact: bool,
    counted: bool,
) -> tuple[Int64Array, Int64Array, FloatArray, Int32Array, Int32Array, Int64Array, Int64Array, Int64Array]:
    """The payloads ``raw[starts[i] : starts[i] + lengths[i]]`` read as ``wire.Cursor`` reads them
    (a count of transforms first where ``counted``): of the well-formed messages, each row's
    message, stamp (ns), values (N, 7) and parent and child as ids among the names; each distinct
    name's start and length in ``raw`` (a CDR NUL left out); the messages not well-formed."""
