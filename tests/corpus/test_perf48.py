"""What perf48 measured on real recordings: a read with the sensors' headers (wtf's) imports no numpy.ma, where the
bag's transforms share record times with other topics' messages and so are put in ``rosbag play``'s order (its
connections were told apart by ``np.unique``, whose first call imports numpy.ma: ~10 ms of CPU)."""

from __future__ import annotations

from tests.cli.test_start_up import loaded, modules_after
from tests.corpus.recordings import BY_ID, Corpus

#: Unity's sim-time robot: its tf shares record times with its other topics, so the read works out the replay order.
UNITY = "ros1-unity-robot-sim-time-2022-bag"


def test_a_bag_read_in_replay_order_imports_no_numpy_ma(corpus: Corpus) -> None:
    bag = str(corpus(BY_ID[UNITY]))
    modules = modules_after(f"import tftools; tftools.read_recording([{bag!r}], headers=())")
    assert "tftools.sources.bag.ros1.index" in modules
    assert loaded(modules, ("numpy.ma",)) == []
