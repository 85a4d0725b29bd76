"""The commands other than ``wtf`` and ``monitor`` on the corpus, judged by each recording's bytes (read here
with rosbags, ``tests/corpus/data.py``) and its manifest entry: where the report places findings, what
``tfx diff`` says of two recordings of one robot, and what ``tfx filter`` says of recordings without sensor data
tied to tf."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus import data
from tests.corpus.fetch import Recording, load_manifest
from tftools.core.time import NS_PER_S

_, RECORDINGS = load_manifest()
WITH_TF = [r for r in RECORDINGS if r.meta["frames"]]
BY_ID = {r.id: r for r in RECORDINGS}

Corpus = Callable[[Recording], Path]


def _span(contents: data.Contents) -> tuple[int, int]:
    """The times a finding may be at: the moving edges' stamps and the record times (ns). A static's stamp is
    not one: robot_state_publisher stamps its statics when it starts, hours before a recording may begin."""
    times = [contents.first_record, contents.last_record]
    times += [t for samples in contents.dynamic.values() for t in (min(samples.stamps), max(samples.stamps))]
    return min(times), max(times)


@pytest.mark.parametrize("recording", WITH_TF, ids=[r.id for r in WITH_TF])
def test_findings_are_placed_inside_the_recording(recording: Recording, corpus: Corpus, tfx: Tfx) -> None:  # noqa: F811
    """Each finding's time (where the report's timelines zoom when it is clicked, and wtf's JSON ``first_time``)
    lies within the recording's stamps or record times: a real Create 3's 21 ``urdf_moved`` were placed 4.1 h
    before the recording, at their /tf_static message's stamp."""
    path = corpus(recording)
    result = tfx("wtf", path, "--format", "json")
    assert result.code in (0, 1), result.stderr
    low, high = _span(data.read_contents(path))
    for finding in json.loads(result.stdout)["bags"][0]["findings"]:
        for key in ("first_time", "last_time"):
            when = finding.get(key)
            if when:
                assert low - NS_PER_S <= when * NS_PER_S <= high + NS_PER_S, (finding["code"], key, when, low, high)
