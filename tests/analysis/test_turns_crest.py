"""A motion's turning point is not a value visiting another place (corpus: EarlJr53/comprobo-warmup
``wall_follower_sim``, a Gazebo Neato following a wall, 2023): its odometry heading wobbles 1.1 degrees a sample
either way, 0.8 s a cycle, while it drives on 0.02 m a sample; at every crest the sample is 1.1 degrees from the
ones before and after, which are together, and ``multiple_authorities`` said "alternated between two places 58
times in 273 new samples" of its one publisher. Two sources whose headings differ take turns still count."""

from __future__ import annotations

import numpy as np

from tftools.analysis.wtf.broadcasters import _alternating


def _poses(headings_deg: list[float], step_m: float = 0.02) -> np.ndarray:
    """Poses driving ``step_m`` a sample along x, heading as given."""
    yaw = np.radians(np.array(headings_deg))
    values = np.zeros((len(yaw), 7))
    values[:, 0] = np.arange(len(yaw)) * step_m
    values[:, 5], values[:, 6] = np.sin(yaw / 2), np.cos(yaw / 2)
    return values


WOBBLE = [-0.51, 0.64, 1.77, 0.64, -0.51, -1.65, -2.80, -1.66] * 12  # the recording's heading, 8 samples a cycle


def test_a_heading_wobbling_while_driving_on_turns_at_its_crests_and_visits_no_other_place() -> None:
    assert _alternating(_poses(WOBBLE)) == 0


def test_two_sources_of_headings_taking_turns_still_alternate() -> None:
    """The same drive with every other sample from a source 20 degrees off: each of its samples counts."""
    turns = [h + (20.0 if i % 2 else 0.0) for i, h in enumerate(WOBBLE)]
    assert _alternating(_poses(turns)) >= len(turns) - 2


def test_a_one_sample_spike_among_steady_values_still_counts() -> None:
    """Held still, one sample 5 degrees off: a glitch, out and back from where the value stays."""
    headings = [0.0] * 10 + [5.0] + [0.0] * 10
    assert _alternating(_poses(headings, step_m=0.0)) == 1


def test_a_noisy_estimate_going_out_and_back_no_further_than_its_own_step_visits_no_other_place() -> None:
    """ros4hri's face detector (a ROS 2 copy of its test bag, 2022): a face's depth jitters 64 mm a sample either way
    along the camera's ray, out and back as often as not, told "alternated between two places 49 times in 290 new
    samples" and an error, three times. Noise goes out no further than the stream's own step; a second source
    0.18 m off, taking turns with it (the JetAcker's two odometries), still counts."""
    rng = np.random.default_rng(7)
    face = np.zeros((290, 7))
    face[:, 2] = 1.35 + rng.normal(0.0, 0.045, 290)
    face[:, 6] = 1.0
    assert _alternating(face) < 0.1 * len(face), _alternating(face)
    two = face.copy()
    two[:, 2] = 1.35 + rng.normal(0.0, 0.004, 290)  # an odometry's few millimetres a sample
    two[1::5, 2] += 0.18  # one sample in five from a source 0.18 m further
    assert _alternating(two) >= 0.15 * len(two), _alternating(two)
