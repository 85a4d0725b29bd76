"""``tfx filter`` against the real ``tf2_ros::MessageFilter`` (ROS 1's, built from Debian's packages by
tests/oracle/message_filter.py), message by message: on the designed bag (one topic per case) and on the
corpus' ROS 1 recordings with header topics. Where tf2 0.7's ``testTransformableRequests`` defect decides
(msgfilter/repro_tf2_defect.cpp), tftools follows tf2's own rule and the comparison says so."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.corpus.fetch import Recording, shared_dir
from tests.corpus.recordings import RECORDINGS, Corpus
from tests.oracle import message_filter as mf
from tests.oracle import unavailable_reason
from tftools.analysis.filter import FilterQuery, filter_streams
from tftools.analysis.filter.fates import Fate, message_fates, recording_end
from tftools.core.figures import KEEP
from tftools.core.time import NS_PER_S
from tftools.sources.errors import NoTransformsError
from tftools.sources.recording import read_recording


def _unusable(reason: str) -> None:
    if os.environ.get("CI") == "true":
        pytest.fail(f"CI must compare with the real MessageFilter, but {reason}")
    pytest.skip(reason)


@pytest.fixture(scope="session")
def oracle() -> Path:
    """The real MessageFilter's binary: built once per machine, skipped (failed in CI) where it cannot be."""
    reason = unavailable_reason()
    if reason is not None:
        _unusable(reason)
    binary, why = mf.build()
    if binary is None:
        _unusable(why)
    assert binary is not None
    return binary


@pytest.fixture(scope="session")
def designed(tmp_path_factory: pytest.TempPathFactory, oracle: Path) -> Path:
    return mf.designed_bag(tmp_path_factory.mktemp("designed") / "designed.bag")


def agreement(
    oracle: Path, bag: Path, target: str, out: Path, queue: int = 0, cache_s: float = 10.0
) -> list[mf.Agreement]:
    """Per header topic of ``bag``: how ``tfx filter``'s replay agrees with the real filter's."""
    verdicts = mf.run(oracle, bag, target, out, queue, cache_s)
    recording = read_recording([bag], headers=sorted(verdicts))  # one read, as tfx filter's
    buffer = recording.buffer
    streams = {s.topic: s for s in recording.stamped.streams}
    end = recording_end(buffer, list(streams.values()))
    found = []
    for topic, theirs in sorted(verdicts.items()):
        fates = message_fates(buffer, streams[topic], target, round(cache_s * NS_PER_S), end)
        found.append(mf.compare(theirs, streams[topic], fates, queue))
    return found


def _said(found: list[mf.Agreement]) -> str:
    messages, agree = sum(a.messages for a in found), sum(a.agree for a in found)
    lines = [f"{agree} of {messages} messages, {sum(a.ok for a in found)} of {len(found)} topics agree"]
    lines += [line for a in found for line in a.disagree]
    return "\n".join(lines)


@pytest.mark.parametrize(("queue", "cache_s"), [(0, 10.0), (5, 10.0), (0, 2.0)])
def test_every_message_of_the_designed_bag_meets_the_real_filters_fate(
    oracle: Path, designed: Path, tmp_path: Path, queue: int, cache_s: float
) -> None:
    found = agreement(oracle, designed, "odom", tmp_path / "out.jsonl", queue, cache_s)
    assert len(found) == 19 and all(a.ok for a in found), _said(found)
    print(_said(found), file=sys.stderr)


def test_where_tf2_0_7_drops_a_ready_message_tftools_follows_tf2s_rule(oracle: Path, tmp_path: Path) -> None:
    """The designed bag's 'defect' cut: three /scan_early messages go out the back in the setTransform that
    makes a /scan_early_peer message transformable, and tf2 0.7 drops that one too."""
    bag = mf.designed_bag(tmp_path / "defect.bag", defect=True)
    verdicts = mf.run(oracle, bag, "odom", tmp_path / "out.jsonl")
    spurious = [v for v in verdicts["/scan_early_peer"] if v.outcome == "drop_spurious"]
    assert len(spurious) == 1
    found = agreement(oracle, bag, "odom", tmp_path / "again.jsonl")
    assert all(a.ok for a in found) and sum(a.defect for a in found) == 1, _said(found)


