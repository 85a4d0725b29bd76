"""ROS 2 mode against ROS 2's tf2 itself: its ``BufferCore`` built from ros2/geometry2's sources
(``tests/oracle/ros2_tf2``), fed the same random episodes, every answer compared bit for bit:
lookups (translation, rotation, stamp), their errors' classes and texts, ``canTransform``,
lookups with a fixed frame, the refusal logs and ``allFramesAsYAML``. Skipped without the sources."""

from __future__ import annotations

import math
import random

import pytest

from tests.corpus.fetch import Recording, load_manifest, member_path, missing_members, root_of
from tests.oracle import ros2_core, run_ros2_core
from tftools.core import Buffer, Transform, TransformError
from tftools.sources import read_recording

S = 1_000_000_000
AUTHORITY = "Authority_undetectable"  # one word for the driver; what ROS 2's listener passes
EPISODES = 150

Op = tuple  # (kind, ...): set, lookup, can, full or yaml, as episode() makes them


@pytest.fixture(scope="module", autouse=True)
def _core() -> None:
    program = ros2_core()
    if isinstance(program, str):
        pytest.skip(program)


def _rotation(rng: random.Random) -> tuple[float, ...]:
    kind = rng.random()
    if kind < 0.05:
        return (0.0, 0.0, 0.0, 0.0)
    if kind < 0.08:
        return (math.nan, 0.0, 0.0, 1.0)
    if kind < 0.10:
        return (math.inf, 0.0, 0.0, 1.0)
    if kind < 0.15:
        return (0.0, 0.0, 0.0, rng.choice([2.0, -1.0, 1.004, -0.996, 0.5]))
    if kind < 0.25:
        return rng.choice([(0.0, 0.0, 1.0, 0.0), (1.0, 0.0, 0.0, 0.0), (0.0, -1.0, 0.0, 0.0), (0.0, 0.0, 0.0, -1.0)])
    v = [rng.gauss(0, 1) for _ in range(4)]
    n = math.sqrt(sum(x * x for x in v)) / (1 + rng.choice([0, 0, 0, 1e-3, -2e-3]))
    return tuple(x / n for x in v)


