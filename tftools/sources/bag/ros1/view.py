"""The order ``rosbag play`` (``rosbag::View``) replays a ROS1 bag's messages in, ties of record time included.

``View`` keeps one iterator per connection (in connection id order), and after each message it hands over
re-sorts them with ``std::sort`` by their next message's time, taking the last. Messages of one record time
(a simulation recorded under use_sim_time) therefore come in an order that follows from the whole history
of that sort, neither file order nor connection order, and a listener's MessageFilter sees a sensor message
before or after the tf of its instant by it. ``std::sort`` is libstdc++'s introsort, followed here step by
step: an insertion sort up to 16 iterators (stable), a median-of-three partition above.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from tftools.core.arrays import Int64Array

#: libstdc++'s ``_S_threshold``: ranges this short are left to the final insertion sort.
_THRESHOLD = 16
#: Messages at most whose order is followed (in Python, a few microseconds each per connection);
#: beyond, ties keep the reader's own order.
MAX_MESSAGES = 300_000


def view_order(times: Sequence[Int64Array]) -> list[Int64Array]:
    """For each connection (in connection id order; its record times in index order), the place in
    ``rosbag::View``'s order of each of its messages."""
    placed = [np.zeros(len(t), np.int64) for t in times]
    lists = [t.tolist() for t in times]
    now = [t[0] if t else 0 for t in lists]  # each iterator's next record time
    at = [0] * len(lists)
    iterators = [c for c, t in enumerate(lists) if t]
    _sort(iterators, now)
    for place in range(sum(len(t) for t in lists)):
        c = iterators[-1]
        placed[c][at[c]] = place
        at[c] += 1
        if at[c] == len(lists[c]):
            iterators.pop()
        else:
            now[c] = lists[c][at[c]]
        _sort(iterators, now)
    return placed


def _sort(v: list[int], t: list[int]) -> None:
    """libstdc++'s ``std::sort(v)`` with ``comp(a, b) = t[a] > t[b]`` (``ViewIterHelperCompare``)."""
    if len(v) > 1:
        _introsort_loop(v, 0, len(v), 2 * (len(v).bit_length() - 1), t)
        _final_insertion_sort(v, 0, len(v), t)


def _introsort_loop(v: list[int], first: int, last: int, depth: int, t: list[int]) -> None:
    while last - first > _THRESHOLD:
        if depth == 0:
            _heap_sort(v, first, last, t)
            return
        depth -= 1
        cut = _partition_pivot(v, first, last, t)
        _introsort_loop(v, cut, last, depth, t)
        last = cut


def _partition_pivot(v: list[int], first: int, last: int, t: list[int]) -> int:
    mid = first + (last - first) // 2
    a, b, c = first + 1, mid, last - 1
    if t[v[a]] > t[v[b]]:
        median = b if t[v[b]] > t[v[c]] else c if t[v[a]] > t[v[c]] else a
    else:
        median = a if t[v[a]] > t[v[c]] else c if t[v[b]] > t[v[c]] else b
    v[first], v[median] = v[median], v[first]
    pivot = t[v[first]]
    low, high = first + 1, last
    while True:
        while t[v[low]] > pivot:
            low += 1
        high -= 1
        while pivot > t[v[high]]:
            high -= 1
        if not low < high:
            return low
        v[low], v[high] = v[high], v[low]
        low += 1


def _final_insertion_sort(v: list[int], first: int, last: int, t: list[int]) -> None:
    if last - first > _THRESHOLD:
        _insertion_sort(v, first, first + _THRESHOLD, t)
        for i in range(first + _THRESHOLD, last):
            _linear_insert(v, i, t)
    else:
        _insertion_sort(v, first, last, t)


def _insertion_sort(v: list[int], first: int, last: int, t: list[int]) -> None:
    for i in range(first + 1, last):
        if t[v[i]] > t[v[first]]:
            v[first : i + 1] = [v[i], *v[first:i]]
        else:
            _linear_insert(v, i, t)


def _linear_insert(v: list[int], last: int, t: list[int]) -> None:
    value = v[last]
    while t[value] > t[v[last - 1]]:
        v[last] = v[last - 1]
        last -= 1
    v[last] = value


def _heap_sort(v: list[int], first: int, last: int, t: list[int]) -> None:
    """libstdc++'s ``__partial_sort(first, last, last)``: ``make_heap``, then ``sort_heap``."""
    n = last - first
    for parent in range((n - 2) // 2, -1, -1):
        _adjust_heap(v, first, parent, n, v[first + parent], t)
    while last - first > 1:
        last -= 1
        value = v[last]
        v[last] = v[first]
        _adjust_heap(v, first, 0, last - first, value, t)


def _adjust_heap(v: list[int], first: int, hole: int, n: int, value: int, t: list[int]) -> None:
    top, child = hole, hole
    while child < (n - 1) // 2:
        child = 2 * (child + 1)
        if t[v[first + child]] > t[v[first + child - 1]]:
            child -= 1
        v[first + hole] = v[first + child]
        hole = child
    if n % 2 == 0 and child == (n - 2) // 2:
        child = 2 * (child + 1)
        v[first + hole] = v[first + child - 1]
        hole = child - 1
    parent = (hole - 1) // 2
    while hole > top and t[v[first + parent]] > t[value]:
        v[first + hole] = v[first + parent]
        hole = parent
        parent = (hole - 1) // 2
    v[first + hole] = value
