"""A replay of a recording whose record times were read off a simulation's ticks, on the real recording that showed
it (designed reproductions: tests/cli/test_time_figures.py, ``test_a_stream_finds_the_ticks_a_whole_read_finds``):
ros1_stage_amcl_sim_time_2015, recorded under use_sim_time on Stage's 100 ms ticks without /clock. The whole read
knew the ticks (``TickedGrid``), the stream did not, so ``--play`` said the delays of amcl's map -> odom and of the
fixed joints post-dated by robot_state_publisher a tick further from zero (-0.502 s where the whole read says
-0.402 s); now every edge's delays, replayed to the end over a window holding all of it, are the whole read's."""

from __future__ import annotations

import json

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

STAGE = "ros1-stage-amcl-sim-time-2015-bag"


def test_the_replay_says_the_delays_of_the_whole_read(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    path = corpus(BY_ID[STAGE])
    whole = tfx("monitor", "-b", path, "--format", "json")
    played = tfx("monitor", "-b", path, "--play", "--rate", "1000", "--window", "100", "--format", "json")
    assert whole.code == 0 and played.code == 0, whole.stderr + played.stderr
    figures = ("count", "delay_mean_s", "delay_max_s")

    def delays(report: dict[str, list[dict[str, object]]]) -> dict[tuple[object, object], list[object]]:
        return {(e["parent"], e["child"]): [e[k] for k in figures] for e in report["edges"]}

    read, replayed = delays(json.loads(whole.stdout)), delays(json.loads(played.stdout.splitlines()[-1]))
    assert replayed == read
    assert read["camera_rgb_frame", "camera_depth_frame"][2] == -0.4  # a fixed joint post-dated 0.5-0.6 s
