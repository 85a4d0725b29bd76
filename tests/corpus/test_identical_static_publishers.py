"""Several static_transform_publisher processes left running, sending one static with the same values, each
stamped at its own start, on the real recordings that show it: told apart by their stamps (sent before the
recording began, or more of them than metadata.yaml lists heard), counted in one note, never a conflict."""

from __future__ import annotations

import json

import pytest

from tests.cli.conftest import Tfx, tfx  # noqa: F401 (the fixture)
from tests.corpus.recordings import BY_ID, Corpus

#: (recording, how many publishers, the edge, what told them apart)
SAME = [
    ("ros2-ias0220-imu-device-seven-static-publishers-2025-db3", 7, "map -> imu_link", "metadata.yaml lists 7"),
    ("ros2-ias0220-imu-device-five-static-publishers-2025-db3", 5, "world -> imu_link", "before the recording began"),
]


@pytest.mark.parametrize(("recording_id", "publishers", "edge", "evidence"), SAME, ids=[s[0] for s in SAME])
def test_identical_static_publishers_are_counted_in_one_note(
    recording_id: str,
    publishers: int,
    edge: str,
    evidence: str,
    corpus: Corpus,
    tfx: Tfx,  # noqa: F811
) -> None:
    result = tfx("wtf", corpus(BY_ID[recording_id]), "--format", "json")
    assert result.code == 0, result.stdout
    (bag,) = json.loads(result.stdout)["bags"]
    (same,) = [f for f in bag["findings"] if f["code"] == "multiple_authorities"]
    assert same["severity"] == "info"
    assert same["message"].startswith(f"{publishers} /tf_static publishers (unnamed) all send 1 static transform")
    assert f"with the same values: {edge}" in same["message"] and evidence in same["message"]
