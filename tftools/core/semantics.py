"""Which tf2 a buffer answers as: ROS 1's (Noetic, 0.7) or ROS 2's (Rolling and Jazzy; Humble noted).

The one place that lists every difference tftools keeps between the two, and where it departs
from both. Both share the walk, interpolation and latest-common-time; a ``Buffer`` varies only
what differs between ros/geometry2 (noetic-devel) and ros2/geometry2 (rolling, jazzy, humble),
read from their ``buffer_core.cpp``, ``cache.cpp``, ``static_cache.cpp``, ``time.cpp`` and
``LinearMath/Matrix3x3.h``:

=========================  ======================================  ========================================
what                       ROS 1                                   ROS 2
=========================  ======================================  ========================================
the rotation tf2 holds     the message's quaternion as given       ``tf2::Transform``'s: the quaternion
and returns                (a lookup returns the composed one,     through ``Matrix3x3::setRotation`` and
                           of any sign and norm)                   ``getRotation`` (Shepperd's branch on
                                                                   the trace), on ``setTransform`` (what
                                                                   is checked, compared and interpolated)
                                                                   and on ``lookupTransform`` (what is
                                                                   returned): unit, w > 0 where the trace
                                                                   is positive, else the largest of x, y,
                                                                   z > 0; (0, 0, 0, 1.004) is held as
                                                                   (0, 0, 0, 1), so an inverse's
                                                                   translation is not scaled by |q|²
a denormalized rotation    refused, ``TF_DENORMALIZED_             checked after the trip, so only a zero
                           QUATERNION`` (|q|² - 1 off by 10e-3)    or non-finite one is refused, with
                                                                   ``TF_NAN_INPUT`` and ``TF_DENORMALIZED_
                                                                   QUATERNION``, its values as the matrix
                                                                   gives them (``-nan``); (0, 0, 0, 2) is
                                                                   accepted
an infinite rotation       ``TF_DENORMALIZED_QUATERNION`` alone    both codes (NaNs after the trip)
                           (tf2 checks ``isnan``)
several samples, one       the second refused, ``TF_REPEATED_      all stored, in arrival order; at that
stamp                      DATA``                                  stamp (or just after it) the last one
                                                                   counts, as the oldest stamp the first
an identical sample again  refused, ``TF_REPEATED_DATA``           accepted, not stored, no warning;
                                                                   identical after the trip: q and -q
                                                                   are one sample
a sample older than the    refused, ``TF_OLD_DATA``                refused, ``TF_OLD_DATA`` (other text)
cache time
pruning                    after each insertion, against the       before each insertion, against the
                           newest sample then                      newest sample before it
static after dynamic (or   stored in the cache the first sample    the frame's cache is replaced by one of
the reverse)               made (the frame stays dynamic)          the new kind, its samples dropped
a lookup with a fixed      ``tf2::Transform`` product of the two   the same product of the two lookups as
frame                      lookups as returned                     composed, read back from its matrix
extrapolation errors       ``ExtrapolationException``; ``%.9f``    ``Forward``/``Backward``/``NoDataFor``
                           of a double, cut to tf2's buffers; the  ``ExtrapolationException`` (Humble: the
                           amount an integer ``ros::Duration``     base class); "extrapolation into the
                           (every nanosecond of the stamps)        future/past", no amount, ``%.6f``
invalid frame arguments    "Invalid argument passed to ..."        "Invalid argument "" passed to ... - "
``allFramesAsYAML``        ``{}`` when empty; times ``%.3f``;      ``[]`` when empty; times ``%.6f``; rate
                           rate = n / max(span s, 0.0001); the     = n * 1e9 / max(span ns, 100000); the
                           broadcaster the last sample's           broadcaster "Authority undetectable",
                           publisher (a listener passes the        which ROS 2's C++ listener passes for
                           callerid)                               every sample (rclpy's passes
                                                                   "default_authority"); tftools keeps
                                                                   the publisher it knows for its own
                                                                   output
``TF_SELF_TRANSFORM``,     their ROS 1 texts                       ``"... frame_id and  child_frame_id"``,
``TF_OLD_DATA`` logs                                               its time ``%.6f``, a second line
=========================  ======================================  ========================================

Several samples of one stamp under ROS 2, as ``TimeCache::insertData`` (cache.cpp) has it in Humble, Jazzy and
Rolling alike: no ``TF_REPEATED_DATA`` (ROS 2's tf2 has none); a sample goes in before those of its stamp in a list
held newest first, so ``findClosest`` meets the last received first, except at the oldest stamp, which it reads
from the list's back; one equal to a sample held (values, stamp and frames) is skipped since ros2/geometry2#636
(Rolling, January 2024; Humble 0.25.6), stored again before it (Foxy, Galactic, older Humble), which changes no
answer.

Over a recording's rows, without a buffer of that cache: ``history.old_data`` is the ``TF_OLD_DATA`` rule
of the table, ``Buffer.in_static_cache`` the frame that keeps its first kind of cache
(``Dialect.keeps_first_cache``).

The same in both: a leading ``/`` is stripped (once) from inserted frame ids and refused in queried
ones, by ``lookup`` and ``can_transform`` alike (a frame sent as ``//b`` is stored as ``/b``, which
no query can name); which sample a lookup uses between two stamps; the connectivity, loop and
unknown-frame messages; ``TF_NAN_INPUT``'s text (``(x y z) (x y z w)``, C's ``%f``: ``-nan`` for a
NaN with its sign bit set); validation codes other than those named above.

Where tftools departs from both, on purpose: an **infinite translation** is refused with
``TF_NAN_INPUT`` (both tf2s check ``isnan`` only and would store it). Stored, it turns every lookup
through its edge into infinities and NaNs (inf - inf) with no error to say why; refused, it is a
rejection that ``tfx wtf`` reports with the edge, the publisher and the time.

How exact: ROS 2 mode gives ROS 2's tf2's bits as GCC builds it for x86-64 (no fused multiply-adds:
its default there); a build that contracts (aarch64's GCC does by default) differs in last bits.
Measured against ros2/geometry2 1b005c6 (tf2 0.39.1) built from its sources: 60,190 of 60,190
answers of 1,000 random episodes (lookups, ``canTransform``, fixed-frame lookups, logs, YAML) and
42,000 of 42,000 lookups on the 21 corpus recordings, bit for bit (checked by hand; the tests port its
own tests' cases and the values it gave). ROS 1 mode follows tf2 as C++
(a roscpp node) has it: every stamp to the nanosecond. tf2_py, the Python binding, rounds each
stamp through a double (up to ~120 ns off near 1.7e9 s), so its extrapolation amounts can differ
from C++ tf2's by a nanosecond or more; ``tests/core/test_tf2_cpp.py`` checks tftools against
Debian's libtf2 itself.

Times in tf2's messages go through a double in both (ROS 1 ``%.09f`` of ``toSec()``, ROS 2
``%.6f`` of ``timeToSec``), so neither prints every nanosecond; tftools' copies of those messages
print what tf2 prints (``Dialect.seconds``), while ``time.format_sec``, for tftools' own output,
is exact. Rolling also words the "no data" error of an empty cache, where Jazzy and Humble leave it
empty; tftools never holds an empty cache, so it does not show. A ROS 2 buffer's histories keep
each sample as it was sent (``Buffer.history``, a recording's ``transforms``); tf2's view of its
rotation is taken where the walk reads it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Literal, get_args

from tftools.core.errors import (
    BackwardExtrapolationError,
    ExtrapolationError,
    ForwardExtrapolationError,
    InvalidArgumentError,
    NoDataForExtrapolationError,
)
from tftools.core.time import duration_to_sec, to_sec

if TYPE_CHECKING:  # the kinds of extrapolation are imported where a message is worded: naming a
    from tftools.core.history import Extrapolation  # semantics (tfx --help) needs no numpy

#: Which tf2 a buffer follows: ROS 1's for ROS 1 bags and systems, ROS 2's for ROS 2 ones.
Semantics = Literal["ros1", "ros2"]
SEMANTICS: tuple[Semantics, ...] = get_args(Semantics)


def check_semantics(value: str) -> Semantics:
    """``value`` as a ``Semantics``, or a ``ValueError`` naming the choices."""
    for choice in SEMANTICS:
        if value == choice:
            return choice
    raise ValueError(f"tf2 semantics must be one of {', '.join(SEMANTICS)}, got {value!r}")


class Dialect:
    """How a tf2 words what it reports; ``ROS1`` and ``ROS2`` are the two."""

    semantics: Semantics = "ros1"
    #: Whether a frame keeps the kind of cache its first sample made (ROS 1's ``BufferCore`` allocates a frame's
    #: cache once): a frame first sent static keeps its ``StaticCache``, and every later sample, from /tf too,
    #: replaces its value for every time. ROS 2's replaces the cache with one of the new sample's kind.
    keeps_first_cache: bool = True
    #: What ``allFramesAsYAML`` names as each frame's broadcaster: None for the publisher of its
    #: latest sample (ROS 1's listener passes the message's callerid), else this for every frame
    #: (ROS 2's C++ ``TransformListener`` passes it: a DDS sample names no publisher).
    listener_authority: str | None = None

    @property
    def ros2(self) -> bool:
        return self.semantics == "ros2"

    def seconds(self, ns: int) -> str:
        """A time or duration as this tf2 prints it in its messages."""
        return f"{to_sec(ns):.9f}"

    def extrapolation_message(self, missing: Extrapolation) -> str:
        """The cache's reason it has no sample at ``missing.time`` (tf2's ``findClosest``)."""
        # tf2 0.7.6 formats these into fixed-size buffers that can cut the text short
        # ("... is in the buffe"); the cut is kept so that messages match byte for byte.
        from tftools.core.history import FUTURE, NO_DATA, PAST

        if missing.kind == NO_DATA:
            return ""
        if missing.kind in (FUTURE, PAST):
            return _fixed(self._beyond(missing, f"{self.seconds(abs(missing.time - missing.stamp))}s "), 163)
        return _fixed(self._between(missing), 116)

    def _beyond(self, missing: Extrapolation, amount: str = "") -> str:
        """Why a time past the newest sample, or before the oldest, has none (``amount``: ROS 1's)."""
        from tftools.core.history import FUTURE

        direction, edge = ("future", "latest") if missing.kind == FUTURE else ("past", "earliest")
        return (
            f"Lookup would require extrapolation {amount}into the {direction}.  "
            f"Requested time {self.seconds(missing.time)} but the {edge} data is at time {self.seconds(missing.stamp)}"
        )

    def _between(self, missing: Extrapolation) -> str:
        time, stamp = self.seconds(missing.time), self.seconds(missing.stamp)
        return f"Lookup would require extrapolation at time {time}, but only time {stamp} is in the buffer"

    def extrapolation(self, missing: Extrapolation, source: str, target: str) -> ExtrapolationError:
        """The lookup's error for ``missing``, met walking from ``source`` to ``target``."""
        where = f"when looking up transform from frame [{source}] to frame [{target}]"
        text = f"{self.extrapolation_message(missing)}, {where}"
        if self.ros2:
            return _ros2_error(missing.kind)(text)
        return ExtrapolationError(text[:999])  # tf2 formats it into char[1000]

    def empty_frame(self, argument: str) -> InvalidArgumentError:
        if self.ros2:
            return InvalidArgumentError(f'Invalid argument "" passed to {argument} - in tf2 frame_ids cannot be empty')
        return InvalidArgumentError(f"Invalid argument passed to {argument} in tf2 frame_ids cannot be empty")

    def leading_slash(self, frame: str, argument: str) -> InvalidArgumentError:
        text = f'Invalid argument "{frame}" passed to {argument}'
        if self.ros2:
            return InvalidArgumentError(f"{text} - in tf2 frame_ids cannot start with a '/'")
        return InvalidArgumentError(f"{text} in tf2 frame_ids cannot start with a '/' like: ")


class _Ros2Dialect(Dialect):
    semantics: Semantics = "ros2"
    keeps_first_cache: bool = False
    listener_authority: str | None = "Authority undetectable"

    def seconds(self, ns: int) -> str:
        return f"{duration_to_sec(ns):.6f}"  # tf2::displayTimePoint

    def extrapolation_message(self, missing: Extrapolation) -> str:
        # Rolling's wording, also for an empty cache (stamp 0), which Jazzy leaves unworded.
        from tftools.core.history import FUTURE, PAST

        return self._beyond(missing) if missing.kind in (FUTURE, PAST) else self._between(missing)


def _ros2_error(kind: int) -> type[ExtrapolationError]:
    """ROS 2's class of extrapolation error for a missing of ``kind``."""
    from tftools.core.history import FUTURE, PAST

    return {FUTURE: ForwardExtrapolationError, PAST: BackwardExtrapolationError}.get(kind, NoDataForExtrapolationError)


ROS1: Dialect = Dialect()
ROS2: Dialect = _Ros2Dialect()


def dialect(semantics: Semantics) -> Dialect:
    return ROS2 if semantics == "ros2" else ROS1


def _fixed(text: str, size: int) -> str:
    """What C's ``snprintf`` leaves of ``text`` in a buffer of ``size`` bytes."""
    return text[: size - 1]
