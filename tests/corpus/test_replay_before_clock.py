"""A replay of a recording whose recorder heard /clock late, on the real recording that showed it (designed
reproductions: tests/cli/test_monitor.py, ``_clock_heard_late``): the Webots TurtleBot3's first 96 /tf messages
were recorded 1.92 s before its first /clock. ``monitor --play`` played them all at /clock's first value, and
its first three tables said /tf at 143, 98 and 82 msgs/s (the robot sends 50); its header counted ``+S`` from
that first /clock, ``+4.1 s`` where ``--start +5`` had begun the table."""

from __future__ import annotations

import json
import re

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

WEBOTS = "ros2-turtlebot3-webots-resends-2025-db3"
FIRST_STAMP = 90.62  # the first /tf stamp (simulated time); /clock was first recorded at 92.54


@pytest.mark.parametrize("end", ["+3", "+4", "+5"])
def test_the_replay_counts_messages_before_the_first_clock_as_the_whole_read(
    end: str,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """Over the first seconds, the replay's /tf figures are the whole read's over the same window: ~50 msgs/s."""
    path = corpus(BY_ID[WEBOTS])
    played = tfx("monitor", "-b", path, "--play", "--rate", "50", "--end", end, "--format", "json")
    whole = tfx("monitor", "-b", path, "--end", end, "--format", "json")
    assert played.code == 0 and whole.code == 0, played.stderr + whole.stderr
    replayed, read = json.loads(played.stdout.splitlines()[-1]), json.loads(whole.stdout)
    (tf,) = (a for a in replayed["authorities"] if a["authority"] == "/tf")
    (truth,) = (a for a in read["authorities"] if a["authority"] == "/tf")
    assert tf["messages"] == pytest.approx(truth["messages"], abs=1)  # a window's edge: one message either way
    assert tf["rate_hz"] == pytest.approx(truth["rate_hz"], rel=0.02) and 48 < tf["rate_hz"] < 51, (tf, truth)


def test_the_replays_header_counts_from_the_first_stamp_as_start_does(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    played = tfx("monitor", "-b", corpus(BY_ID[WEBOTS]), "--play", "--rate", "50", "--start", "+5", "--end", "+8")
    assert played.code == 0, played.stderr
    headers = re.findall(r"^time ([\d.]+) \(\+([\d.]+) s\)", played.stdout, re.MULTILINE)
    assert headers and headers[-1] == ("98.620", "8.0"), played.stdout
    assert all(float(since) == pytest.approx(float(time) - FIRST_STAMP, abs=0.06) for time, since in headers)
