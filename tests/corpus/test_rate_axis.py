"""A publisher's rate is one figure whether the recording is read whole or replayed (issue 39): its messages over
the time they arrived in on the clock they arrived on, the record clock where no /clock gives ROS time at arrival
(a Husky at 0.81x real time: 10.00 msgs/s by stamp whole, 8.10 replayed; a JetAcker's slam_toolbox re-sending
every 20 ms of a simulation at 0.067x: 794 for 53.7). Each recording's ``expected.publisher_rates_hz`` is written
from its record times; ``expected.replayed_edge_counts`` says what a replay's window holds where it differs from
the whole read, and its entry's ``replay`` why."""

from __future__ import annotations

import json
from typing import Any

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import RECORDINGS, Corpus

RATED = [r for r in RECORDINGS if "publisher_rates_hz" in r.meta["expected"]]
REPLAYED = [r for r in RECORDINGS if "replayed_edge_counts" in r.meta["expected"]]


def _monitor(tfx: Tfx, *args: Any, window: float | None = None) -> Any:  # noqa: F811
    played = ["--play", "--rate", "1000", "--window", str(window)] if window is not None else []
    result = tfx("monitor", *args, *played, "--format", "json")
    assert result.code == 0, result.stderr
    return json.loads(result.stdout.splitlines()[-1] if played else result.stdout)


@pytest.mark.parametrize("recording", RATED, ids=[r.id for r in RATED])
@pytest.mark.parametrize("play", [False, True], ids=["whole", "play"])
def test_a_publishers_rate_is_on_its_arrival_clock(recording: Any, corpus: Corpus, tfx: Tfx, play: bool) -> None:  # noqa: F811
    path = corpus(recording)
    window = int(recording.meta["duration_s"]) + 10 if play else None
    shown = {a["authority"]: a["rate_hz"] for a in _monitor(tfx, "-b", path, window=window)["authorities"]}
    for publisher, hz in recording.meta["expected"]["publisher_rates_hz"].items():
        assert shown[publisher] == pytest.approx(hz, rel=1e-3), publisher


@pytest.mark.parametrize("recording", REPLAYED, ids=[r.id for r in REPLAYED])
def test_a_replay_holds_what_its_window_keeps(recording: Any, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """The raspimouse replayed beside a live gmapping: map -> odom's replayed samples, 7.0 days older than the
    live ones, are refused by a replay's window of 64 s as by a listener's cache; a window over 7 days holds them."""
    path = corpus(recording)
    whole = _monitor(tfx, "-b", path)
    short = _monitor(tfx, "-b", path, window=int(recording.meta["duration_s"]) + 10)
    counts = {f"{e['parent']} -> {e['child']}": e["count"] for e in short["edges"]}
    assert counts == recording.meta["expected"]["replayed_edge_counts"]
    long = _monitor(tfx, "-b", path, window=1_000_000)
    for report in (short, long):
        assert [(a["authority"], a["messages"]) for a in report["authorities"]] == [
            (a["authority"], a["messages"]) for a in whole["authorities"]
        ]
        rates = [a["rate_hz"] for a in whole["authorities"]]
        assert [a["rate_hz"] for a in report["authorities"]] == pytest.approx(rates)
    assert [(e["parent"], e["child"], e["count"]) for e in long["edges"]] == [
        (e["parent"], e["child"], e["count"]) for e in whole["edges"]
    ]
