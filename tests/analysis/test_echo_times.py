"""echo's choice of times from Python (``tftools.analysis.echo.echo_times``, the times' grammar in
``tftools.analysis.times``), as ``tfx echo`` makes it."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from tests.cli.conftest import SAMPLE_BAGS
from tftools.analysis.echo import MAX_ECHO_LINES, chain_span, echo, echo_times
from tftools.analysis.times import parse_time, time_range
from tftools.core.errors import UsageError
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources import Recording, read_recording


@pytest.fixture(scope="module")
def recording() -> Recording:
    return read_recording([SAMPLE_BAGS["db3"]])


def test_times_step_at_the_rate_over_where_every_moving_edge_between_has_data(recording: Recording) -> None:
    times = echo_times(recording.buffer, recording.timeline, "map", "base_link", rate=2.0)
    span = chain_span(recording.buffer, "map", "base_link")
    assert span is not None and times[0] == span[0] and times[-1] <= span[1]
    assert set(np.diff(times).tolist()) == {NS_PER_S // 2}
    assert echo(recording.buffer, "map", "base_link", times).valid.all()


def test_times_in_the_grammar_from_the_recordings_tf(recording: Recording) -> None:
    timeline = recording.timeline
    times = echo_times(recording.buffer, timeline, "map", "base_link", rate=1.0, start="+1", end="+3")
    assert times.tolist() == [timeline.tf_start + s * NS_PER_S for s in (1, 2, 3)]
    assert parse_time("-1", timeline, "--at") == timeline.tf_end - NS_PER_S
    assert echo_times(recording.buffer, timeline, "map", "base_link", at="0").tolist() == [0]  # the latest
    every = echo_times(recording.buffer, timeline, "map", "base_link", every=True, end="+2")
    assert len(every) > 2 and every[-1] <= timeline.tf_start + 2 * NS_PER_S


@pytest.mark.parametrize(
    ("call", "says"),
    [
        (lambda r: time_range(r.timeline, "+3", "+1", (0, 0)), "the time range is empty"),
        (lambda r: parse_time("soon", r.timeline, "--at"), "--at soon: not a time"),
        (lambda r: parse_time("+99999", r.timeline, "--end"), "is more than 3600 s after the recording's tf"),
        (lambda r: echo_times(r.buffer, r.timeline, "map", "base_link", rate=1e6), f"at most {MAX_ECHO_LINES:,}"),
    ],
)
def test_times_that_cannot_work_are_a_usage_error_with_a_hint(
    recording: Recording, call: Callable[[Recording], object], says: str
) -> None:
    with pytest.raises(UsageError, match=says.replace("+", r"\+")) as raised:
        call(recording)
    assert raised.value.hint


def test_plus_s_counts_on_the_clock_of_the_frames_asked_about() -> None:
    """Issue 39 (ros2_db3_ur5_topic_tf_two_clocks: an arm on simulated time, ArUco detections on wall time):
    ``--at +1`` between two of the arm's frames is a second into the arm's stamps, not the detections'."""
    from tests.analysis import wtf_scenes as scenes

    def arm(stamp: int) -> list[Transform]:
        return [scenes._t("base_link", "arm", stamp, 0.1 * (stamp - scenes.SIM_START) / NS_PER_S)]

    detections = scenes.periodic("/det", 2, lambda t: [scenes._t("camera", "tag", t)])
    arm_on_sim = scenes.periodic("/arm", 20, arm, stamp=scenes.sim)
    recording = scenes.recording(sorted(detections + arm_on_sim, key=lambda m: m.record_time), ros1=False)
    timeline = recording.timeline
    assert timeline.tf_start == scenes.START  # the recording's tf span is the detections' (the record clock's)
    (at,) = echo_times(recording.buffer, timeline, "base_link", "arm", at="+1")
    assert at == scenes.SIM_START + NS_PER_S
    assert echo(recording.buffer, "base_link", "arm", [at]).valid.all()
    first, last = time_range(timeline, "+1", "-1", (0, 0), ["arm"])
    assert (first, last) == (scenes.SIM_START + NS_PER_S, timeline.span_of(["arm"])[1] - NS_PER_S)
    (tag,) = echo_times(recording.buffer, timeline, "camera", "tag", at="+1")  # the detections: their own clock
    assert tag == timeline.tf_start + NS_PER_S
