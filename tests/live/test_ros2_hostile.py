"""A hostile ROS 2 participant on loopback (issue 32): a /tf writer flooding new frame names, sending
names made of escape codes, values tf2 refuses, a graph announcement of a thousand hostile node names,
bursts of thousands of samples. Each command ends on time with one-line notices, nothing else."""

from __future__ import annotations

import os
import resource
import socket
import time

import pytest

from tests.live.ros2_processes import Ros2Domain, domain_fixture  # noqa: F401 - the fixture `domain`
from tftools.sources.live import base, open_live
from tftools.sources.live.capture import capture
from tftools.sources.live.ros2 import conventions as ros2

KINDS = ["flood", "names", "values", "graph", "burst"]
COMMANDS = {
    "monitor": ("monitor", "--ros2", "--duration", "3", "-f", "json"),
    "frames": ("frames", "--ros2", "-d", "3"),
    "wtf": ("wtf", "--ros2", "-d", "3"),
}


@pytest.mark.parametrize("command", COMMANDS.values(), ids=COMMANDS.keys())
@pytest.mark.parametrize("kind", KINDS)
def test_a_hostile_participant_gets_one_line_notices(domain: Ros2Domain, kind: str, command: tuple[str, ...]) -> None:
    domain.node("hostile", kind).wait_for("ready", timeout=30)
    finished = domain.tfx(*command).finish(timeout=120)  # a hang guard, not a time limit
    assert finished.returncode in (0, 1), finished.stderr
    assert "Traceback" not in finished.stderr and "internal error" not in finished.stderr
    assert "\x1b" not in finished.stderr and "\x1b" not in finished.stdout  # escape codes shown escaped
    assert all(len(line) < 12_000 for line in finished.stderr.splitlines())


def test_a_flood_of_frame_names_is_cut_at_the_limit_and_said_once(
    domain: Ros2Domain, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(base, "MAX_LIVE_FRAMES", 30_000)
    domain.node("hostile", "flood").wait_for("ready", timeout=30)
    notices: list[str] = []
    recording = capture(open_live("ros2", on_notice=notices.append), duration=3.0)
    transforms = recording.transforms
    heard = {transforms.frame_names[i] for i in transforms.child}
    assert 20_000 <= len(heard) <= 30_000
    said = "more than 30,000 frames heard: transforms naming further frames are dropped"
    assert [n for n in notices if "frames heard" in n] == [f"{said} (a publisher inventing frame names?)"]


def test_samples_larger_than_the_limit_are_dropped_and_said_once(domain: Ros2Domain) -> None:
    """A peer sending samples of 60 MiB back to back: taken a bounded number of bytes at a time, dropped
    unread, said once with the first one's size (the monitor grew to 1.57 GB)."""
    domain.node("hostile", "huge").wait_for("ready", timeout=30)
    notices: list[str] = []
    recording = capture(open_live("ros2", on_notice=notices.append), duration=10.0)  # a 60 MiB sample takes seconds
    assert not len(recording.transforms)
    said = [n for n in notices if "larger than" in n]
    assert said == [
        "/hostile sent a sample of 60.0 MiB on /tf, larger than 16 MiB (100,000 transforms take 8.5 MB):"
        " such are dropped unread"
    ]
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss < 1_500_000  # KiB: within the 1.5 GB


def test_a_flood_of_participants_is_forgotten_oldest_first_and_said_once(
    domain: Ros2Domain, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(ros2, "MAX_PARTICIPANTS", 5)
    domain.node("hostile", "participants").wait_for("ready", timeout=30)
    notices: list[str] = []
    capture(open_live("ros2", on_notice=notices.append), duration=3.0)
    said = [n for n in notices if "participants announced" in n]
    assert said == [
        "more than 5 participants announced on ros_discovery_info: the oldest are forgotten, their writers named"
        " by participant (a flood of participants?)"
    ]


def _malformed_packets(domain_id: int, seconds: float) -> int:
    """RTPS packets whose DATA submessage runs past the packet's end, sent to every participant's unicast
    ports of the domain for ``seconds``: Cyclone DDS logs each one it receives on stderr; how many were sent."""
    sent = 0
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            for index in range(8):
                for offset in (10, 11):  # discovery and user unicast ports of participant ``index``
                    packet = b"RTPS\x02\x01\x01\x10" + os.urandom(12) + b"\x15\x05\xff\x7f" + os.urandom(20)
                    sock.sendto(packet, ("127.0.0.1", 7400 + 250 * domain_id + offset + 2 * index))
                    sent += 1
            time.sleep(0.01)
    return sent


@pytest.mark.parametrize("debug", [False, True], ids=["quiet", "TFX_DEBUG"])
def test_cyclone_s_own_log_of_malformed_packets_stays_off_stderr(domain: Ros2Domain, debug: bool) -> None:
    """Cyclone DDS printed a line of its own for each malformed packet (100 to 640 lines in 5 s); with
    TFX_DEBUG=1 its log is kept (which shows the packets did reach tfx)."""
    env = {**domain.env, **({"TFX_DEBUG": "1"} if debug else {})}
    command = domain.tfx("monitor", "--ros2", "--duration", "4", "-f", "json", env=env)
    time.sleep(1.0)
    assert _malformed_packets(domain.id, 2.0) > 100
    finished = command.finish(timeout=60)  # a hang guard
    assert finished.returncode == 0, finished.stderr
    malformed = [line for line in finished.stderr.splitlines() if "malformed packet" in line]
    assert bool(malformed) is debug, finished.stderr[-500:]
