"""The real ``tf2_ros::MessageFilter`` (ROS 1, Debian's libtf2-ros) on bags, as the oracle of ``tfx filter``.

``msgfilter/mf_oracle.cpp`` is compiled once per machine (``msgfilter/build.sh``, 1-6 min) into a cache
outside the repository: ``$TFTOOLS_ORACLE_CACHE``, default ``~/.cache/tftools``, in a folder named after
the source's hash. ``msgfilter/make_designed_bag.py`` writes a bag with one topic per case (its docstring
lists them) with the real rosbag (Debian's /usr/bin/python3).
"""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np

from tests.oracle import ROS_PYTHON
from tftools.analysis.filter.fates import NEVER, Fate, Fates, pushed_out
from tftools.sources.contents import StampedMessages

HERE = Path(__file__).with_name("msgfilter")
SOURCE = HERE / "mf_oracle.cpp"


def cache_dir() -> Path:
    digest = hashlib.sha256(SOURCE.read_bytes()).hexdigest()[:16]
    root = Path(os.environ.get("TFTOOLS_ORACLE_CACHE", Path.home() / ".cache" / "tftools"))
    return root / f"mf_oracle-{digest}"


@cache
def build() -> tuple[Path | None, str]:
    """The oracle's binary, built where it is missing; else None and why it cannot be built here."""
    out = cache_dir()
    binary = out / "mf_oracle"
    if binary.exists():
        return binary, ""
    try:
        done = subprocess.run(["bash", str(HERE / "build.sh"), str(out)], capture_output=True, text=True, timeout=1800)
    except (OSError, subprocess.TimeoutExpired) as e:
        return None, f"the MessageFilter oracle could not be built: {e}"
    if done.returncode == 3:
        return None, f"the MessageFilter oracle cannot be built here: {done.stderr.strip()}"
    if done.returncode != 0 or not binary.exists():
        return None, f"building the MessageFilter oracle failed:\n{done.stderr[-3000:]}"
    return binary, ""


def designed_bag(path: Path, defect: bool = False) -> Path:
    """The bag of designed cases (``defect``: only the two topics that show tf2 0.7's defect)."""
    command = [ROS_PYTHON, str(HERE / "make_designed_bag.py"), str(path), *(["defect"] if defect else [])]
    done = subprocess.run(command, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    return path


@dataclass(frozen=True)
class Verdict:
    """One message as the real filter left it (``mf_oracle``'s output line)."""

    topic: str
    index: int
    stamp: int
    frame: str
    arrival: int
    outcome: str
    decided: int


def run(
    binary: Path, bag: Path, target: str, out: Path, queue: int = 0, cache_s: float = 10.0, topics: Sequence[str] = ()
) -> dict[str, list[Verdict]]:
    """Each header topic's messages, in record order, as the real filter decided them."""
    command = [str(binary), "offline", str(bag), "--target", target, "--queue", str(queue), "--cache", str(cache_s)]
    for topic in topics:
        command += ["--topic", topic]
    done = subprocess.run([*command, "--out", str(out)], capture_output=True, text=True, timeout=3600)
    assert done.returncode == 0, done.stderr[-2000:]
    verdicts: dict[str, list[Verdict]] = {}
    for line in out.read_text().splitlines():
        r = json.loads(line)
        v = Verdict(r["topic"], r["index"], r["stamp"], r["frame"], r["arrival"], r["outcome"], r["decided"])
        verdicts.setdefault(v.topic, []).append(v)
    return verdicts


#: The real filter's outcomes, and the fates of tf2's rule that agree with each. ``drop_spurious`` and
#: ``later_defect`` are tf2 0.7's defect (``msgfilter/repro_tf2_defect.cpp``): tf2's rule passes the
#: first (so tftools says LATER) and drops the second.
AGREE = {
    "on_arrival": {Fate.ON_ARRIVAL},
    "later": {Fate.LATER},
    "drop_out_the_back": {Fate.TOO_OLD_ON_ARRIVAL},
    "drop_waiting": {Fate.OLDER_THAN_CACHE, Fate.BEFORE_RECORDED_TF, Fate.BEFORE_ANY_TF},
    "drop_empty_frame": {Fate.EMPTY_FRAME},
    "pending_unknown_frame": {Fate.UNKNOWN_FRAME},
    "pending_not_connected": {Fate.NOT_CONNECTED},
    "pending_future": {Fate.NEEDS_NEWER_TF, Fate.AFTER_RECORDED_TF},
    "pending_past": {Fate.OLDER_THAN_CACHE, Fate.BEFORE_RECORDED_TF, Fate.BEFORE_ANY_TF},
    "drop_spurious": {Fate.LATER},
    "later_defect": {Fate.OLDER_THAN_CACHE, Fate.BEFORE_RECORDED_TF, Fate.BEFORE_ANY_TF},
}
DEFECT = ("drop_spurious", "later_defect")
PASSED = ("on_arrival", "later")


@dataclass
class Agreement:
    """How many messages of a topic agree with the real filter, and the first few that do not."""

    topic: str
    messages: int
    agree: int
    defect: int  # of ``agree``: where the real filter's defect decided and tf2's rule is followed
    disagree: list[str]

    @property
    def ok(self) -> bool:
        return not self.disagree


def compare(verdicts: Sequence[Verdict], stream: StampedMessages, fates: Fates, queue: int = 0) -> Agreement:
    """Per message: the fate (a message the real filter passed, when: the wait to the nanosecond; one it
    dropped while waiting, when), with ``queue`` (0: unlimited) applied to ``fates`` as the filter does."""
    assert len(verdicts) == len(stream), (stream.topic, len(verdicts), len(stream))
    out = pushed_out(fates, stream, queue) if queue else np.zeros(len(stream), bool)
    agree, defect = 0, 0
    wrong: list[str] = []
    for i, v in enumerate(verdicts):
        fate = Fate(int(fates.fate[i]))
        assert v.arrival == int(stream.record_time[i]) and v.stamp == int(stream.stamp[i]), (stream.topic, i)
        if out[i]:
            good = v.outcome == "drop_queue"
        elif v.outcome not in AGREE or fate not in AGREE[v.outcome]:
            good = False
        elif v.outcome in PASSED:
            good = int(fates.ready[i]) == v.decided
        elif v.outcome == "drop_waiting":
            good = int(fates.left[i]) == v.decided
        elif v.outcome.startswith("pending"):
            good = int(fates.left[i]) == NEVER
        else:
            good = True
        agree += good
        defect += good and v.outcome in DEFECT
        if not good and len(wrong) < 5:
            wrong.append(
                f"{v.topic}[{i}] frame {v.frame!r} stamp {v.stamp} arrival {v.arrival}: real filter {v.outcome} at "
                f"{v.decided}; tftools {fate.name} ready {int(fates.ready[i])} left {int(fates.left[i])}"
                + (" pushed out" if out[i] else "")
            )
    return Agreement(stream.topic, len(verdicts), agree, defect, wrong)
