"""A ROS engineer's habits and issue 39's leftovers (left41), each on the real recording that showed it.

Each test skips while its recording awaits placement in the shared corpus, as the rest of the corpus tests do."""

from __future__ import annotations

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

LISTENER = "beginner-tutorials-constant-world-2019-bag"


def test_filter_of_named_topics_does_not_suggest_the_command_just_run(corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Arjung27's beginner_tutorials listener bag holds /chatter (std_msgs/String), /rosout, /rosout_agg and /tf:
    ``tfx filter /scan`` (not there), ``/chatter`` (no header) and ``/rosout`` (a header without a frame_id)
    each answered 'e.g. tfx filter /scan -b BAG', /scan's the very command run. Each says what it is, and that
    naming none checks every topic with a Header."""
    path = corpus(BY_ID[LISTENER])
    for topic, why in (
        ("/scan", "/scan: not in the recording"),
        ("/chatter", "/chatter: std_msgs/String messages have no header"),
        ("/rosout", "only /rosout, whose header has no frame_id"),
    ):
        said = tfx("filter", topic, "-b", path)
        assert said.code == 2 and not said.stdout and len(said.stderr.strip().splitlines()) == 1, said.stderr
        assert why in said.stderr and "e.g. tfx filter" not in said.stderr, said.stderr
        assert "or none: tfx filter -b BAG checks every such topic" in said.stderr, said.stderr
