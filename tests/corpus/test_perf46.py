"""What perf46 measured on real recordings: a read that imports no numpy.ma (``np.unique``'s first call imports it,
~9 ms of a fresh process's first load), on the recordings whose read did."""

from __future__ import annotations

from tests.cli.test_start_up import loaded, modules_after
from tests.corpus.recordings import BY_ID, Corpus

#: Its samples share record times enough that the read looks for a grid of them (``record_grid``), which has none.
WATERCAN = "ros1-jsk-jaxon-humanoid-hrpsys-multisense-two-publishers-of-the-force-sensors-2018-bag"
#: 182 samples the ROS 2 buffer took for identical ones it holds: kept aside, by their arrival numbers.
RESENDS = "ros2-webots-epuck-resends-2025-db3"


def test_a_bag_whose_record_times_are_looked_at_for_a_grid_imports_no_numpy_ma(corpus: Corpus) -> None:
    check = (
        "from tftools.sources.timeline import SHARED_TICKS, shared_ticks; "
        "assert shared_ticks([h for _, h in r.buffer.histories()]) >= SHARED_TICKS"
    )
    modules = modules_after(f"import tftools; r = tftools.read_recording([{str(corpus(BY_ID[WATERCAN]))!r}]); {check}")
    assert loaded(modules, ("numpy.ma",)) == []


def test_a_db3_with_samples_set_aside_imports_no_numpy_ma(corpus: Corpus) -> None:
    read = f"r = tftools.read_recording([{str(corpus(BY_ID[RESENDS]))!r}])"
    modules = modules_after(f"import tftools; {read}; assert len(r.refused) == 182, len(r.refused)")
    assert loaded(modules, ("numpy.ma",)) == []
