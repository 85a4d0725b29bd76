"""``sensor_wait`` as CyberShip Voyager's IMU showed it (brief siblings39): streams in a frame fixed under the moving
edge they wait for transform into that edge's child at once, which the hint says; several streams waiting for one
edge are one cause, said once with each stream beneath (every finding kept, with its own figures, in JSON)."""

from __future__ import annotations

from tests.analysis import wtf_scenes as scenes
from tftools.analysis.findings import Finding
from tftools.analysis.wtf import Scene, findings_of

MS = 1_000_000


def _waits(*frames: str) -> list[Finding]:
    """Sensors stamped at the present (recorded 1 ms later) at 50 Hz, one per frame, checked in odom (the root)."""
    streams = [scenes.sensor(f"/data{i}", frame, 50, MS) for i, frame in enumerate(frames)]
    recording = scenes.recording(scenes.healthy(), ros1=False)
    return [f for f in findings_of(Scene(recording, streams=streams)) if f.code == "sensor_wait"]


def test_streams_waiting_for_one_edge_are_one_cause_each_said_beneath_it() -> None:
    first, second = _waits("laser", "camera")
    assert first.frames == second.frames == ("odom", "base_link")
    assert first.key and second.cause == first.key and not first.cause
    assert first.message.startswith("/data0: ") and second.message.startswith("/data1: ")  # each stream's own figures


def test_a_stream_fixed_under_the_late_edge_transforms_into_its_child_at_once() -> None:
    (fixed,) = _waits("laser")
    assert fixed.hint.startswith(
        "into base_link (laser fixed to it) it transforms at once, with no wait; into odom, a node transforming it "
        "at once fails with 'extrapolation into the future'"
    ), fixed.hint


def test_a_stream_in_the_late_edges_own_child_is_told_only_how_long_to_wait() -> None:
    (moving,) = _waits("wheel")  # base_link -> wheel turns: the wait is for the data's own frame
    assert moving.frames == ("base_link", "wheel")
    assert moving.hint.startswith("a node transforming it at once fails with 'extrapolation into the future'")
