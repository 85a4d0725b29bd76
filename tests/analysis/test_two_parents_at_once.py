"""A frame sent under two moving parents at the same stamps (aerostack2's Crazyflie, tests/corpus/test_corpus49.py:
Gazebo's pose bridge sends cf0 -> cf0/base_link, the state estimator cf0/odom -> cf0/base_link, at each of the same
stamps, in one ROS 2 bag naming no publisher). Designed twin: the parent tf2 answers a stamp from changes with the
order the two samples and a message of that stamp arrive in, as tf2 ROS 2's and ROS 1's caches keep them."""

from __future__ import annotations

import numpy as np
import pytest

from tests.analysis import wtf_scenes as scenes
from tests.bags import TfMessage
from tftools.analysis.filter.fates import Fate, message_fates
from tftools.analysis.frames import tree_of
from tftools.analysis.targets import default_target
from tftools.analysis.wtf import check
from tftools.core.time import NS_PER_S
from tftools.sources.contents import StampedMessages

MS = 1_000_000
START = 100 * NS_PER_S
STEP = 12 * MS
#: Per stamp, the order the bridge's sample ("cf0"), the estimator's ("odom") and a message stamped alike arrive in.
ORDERS = [("cf0", "odom", "msg"), ("cf0", "msg", "odom"), ("odom", "cf0", "msg"), ("odom", "msg", "cf0")]


def _scene() -> tuple[list[TfMessage], StampedMessages]:
    statics = TfMessage(
        "/tf_static", START, [scenes._t("earth", "cf0/map", 0), scenes._t("cf0/map", "cf0/odom", 0)], "/static"
    )
    messages, arrivals = [statics], []
    for i in range(40):
        stamp = START + (i + 1) * STEP
        for k, who in enumerate(ORDERS[i % len(ORDERS)]):
            at = stamp + (k + 1) * MS
            if who == "msg":
                arrivals.append((at, stamp))
            elif who == "cf0":
                bridge = [scenes._t("cf0", "cf0/base_link", stamp, x=0.05), scenes._t("cf0", "cf0/imu", stamp)]
                messages.append(TfMessage("/tf", at, bridge, "/gazebo_bridge"))
            else:
                messages.append(TfMessage("/tf", at, [scenes._t("cf0/odom", "cf0/base_link", stamp, x=1.0)], "/ekf"))
    twist = StampedMessages(
        "/twist",
        "geometry_msgs/msg/TwistStamped",
        np.array([a for a, _ in arrivals], np.int64),
        np.array([s for _, s in arrivals], np.int64),
        np.zeros(len(arrivals), np.int32),
        ["cf0/base_link"],
    )
    return messages, twist


@pytest.mark.parametrize("ros1", [False, True])
def test_multiple_parents_says_the_stamps_sent_under_both_and_no_stamp_goes_back(ros1: bool) -> None:
    messages, _ = _scene()
    findings = check(scenes.recording(messages, ros1=ros1))
    (parents,) = [f for f in findings if f.code == "multiple_parents"]
    assert "40 stamps came under both" in parents.message
    assert "two sources place cf0/base_link at once" in parents.hint
    assert "cf0/odom -> cf0" in parents.hint and "an object picked up" not in parents.hint
    assert not [f for f in findings if f.code == "time_backwards"]


def test_the_one_robots_namespaced_odom_is_the_target() -> None:
    messages, _ = _scene()
    tree = tree_of(scenes.recording(messages, ros1=False).buffer)
    assert default_target(tree) == ("cf0/odom", "REP 105's odom frame of the one robot")
    two_robots = [*messages, TfMessage("/tf_static", START, [scenes._t("earth", "cf1/odom", 0)], "/static")]
    assert default_target(tree_of(scenes.recording(two_robots, ros1=False).buffer))[1] == "the root of the largest tree"


@pytest.mark.parametrize(
    ("ros1", "expected"),
    [
        # ROS 2's tf2 answers a stamp from the sample of it received last: odom after cf0 passes on arrival; cf0
        # after odom never (every later sample is newer, the cf0 one stays the answer); a message between them
        # waits for odom's sample.
        (False, [Fate.ON_ARRIVAL, Fate.LATER, Fate.NOT_CONNECTED, Fate.ON_ARRIVAL]),
        # ROS 1's refuses a stamp's second sample (TF_REPEATED_DATA): the first received answers.
        (True, [Fate.NOT_CONNECTED, Fate.NOT_CONNECTED, Fate.ON_ARRIVAL, Fate.ON_ARRIVAL]),
    ],
)
def test_a_message_passes_while_tf2_answers_its_stamp_under_the_targets_parent(ros1: bool, expected: list[int]) -> None:
    messages, twist = _scene()
    fates = message_fates(scenes.recording(messages, ros1=ros1).buffer, twist, "cf0/odom")
    by_order = [fates.fate[i :: len(ORDERS)].tolist() for i in range(len(ORDERS))]
    assert [set(f) for f in by_order] == [{e} for e in expected]
    later = fates.fate == Fate.LATER
    assert (fates.ready[later] == twist.record_time[later] + MS).all()  # when the estimator's sample came
