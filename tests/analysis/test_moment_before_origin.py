"""A finding's first moment before the recording's origin (its first tf stamp) is said as observed."""

from __future__ import annotations

from tests.analysis.wtf_scenes import recording
from tests.bags import TfMessage
from tftools.analysis.wtf import Scene, findings_of
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

START = 100 * NS_PER_S
MS = 1_000_000


def _slashed(ahead: int) -> list[TfMessage]:
    """/odom -> base_link at 10 Hz, each recorded ``ahead`` ns before its stamp (its clock ahead)."""
    return [
        TfMessage(
            "/tf",
            START + i * 100 * MS - ahead,
            [Transform((0.01 * i, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), START + i * 100 * MS, "/odom", "base_link")],
            "/cartographer",
        )
        for i in range(100)
    ]


def _leading_slash(ahead: int) -> str:
    (found,) = [f for f in findings_of(Scene(recording(_slashed(ahead)))) if f.code == "leading_slash"]
    return found.message


def test_a_first_moment_before_the_first_tf_stamp_is_said_as_observed_not_as_a_negative_offset() -> None:
    """Issue 39 (a cartographer bag): leading_slash said 'first at 0.020 (-0.1 s)', which reads as an error. The
    first message arrived 0.1 s before the first stamp of the tf data: say that."""
    message = _leading_slash(100 * MS)
    assert "first at 99.900 (0.1 s before the first tf stamp)" in message
    assert "(-" not in message


def test_a_first_moment_after_the_origin_keeps_its_offset() -> None:
    assert "first at 100.002 (+0.0 s)" in _leading_slash(-2 * MS)  # a hair after: "+0.0", never "-0.0"
