"""``/diagnostics``' messages: the statuses a report makes, and their bytes as ROS 1 and ROS 2 read them."""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from tftools.analysis.edges import EdgeStats
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf.fleet import BagReport
from tftools.analysis.wtf.health import CHECKS_KEY, Level, Status, check_name, edge_name, statuses
from tftools.core.time import NS_PER_S
from tftools.sinks.diagnostics import DIAGNOSTIC_ARRAY, encode_cdr, encode_ros1
from tftools.sources.codecs.types import ros1_message_type

NOW = 1_700_000_010 * NS_PER_S


def _edge(parent: str, child: str, *, static: bool = False, last: int = NOW - NS_PER_S // 10) -> EdgeStats:
    return EdgeStats(
        parent,
        child,
        static,
        200,
        ("/robot",),
        NOW - 10 * NS_PER_S,
        last,
        0.0 if static else 20.0,
        0.001,
        60_000_000,
        NOW - 5 * NS_PER_S,
        2_000_000.0 if not static else math.nan,
        9_000_000.0,
        last,
        silent_for=0 if static else NOW - last,
    )


def _report(*findings: Finding) -> BagReport:
    return BagReport(("live",), list(findings), transforms=400, frames=3, start=NOW - 10 * NS_PER_S, end=NOW)


SLASH = Finding(Severity.warning, "leading_slash", "frame '/laser' starts with '/'", "drop it", ("/laser",))
STALE = Finding(Severity.error, "stale", "odom -> base_link stopped", "check that node", ("odom", "base_link"))


def _by_name(said: list[Status]) -> dict[str, Status]:
    return {s.name: s for s in said}


def test_each_check_and_edge_has_a_status_at_the_level_of_its_worst_finding() -> None:
    said = _by_name(
        statuses(_report(STALE, SLASH), [_edge("odom", "base_link"), _edge("base_link", "laser", static=True)], NOW)
    )
    assert said["tf: tree"].level is Level.ERROR and said["tf: tree"].message == "1 error, 1 warning"
    assert said[check_name("stale")].level is Level.ERROR
    assert said[check_name("stale")].message == STALE.message
    assert dict(said[check_name("stale")].values)["hint"] == "check that node"
    assert said[check_name("leading_slash")].level is Level.WARN
    assert said[check_name("cycle")].level is Level.OK and said[check_name("cycle")].message == "OK"
    assert said[edge_name("odom", "base_link")].level is Level.ERROR
    assert said[edge_name("base_link", "laser")].level is Level.OK
    assert all(s.hardware_id == "tf" for s in said.values())


def test_an_edge_names_the_checks_that_set_its_level() -> None:
    """A late arrival and a wrong value both make an edge WARN: its ``checks`` say which (the Neato's replay on a
    loaded machine made odom -> base_link WARN by ``delay`` alone, which the live test could not tell from another
    check's finding about it). An edge without findings has none."""
    late = Finding(Severity.warning, "delay", "odom -> base_link arrives late", "wait", ("odom", "base_link"))
    said = _by_name(
        statuses(_report(late, STALE, SLASH), [_edge("odom", "base_link"), _edge("base_link", "laser")], NOW)
    )
    assert dict(said[edge_name("odom", "base_link")].values)[CHECKS_KEY] == "delay stale"
    assert said[edge_name("odom", "base_link")].level is Level.ERROR
    assert CHECKS_KEY not in dict(said[edge_name("base_link", "laser")].values)


def test_an_edges_figures_are_its_rate_delay_longest_gap_and_silence() -> None:
    """The time since an edge's last sample arrived is its silence (``figures.silence``), under that name: tfx sent
    it as "age (s)" too, a second figure for one thing, which read as how old its newest stamp was."""
    said = _by_name(statuses(_report(), [_edge("odom", "base_link")], NOW))
    values = dict(said[edge_name("odom", "base_link")].values)
    assert values["rate (Hz)"] == "20.000"
    assert values["delay mean (s)"] == "0.002" and values["delay max (s)"] == "0.009"
    assert values["silent for the last (s)"] == "0.100" and values["longest gap (s)"] == "0.060"
    assert "age (s)" not in values
    assert values["publishers"] == "/robot"


def test_an_edge_of_one_sample_has_an_unknown_rate_and_gap_not_0() -> None:
    """A marker seen once (DIGIT_works' marker_367): its rate and gap unknown, as monitor's '-' and null."""
    once = dataclasses.replace(_edge("camera", "marker_367"), count=1, rate_hz=0.0, jitter=0.0, longest_interval=0)
    said = _by_name(statuses(_report(), [once], NOW))[edge_name("camera", "marker_367")]
    values = dict(said.values)
    assert (values["rate (Hz)"], values["longest gap (s)"], said.message) == ("unknown", "unknown", "OK, 1 sample")


def test_an_edge_heard_before_but_not_now_is_stale_and_nothing_heard_is_a_stale_tree() -> None:
    said = _by_name(statuses(_report(), [], NOW, gone={("odom", "base_link"): NOW - 30 * NS_PER_S}))
    gone = said[edge_name("odom", "base_link")]
    assert gone.level is Level.STALE and gone.message == "not heard for 30.000 s"
    assert dict(gone.values)["silent for the last (s)"] == "30.000" and "age (s)" not in dict(gone.values)
    nothing = Finding(Severity.error, "no_tf", "no transforms on /tf, /tf_static", "start the robot")
    empty = _by_name(statuses(BagReport(("live",), [nothing]), [], NOW))
    assert empty["tf: tree"].level is Level.STALE
    assert empty[check_name("no_tf")].level is Level.STALE  # no data yet, as the aggregator says it


def test_ignored_checks_have_no_status() -> None:
    said = _by_name(statuses(_report(), [], NOW, ignore=("cycle",)))
    assert check_name("cycle") not in said and check_name("stale") in said


def _decoded(store_name: Stores, data: bytes, ros1: bool) -> Any:
    """Decoded with a type store built from the published message definition (not tftools' encoder)."""
    store = get_typestore(Stores.EMPTY)
    definition = ros1_message_type(DIAGNOSTIC_ARRAY).definition
    store.register(get_types_from_msg(definition, DIAGNOSTIC_ARRAY))
    if ros1:
        return store.deserialize_ros1(data, DIAGNOSTIC_ARRAY)
    return get_typestore(store_name).deserialize_cdr(data, DIAGNOSTIC_ARRAY)


def test_the_array_decodes_as_ros1_and_ros2_read_it() -> None:
    said = statuses(_report(STALE), [_edge("odom", "base_link")], NOW)
    for data, ros1 in ((encode_ros1(NOW, said), True), (encode_cdr(NOW, said), False)):
        message = _decoded(Stores.ROS2_HUMBLE, data, ros1)
        assert message.header.stamp.sec == NOW // NS_PER_S
        assert [(s.level, s.name, s.message, s.hardware_id) for s in message.status] == [
            (int(s.level), s.name, s.message, s.hardware_id) for s in said
        ]
        edge = next(s for s in message.status if s.name == edge_name("odom", "base_link"))
        assert {kv.key: kv.value for kv in edge.values}["rate (Hz)"] == "20.000"


def test_the_ros1_type_is_diagnostic_msgs_own() -> None:
    # the md5sum rospy's diagnostic_msgs/DiagnosticArray has: a subscriber refuses any other
    assert ros1_message_type(DIAGNOSTIC_ARRAY).md5sum == "60810da900de1dd6ddd437c3503511da"
