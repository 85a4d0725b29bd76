"""echo's choice of times from Python (``tftools.analysis.echo.echo`` with an ``EchoQuery``, the times as library
values of ``tftools.analysis.times``), as ``tfx echo`` makes it; errors in the library's words."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from tests.cli.conftest import SAMPLE_BAGS
from tftools.analysis.echo import MAX_ECHO_LINES, EchoQuery, chain_span, echo, echo_times, lookups
from tftools.analysis.times import Offset, Stamp, parse_time_spec, resolve_range, resolve_time
from tftools.core.errors import InvalidTimeError, TfToolsError, TimeRangeError, TooManyLinesError
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform
from tftools.sources import Recording, read_recording


@pytest.fixture(scope="module")
def recording() -> Recording:
    return read_recording([SAMPLE_BAGS["db3"]])


def _times(recording: Recording, **asked: object) -> list[int]:
    query = EchoQuery(target="map", source="base_link", **asked)  # type: ignore[arg-type]  # EchoQuery's keywords, passed on
    times: list[int] = echo_times(recording.buffer, recording.timeline, query).tolist()
    return times


def test_times_step_at_the_rate_over_where_every_moving_edge_between_has_data(recording: Recording) -> None:
    times = _times(recording, rate=2.0)
    span = chain_span(recording.buffer, "map", "base_link")
    assert span is not None and times[0] == span[0] and times[-1] <= span[1]
    assert set(np.diff(times).tolist()) == {NS_PER_S // 2}
    series = echo(recording, EchoQuery(target="map", source="base_link", rate=2.0))
    assert series.times.tolist() == times and series.valid.all()


def test_times_as_library_values_from_the_recordings_tf(recording: Recording) -> None:
    timeline = recording.timeline
    times = _times(recording, start=Offset(1), end=Offset(3))
    assert times == [timeline.tf_start + s * NS_PER_S for s in (1, 2, 3)]
    assert resolve_time(parse_time_spec("-1"), timeline) == timeline.tf_end - NS_PER_S
    assert resolve_time(Stamp(timeline.tf_start + 5), timeline) == timeline.tf_start + 5
    assert _times(recording, at=Stamp(0)) == [0]  # the latest, as tf2's time 0
    every = _times(recording, every=True, end=Offset(2))
    assert len(every) > 2 and every[-1] <= timeline.tf_start + 2 * NS_PER_S


def test_the_grammar_reads_each_form() -> None:
    assert parse_time_spec(" +2.5") == Offset(2.5)
    assert parse_time_spec("-1") == Offset(-1, from_end=True)
    assert parse_time_spec("1700000012.5") == Stamp(1_700_000_012_500_000_000)
    assert parse_time_spec("0") == Stamp(0)
    assert str(parse_time_spec("+99999", "end")) == "+99999"


@pytest.mark.parametrize(
    ("call", "error", "says"),
    [
        (lambda r: resolve_range(r.timeline, Offset(3), Offset(1), (0, 0)), TimeRangeError, "the time range is empty"),
        (lambda r: parse_time_spec("soon", "at"), InvalidTimeError, "at soon: not a time"),
        (lambda r: parse_time_spec("nan", "at"), InvalidTimeError, "at nan: not a finite number"),
        (
            lambda r: resolve_time(parse_time_spec("+99999"), r.timeline, (), "end"),
            InvalidTimeError,
            "end \\+99999: more than 3600 s after the recording's tf",
        ),
        (lambda r: _times(r, rate=1e6), TooManyLinesError, f"at most {MAX_ECHO_LINES:,}"),
    ],
)
def test_times_that_cannot_work_are_errors_in_the_librarys_words(
    recording: Recording, call: Callable[[Recording], object], error: type[TfToolsError], says: str
) -> None:
    with pytest.raises(error, match=says) as raised:
        call(recording)
    assert "--" not in str(raised.value)  # no option a Python caller never typed


def test_an_invalid_time_carries_what_was_given_and_the_span(recording: Recording) -> None:
    with pytest.raises(InvalidTimeError) as raised:
        echo(recording, EchoQuery(target="map", source="base_link", at=parse_time_spec("+99999", "at")))
    timeline = recording.timeline
    assert (raised.value.text, raised.value.role) == ("+99999", "at")
    assert raised.value.span == (timeline.tf_start, timeline.tf_end)


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
    (at,) = echo(recording, EchoQuery(target="base_link", source="arm", at=Offset(1))).times.tolist()
    assert at == scenes.SIM_START + NS_PER_S
    assert lookups(recording.buffer, "base_link", "arm", [at]).valid.all()
    first, last = resolve_range(timeline, Offset(1), Offset(-1, from_end=True), (0, 0), ["arm"])
    assert (first, last) == (scenes.SIM_START + NS_PER_S, timeline.span_of(["arm"])[1] - NS_PER_S)
    (tag,) = echo(recording, EchoQuery(target="camera", source="tag", at=Offset(1))).times.tolist()
    assert tag == timeline.tf_start + NS_PER_S  # the detections: their own clock
