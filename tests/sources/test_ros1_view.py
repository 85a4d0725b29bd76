"""``view_order``: the order rosbag play (``rosbag::View``) replays a ROS1 bag's messages of one record time in.

The real librosbag's order on the corpus' Kobuki bag (29 connections, recorded under use_sim_time) is
checked end to end by tests/oracle/test_msgfilter.py, where the real MessageFilter reads the bag with it."""

from __future__ import annotations

import numpy as np

from tftools.sources.bag.ros1.view import _sort, view_order


def _places(times: list[list[int]]) -> list[list[int]]:
    return [p.tolist() for p in view_order([np.array(t, np.int64) for t in times])]


def test_up_to_16_connections_ties_go_to_the_one_that_moved_last() -> None:
    """At most 16 iterators: std::sort is an insertion sort, stable. At the start the connection of the
    highest id comes first (View takes the last iterator); after that, among ties, the one whose previous
    message was replayed last (worked through by hand from View::iterator::increment)."""
    assert _places([[5, 7], [5, 7], [5, 7]]) == [[2, 3], [1, 4], [0, 5]]


def test_the_order_is_record_time_order_with_ties_among_connections() -> None:
    rng = np.random.default_rng(3)
    times = [np.sort(rng.integers(0, 40, int(rng.integers(1, 30)))) for _ in range(25)]
    places = view_order(times)
    replayed = np.empty(sum(len(t) for t in times), np.int64)
    for t, p in zip(times, places, strict=True):
        assert (np.diff(p) > 0).all()  # a connection's messages in their order
        replayed[p] = t
    assert (np.diff(replayed) >= 0).all()


def test_more_than_16_iterators_are_sorted_as_libstdcxx_sorts_them() -> None:
    """Above 16 the introsort's median-of-three partition reorders ties: the order differs from a stable
    sort, as the real View's does on the Kobuki bag; every order still sorts by time."""
    t = [1] * 20 + [0] * 5
    v = list(range(25))
    _sort(v, t)
    assert sorted(v[:20]) == list(range(20)) and sorted(v[20:]) == list(range(20, 25))
    assert v[:20] != list(range(20))  # not stable
