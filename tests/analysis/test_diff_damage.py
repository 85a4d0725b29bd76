"""Which of diff's differences a damaged side may have made (``damage_notes``), on differences built here."""

from __future__ import annotations

from tftools.analysis.diff.damage import Damaged, damage_notes
from tftools.analysis.differences import Change, Difference
from tftools.analysis.expected import FrameShape, Tail

S = 1_000_000_000
LOST = Damaged("a chunk is damaged", ((40 * S, 60 * S),))


def _edge(rate: float, tail: Tail | None = None) -> FrameShape:
    return FrameShape("base_link", "odom", rate_hz=rate, tail=tail)


def test_a_frame_missing_from_the_damaged_side_is_said_perhaps_lost_with_it() -> None:
    lost = Difference(Change.lost, "laser", _edge(10.0), None)
    added = Difference(Change.added, "laser", None, _edge(10.0))
    assert damage_notes([lost, added], None, LOST) == (
        "B is damaged: its transforms from 40.0 s to 60.0 s into it were lost; the frame may have been sent only in "
        "what was lost",
        "",  # added in B: A, read whole, did not lose it
    )
    assert damage_notes([added], Damaged("cut short"), None) == (
        "A was read only in part (cut short); the frame may have been sent only in what was lost",
    )


def test_a_rate_is_put_to_the_damage_of_the_slower_side_only() -> None:
    slower_b = Difference(Change.rate, "base_link", _edge(20.0), _edge(15.0), rate_change=-0.25)
    assert damage_notes([slower_b], None, LOST)[0].endswith("the transforms lost there count as silence in its rate")
    assert damage_notes([slower_b], LOST, None) == ("",)  # A's damage did not make B slower


def test_an_early_stop_is_put_to_the_damage_only_where_it_reaches_the_last_sample() -> None:
    stopped = Tail(arrived=30 * S, stamp=0, length=100 * S, stopped=True)
    sent = Tail(arrived=100 * S, stamp=0, length=100 * S, stopped=False)
    early = Difference(Change.stopped, "base_link", _edge(20.0, sent), _edge(20.0, stopped))
    assert damage_notes([early], None, LOST)[0].startswith("B is damaged: its transforms from 40.0 s")
    before = Damaged("a chunk is damaged", ((5 * S, 10 * S),))  # lost before it stopped: not why it stopped
    assert damage_notes([early], None, before) == ("",)
    assert damage_notes([early], None, None) == ("",)


def test_a_difference_said_with_others_keeps_each_ones_damage_once() -> None:
    """Two edges that stopped together are one line (``Difference.folded``): where the damage reaches only the second
    edge's last sample, its note is kept (it was lost with the first's); where both reach it, said once."""
    sent = Tail(arrived=100 * S, stamp=0, length=100 * S, stopped=False)
    first = Difference(Change.stopped, "base_link", _edge(20.0, sent), _edge(20.0, _stop(70)))
    second = Difference(Change.stopped, "wheel", _edge(20.0, sent), _edge(20.0, _stop(50)))
    said = Difference(Change.stopped, "base_link", first.before, first.after, said_with=("wheel",), folded=(second,))
    assert damage_notes([said], None, LOST)[0].startswith("B is damaged: its transforms from 40.0 s")
    assert damage_notes([first], None, LOST) == ("",)  # the first alone: lost before it stopped
    both = Difference(Change.stopped, "base_link", second.before, second.after, said_with=("wheel",), folded=(second,))
    (note,) = damage_notes([both], None, LOST)
    assert note.count("B is damaged") == 1


def _stop(at_s: int) -> Tail:
    return Tail(arrived=at_s * S, stamp=0, length=100 * S, stopped=True)
