"""Issue 44's cases re-run as the issue describes them, each against its "done when": exit 0, 1 or 2, a few
lines on stderr, no traceback, within 20 s (30 s live or remote) and 1.5 GB, nothing a user gave (nor a
special file) replaced. Inputs are built in a scratch folder; each command runs under ``/usr/bin/time -v``.

Prints one row per command: case, command, exit code, seconds, peak RSS, stderr lines (and stdout bytes),
and whether it meets the bound; ``--show`` prints each command's stderr too. The live ROS 2 floods are
``benchmarks/hostile_ros2.py``'s; the live frame names and /clock jumps are pinned by tests/live.

    .venv/bin/python benchmarks/issue44.py [--only NAME ...] [--show] [--keep DIR]
"""

from __future__ import annotations

import argparse
import contextlib
import os
import re
import shutil
import socket
import stat
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tests.bags import BagFormat, TfMessage, write_bag
from tftools.core.transform import Transform

S = 1_000_000_000
TFX = [sys.executable, "-m", "tftools"]


@dataclass
class Run:
    case: str
    command: str
    exit: int
    seconds: float
    peak_mb: int
    stderr: list[str]
    stdout_bytes: int
    limit_s: float
    cpu_s: float = 0.0
    problems: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return not self.problems


def run(case: str, args: list[str], cwd: Path, limit_s: float = 20.0, stdin: str = "") -> Run:
    """``tfx ARGS`` timed, its peak RSS, and what the issue's bound says of it."""
    started = time.monotonic()
    try:
        finished = subprocess.run(
            ["/usr/bin/time", "-v", *TFX, *args],
            cwd=cwd,
            capture_output=True,
            timeout=max(120.0, 3 * limit_s),
            check=False,
            input=stdin.encode(),
        )
    except subprocess.TimeoutExpired:
        return Run(case, " ".join(args), -1, time.monotonic() - started, -1, [], 0, limit_s, ["killed: no end"])
    seconds = time.monotonic() - started
    err = finished.stderr.decode(errors="replace")
    rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", err)
    cpu = sum(float(m) for m in re.findall(r"(?:User|System) time \(seconds\): ([\d.]+)", err))
    said = [line for line in err.split("\n") if line and not line.startswith("\t") and "Command exited" not in line]
    result = Run(
        case,
        " ".join(a if len(a) < 60 else a[:57] + "..." for a in args),
        finished.returncode,
        seconds,
        int(rss.group(1)) // 1024 if rss else -1,
        said,
        len(finished.stdout),
        limit_s,
        cpu,
    )
    if finished.returncode not in (0, 1, 2):
        result.problems.append(f"exit {finished.returncode}")
    if any("Traceback" in line or "internal error" in line for line in said):
        result.problems.append("traceback")
    if len(said) > 6:
        result.problems.append(f"{len(said)} stderr lines")
    if seconds > limit_s:
        result.problems.append(f"{seconds:.0f} s")
    if result.peak_mb > 1536:
        result.problems.append(f"{result.peak_mb} MB")
    return result


# ---- inputs ------------------------------------------------------------------------------------------------


def tf(parent: str, child: str, stamp: int, x: float = 0.0, rotation: tuple[float, ...] = (0, 0, 0, 1)) -> Transform:
    return Transform((x, 0.0, 0.0), rotation, stamp, parent, child)  # type: ignore[arg-type]


