"""The robot's own messages and descriptions from hostile input: the joint state and string decoders on any
payload (through the bag readers' message set), and the URDF reader on any text made of URDF pieces:
either what they read or one line saying why not, never another exception.

A few examples per case by default (CI); ``TFTOOLS_FUZZ_EXAMPLES=2000`` runs them at length."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.analysis.robot_scenes import URDF
from tests.fuzz.test_bag_fuzz import FUZZ
from tftools.sources.bag.messages import MessageSet
from tftools.sources.codecs.robot import WHOLE_DECODERS
from tftools.sources.codecs.select import WholeCodec
from tftools.sources.codecs.wire import MAX_FRAME_ID
from tftools.sources.urdf import RobotDescription, UrdfError, parse_urdf


@pytest.mark.parametrize("key", list(WHOLE_DECODERS), ids=lambda key: f"{key[0]}-{key[1]}")
def test_whole_decoders_on_any_payload(key: tuple[str, str]) -> None:
    codec = WholeCodec(*key, WHOLE_DECODERS[key])

    @FUZZ
    @given(st.lists(st.binary(max_size=600), min_size=1, max_size=8))
    def check(payloads: list[bytes]) -> None:
        messages = MessageSet()
        channel = messages.channel("/joint_states", codec)
        messages.add(channel, np.arange(len(payloads)), np.arange(len(payloads)), payloads)
        _, _, _, problems = messages.decode()
        assert all("\n" not in p for p in problems)
        read = sum(len(w) for w in messages.whole)
        assert read + sum(int(p.split(" of ")[0].split(": ")[-1]) for p in problems) == len(payloads)

    check()


PIECES = [
    *URDF.splitlines(),
    '<joint name="j" type="revolute"><parent link="laser"/><child link="x"/></joint>',
    '<origin xyz="1e308 1e308 1e308" rpy="nan 0 0"/>',
    "<!DOCTYPE robot>",
    '<!ENTITY a "a">',
    "&a;",
    "<![CDATA[<robot>]]>",
    '<xacro:macro name="m"/>',
    "${r}",
    "\x00",
    "</robot></robot>",
]


def test_urdf_reader_on_any_text() -> None:
    @FUZZ
    @given(st.lists(st.sampled_from(PIECES) | st.text(max_size=40), max_size=30))
    def check(lines: list[str]) -> None:
        try:
            robot = parse_urdf("\n".join(lines).encode("utf-8", "surrogatepass"), "fuzz.urdf")
        except UrdfError as error:
            assert "\n" not in str(error) and str(error).startswith("fuzz.urdf: ")
        else:
            assert isinstance(robot, RobotDescription)
            for joint in robot.joints:
                joint.transform_at(0.5)

    check()


LONG = "n" * (MAX_FRAME_ID + 1)
#: Where a URDF names a frame, a joint or itself: each place given a name one character too long.
NAME_PLACES = {
    "robot": URDF.replace('<robot name="rover">', f'<robot name="{LONG}">'),
    "link": URDF.replace('"laser"', f'"{LONG}"'),
    "joint": URDF.replace('"laser_joint"', f'"{LONG}"'),
    "mimic": URDF.replace(
        '<joint name="laser_joint" type="fixed">', f'<joint name="laser_joint" type="fixed"><mimic joint="{LONG}"/>'
    ),
}


@pytest.mark.parametrize("place", NAME_PLACES)
def test_a_name_longer_than_frame_names_may_be_is_refused_in_one_line(place: str) -> None:
    with pytest.raises(UrdfError) as refused:
        parse_urdf(NAME_PLACES[place], "long.urdf")
    said = str(refused.value)
    assert said.startswith("long.urdf: a <") and f"of {MAX_FRAME_ID + 1:,} characters, longer than 4,096" in said
    assert len(said) < 200 and "4,096" in refused.value.hint


def test_a_name_as_long_as_frame_names_may_be_is_read() -> None:
    longest = "n" * MAX_FRAME_ID
    robot = parse_urdf(URDF.replace('"laser"', f'"{longest}"'), "long.urdf")
    assert longest in robot.links and robot.joint("laser_joint").child == longest
