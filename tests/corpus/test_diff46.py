"""Issue 39 (brief diff46), on the real pairs that showed it: `tfx diff` measures a stop as wtf's stale does."""

from __future__ import annotations

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import Corpus
from tests.corpus.test_corpus44b import PAUSED, TB4
from tests.corpus.test_diff42 import _diff


def test_the_turtlebot4_simulation_paused_at_the_end_stopped_no_edge(
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    """The TurtleBot 4 simulator's two runs of March 2025: in the later, /clock advances 12 ms over the recording's
    last 2.2 s (the simulation all but paused) and tf's last samples arrive then, 9 ms of simulated time before
    /clock's last value. diff said five edges 'stopped early in B ... silent for its last 2.2 s', measured on the
    record clock, where wtf (on the simulation's time, as a listener with use_sim_time sees it) says tf is fresh.
    A stop is now measured as wtf's stale is: no difference."""
    code, found = _diff(tfx, corpus, TB4, PAUSED)
    assert (code, found) == (0, [])
