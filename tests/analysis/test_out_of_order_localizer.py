"""One localizer sending map -> odom out of order, in bursts, where the recording names no publisher: a real cart's
amcl (tests/corpus/test_corpus43b.py) waiting for odometry that came at 0.9 Hz, then sending one map -> odom per
queued scan at once, in no order, each stamped its scan's stamp plus its transform_tolerance."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import yaml

from tests.analysis import wtf_scenes as scenes
from tests.bags import BagFormat, TfMessage
from tftools.analysis.findings import Finding, Severity
from tftools.analysis.wtf.fleet import check
from tftools.sources.recording import read_recording

MS = scenes.MS
START = scenes.START
ODOMETRY = 800 * MS  # the odometry interval (the cart's: 1.11 s; here a burst spans less than a jump back in time)
TOLERANCE = 1500 * MS  # amcl's transform_tolerance: map -> odom stamped this long after its scan
#: The scans' stamps: every fifth missing (0.13, 0.13, 0.13 then 0.26 s apart), every tenth time the fourth
CYCLE = ([130 * MS] * 3 + [260 * MS]) * 9 + [130 * MS] * 2 + [260 * MS]
SCANS = np.cumsum(CYCLE * 8)


def _listed_bag(tmp_path: Path, messages: list[TfMessage], publishers: int) -> Path:
    """A rosbag2 recording whose metadata.yaml lists ``publishers`` publishers of /tf (one QoS profile each)."""
    bag = scenes.write(tmp_path, "bag", BagFormat.rosbag2_sqlite3, sorted(messages, key=lambda m: m.record_time))
    metadata = bag / "metadata.yaml"
    document = yaml.safe_load(metadata.read_text())
    for entry in document["rosbag2_bagfile_information"]["topics_with_message_count"]:
        if entry["topic_metadata"]["name"] == "/tf":
            profile = {"history": "keep_last", "depth": 100, "reliability": "reliable", "durability": "volatile"}
            entry["topic_metadata"]["offered_qos_profiles"] = [dict(profile) for _ in range(publishers)]
    metadata.write_text(yaml.safe_dump(document))
    return bag


def _cart() -> list[TfMessage]:
    """Odometry every 0.8 s; after each sample, amcl sends map -> odom for every scan stamped before it, in a
    shuffled order, its estimate stepping 0.05 m and 2 degrees at every third odometry sample, part-way through."""
    rng = np.random.default_rng(43)
    messages, sent, estimate = [], 0, 0
    for k in range(1, 60):
        came = START + k * ODOMETRY
        messages.append(TfMessage("/tf", came + scenes.DELAY, scenes.odom_base(came), ""))
        queued = [int(s) for s in SCANS[sent:] if START + s <= came]
        sent += len(queued)
        sending = came + np.cumsum(rng.uniform(0.5 * MS, 3 * MS, len(queued))).astype(np.int64)  # one after another
        for i, (scan, sent_at) in enumerate(zip(rng.permutation(queued), sending, strict=True)):
            if k % 3 == 0 and i == len(queued) // 2:
                estimate += 1
            stamp = START + int(scan) + TOLERANCE
            correction = scenes._t("map", "odom", stamp, 1.0 + 0.05 * estimate, 0.035 * estimate)
            messages.append(TfMessage("/tf", int(sent_at), [correction], ""))
    return messages


def _findings(tmp_path: Path, messages: list[TfMessage], publishers: int) -> list[Finding]:
    return check(read_recording([_listed_bag(tmp_path, messages, publishers)])).findings


def test_one_localizer_sending_queued_scans_out_of_order_is_out_of_order_not_several_publishers(tmp_path: Path) -> None:
    """Stamps falling five and six times in a row in one burst: two publishers each sending in order fall at most
    twice in a row, so this is one publisher out of order (``time_backwards``), though metadata.yaml lists two
    publishers of /tf (the odometry's and amcl's); nor is its rate irregular: its stamps follow the scans' cycle."""
    findings = _findings(tmp_path, _cart(), publishers=2)
    assert not [f for f in findings if f.code in ("multiple_authorities", "rate")], findings
    (backwards,) = [f for f in findings if f.code == "time_backwards"]
    assert backwards.severity is Severity.warning and backwards.frames == ("map", "odom")
    assert "arrived out of order" in backwards.message
    assert "carry another value than the one already stamped after them" in backwards.message, backwards.message
    assert "go from the newer value back to the older" in backwards.message
    assert "inputs it queued in no order" in backwards.hint and "lookups cope" not in backwards.hint


def test_an_unchanging_estimate_sent_out_of_order_says_lookups_cope(tmp_path: Path) -> None:
    """The same bursts with an estimate that never changes: tf2 sorts them and every lookup answers the same."""
    still = [
        TfMessage(m.topic, m.record_time, [scenes._t("map", "odom", t.stamp, 1.0)], "")
        if m.transforms[0].child_frame_id == "odom"
        else m
        for m in _cart()
        for t in m.transforms[:1]
    ]
    (backwards,) = [f for f in _findings(tmp_path, still, publishers=2) if f.code == "time_backwards"]
    assert "carry another value" not in backwards.message
    assert backwards.hint.startswith("tf2 sorts them into its cache, so lookups cope")


def test_two_publishers_taking_turns_are_still_told_where_one_of_them_is_not_listed(tmp_path: Path) -> None:
    """Two odometries of the same values taking turns, each in order, the second's arriving 35 ms after its stamp:
    stamps going back and forth, but falling at most twice in a row, where metadata.yaml lists one publisher of /tf
    (the second started after recording began): still two publishers taking turns."""
    first = scenes.periodic("", 50, scenes.odom_base)
    second = scenes.periodic("", 50, scenes.odom_base, phase=0.01, delay=35 * MS)
    (turns,) = [f for f in _findings(tmp_path, first + second, publishers=1) if f.code == "multiple_authorities"]
    assert "its stamps went back" in turns.message and "taking turns" in turns.message, turns.message
