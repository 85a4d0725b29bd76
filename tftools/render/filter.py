"""``tfx filter`` output: a table a person reads at a glance, or one JSON document for scripts."""

from __future__ import annotations

import dataclasses
from typing import IO, Any

from rich.console import Group, RenderableType
from rich.table import Table
from rich.text import Text

from tftools.analysis.filter.fates import FilterReport, StreamReport, Unchecked, began_late_in_words
from tftools.analysis.filter.namesakes import renamed_in_words
from tftools.analysis.targets import is_odometry, odometry_tf_unpublished
from tftools.core.figures import KEEP, seconds, wait_in_words
from tftools.core.time import NS_PER_S, duration
from tftools.render import jsonl
from tftools.render.escape import printable
from tftools.render.fitted import Fitted, Paragraphs


def renderable(report: FilterReport, header: str = "") -> RenderableType:
    """Per stream: messages, on arrival, later (and how long they waited), never (and why), the edge
    they waited for, and the filter settings that would keep ``KEEP`` of them."""
    if report.unchecked is not None:
        return Group(*([Text(header, style="dim")] if header else []), Text(unchecked_in_words(report.unchecked)))
    cache = f"{seconds(report.cache_time):g} s cache"
    title = f"MessageFilter into {printable(report.target)} ({report.target_reason}), {cache}"
    table = Table(title=Text(title, style="bold"), title_justify="left", show_lines=False)
    for name, justify in (
        ("Topic", "left"), ("Frames", "left"), ("Msgs", "right"), ("On arrival", "right"), ("Later", "right"),
        ("Wait p50 / p99 / max (s)", "right"), ("Never", "right"), ("Why never", "left"), ("Undecided", "left"),
        ("Waited for", "left"), (f"To keep {KEEP:.1%}", "left"),
    ):  # fmt: skip
        table.add_column(name, justify=justify, no_wrap=True)  # type: ignore[arg-type]
    for s in report.streams:
        table.add_row(
            Text(printable(s.topic)),
            Text(printable(", ".join(_named(f) for f in s.frame_ids))),
            str(s.messages),
            str(s.on_arrival),
            Text(str(s.later), style="yellow" if s.later else ""),
            " / ".join(wait_in_words(s.wait[p], s.tick).removesuffix(" s") for p in ("p50", "p99", "max"))
            if s.later
            else "",
            Text(str(s.never), style="bold red" if s.never else ""),
            Text(fates_in_words(s.reasons)),
            Text(fates_in_words(s.undecided), style="dim"),
            Text(printable(_late(s))),
            Text(_advice(s)),
        )
    parts: list[RenderableType] = [Text(header, style="dim")] if header else []
    parts.append(Fitted(table, Paragraphs(Text(title, style="bold"), [_paragraph(s) for s in report.streams])))
    if report.skipped:
        skipped = printable(", ".join(report.skipped))
        parts.append(Text(f"with a header but no frame_id (not tied to tf): {skipped}", style="dim"))
    return Group(*parts)


#: At most this many of a recording's topics are named where none holds sensor data to check.
_TOPICS_NAMED = 12


def unchecked_in_words(unchecked: Unchecked) -> str:
    """Why no topic was checked, the topics there are, and what to do if sensor data was expected: a note,
    not a fault (a recording of tf alone is a recording of tf)."""
    why = "; ".join(unchecked.reasons) or "no topic's messages start with a Header"
    topics = [f"{t} ({kind})" for t, kind in unchecked.topics.items()]
    more = len(topics) - _TOPICS_NAMED
    seen = ", ".join(topics[:_TOPICS_NAMED]) + (f" and {more} more" if more > 0 else "")
    todo = unchecked.hint or (
        "name a topic to check (e.g. tfx filter /scan), or listen longer (--duration)"
        if unchecked.live
        else "record its topics beside /tf and /tf_static, or name a topic to check (e.g. tfx filter /scan -b BAG)"
    )
    return printable(f"No sensor data to check: {why}. Topics: {seen or 'none'}. If you expected sensor data: {todo}.")


