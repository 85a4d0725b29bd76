"""``jumps._sent_together`` compares messages a span of record times at a time (``MESSAGES_AT_ONCE``: 4.1M transforms'
message keys held 0.4 GB at once): the edges it finds are those it finds in one span."""

from __future__ import annotations

import pytest

from tests.analysis.wtf_scenes import _t, ekf, healthy, periodic, recording, wheel
from tftools.analysis.wtf import Scene, jumps
from tftools.core.transform import Transform


def _arm(stamp: int) -> list[Transform]:
    """Two joints in one message, as robot_state_publisher sends them."""
    return [*wheel(stamp), _t("wheel", "finger", stamp, 0.05, 0.001 * (stamp % 7))]


def _localizer(stamp: int) -> list[Transform]:
    """map -> odom and odom -> base_link in one message (cartographer providing the odom frame)."""
    return [_t("map", "odom", stamp, 1.0), _t("odom", "base_link", stamp, 0.4)]


@pytest.mark.parametrize("spans", [1, 7, 300])
def test_joints_found_a_span_at_a_time_are_those_of_one_span(monkeypatch: pytest.MonkeyPatch, spans: int) -> None:
    messages = healthy(
        amcl=periodic("/cartographer", 10, _localizer), ekf=ekf(end=0.0), wheels=periodic("/rsp", 20, _arm)
    )
    scene = Scene(recording(messages))
    total = len(scene.rows)
    monkeypatch.setattr(jumps, "MESSAGES_AT_ONCE", -(-total // spans))
    assert len(jumps._record_spans(scene.rows.record_time.whole(), total)) >= min(spans, 100)
    # the arm's two joints share every message, and map -> odom the localizer's; but odom -> base_link, under
    # odom, shares its messages with map's edge alone: a localizer's pair, not a state publisher's joint
    assert jumps._sent_together(scene) | jumps._turning_in_place(scene) == {
        ("base_link", "wheel"),
        ("wheel", "finger"),
        ("map", "odom"),
    }