def episode(rng: random.Random) -> list[Op]:
    """Samples on a small tree (re-parented now and then, repeated or negated at one stamp, some
    static, some invalid), then lookups (slashed and unknown names too), canTransforms and a YAML."""
    frames, parents = ["a", "b", "c", "d", "e"], {"b": "a", "c": "b", "d": "a", "e": "d"}
    base = rng.choice([0, 1_700_000_000 * S])
    ops: list[Op] = []
    for _ in range(rng.randint(3, 40)):
        child = rng.choice(list(parents))
        parent = parents[child] if rng.random() < 0.95 else rng.choice([f for f in frames if f != child])
        stamp = base + rng.randint(1, 30) * S // 10 + rng.choice([0, 0, 1, 7, 123456789])
        translation, rotation = tuple(rng.uniform(-5, 5) for _ in range(3)), _rotation(rng)
        static = rng.random() < 0.05
        ops.append(("set", parent, child, stamp, translation, rotation, static))
        if rng.random() < 0.15:  # the same again, or negated
            sign = rng.choice([1.0, -1.0])
            ops.append(("set", parent, child, stamp, translation, tuple(sign * x for x in rotation), static))
    for _ in range(30):
        target, source = rng.choice([*frames, "/b", "x"]), rng.choice([*frames, "/c"])
        time = rng.choice([0, base + rng.randint(0, 35) * S // 10 + rng.choice([0, 3, 555])])
        ops.append((rng.choice(["lookup", "lookup", "can"]), target, source, time))
    for _ in range(5):
        times = [base + rng.randint(0, 35) * S // 10 for _ in range(2)]
        ops.append(("full", rng.choice(frames), times[0], rng.choice(frames), times[1], rng.choice(frames)))
    ops.append(("yaml",))
    return ops


def _found(found: Transform) -> str:
    return f"T {found.stamp} " + " ".join(repr(x) for x in (*found.translation, *found.rotation))


def ours(ops: list[Op]) -> tuple[list[str], list[str]]:
    """tftools' answers (one per op) and refusal logs."""
    buffer = Buffer(cache_time=10 * S, semantics="ros2")
    answers: list[str] = []
    for op in ops:
        if op[0] == "set":
            _, parent, child, stamp, translation, rotation, static = op
            answers.append(str(int(buffer.set_transform(Transform(translation, rotation, stamp, parent, child),
                                                        AUTHORITY, static))))  # fmt: skip
        elif op[0] in ("lookup", "full"):
            try:
                found = buffer.lookup(*op[1:]) if op[0] == "lookup" else buffer.lookup_full(*op[1:])
                answers.append(_found(found))
            except TransformError as e:
                answers.append(f"E {type(e).__name__} {e}".replace("\n", "\\n") if op[0] == "lookup" else "E")
        elif op[0] == "can":
            answers.append(str(int(buffer.can_transform(*op[1:]))))
        else:
            answers.append(buffer.all_frames_as_yaml().replace("Authority undetectable", AUTHORITY).rstrip("\n"))
    return answers, [r.message.split("\n")[0] for r in buffer.rejections]


def theirs(ops: list[Op]) -> tuple[list[str], list[str]]:
    """ROS 2's tf2's answers (one per op) and refusal logs."""

    def number(x: float) -> str:
        return "nan" if math.isnan(x) else repr(x)

    lines = ["new 10000000000"]
    for op in ops:
        if op[0] == "set":
            _, parent, child, stamp, translation, rotation, static = op
            values = " ".join(map(number, (*translation, *rotation)))
            lines.append(f"set {parent} {child} {stamp} {values} {int(static)} {AUTHORITY}")
        else:
            lines.append(" ".join(map(str, op)))
    out, log = run_ros2_core(lines)
    answers, at = [], 1  # after "new"'s ok
    for op in ops:
        line = out[at]
        at += 1
        if op[0] == "yaml":
            size = int(line)
            line = "\n".join(out[at:])[:size].rstrip("\n")
        elif line.startswith("T "):
            stamp, *values = line.split()[1:]
            line = f"T {stamp} " + " ".join(repr(float.fromhex(v)) for v in values)
        elif line.startswith("E ") and op[0] == "full":
            line = "E"
        answers.append(line)
    logs = [line for line in log.splitlines() if line.startswith("TF_")]
    return answers, logs


#: tftools' error classes as the driver names tf2's.
NAMES = {"ForwardExtrapolationError": "Forward", "BackwardExtrapolationError": "Backward",
         "NoDataForExtrapolationError": "NoData", "ConnectivityError": "Connectivity", "UnknownFrameError": "Lookup",
         "InvalidArgumentError": "InvalidArgument", "ExtrapolationError": "Extrapolation"}  # fmt: skip


def _renamed(line: str) -> str:
    if not line.startswith("E ") or line == "E":
        return line
    _, name, text = line.split(" ", 2)
    return f"E {NAMES[name]} {text}"


def test_random_episodes_bit_for_bit() -> None:
    rng = random.Random(29)
    answers = 0
    for _ in range(EPISODES):
        ops = [op for op in episode(rng) if not (op[0] == "set" and math.isinf(op[4][0]))]  # refused on purpose
        (mine, my_logs), (real, real_logs) = ours(ops), theirs(ops)
        mine = [_renamed(line) for line in mine]
        for op, a, b in zip(ops, mine, real, strict=True):
            assert a == b, op
        assert my_logs == real_logs
        answers += len(ops)
    assert answers > 5000


_, RECORDINGS = load_manifest()


@pytest.mark.parametrize("recording", [r for r in RECORDINGS if r.meta["frames"]], ids=lambda r: r.id)
def test_corpus_recordings_bit_for_bit(recording: Recording) -> None:
    """Each corpus recording's transforms as sent (a ROS 1 buffer keeps them so), through ROS 2's
    tf2 and through tftools' ROS 2 mode: 300 lookups between random frames at random times (0, a
    stamp, any time between), answers and errors identical."""
    root = root_of(recording)
    if missing_members(root, recording.members):
        pytest.skip(f"corpus recording {recording.id} is not in {root}")
    path = member_path(root, recording.open)
    sent = read_recording([path], semantics="ros1").transforms
    names = sent.frame_names
    if any(" " in name for name in names):
        pytest.skip("a frame name with a space: the driver's lines cannot carry it")
    buffer = Buffer(cache_time=None, semantics="ros2")
    buffer.insert(sent)
    lines = ["new 1000000000000000000"]
    for i in range(len(sent)):
        values = " ".join(repr(float(x)) for x in (*sent.translation[i], *sent.rotation[i]))
        parent, child = names[sent.parent[i]] or "-", names[sent.child[i]] or "-"
        lines.append(f"set {parent} {child} {sent.stamp[i]} {values} {int(sent.static[i])} {AUTHORITY}")
    rng = random.Random(recording.id)
    frames, stamps = buffer.frames, sent.stamp.tolist()
    times = [rng.choice([0, rng.randint(min(stamps), max(stamps)), rng.choice(stamps)]) for _ in range(300)]
    queries = [(rng.choice(frames), rng.choice(frames), time) for time in times]
    lines += [f"lookup {target} {source} {time}" for target, source, time in queries]
    out, _ = run_ros2_core(lines)
    real = [line for line in out if line.startswith(("T ", "E "))]
    for query, line in zip(queries, real, strict=True):
        try:
            mine = _found(buffer.lookup(*query))
        except TransformError as e:
            mine = _renamed(f"E {type(e).__name__} {e}".replace("\n", "\\n"))
        if line.startswith("T "):
            stamp, *values = line.split()[1:]
            line = f"T {stamp} " + " ".join(repr(float.fromhex(v)) for v in values)
        assert mine == line, query