def _paragraph(s: StreamReport) -> list[Text]:
    """A stream as words, its clauses apart by semicolons: topic and frames, counts, the wait, why never,
    the edge waited for, the advice. A name is one word: never split."""
    clauses = [f"{s.messages} messages", f"{s.on_arrival} on arrival"]
    if s.later:
        wait = ", ".join(f"{p} {wait_in_words(s.wait[p], s.tick)}" for p in ("p50", "p99", "max"))
        clauses.append(f"{s.later} later, waiting {wait}")
    else:
        clauses.append("0 later")
    clauses.append(f"{s.never} never" + (f": {fates_in_words(s.reasons)}" if s.never else ""))
    if s.undecided:
        clauses.append(f"undecided: {fates_in_words(s.undecided)}")
    words = [Text(printable(s.topic), style="bold"), Text("in"), *(Text(printable(_named(f))) for f in s.frame_ids)]
    words[-1].append(":")
    words += [Text(word) for word in "; ".join(clauses).split(" ")]
    if s.late_edge is not None:
        parent, child = (Text(printable(name)) for name in s.late_edge)
        child.append(":")
        words[-1].append(";")
        words += [
            Text("waited"),
            Text("for"),
            parent,
            Text("->"),
            child,
            *(Text(w) for w in s.wait_made_of().split(" ")),
        ]
        if s.longest_edge is not None:
            parent, child = (Text(printable(name)) for name in s.longest_edge)
            child.append(":")
            words[-1].append(";")
            words += [Text("the"), Text("longest"), Text("for"), parent, Text("->"), child]
            words += [Text(w) for w in s.longest_made_of().split(" ")]
    words[-1].append(";")
    words += [Text(word) for word in f"to keep {KEEP:.1%}: {_advice(s)}".split(" ")]
    return words


def fates_in_words(reasons: dict[str, int]) -> str:
    """Fates and their counts in words: ``unknown frame 143, before recorded tf 26``."""
    return ", ".join(f"{reason.replace('_', ' ')} {n}" for reason, n in reasons.items())


def _late(s: StreamReport) -> str:
    if s.late_edge is None:
        return ""
    longest = ""
    if s.longest_edge is not None:
        longest = f"; the longest for {s.longest_edge[0]} -> {s.longest_edge[1]}: {s.longest_made_of()}"
    return f"{s.late_edge[0]} -> {s.late_edge[1]} ({s.wait_made_of()}{longest})"


#: What keeps the messages no timeout keeps, by why most of them were lost (``Fate.reason``).
_INSTEAD = {
    "unknown_frame": "publish its frame's transform, or fix the frame_id",
    "not_connected": "join its frame's tree to the target's",
    "empty_frame": "set the frame_id",
    "needs_newer_tf": "keep the tf it waits for publishing",
    # older than the cache behind the chain's newest stamp (stamp 0, an old stamp): where no cache keeps them
    "older_than_cache": "stamp each message when it was measured, on the clock tf is stamped on",
    "too_old_on_arrival": "stamp each message when it was measured, on the clock tf is stamped on",
    "before_any_tf": "start tf's publishers before the sensor",
}


def clocks_apart(apart: int) -> str:
    """What keeps messages stamped ``apart`` ns from the tf they wait for: one clock, not a wait."""
    side = "ahead of" if apart > 0 else "behind"
    return (
        f"it is stamped {duration(abs(apart) / NS_PER_S)} {side} tf's clock: sync the machines' clocks "
        "(chrony/NTP) or stamp it with the clock tf is stamped on"
    )