def small_bag(path: Path) -> Path:
    """odom -> base moving at 10 Hz for 5 s, base -> laser static."""
    messages = [TfMessage("/tf_static", S, [tf("base", "laser", S, 1.0)])]
    messages += [TfMessage("/tf", S + i * S // 10, [tf("odom", "base", S + i * S // 10, i / 10)]) for i in range(50)]
    return write_bag(path, messages)


def rosbags_ros1(path: Path, messages: list[tuple[str, str, int, object]], compression: str = "") -> Path:
    """A ROS1 bag of (topic, type, time, message built by rosbags' store), chunks compressed as asked."""
    from rosbags.rosbag1 import Writer

    from tests.bags import _typestore

    store = _typestore("ros1")
    writer = Writer(path)
    if compression:
        writer.set_compression(Writer.CompressionFormat[compression.upper()])
    with writer:
        connections: dict[str, object] = {}
        for topic, kind, at, message in messages:
            if topic not in connections:
                connections[topic] = writer.add_connection(topic, kind, typestore=store)
            writer.write(connections[topic], at, bytes(store.serialize_ros1(message(store), kind)))  # type: ignore[arg-type,operator]
    return path


def tf_of(store: object, transforms: list[Transform]) -> object:
    from tests.bags import rosbags_tf_message

    return rosbags_tf_message(store, transforms)


def string_of(text: str) -> Callable[[object], object]:
    return lambda store: store.types["std_msgs/msg/String"](data=text)  # type: ignore[attr-defined]


def joint_state(name: str, position: float, at: int) -> Callable[[object], object]:
    def build(store: object) -> object:
        import numpy as np

        types = store.types  # type: ignore[attr-defined]
        stamp = types["builtin_interfaces/msg/Time"](sec=at // S, nanosec=at % S)
        header = types["std_msgs/msg/Header"](seq=0, stamp=stamp, frame_id="")
        values = np.array([position], dtype=np.float64)
        return types["sensor_msgs/msg/JointState"](
            header=header, name=[name], position=values, velocity=np.array([]), effort=np.array([])
        )

    return build


ARM = """<robot name="arm"><link name="base"/><link name="link1"/><link name="link2"/>
<joint name="j1" type="revolute"><parent link="base"/><child link="link1"/><axis xyz="0 0 1"/>
<limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
<joint name="j2" type="revolute"><parent link="link1"/><child link="link2"/><axis xyz="0 0 1"/>
<mimic joint="j1" multiplier="MULT"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint></robot>"""


def arm_bag(path: Path, position: float) -> Path:
    """base -> link1 -> link2 moving (j2 mimics j1) at 10 Hz, /joint_states of j1 at ``position``."""
    messages: list[tuple[str, str, int, object]] = []
    for i in range(30):
        at = S + i * S // 10
        moving = [tf("base", "link1", at), tf("link1", "link2", at)]
        messages.append(("/tf", "tf2_msgs/msg/TFMessage", at, lambda store, m=moving: tf_of(store, m)))
        messages.append(("/joint_states", "sensor_msgs/msg/JointState", at + 1, joint_state("j1", position, at)))
    return rosbags_ros1(path, messages)


def many_frames_bag(path: Path, frames: int, moving: bool, hz: int = 2, seconds: int = 3) -> Path:
    """A chain-free fan of ``frames`` frames under root (static, or each moving at ``hz``)."""
    if not moving:
        return write_bag(path, [TfMessage("/tf_static", S, [tf("root", f"f{i}", S, 1.0) for i in range(frames)])])
    messages = []
    for k in range(hz * seconds):
        at = S + k * S // hz
        messages.append(TfMessage("/tf", at, [tf("root", f"f{i}", at, k / 10) for i in range(frames)]))
    return write_bag(path, messages)


def tree_file(path: Path, frames: int, rotation: str = "") -> Path:
    lines = ["tolerances: {translation_mm: 1.0, rotation_deg: 0.1, rate_percent: 20.0}", "frames:", "  odom: {}"]
    lines.append("  base: {parent: odom, rate_hz: 10.0}")
    lines.append(
        f"  laser: {{parent: base, static: true, translation: [1.0, 0.0, 0.0], {rotation or 'rpy_deg: [0, 0, 0]'}}}"
    )
    lines += [f"  f{i}: {{parent: base, static: true, translation: [1.0, 0.0, 0.0]}}" for i in range(frames)]
    path.write_text("\n".join(lines) + "\n")
    return path


@contextlib.contextmanager
def silent_server() -> Iterator[int]:
    """A TCP port that accepts and never answers (a Dask scheduler that hangs)."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    held: list[socket.socket] = []
    stop = threading.Event()

    def accept() -> None:
        server.settimeout(0.2)
        while not stop.is_set():
            with contextlib.suppress(OSError):
                held.append(server.accept()[0])

    thread = threading.Thread(target=accept, daemon=True)
    thread.start()
    try:
        yield server.getsockname()[1]
    finally:
        stop.set()
        thread.join()
        for connection in held:
            connection.close()
        server.close()


# ---- the cases ---------------------------------------------------------------------------------------------


def case_outputs(d: Path) -> list[Run]:
    """1. --force on a FIFO and a character device (made in the scratch folder: /dev/null's numbers)."""
    bag = small_bag(d / "in.bag")
    os.mkfifo(d / "pipe")
    runs = [
        run(
            "1 output: FIFO",
            ["static", "1", "0", "0", "0", "0", "0", "a", "b", "-b", str(bag), "-o", "pipe", "--force"],
            d,
        )
    ]
    runs.append(run("1 output: FIFO repair", ["static", "--repair", "-b", str(bag), "-o", "pipe", "--force"], d))
    if not stat.S_ISFIFO((d / "pipe").stat().st_mode):
        runs[-1].problems.append("FIFO replaced")
    if os.geteuid() == 0:
        os.mknod(d / "dev", 0o666 | stat.S_IFCHR, os.makedev(1, 3))
        runs.append(run("1 output: device", ["static", "--repair", "-b", str(bag), "-o", "dev", "--force"], d))
        if not stat.S_ISCHR((d / "dev").stat().st_mode):
            runs[-1].problems.append("device replaced")
    return runs


def case_urdf_dtd(d: Path) -> list[Run]:
    """2. a UTF-16 URDF (with and without BOM) declaring an entity; 600,000 references to a 400-character one;
    21. a UTF-8 URDF with <!DOCTYPE only in a comment (must be read)."""
    bag = small_bag(d / "in.bag")
    entity = (
        '<?xml version="1.0" encoding="UTF-16"?><!DOCTYPE r [<!ENTITY a "aaaa">]>'
        '<robot name="r"><link name="&a;"/></robot>'
    )
    (d / "bom.urdf").write_bytes(entity.encode("utf-16"))
    (d / "nobom.urdf").write_bytes(entity.encode("utf-16-le"))
    laughs = (
        '<!DOCTYPE r [<!ENTITY a "' + "x" * 400 + '">]><robot name="r"><link name="' + "&a;" * 600_000 + '"/></robot>'
    )
    (d / "laughs.urdf").write_bytes(laughs.encode("utf-16"))
    (d / "comment.urdf").write_text('<!-- no <!DOCTYPE here --><robot name="r"><link name="base"/></robot>')
    runs = []
    for name in ("bom", "nobom", "laughs"):
        runs.append(run(f"2 URDF DTD {name}", ["wtf", str(bag), "--urdf", f"{name}.urdf"], d))
        if runs[-1].exit != 2:
            runs[-1].problems.append(f"exit {runs[-1].exit}, not 2")
    runs.append(run("21 DOCTYPE in a comment", ["wtf", str(bag), "--urdf", "comment.urdf"], d))
    if any("DOCTYPE" in line or "document type" in line for line in runs[-1].stderr):
        runs[-1].problems.append("refused")
    return runs


def case_dask(d: Path) -> list[Run]:
    """3 and 5. --dask at addresses that are no scheduler, and at one that accepts and never answers."""
    bag = small_bag(d / "in.bag")
    runs = [
        run(f"3 dask {a!r}", ["wtf", str(bag), "--dask", a], d, 30.0)
        for a in ("ucx://127.0.0.1:1", "", "inproc://x", "garbage", "tcp://[::1")
    ]
    with silent_server() as port:
        runs.append(run("5 dask silent scheduler", ["wtf", str(bag), "--dask", f"tcp://127.0.0.1:{port}"], d, 30.0))
    return runs


def case_zero_quaternion(d: Path) -> list[Run]:
    """3. a tree file whose static rotation is [0, 0, 0, 0]: tfx diff and wtf --expect."""
    bag = small_bag(d / "in.bag")
    tree = tree_file(d / "zero.yaml", 0, "rotation: [0, 0, 0, 0]")
    return [
        run("3 zero quaternion: diff", ["diff", str(tree), str(bag)], d),
        run("3 zero quaternion: --expect", ["wtf", str(bag), "--expect", str(tree)], d),
    ]


def case_joint_values(d: Path) -> list[Run]:
    """3. a /joint_states position of +inf, and a mimic multiplier of 1e308, against a URDF: wtf and report."""
    (d / "arm.urdf").write_text(ARM.replace("MULT", "1"))
    (d / "mimic.urdf").write_text(ARM.replace("MULT", "1e308"))
    inf = arm_bag(d / "inf.bag", float("inf"))
    fine = arm_bag(d / "fine.bag", 0.5)
    runs = []
    for name, bag, urdf in (("+inf position", inf, "arm.urdf"), ("1e308 mimic", fine, "mimic.urdf")):
        runs.append(run(f"3 {name}: wtf", ["wtf", str(bag), "--urdf", urdf], d))
        runs.append(run(f"3 {name}: report", ["report", str(bag), "--urdf", urdf, "-o", f"{name[:4]}.html"], d))
    return runs


def case_descriptions(d: Path) -> list[Run]:
    """4. 500 recorded /robot_description messages of (nearly) 4 MiB in lz4 and bz2 chunks (ROS 1's codecs)."""
    runs = []
    text = ARM.replace("MULT", "1") + "<!--" + "x" * ((4 << 20) - 4096) + "-->"
    for codec in ("lz4", "bz2"):
        messages: list[tuple[str, str, int, object]] = [
            ("/robot_description", "std_msgs/msg/String", S + k, string_of(text)) for k in range(500)
        ]
        messages += [
            (
                "/tf",
                "tf2_msgs/msg/TFMessage",
                S + i * S // 10,
                lambda store, i=i: tf_of(store, [tf("base", "link1", S + i * S // 10)]),
            )
            for i in range(20)
        ]
        bag = rosbags_ros1(d / f"desc_{codec}.bag", messages, codec)
        runs.append(run(f"4 500 x 4 MiB descriptions ({codec}): wtf", ["wtf", str(bag)], d))
        runs.append(
            run(f"4 500 x 4 MiB descriptions ({codec}): report", ["report", str(bag), "-o", f"desc_{codec}.html"], d)
        )
        bag.unlink()
    return runs


def case_many_edges(d: Path) -> list[Run]:
    """4. a report of 20,000 moving edges."""
    bag = many_frames_bag(d / "edges.bag", 20_000, moving=True)
    result = run("4 report of 20,000 moving edges", ["report", str(bag), "-o", "edges.html"], d)
    size = (d / "edges.html").stat().st_size if (d / "edges.html").exists() else 0
    result.stderr.append(f"(page {size / 1e6:.1f} MB)")
    return [result]


def case_long_link(d: Path) -> list[Run]:
    """4. link names of 1 MiB and 4 MiB in a URDF file, and of 1 MiB in a recorded /robot_description: report."""
    bag = small_bag(d / "in.bag")
    runs = []
    for size, name in ((1 << 20, "1 MiB"), (4 << 20, "4 MiB")):
        (d / "long.urdf").write_text(f'<robot name="r"><link name="{"l" * size}"/></robot>')
        runs.append(run(f"4 {name} link name: report", ["report", str(bag), "--urdf", "long.urdf", "-o", "u.html"], d))
    description = f'<robot name="r"><link name="{"l" * (1 << 20)}"/><link name="odom"/></robot>'
    messages: list[tuple[str, str, int, object]] = [
        ("/robot_description", "std_msgs/msg/String", S, string_of(description))
    ]
    messages += [
        ("/tf", "tf2_msgs/msg/TFMessage", S + i, lambda store: tf_of(store, [tf("odom", "base", S)])) for i in range(3)
    ]
    recorded = rosbags_ros1(d / "described.bag", messages)
    runs.append(run("4 1 MiB link name recorded: report", ["report", str(recorded), "-o", "r.html"], d))
    return runs


def case_graphviz(d: Path) -> list[Run]:
    """5. Graphviz on a 10,000-frame tree: report and view-frames."""
    bag = many_frames_bag(d / "wide.bag", 10_000, moving=False)
    return [
        run("5 10,000 frames: report", ["report", str(bag), "-o", "wide.html"], d),
        run("5 10,000 frames: view-frames", ["view-frames", "-b", str(bag), "-o", "wide.pdf"], d),
    ]


def case_expect(d: Path) -> list[Run]:
    """5. --expect with a 100,000-frame tree file."""
    bag = small_bag(d / "in.bag")
    tree = tree_file(d / "huge.yaml", 100_000)
    return [run("5 --expect of 100,000 frames", ["wtf", str(bag), "--expect", str(tree)], d)]


def case_statics(d: Path) -> list[Run]:
    """5. 100,000 /tf_static transforms in one ROS 2 message: wtf and --init."""
    transforms = [tf("root", f"s{i}", S, 1.0) for i in range(100_000)]
    bag = write_bag(d / "statics", [TfMessage("/tf_static", S, transforms)], BagFormat.rosbag2_sqlite3)
    return [
        run("5 100,000 statics: wtf", ["wtf", str(bag)], d),
        run("5 100,000 statics: --init", ["wtf", "--init", str(bag)], d),
    ]


def case_metadata(d: Path) -> list[Run]:
    """5. a metadata.yaml listing 200,000 missing files (distinct, then one repeated)."""
    runs = []
    for name, paths in (("distinct", [f"gone_{i}.db3" for i in range(200_000)]), ("repeated", ["gone.db3"] * 200_000)):
        bag = write_bag(d / f"meta_{name}", [TfMessage("/tf", S, [tf("odom", "base", S)])], BagFormat.rosbag2_sqlite3)
        meta = bag / "metadata.yaml"
        lines = meta.read_text().splitlines()
        at = next(i for i, line in enumerate(lines) if line.strip() == "relative_file_paths:") + 1
        indent = lines[at][: len(lines[at]) - len(lines[at].lstrip())]
        end = next(i for i in range(at, len(lines)) if not lines[i].lstrip().startswith("- "))
        lines[at:end] = [f"{indent}- {p}" for p in paths]
        meta.write_text("\n".join(lines) + "\n")
        runs.append(run(f"5 metadata.yaml of 200,000 missing files ({name})", ["wtf", str(bag)], d))
    return runs


def case_numbers(d: Path) -> list[Run]:
    """6. 1e308 translations (numpy overflow, 1e308 printed), U+2028/U+2029 in frame names."""
    messages = [
        TfMessage(
            "/tf",
            S + i * S // 10,
            [tf("odom", "base", S + i * S // 10, 1e308), tf("odom", "a\u2028b\u2029c", S + i * S // 10)],
        )
        for i in range(20)
    ]
    bag = write_bag(d / "numbers.bag", messages)
    runs = [
        run("6 1e308: wtf", ["wtf", str(bag)], d),
        run("6 1e308: echo", ["echo", "odom", "base", "-b", str(bag), "--at", "+1"], d),
        run("6 U+2028 names: frames", ["frames", "-b", str(bag)], d),
    ]
    out = subprocess.run(
        [*TFX, "echo", "odom", "base", "-b", str(bag), "--at", "+1"], cwd=d, capture_output=True, text=True, check=False
    )
    if re.search(r"\d{30,}", out.stdout + out.stderr):
        runs[1].problems.append("a 309-digit number")
    frames = subprocess.run([*TFX, "frames", "-b", str(bag)], cwd=d, capture_output=True, text=True, check=False)
    if "\u2028" in frames.stdout + frames.stderr or "\u2029" in frames.stdout + frames.stderr:
        runs[2].problems.append("U+2028 unescaped")
    if any("overflow encountered" in line for r in runs for line in r.stderr):
        runs[0].problems.append("numpy's overflow note")
    return runs


CASES: dict[str, Callable[[Path], list[Run]]] = {
    "outputs": case_outputs,
    "urdf_dtd": case_urdf_dtd,
    "dask": case_dask,
    "zero_quaternion": case_zero_quaternion,
    "joint_values": case_joint_values,
    "descriptions": case_descriptions,
    "many_edges": case_many_edges,
    "long_link": case_long_link,
    "graphviz": case_graphviz,
    "expect": case_expect,
    "statics": case_statics,
    "metadata": case_metadata,
    "numbers": case_numbers,
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--only", nargs="+", choices=list(CASES), default=list(CASES))
    parser.add_argument("--show", action="store_true", help="print each command's stderr")
    parser.add_argument("--keep", type=Path, help="build inputs here and keep them")
    options = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print("| case | command | exit | wall s | CPU s | peak MB | stderr lines | stdout bytes | meets the bound |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name in options.only:
        folder = Path(tempfile.mkdtemp(prefix=f"issue44_{name}_", dir=options.keep))
        try:
            for r in CASES[name](folder):
                verdict = "yes" if r.ok else "NO: " + ", ".join(r.problems)
                figures = (
                    f"{r.exit} | {r.seconds:.1f} | {r.cpu_s:.1f} | {r.peak_mb} | {len(r.stderr)} | {r.stdout_bytes}"
                )
                print(f"| {r.case} | `tfx {r.command}` | {figures} | {verdict} |", flush=True)
                if options.show:
                    for line in r.stderr:
                        print(f"|   | {line[:300]} ||||||||")
        finally:
            if options.keep is None:
                shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
