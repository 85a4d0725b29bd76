"""A ROS 1 bag one of whose connections declares an md5sum its own definition does not hash to, on the real
recording that showed it (ros1-microstrain-imu-driver-static-mount-only-ekf-status-md5-mismatch-2024-bag:
microstrain_inertial_driver's /ekf/status): rosbags' AnyReader refuses the whole bag, rosbag and tf2 read it, the
md5 being compared between live peers only. The corpus's own reader (``data.read_contents``) read nothing of it;
now it reads tf as tfx does. A designed reproduction beside it: the same quirk on a bag written here."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from rosbags.highlevel import AnyReader, AnyReaderError
from rosbags.rosbag1 import Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.data import read_contents

T0 = 1_721_935_696_000_000_000


def _bag(path: Path) -> Path:
    """/tf_static: base_link -> imu_link, latched; /status: a std_msgs/String whose md5sum is not its definition's."""
    store = get_typestore(Stores.ROS1_NOETIC)
    store.register(get_types_from_msg("geometry_msgs/TransformStamped[] transforms", "tf2_msgs/msg/TFMessage"))
    types: Any = store.types
    stamp = types["builtin_interfaces/msg/Time"](sec=T0 // 10**9 - 58, nanosec=0)
    header = types["std_msgs/msg/Header"](seq=0, stamp=stamp, frame_id="base_link")
    transform = types["geometry_msgs/msg/Transform"](
        translation=types["geometry_msgs/msg/Vector3"](x=0.1, y=0.0, z=0.0),
        rotation=types["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
    )
    stamped = types["geometry_msgs/msg/TransformStamped"](header=header, child_frame_id="imu_link", transform=transform)
    tf = store.serialize_ros1(types["tf2_msgs/msg/TFMessage"](transforms=[stamped]), "tf2_msgs/msg/TFMessage")
    with Writer(path) as writer:
        statics = writer.add_connection("/tf_static", "tf2_msgs/msg/TFMessage", typestore=store, latching=1)
        status = writer.add_connection("/status", "std_msgs/msg/String", msgdef="string data", md5sum="0" * 32)
        writer.write(statics, T0, tf)
        for i in range(3):
            writer.write(status, T0 + (i + 1) * 10**9, b"\x02\x00\x00\x00ok")
    return path


def test_a_bag_anyreader_refuses_for_a_types_md5_is_read_by_both_readers(tmp_path: Path, tfx: Tfx) -> None:  # noqa: F811
    bag = _bag(tmp_path / "mismatch.bag")
    try:
        with AnyReader([bag]):
            refused = False
    except AnyReaderError as error:
        refused = "hash mismatch" in str(error)
    assert refused, "the reproduction no longer shows AnyReader's refusal"
    contents = read_contents(bag)
    assert set(contents.edges) == {("base_link", "imu_link")}
    assert contents.topics == {"/tf_static", "/status"}
    assert contents.last_record - contents.first_record == 3 * 10**9
    said = tfx("frames", "-b", bag)
    assert said.code == 0, said.stderr
    assert "imu_link" in said.stdout and "static" in said.stdout
