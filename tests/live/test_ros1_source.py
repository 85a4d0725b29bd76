"""The library side of live ROS1: capture(), listen(), reconnection and publisher updates, in-process."""

from __future__ import annotations

import threading
from typing import TYPE_CHECKING, cast

import numpy as np
import pytest

from tests.live.conftest import STATIC_PUBLISHER, Master, Ros, read_line, wait_until
from tftools.core.batch import TransformBatch
from tftools.core.time import WallClock
from tftools.core.transform import Transform
from tftools.sinks import open_static_broadcaster
from tftools.sources.codecs.ros1 import encode_tf_message
from tftools.sources.codecs.types import TF_MESSAGE, ros1_message_type
from tftools.sources.live import LiveError, LiveSource, open_live
from tftools.sources.live.capture import capture, listen
from tftools.sources.live.ros1.node import Node
from tftools.sources.live.ros1.source import Ros1Source

if TYPE_CHECKING:
    from tftools.sinks.ros1_broadcaster import Ros1StaticBroadcaster


@pytest.fixture(autouse=True)
def _environment(master: Master, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("ROS_MASTER_URI", master.uri)
    monkeypatch.setenv("ROS_HOSTNAME", "127.0.0.1")


class Collected:
    """Batches a source delivers, and notices."""

    def __init__(self) -> None:
        self.batches: list[TransformBatch] = []
        self.notices: list[str] = []
        self.lock = threading.Lock()

    def add(self, batch: TransformBatch) -> None:
        with self.lock:
            self.batches.append(batch)

    def children(self) -> list[str]:
        with self.lock:
            return [b.frame_names[c] for b in self.batches for c in b.child]


def test_capture_is_a_recording_of_the_live_source(ros: Ros) -> None:
    ros.spawn(STATIC_PUBLISHER, "1", "0", "0", "0", "0", "0", "cap_base", "cap_laser")
    read_line(ros.node("dynamic", "/cap_odometry", "cap_odom", "cap_base", "2", "50"), "ready", timeout=20)
    wait_until(lambda: "/cap_odometry" in ros.master.publishers("/tf"), 10, "the publisher")
    source = open_live()
    assert isinstance(source, LiveSource) and isinstance(source.clock, WallClock)
    recording = capture(source, duration=1.0)
    (info,) = recording.contents.files
    assert info.path == f"ROS1 master {ros.master.uri}" and info.format == "ros1-live"
    assert info.topics == {"/tf": "tf2_msgs/msg/TFMessage", "/tf_static": "tf2_msgs/msg/TFMessage"}
    transforms = recording.transforms
    assert info.transform_count == len(transforms) >= 30 and info.message_count >= 30
    assert (info.start <= transforms.record_time).all() and (transforms.record_time <= info.end).all()
    assert 0.9e9 <= info.end - info.start < 5e9
    assert recording.buffer.lookup("cap_base", "cap_laser").translation == (1.0, 0.0, 0.0)
    assert recording.buffer.lookup("cap_odom", "cap_base").translation[0] == 2.0
    laser, base = recording.buffer.history("cap_laser"), recording.buffer.history("cap_base")
    assert laser is not None and base is not None and laser.static and not base.static
    assert "/cap_odometry" in recording.buffer.authorities
    delays = transforms.record_time - transforms.stamp  # received after they were stamped (same host clock)
    assert (delays[~transforms.static] > 0).all()


def test_listen_fills_a_buffer_while_lookups_wait(ros: Ros) -> None:
    with open_live(use_sim_time=False) as source:
        buffer = listen(source)
        assert buffer.cache_time == 10 * 10**9
        ros.node("dynamic", "/listen_pub", "listen_a", "listen_b", "0.5", "50")
        first = buffer.wait_for_transform("listen_a", "listen_b", 0, timeout_s=20)
        later = wait_until(
            lambda: (t := buffer.lookup("listen_a", "listen_b")).stamp > first.stamp and t, 10, "newer data"
        )
        assert later and later.translation[0] == 0.5


def test_a_dropped_connection_is_made_again(ros: Ros) -> None:
    collected = Collected()
    node = Node("/drop_publisher")
    try:
        publication = node.advertise("/tf_static", ros1_message_type(TF_MESSAGE), latched=True)
        publication.publish(encode_tf_message([Transform((1, 2, 3), (0, 0, 0, 1), 5, "drop_a", "drop_b")]))
        with Ros1Source(topics=["/tf_static"], on_notice=collected.notices.append) as source:
            source.start(collected.add)
            wait_until(lambda: collected.children() == ["drop_b"], 10, "the latched message")
            publication.close()  # the connection drops; the publisher is still registered
            wait_until(lambda: collected.children() == ["drop_b", "drop_b"], 10, "the latched message again")
            assert any("lost the connection to /drop_publisher" in n for n in collected.notices)
            assert [b.authorities[0] for b in collected.batches] == ["/drop_publisher"] * 2
    finally:
        node.close()


def test_publishers_that_leave_are_dropped(ros: Ros) -> None:
    collected = Collected()
    with Ros1Source(topics=["/tf_static"]) as source, open_static_broadcaster() as opened:
        broadcaster = cast("Ros1StaticBroadcaster", opened)
        source.start(collected.add)
        broadcaster.send([Transform((0, 0, 1), (0, 0, 0, 1), 7, "leave_a", "leave_b")])
        wait_until(lambda: "leave_b" in collected.children(), 10, "the static transform")
        subscription = source._node._subscriptions["/tf_static"]
        wait_until(lambda: broadcaster.name in [n for _uri, n in subscription.connections], 10, "the connection")
        broadcaster.close()  # unregisters: the master sends publisherUpdate without it
        wait_until(lambda: broadcaster.name not in [n for _uri, n in subscription.connections], 10, "the update")


def test_a_broadcaster_sends_every_transform_again_with_a_new_one(ros: Ros) -> None:
    collected = Collected()
    with open_static_broadcaster() as broadcaster, Ros1Source(topics=["/tf_static"]) as source:
        broadcaster.send([Transform((1, 0, 0), (0, 0, 0, 1), 1, "bc_a", "bc_b")])
        source.start(collected.add)
        wait_until(lambda: collected.children() == ["bc_b"], 10, "the first")
        q = (0.0, 0.0, 0.0, 1.0)
        broadcaster.send([Transform((2, 0, 0), q, 2, "bc_a", "bc_c"), Transform((3, 0, 0), q, 3, "bc_a", "bc_b")])
        wait_until(lambda: len(collected.batches) == 2, 10, "the second message")
        last = collected.batches[-1]
        assert [last.frame_names[c] for c in last.child] == ["bc_b", "bc_c"]  # one message, bc_b replaced in place
        np.testing.assert_array_equal(last.translation[:, 0], [3.0, 2.0])


def test_a_dead_master_fails_at_open() -> None:
    with pytest.raises(LiveError, match=r"cannot reach the ROS master at http://127\.0\.0\.1:9 "):
        open_live(master_uri="http://127.0.0.1:9")
