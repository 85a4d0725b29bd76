"""/tf_static messages with the same values and other stamps, all sent before the recording began, are as many
publishers (a late subscriber gets only the latest message of each static broadcaster, whose history holds one):
several static_transform_publisher processes left running, said as one harmless note. A node re-sending its
static with fresh stamps while recorded stays one publisher.

As on the corpus' ros2_db3_ias0220_recorded_vladislavichek_2025 (five of world -> imu_link, stamped 141.7 to
840.9 s before they arrived); its sibling with seven (metadata.yaml listing 7) is checked on the recording."""

from __future__ import annotations

from tests.analysis.wtf_scenes import recording
from tests.bags import TfMessage
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf import check
from tftools.core.time import NS_PER_S
from tftools.core.transform import Transform

START = 1_761_140_148 * NS_PER_S
PERIOD = NS_PER_S // 10


def _static(stamp: int) -> Transform:
    return Transform.from_rpy((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), stamp, "world", "imu_link")


def _device(n: int = 300) -> list[TfMessage]:
    """The device's moving edge, stamped every 0.1 s and recorded 0.2 ms after."""
    return [
        TfMessage(
            "/tf", t + 200_000, [Transform.from_rpy((0.0, 0.01 * i, 0.0), (0.0, 0.0, 0.0), t, "imu_link", "sensor")]
        )
        for i, t in enumerate(START + k * PERIOD for k in range(n))
    ]


def _findings(statics: list[TfMessage]) -> list[Finding]:
    return check(recording(sorted([*statics, *_device()], key=lambda m: m.record_time), ros1=False))


def test_the_same_static_sent_before_the_recording_with_other_stamps_is_as_many_publishers() -> None:
    ago = [840.9, 360.7, 807.7, 529.0, 141.7]
    statics = [
        TfMessage("/tf_static", START + int(at * NS_PER_S), [_static(START - int(a * NS_PER_S))])
        for a, at in zip(ago, [0.12, 0.37, 1.15, 2.19, 3.00], strict=True)
    ]
    findings = _findings(statics)
    (same,) = [f for f in findings if f.code == "multiple_authorities"]
    assert same.severity is Severity.info
    assert same.message.startswith(
        "5 /tf_static publishers (unnamed) all send 1 static transform, with the same values"
    )
    assert "other stamps, both sent before the recording began" in same.message
    assert not [f for f in findings if f.code in ("static_conflict", "dynamic_on_static", "time_backwards")]


def test_a_static_re_sent_with_fresh_stamps_while_recorded_is_one_publisher() -> None:
    statics = [
        TfMessage("/tf_static", START + k * NS_PER_S // 2 + 1000, [_static(START + k * NS_PER_S // 2)])
        for k in range(30)
    ]
    findings = _findings(statics)
    assert not [f for f in findings if f.code == "multiple_authorities"], findings
