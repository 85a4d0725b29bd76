"""A read gives one recording however it groups its payloads into parts decoded at once (issue 39): with every
part decoded alone, the e-puck's and the Kobuki's reads (repeated stamps, refused rows) gave the same histories
but refused rows numbered over the reader's table of names, interned in the order the parts were decoded."""

from __future__ import annotations

from typing import Any

import pytest

from tests.corpus.recordings import BY_ID, Corpus
from tftools.core.batch import ROW_COLUMNS
from tftools.sources.recording import Recording as Read
from tftools.sources.recording import read_recording

EPUCK = "ros2-webots-epuck-resends-2025-db3"
KOBUKI = "ros1-gazebo-kobuki-repeated-stamps-2017-bag"
_HISTORY = ("stamps", "values", "parents", "authorities", "record_times", "sequence", "flags")


def _read(read: Read) -> tuple[Any, ...]:
    """Everything of ``read`` a grouping could change, as bytes and names."""
    refused = read.refused
    return (
        [(child, [getattr(h, c).tobytes() for c in _HISTORY]) for child, h in read.buffer.histories()],
        list(refused.frame_names),
        list(refused.authorities),
        [getattr(refused, c).tobytes() for c in ROW_COLUMNS],
        read.refused_sequence.tobytes(),
        [
            (s.topic, list(s.frame_ids), s.frame.tobytes(), s.stamp.tobytes(), s.tf_before.tobytes())
            for s in read.stamped.streams
        ],
    )


@pytest.mark.parametrize("name", [EPUCK, KOBUKI])
def test_every_grouping_of_a_real_read_gives_one_recording(
    corpus: Corpus, monkeypatch: pytest.MonkeyPatch, name: str
) -> None:
    """The e-puck (182 rows refused or taken again: resent samples) and the Kobuki (31 repeated stamps) read with
    their headers, as wtf reads them, by default and with every part decoded alone, on one core and two: the same
    histories, refused rows (their names as they first come: 'odom' then the child) and headers."""
    from tftools.sources.bag import messages

    bag = corpus(BY_ID[name])
    found = [_read(read_recording([bag], headers=()))]
    monkeypatch.setattr(messages, "_ALONE_BYTES", 1)
    for cores in (1, 2):
        monkeypatch.setattr(messages, "_cores", lambda cores=cores: cores)
        found.append(_read(read_recording([bag], headers=())))
    assert found[0] == found[1] == found[2]
    assert found[0][1][0] == "odom" and len(found[0][1]) == 2