def _advice(s: StreamReport) -> str:
    said = []
    if s.wait_needed is None:
        most = max(s.reasons, key=lambda r: s.reasons[r]) if s.reasons else ""
        instead = _INSTEAD.get(most)
        if most == "unknown_frame" and s.unplaced:  # REP 105's map or odom, a pose in the world: tfx wtf's words
            instead = s.unplaced
        elif most == "unknown_frame" and is_odometry(s.type):  # its frame is its own tf's, not a mount's
            instead = odometry_tf_unpublished(", ".join(repr(f) for f in s.frame_ids), s.children)
        elif most == "unknown_frame" and s.namesakes:  # its mount under another name
            instead = renamed_in_words(s.namesakes)
        if s.clock_apart:  # no wait or cache meets a stamp hours from tf's
            instead = clocks_apart(s.clock_apart)
        if s.stamped_zero >= sum(s.reasons.values()):  # every one lost was stamped 0: said below, once
            instead = None
        said.append("no timeout can" + (f" ({instead})" if instead else ""))
    elif s.wait_needed > 0 or (s.later and s.tick):  # waits under a tick: read as 0, not none
        said.append(f"wait {wait_in_words(s.wait_needed, s.tick)}")
    if s.queue_needed:
        said.append(f"queue {s.queue_needed}")
    if s.cache_needed is not None:
        said.append(f"cache {seconds(s.cache_needed):g} s")
    if s.before_tf and s.before_any_tf:
        said.append(
            f"{s.before_tf} stamped before the first tf anyone published: the sensor started before tf; no cache "
            "keeps them and there is nothing to record earlier"
        )
    elif s.before_tf and s.began_late is not None:
        said.append(f"{s.before_tf} stamped before tf began: {began_late_in_words(s.began_late)}")
    elif s.before_tf:
        said.append(f"{s.before_tf} stamped before tf began: no cache keeps them; record tf from before the sensor")
    if s.stamped_zero:
        said.append(f"{s.stamped_zero} stamped 0 arrived before their tf: no cache keeps them; set header.stamp")
    return ", ".join(said) or "fine as it is"


def as_dict(report: FilterReport) -> dict[str, Any]:
    return {
        "target": report.target or None,  # no tree, no frame (its reason: targets.NO_TREE)
        "target_reason": report.target_reason,
        "cache_s": seconds(report.cache_time),
        "topics": [_stream_dict(s) for s in report.streams],
        "skipped": report.skipped,
        "unchecked": None
        if report.unchecked is None
        else {
            "reasons": report.unchecked.reasons,
            "topics": report.unchecked.topics,
            "note": unchecked_in_words(report.unchecked),
        },
    }


def _stream_dict(s: StreamReport) -> dict[str, Any]:
    """A stream's report, its durations in seconds (tuples become JSON lists)."""
    shown = dataclasses.asdict(s)
    for name in ("wait", "late_by", "late_after", "wait_needed", "cache_needed", "tick", "clock_apart"):
        del shown[name]
    return {
        **{k: shown[k] for k in ("topic", "type", "frame_ids", "messages", "on_arrival", "later", "never")},
        "wait_s": {p: seconds(ns) for p, ns in s.wait.items()},
        "tick_s": seconds(s.tick),
        "reasons": shown["reasons"],
        "late_edge": shown["late_edge"],
        "late_by_s": seconds(s.late_by),
        "late_after_s": seconds(s.late_after),
        "late_rate_hz": s.late_rate_hz,
        "late_rate_all_hz": s.late_rate_all_hz or None,
        "late_unheld": s.late_unheld,
        "longest_edge": shown["longest_edge"],
        "longest_waited": s.longest_waited,
        "longest_unheld": s.longest_unheld,
        "clock_apart_s": seconds(s.clock_apart),
        "wait_needed_s": None if s.wait_needed is None else seconds(s.wait_needed),
        "queue_needed": s.queue_needed,
        "cache_needed_s": None if s.cache_needed is None else seconds(s.cache_needed),
        **{
            k: shown[k]
            for k in (
                "dropped_by_wait",
                "dropped_by_queue",
                "undecided",
                "lost_edge",
                "before_tf",
                "before_any_tf",
                "stamped_zero",
            )
        },
        # the edge whose first transform came after the messages stamped before it, while tf was recorded already
        "began_late": None
        if s.began_late is None
        else {"parent": s.began_late[0], "child": s.began_late[1], "after_s": seconds(s.began_late[2])},
        # its frames no transform names that have a namesake in the tree: its mount under another name, perhaps
        "namesakes": [{"frame_id": f, "tree_frame": m, "parent": p} for f, m, p in s.namesakes],
    }


def write_json(report: FilterReport, out: IO[str]) -> None:
    jsonl.write_document(as_dict(report), out)


def _named(frame: str) -> str:
    """A frame_id as a reader tells it: an empty one said so (foxglove-wizard's drone.mcap: /pose_stamped's
    17 default-made messages), not a blank before a comma."""
    return frame or "(empty)"