def test_tfx_filter_counts_each_topic_as_the_real_filter(oracle: Path, designed: Path, tmp_path: Path) -> None:
    """The command's figures per topic: passed (on arrival, later), lost, undecided."""
    verdicts = mf.run(oracle, designed, "odom", tmp_path / "out.jsonl")
    done = subprocess.run(
        [sys.executable, "-m", "tftools", "filter", "-b", str(designed), "--target", "odom", "-f", "json"],
        capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert done.returncode == 1, done.stderr  # messages are lost
    topics = {t["topic"]: t for t in json.loads(done.stdout)["topics"]}
    assert json.loads(done.stdout)["skipped"] == ["/scan_noframe"]  # every frame_id empty: not tf's
    for topic, theirs in verdicts.items():
        if topic == "/scan_noframe":
            continue
        ours = topics[topic]
        outcomes = [v.outcome for v in theirs]
        assert ours["on_arrival"] == outcomes.count("on_arrival"), topic
        assert ours["later"] == outcomes.count("later") + outcomes.count("drop_spurious"), topic
        undecided = sum(ours["undecided"].values())
        assert ours["never"] + undecided + ours["later"] + ours["on_arrival"] == len(theirs), topic
        assert sum(ours["reasons"].values()) == ours["never"], topic


def test_each_fault_of_issue_29_is_the_real_filters_answer(oracle: Path, designed: Path, tmp_path: Path) -> None:
    """The designed topics behind tests/analysis/test_filter_faults.py's reproducers, by the real filter."""
    verdicts = mf.run(oracle, designed, "odom", tmp_path / "out.jsonl")

    def outcomes(topic: str) -> set[str]:
        return {v.outcome for v in verdicts[topic]}

    assert outcomes("/cloud_old") == outcomes("/cloud_old_early") == {"drop_out_the_back"}  # A
    dead = [v.outcome for v in verdicts["/scan_dead"] if v.stamp >= 1_700_000_010 * NS_PER_S]
    assert set(dead) == {"pending_future"}  # B: and tftools calls them lost, the edge having stopped
    # F: a stamp-0 message never passes after a wait by tf2's rule; tf2 0.7 passes those waiting for the
    # static transform that makes their frame known only by its defect (a dangling TransformAvailable).
    assert outcomes("/scan_zero_late") == {"on_arrival", "later_defect"}
    recording = read_recording([designed], headers=())
    report = filter_streams(recording.buffer, recording.stamped.streams, FilterQuery(target="odom"))
    streams = {s.topic: s for s in report.streams}
    assert streams["/scan_dead"].reasons == {Fate.NEEDS_NEWER_TF.reason: len(dead)}
    assert streams["/cloud_old"].reasons == {Fate.TOO_OLD_ON_ARRIVAL.reason: len(verdicts["/cloud_old"])}
    defect = sum(v.outcome == "later_defect" for v in verdicts["/scan_zero_late"])
    assert streams["/scan_zero_late"].reasons == {Fate.OLDER_THAN_CACHE.reason: defect}
    assert streams["/tool_points"].later == 300  # C: the first half waits for base_link, its parent then
    multi = streams["/scan_multi"]  # D: under the suggested queue, the real filter keeps every laser scan
    queued = mf.run(oracle, designed, "odom", tmp_path / "q.jsonl", queue=multi.queue_needed, topics=["/scan_multi"])
    kept = [v for v in queued["/scan_multi"] if v.frame == "laser" and v.outcome in mf.PASSED]
    assert len(kept) == multi.later
    fewer = mf.run(oracle, designed, "odom", tmp_path / "f.jsonl", queue=multi.queue_needed - 1, topics=["/scan_multi"])
    assert sum(v.outcome == "drop_queue" and v.frame == "laser" for v in fewer["/scan_multi"]) > 0


def _real_bags() -> list[pytest.param]:  # type: ignore[valid-type]  # its type, ParameterSet, is private
    """The corpus' ROS 1 recordings: the manifest's, and any other .bag placed in the shared corpus folder."""
    manifest = [r for r in RECORDINGS if r.open.endswith(".bag")]
    named = {r.open.rsplit("/", 1)[-1] for r in manifest}
    params = [pytest.param(r, id=r.id, marks=_marks(r.id)) for r in manifest]
    for path in sorted((shared_dir() / "corpus").glob("*.bag")):
        if path.name not in named:
            params.append(pytest.param(path, id=path.stem, marks=_marks(path.stem)))
    return params


def _marks(name: str) -> list[pytest.MarkDecorator]:
    heavy = [pytest.mark.slow] if name in HEAVY else []
    why = DISAGREE.get(name)
    return heavy + (
        [pytest.mark.xfail(reason=f"tfx filter disagrees with the real filter: {why}", strict=True)] if why else []
    )


#: Recordings where tfx filter and the real filter still disagree, and why: a strict expected failure, which
#: fails the run once they agree (and the entry goes).
DISAGREE: dict[str, str] = {}


#: Corpus recordings whose comparison takes more than a few seconds here.
HEAVY = (
    "uwb-robotino-2017-11-17-12-31-28-bag",
    "uwb-robotino-2018-02-08-14-10-05-bag",
    "uwb-slam-Record_2017-11-17-12-31-28",
    "uwb-slam-Record_2018-02-08-14-10-05",
    "ros1_car_path_follower",
)


@pytest.mark.parametrize("recording", _real_bags())
def test_every_message_of_a_real_recording_meets_the_real_filters_fate(
    oracle: Path, corpus: Corpus, recording: Recording | Path, tmp_path: Path
) -> None:
    bag = recording if isinstance(recording, Path) else corpus(recording)
    try:
        target = filter_streams(read_recording([bag]).buffer, [], FilterQuery()).target
    except NoTransformsError:
        pytest.skip(f"{bag.name} holds no tf: tfx filter refuses it (exit 2), there is no fate to compare")
    if not target:
        pytest.skip(f"{bag.name} has no tf to transform into")
    found = agreement(oracle, bag, target, tmp_path / "out.jsonl")
    if not found:
        pytest.skip(f"{bag.name} has no topic whose messages start with a Header")
    assert all(a.ok for a in found), _said(found)
    print(f"{bag.name}: {_said(found)}", file=sys.stderr)
    # Into the last frame tf2 met (a sensor's, mostly), with a short cache and a short queue.
    other = read_recording([bag]).buffer.frames[-1]
    found = agreement(oracle, bag, other, tmp_path / "other.jsonl", queue=3, cache_s=1.0)
    assert all(a.ok for a in found), f"into {other}, cache 1 s, queue 3: {_said(found)}"


def test_the_real_filter_keeps_what_each_suggested_setting_says(oracle: Path, designed: Path, tmp_path: Path) -> None:
    """Issue 29: a suggestion is one under which the real filter keeps what it says. The queue: every message
    that passes with an unlimited queue passes with it. The cache: no more than 0.1% of the messages the
    recording decides are lost to their age with it."""
    recording = read_recording([designed], headers=())
    report = filter_streams(recording.buffer, recording.stamped.streams, FilterQuery(target="odom"))
    for s in report.streams:
        if s.queue_needed:
            run = mf.run(oracle, designed, "odom", tmp_path / "q.jsonl", queue=s.queue_needed, topics=[s.topic])
            outcomes = [v.outcome for v in run[s.topic]]
            assert outcomes.count("later") + outcomes.count("drop_spurious") == s.later, s.topic
        early = report.fates[s.topic].early()  # stamped before their chain's tf began: no cache is claimed to keep
        if s.cache_needed is not None:
            run = mf.run(
                oracle, designed, "odom", tmp_path / "c.jsonl", cache_s=s.cache_needed / NS_PER_S, topics=[s.topic]
            )
            aged = [v.outcome in ("drop_out_the_back", "drop_waiting", "pending_past") for v in run[s.topic]]
            decided = s.messages - sum(s.undecided.values())
            assert sum(a and not e for a, e in zip(aged, early, strict=True)) <= (1 - KEEP) * decided, s.topic
        if s.before_tf:  # issue 39: what no cache keeps, the real filter drops with a long one
            run = mf.run(oracle, designed, "odom", tmp_path / "e.jsonl", cache_s=60.0, topics=[s.topic])
            passed = [v.outcome in mf.PASSED for v, e in zip(run[s.topic], early, strict=True) if e]
            assert len(passed) >= s.before_tf and not any(passed), s.topic
