"""``tfx frames`` on the sample bags: every frame, its parent, rate and publisher; tf2's YAML."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.cli.conftest import SAMPLE_BAGS, Tfx
from tests.oracle import Scenario, run_tf2

TRUE_RATES = {"odom": 10, "base_footprint": 50, "left_wheel": 30, "right_wheel": 30, "arm_link1": 50, "arm_link6": 50}
STATIC = {"base_link", "laser", "imu_link", "camera_link", "camera_optical_frame", "arm_base", "gripper"}


@pytest.mark.parametrize("fmt", list(SAMPLE_BAGS))
def test_json_describes_every_frame(tfx: Tfx, fmt: str) -> None:
    result = tfx("frames", "-b", SAMPLE_BAGS[fmt], "--format", "json")
    assert result.code == 0, result.stderr
    doc = json.loads(result.stdout)
    frames = {f["frame"]: f for f in doc["frames"]}
    assert doc["roots"] == ["map"]
    assert len(frames) == 18
    assert {name for name, f in frames.items() if f["static"]} == STATIC
    for frame, rate in TRUE_RATES.items():
        assert frames[frame]["rate_hz"] == pytest.approx(rate, rel=0.02)
    for frame in STATIC | {"map"}:  # a static edge has no rate, a root no samples: null, not 0.0 ("a rate of zero")
        assert frames[frame]["rate_hz"] is None, frame
    assert frames["arm_link3"]["parent"] == "arm_link2"


def test_text_tree_nests_children_under_parents(tfx: Tfx) -> None:
    result = tfx("frames", "-b", SAMPLE_BAGS["mcap"])
    assert result.code == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0].startswith("map") and "(root)" in lines[0]
    depth = {line.lstrip("│├└─ ").split()[0]: len(line) - len(line.lstrip("│├└─ ")) for line in lines}
    assert depth["odom"] < depth["base_footprint"] < depth["base_link"] < depth["arm_base"] < depth["gripper"]
    assert "50.0 Hz" in next(line for line in lines if "arm_link4" in line)


def test_yaml_is_tf2s_all_frames_as_yaml(tfx: Tfx, tf2_available: None) -> None:
    result = tfx("frames", "-b", SAMPLE_BAGS["ros1"], "--format", "yaml")
    (theirs,) = run_tf2([Scenario(queries=[["yaml"]], bag=str(SAMPLE_BAGS["ros1"]))])
    text = theirs["answers"][0]["text"]
    assert text.endswith("\n") and result.stdout == text


def test_text_tree_of_a_chain_of_thousands_of_frames(tfx: Tfx, tmp_path: Path) -> None:
    """No recursion and no lines of thousands of indents: past a depth it is written out instead."""
    from tests.bags import TfMessage, write_bag
    from tftools.core.transform import Transform
    from tftools.render.frames import MAX_DRAWN_DEPTH

    chain = [Transform((0.1, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), 1, f"f{i}", f"f{i + 1}") for i in range(3000)]
    bag = write_bag(tmp_path / "chain.bag", [TfMessage("/tf_static", 1_000_000_000, chain, "/rsp")])
    result = tfx("frames", "-b", bag)
    assert result.code == 0, result.stderr
    lines = result.stdout.splitlines()
    assert len(lines) == 3001 and lines[-1].split("] ", 1)[1].startswith("f3000")
    assert max(len(line) for line in lines) < 4 * (MAX_DRAWN_DEPTH + 2) + 200
    assert f"[depth {MAX_DRAWN_DEPTH + 1}] f{MAX_DRAWN_DEPTH + 1}" in result.stdout


def test_an_edge_sent_once_has_no_rate(tfx: Tfx, tmp_path: Path) -> None:
    """A marker detected once (DIGIT_works' camera -> marker_367): 'once' and its stamp, not '0.0 Hz, 1 samples'."""
    from tests.bags import detections_bag

    result = tfx("frames", "-b", detections_bag(tmp_path / "detections.bag"))
    assert result.code == 0, result.stderr
    line = next(line for line in result.stdout.splitlines() if "marker_367" in line)
    assert "once" in line and "1 sample, stamped 1.500" in line and "Hz" not in line and "samples" not in line
    assert "25.0 Hz" in next(line for line in result.stdout.splitlines() if "marker_0" in line)


def test_a_tree_too_large_to_colour_is_the_same_text(tfx: Tfx, monkeypatch: pytest.MonkeyPatch) -> None:
    """Past MAX_STYLED_LINES the tree goes out as plain text (rich costs 0.3 ms a line): the same text."""
    from tftools.render import frames

    styled = tfx("frames", "-b", SAMPLE_BAGS["ros1"])
    monkeypatch.setattr(frames, "MAX_STYLED_LINES", 3)
    plain = tfx("frames", "-b", SAMPLE_BAGS["ros1"])
    assert plain.code == styled.code == 0
    assert plain.stdout == styled.stdout and len(plain.stdout.splitlines()) > 3
