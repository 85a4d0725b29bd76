"""``odometry``: nav_msgs/Odometry against tf. Each message states header.frame_id -> child_frame_id; tf should
name that child, and where it holds the edge at the messages' own stamps, agree with it (a driver's /odom beside
its own tf). Real recordings: tests/corpus/test_diff43.py."""

from __future__ import annotations

import numpy as np

from tests.analysis.wtf_scenes import recording
from tests.bags import TfMessage
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf import Scene, findings_of
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources.contents import StampedMessages

START = 1_700_000_000 * NS_PER_S
PERIOD = NS_PER_S // 20
N = 100


def _x(i: int) -> float:
    return 0.05 * i


def _odometry(child: str, offset: float = 0.0) -> StampedMessages:
    """/odom in odom, its child ``child``, at the tf's stamps, its x ``offset`` from tf's."""
    stamps = START + np.arange(N, dtype=np.int64) * PERIOD
    pose = np.zeros((N, 7))
    pose[:, 0] = [_x(i) + offset for i in range(N)]
    pose[:, 6] = 1.0
    return StampedMessages(
        "/odom",
        "nav_msgs/msg/Odometry",
        stamps + 1_000_000,
        stamps,
        np.zeros(N, np.int32),
        ["odom"],
        child=np.zeros(N, np.int32),
        pose=pose,
        child_ids=[child],
    )


def _findings(stream: StampedMessages) -> list[Finding]:
    tf = [
        TfMessage(
            "/tf",
            START + i * PERIOD,
            [Transform((_x(i), 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), START + i * PERIOD, "odom", "base_link")],
        )
        for i in range(N)
    ]
    return [f for f in findings_of(Scene(recording(tf, ros1=False), streams=[stream])) if f.code == "odometry"]


def test_odometry_that_agrees_with_tf_says_nothing() -> None:
    assert _findings(_odometry("base_link")) == []
    assert _findings(_odometry("base_link", offset=0.0005)) == []  # within diff's 1 mm: the same estimate


def test_odometry_apart_from_tf_at_the_same_stamps_says_by_how_much() -> None:
    (f,) = _findings(_odometry("base_link", offset=0.3))
    assert f.severity is Severity.info and f.frames == ("odom", "base_link")
    assert f.message.startswith(
        "/odom: 100 nav_msgs/msg/Odometry messages state odom -> base_link; at the 100 of their stamps tf has "
        "samples at too, tf's value is up to 0.300 m"
    ), f.message
    assert f.figures["compared"] == 100 and abs(float(f.figures["apart_m_max"]) - 0.3) < 1e-9


def test_an_odometry_child_frame_tf_lacks_is_a_warning() -> None:
    (f,) = _findings(_odometry("base_footprint"))
    assert f.severity is Severity.warning
    assert f.message == (
        "/odom: 100 nav_msgs/msg/Odometry messages state odom -> base_footprint; tf has odom but no frame "
        "base_footprint"
    )
