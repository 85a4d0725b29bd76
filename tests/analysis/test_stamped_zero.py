"""Sensor data stamped 0 (an unset header.stamp) that arrives before its tf chain exists (the real Neato's
/wall markers, ros2_db3_neato_real_fsm_odom_jump_2023): tf2 reads stamp 0 as the latest transform only where
there is one; a MessageFilter's request still waiting with it is dropped as older than the cache once tf
comes. ``sensor_lost`` says what was observed and why, and suggests no cache (none keeps them)."""

from __future__ import annotations

import numpy as np

from tests.analysis.test_filter_faults import MS, T0, _moving, _static, _text
from tests.analysis.wtf_scenes import recording
from tftools.analysis.filter import FilterQuery, filter_streams
from tftools.analysis.filter.fates import Fate, message_fates
from tftools.analysis.findings import Finding
from tftools.analysis.wtf import Scene, findings_of
from tftools.sources.contents import StampedMessages

#: odom -> base_link stamped from the start, each arriving 1 s after its stamp: the chain exists from 1 s (the
#: Neato's odometry came 1.04 s after its first marker).
TF = sorted(
    [*_moving("odom", "base_link", 10, 1000 * MS), _static("base_link", "laser")],
    key=lambda m: m.record_time,
)


def _markers(stamp_zero: bool) -> StampedMessages:
    """Markers in base_link at 5 Hz from 0.1 s: the first 5 arrive before odom -> base_link exists."""
    arrivals = T0 + 100 * MS + np.arange(100, dtype=np.int64) * 200 * MS
    stamps = np.zeros(len(arrivals), np.int64) if stamp_zero else arrivals - 5 * MS
    return StampedMessages(
        "/wall", "visualization_msgs/msg/Marker", arrivals, stamps, np.zeros(100, np.int32), ["base_link"]
    )


def _lost(stamp_zero: bool) -> list[Finding]:
    scene = Scene(recording(TF), streams=[_markers(stamp_zero)])
    return [f for f in findings_of(scene) if f.code == "sensor_lost"]


def test_stamped_zero_before_the_chain_is_counted_and_no_cache_is_suggested() -> None:
    rec = recording(TF)
    fates = message_fates(rec.buffer, _markers(True), "odom")
    before = fates.zero_before_chain()
    assert before.tolist() == [True] * 5 + [False] * 95  # arrived before odom -> base_link's first sample
    assert (fates.fate[:5] == Fate.OLDER_THAN_CACHE).all() and (fates.fate[5:] == Fate.ON_ARRIVAL).all()
    whole = filter_streams(rec.buffer, [_markers(True)], FilterQuery(target="odom"))
    report = whole.streams[0]
    assert (report.never, report.stamped_zero, report.before_tf, report.cache_needed) == (5, 5, 0, None)
    said = " ".join(_text(whole).split())  # tfx filter's advice says it too
    assert "5 stamped 0 arrived before their tf: no cache keeps them; set header.stamp" in said, said


def test_sensor_lost_names_stamp_zero_and_the_missing_chain_not_the_cache() -> None:
    (found,) = _lost(stamp_zero=True)
    assert found.count == 5
    said = " ".join(found.message.split())
    assert "all of them stamped 0 (header.stamp unset)" in said, said
    assert "before the recording's tf of their chain existed" in said, said
    assert "older than the 10 s cache holds" not in said and "a cache of" not in said, said
    assert "set header.stamp" in found.hint and "cache" not in found.hint.split(":", 1)[1], found.hint


def test_the_same_markers_stamped_when_measured_wait_and_pass() -> None:
    """The cause is the stamp: stamped when measured, the early markers wait for tf and pass (none lost)."""
    assert _lost(stamp_zero=False) == []
    fates = message_fates(recording(TF).buffer, _markers(False), "odom")
    assert not fates.zero_before_chain().any()
    assert (fates.fate[:5] == Fate.LATER).all()
