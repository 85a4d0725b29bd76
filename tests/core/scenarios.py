"""Random tf scenarios for the differential tests: trees, histories, troubles, and queries."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from tests.oracle import Row, Scenario, binding_time
from tftools import BatchBuilder, Buffer, Semantics, Transform, TransformError
from tftools.core.batch import take_rows

S = 1_000_000_000

#: What a scenario may contain besides a healthy tree.
FEATURES = (
    "reparent",  # a frame changes parent part way
    "cycle",  # an edge closes a loop
    "disconnected",  # a second tree
    "repeat",  # samples re-sent with a stamp already stored
    "shuffle",  # samples arrive out of stamp order
    "bad",  # NaN, denormalized quaternions, self transforms, empty ids, leading slashes
    "near_unit",  # quaternions a little off unit length, which tf2 accepts
    "static_then_dynamic",  # a frame first sent on /tf_static, later on /tf (and vice versa)
    "cache",  # a finite cache time: old data refused, histories pruned
    "sparse",  # edges with one or two samples only
)


def sec_nsec(ns: int) -> tuple[int, int]:
    return divmod(ns, S)


@dataclass
class Built:
    scenario: Scenario
    frames: list[str]


def random_quat(rng: np.random.Generator, near_unit: bool = False) -> list[float]:
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    if near_unit:
        q *= math.sqrt(1.0 + rng.uniform(-0.009, 0.009))
    values: list[float] = q.tolist()
    return values


def build(seed: int, features: frozenset[str], base_s: int) -> Built:
    """A scenario from ``seed`` with the given ``features``, its stamps near ``base_s`` seconds."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(3, 10))
    frames = [f"f{i}" for i in range(n)]
    parent_of = {i: int(rng.integers(0, i)) for i in range(1, n)}
    if "disconnected" in features and n > 3:
        parent_of.pop(int(rng.integers(2, n)))  # that frame becomes a second root
    static = {i: bool(rng.random() < 0.3) for i in parent_of}
    base = base_s * S + int(rng.integers(0, S))
    rows: list[tuple[int, Row]] = []  # (arrival key, row)

    def add(parent: str, child: str, stamp: int, values: list[float], authority: str, is_static: bool) -> None:
        stamp = binding_time(stamp)
        rows.append(
            (stamp + int(rng.integers(0, 3_000_000)), [parent, child, *sec_nsec(stamp), *values, authority, is_static])
        )

    for child, parent in parent_of.items():
        count = int(rng.integers(1, 3)) if "sparse" in features and rng.random() < 0.5 else int(rng.integers(5, 40))
        if static[child]:
            count = 1
        start = base + int(rng.integers(0, 2 * S))
        period = int(rng.integers(S // 100, S // 5))
        for k in range(count):
            stamp = start + k * period + int(rng.integers(-period // 4, period // 4))
            values = [*rng.uniform(-3, 3, 3).tolist(), *random_quat(rng, "near_unit" in features)]
            add(frames[parent], frames[child], stamp, values, f"/node{child % 3}", static[child])

    if "reparent" in features and n > 3:
        child = int(rng.integers(2, n))
        new_parent = int(rng.integers(0, child))
        start = base + 3 * S
        for k in range(10):
            values = [*rng.uniform(-3, 3, 3).tolist(), *random_quat(rng)]
            add(frames[new_parent], frames[child], start + k * S // 10, values, "/other", False)

    if "cycle" in features and n > 2:
        a = int(rng.integers(1, n))
        for k in range(5):
            values = [*rng.uniform(-1, 1, 3).tolist(), *random_quat(rng)]
            add(frames[a], frames[0], base + k * S // 5, values, "/loop", False)

    if "static_then_dynamic" in features:
        add("g0", "g1", base, [0, 0, 1, 0, 0, 0, 1], "/a", True)
        add("g0", "g1", base + S, [0, 0, 2, 0, 0, 0, 1], "/a", False)
        add("g0", "g2", base, [1, 0, 0, 0, 0, 0, 1], "/b", False)
        add("g0", "g2", base + S, [2, 0, 0, 0, 0, 0, 1], "/b", True)
        add("g0", "g2", base + 2 * S, [3, 0, 0, 0, 0, 0, 1], "/b", False)
        frames += ["g0", "g1", "g2"]

    rows.sort(key=lambda r: r[0])
    inserts = [row for _, row in rows]

    if "repeat" in features:
        for row in rng.choice(len(inserts), size=min(5, len(inserts)), replace=False):
            again = list(inserts[row])
            again[4] += 1.0  # same stamp, other value: tf2 keeps the first
            inserts.insert(int(rng.integers(row, len(inserts) + 1)), again)

    if "shuffle" in features:
        for _ in range(len(inserts) // 4):
            i, j = rng.integers(0, len(inserts), 2)
            inserts[i], inserts[j] = inserts[j], inserts[i]

    if "bad" in features:
        inserts += bad_rows(base, frames, rng)
        rng.shuffle(inserts)

    cache_time_s = int(rng.integers(1, 3)) if "cache" in features else 1_000_000
    scenario = Scenario(inserts=inserts, cache_time_s=cache_time_s)
    scenario.queries = queries(scenario, frames, rng)
    return Built(scenario, frames)


def bad_rows(base: int, frames: list[str], rng: np.random.Generator) -> list[Row]:
    """Samples tf2 refuses, plus frame ids with a leading slash that it strips."""
    f1, f2 = frames[1], frames[2 % len(frames)]
    sn = sec_nsec(binding_time(base + S // 2))
    nan = float("nan")
    return [
        [f1, f2, *sn, nan, 0, 0, 0, 0, 0, 1, "/nan", False],
        [f1, f2, *sn, 0, 0, 0, 0, 0, nan, 1, "/nan", False],
        [f1, f2, *sn, 0, 0, 0, 0, 0, 0, 2, "/denormal", False],
        [f1, f2, *sn, 0, 0, 0, 0, 0, 0, 0, "/zero", False],
        [f1, f1, *sn, 0, 0, 0, 0, 0, 0, 1, "/self", False],
        ["", f1, *sn, 0, 0, 0, 0, 0, 0, 1, "/noparent", False],
        [f1, "", *sn, 0, 0, 0, 0, 0, 0, 1, "/nochild", False],
        ["", "", *sn, 0, 0, 0, 0, 0, 0, 1, "/nothing", False],
        ["/slashed_parent", "/slashed_child", *sn, 1, 2, 3, *random_quat(rng), "/slash", False],
        ["/" + f1, "slashed_child2", *sn, 1, 2, 3, *random_quat(rng), "/slash", False],
    ]


def queries(scenario: Scenario, frames: list[str], rng: np.random.Generator) -> list[Row]:
    stamps = sorted({r[2] * S + r[3] for r in scenario.inserts})
    lo, hi = stamps[0], stamps[-1]
    times = [0, lo, hi, lo - 1, hi + 1, lo + 1, hi - 1, hi + S, max(lo - S, 1)]
    times += [stamps[i] for i in rng.integers(0, len(stamps), 20)]
    times += [s + d for s in stamps[:: max(1, len(stamps) // 10)] for d in (-1, 1)]
    times += rng.integers(lo - S // 10, hi + S // 10, 40).tolist()
    times = [binding_time(int(t)) for t in times if t > 0]
    names = [*frames, "ghost", "slashed_child", "slashed_parent"]
    out: list[Row] = []
    for _ in range(160):
        a, b = rng.choice(names, 2)
        t = int(rng.choice(times))
        out.append(["lookup", str(a), str(b), *sec_nsec(t)])
    for _ in range(40):
        a, b = rng.choice(frames, 2)
        out.append(["can", str(a), str(b), *sec_nsec(int(rng.choice(times)))])
    for _ in range(30):
        a, b, c = rng.choice(frames, 3)
        t1, t2 = rng.choice(times, 2)
        out.append(["lookup_full", str(a), *sec_nsec(int(t1)), str(b), *sec_nsec(int(t2)), str(c)])
    for _ in range(10):
        a, b = rng.choice(frames, 2)
        out.append(["lct", str(a), str(b)])
    out += [
        ["lookup", frames[0], frames[0], 0, 0],
        ["lookup", "ghost", "ghost", 0, 0],
        ["lookup", "", frames[0], 0, 0],
        ["lookup", frames[0], "", 0, 0],
        ["lookup", "/" + frames[0], frames[1], 0, 0],
        ["lookup", frames[0], "/" + frames[1], 0, 0],
        ["can", "", frames[0], 0, 0],
        ["can", "ghost", frames[0], 0, 0],
        ["frames"],
    ]
    return out


# --- our side --------------------------------------------------------------------------------


def load_into_buffer(scenario: Scenario, semantics: Semantics = "ros1", rows_per_insert: int | None = None) -> Buffer:
    """Our buffer, fed the scenario's inserts in order as one batch (the bulk path), or as consecutive
    batches of ``rows_per_insert`` rows."""
    buffer = Buffer(cache_time=scenario.cache_time_s * S, semantics=semantics)
    builder = BatchBuilder()
    for parent, child, sec, nsec, *values, authority, is_static in scenario.inserts:
        builder.add(parent, child, sec * S + nsec, values[:3], values[3:7], static=is_static, authority=authority)
    batch = builder.take()
    rows = rows_per_insert or max(len(batch), 1)
    for start in range(0, len(batch), rows):
        buffer.insert(take_rows(batch, slice(start, start + rows)))
    return buffer


def load_one_by_one(scenario: Scenario, semantics: Semantics = "ros1") -> Buffer:
    """Our buffer, fed one ``set_transform`` at a time (the incremental path)."""
    buffer = Buffer(cache_time=scenario.cache_time_s * S, semantics=semantics)
    for parent, child, sec, nsec, *values, authority, is_static in scenario.inserts:
        transform = Transform(tuple(values[:3]), tuple(values[3:7]), sec * S + nsec, parent, child)
        buffer.set_transform(transform, authority, static=is_static)
    return buffer


def stamped(t: Transform) -> dict[str, Any]:
    return {
        "ok": True,
        "t": list(t.translation),
        "q": list(t.rotation),
        "stamp": list(sec_nsec(t.stamp)),
        "frame_id": t.frame_id,
        "child_frame_id": t.child_frame_id,
    }


def answer(buffer: Buffer, query: Row) -> dict[str, Any]:
    kind, args = query[0], query[1:]
    try:
        if kind == "lookup":
            target, source, sec, nsec = args
            return stamped(buffer.lookup(target, source, sec * S + nsec))
        if kind == "lookup_full":
            target, tsec, tnsec, source, ssec, snsec, fixed = args
            return stamped(buffer.lookup_full(target, tsec * S + tnsec, source, ssec * S + snsec, fixed))
        if kind == "can":
            target, source, sec, nsec = args
            return {"ok": True, "can": buffer.can_transform(target, source, sec * S + nsec)}
        if kind == "can_full":
            target, tsec, tnsec, source, ssec, snsec, fixed = args
            can = buffer.can_transform_full(target, tsec * S + tnsec, source, ssec * S + snsec, fixed)
            return {"ok": True, "can": can}
        if kind == "chain":  # only ever asked with the fixed frame = the target, as Buffer.chain walks
            target, tsec, tnsec, source, _ssec, _snsec, _fixed = args
            return {"ok": True, "chain": buffer.chain(target, source, tsec * S + tnsec)}
        if kind == "lct":
            return {"ok": True, "stamp": list(sec_nsec(buffer.latest_common_time(*args)))}
        if kind == "frames":
            return {"ok": True, "text": buffer.all_frames_as_string()}
        if kind == "yaml":
            return {"ok": True, "text": buffer.all_frames_as_yaml()}
    except TransformError as e:
        return {"ok": False, "error": type(e).__name__, "message": str(e)}
    raise ValueError(kind)
