"""One ingest of the 300 s robot, a before and an after in fresh processes alternated: wall time split into
reading, inserting and the TFMessage decode within the reading, with the process's CPU time and minor page
faults (a fault costs ~1.5 us here: ~10k of them are a seventh of an ingest). On a machine shared with other
work, alternated pairs and their medians tell two versions apart where one run of each cannot.

Run: ``python benchmarks/ingest_pairs.py BEFORE [AFTER] [--rounds 9] [--formats ros1,db3,mcap]``. A side is a
git revision (AFTER by default: the working tree), its Python sources beside this environment's compiled
extensions (``ingest_functions.checkout``), or an interpreter whose own environment holds another version, built
(``--against``'s of ``ratios.py``: where the extensions' interface differs between the two). Prints a line per
format and side: medians of ``--rounds`` processes, the best and worst ingest, and the most CPU time one took (a
worst wall time with a usual CPU time was waiting for a CPU another process held).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import sysconfig
import tempfile
from pathlib import Path

from ingest_functions import checkout
from ratios import ENV, cached_bytecode
from vs_tf2 import HERE, UNIT_SECONDS, write_bags

#: One ingest in a process of its own, as ``ours_side.py ingest`` times it, the decode's calls timed within, the
#: insert's CPU time its thread's, and the time the process's threads waited for a CPU another process held.
PROBE = """
import json, resource, sys, time
sys.path.insert(0, {here!r})
from ours_side import import_readers
from spent import spent_since, usage
import_readers()
from timing import read_whole
from tftools.sources.codecs import stepped
from tftools.sources.recording import recording_of
decode, spent = stepped._wire.decode_transforms, [0.0]
def timed(*args):
    began = time.perf_counter()
    out = decode(*args)
    spent[0] += time.perf_counter() - began
    return out
stepped._wire.decode_transforms = timed
spent_before = usage()
before, began = resource.getrusage(resource.RUSAGE_SELF), time.perf_counter()
read_thread = time.thread_time()
contents = read_whole([{bag!r}])
read, thread = time.perf_counter(), time.thread_time()
spare = getattr(contents, "room", None) is not None
recording_of(contents)
done, after = time.perf_counter(), resource.getrusage(resource.RUSAGE_SELF)
insert_cpu = time.thread_time() - thread
cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
print(json.dumps({{"ingest": done - began, "read": read - began, "insert": done - read, "decode": spent[0],
                  "cpu": cpu, "insert_cpu": insert_cpu, "read_cpu": thread - read_thread,
                  "waited": spent_since(spent_before, "s")["s_waited_s"], "spare": spare,
                  "faults": after.ru_minflt - before.ru_minflt}}))
"""
FIGURES = ("ingest", "read", "insert", "decode", "cpu", "read_cpu", "insert_cpu", "waited")
#: A slow process (``issue 41``): the insert's CPU time over 25 ms (~13 ms usually), or an ingest over 77 ms
#: (30x tf2's 2.32 s).
SLOW_INSERT_CPU, SLOW_INGEST = 0.025, 0.077


#: A side: the interpreter to run, and the tree of sources (with extensions) it reads first, if any.
Side = tuple[str, Path | None]


def side_of(given: str | None, into: Path) -> Side:
    """An interpreter as it is, or a revision's sources beside this environment's extensions."""
    if given is not None and os.path.isfile(given) and os.access(given, os.X_OK):
        return given, None
    return sys.executable, checkout(given, into)


def measure(side: Side, bag: Path) -> dict[str, float]:
    """One ingest of ``bag`` by ``side``, in a process of its own (``python -S`` with a tree first on its path)."""
    python, tree = side
    env = {**ENV, "PYTHONHASHSEED": "0"}
    if tree is not None:
        env["PYTHONPATH"] = f"{tree}:{sysconfig.get_paths()['purelib']}"
    code = PROBE.format(here=str(HERE), bag=str(bag))
    command = [python, *(["-S"] if tree is not None else []), "-c", code]
    done = subprocess.run(command, capture_output=True, text=True, cwd="/", env=env)
    if done.returncode != 0:
        sys.exit(done.stderr)
    return dict(json.loads(done.stdout.strip().splitlines()[-1]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("before", help="a git revision, or an interpreter with its own tftools")
    parser.add_argument("after", nargs="?", help="the same (default: the working tree)")
    parser.add_argument("--rounds", type=int, default=9, help="processes of each side and format, alternated")
    parser.add_argument("--formats", default="ros1,db3,mcap", help="comma-separated: ros1, db3, mcap")
    parser.add_argument("--json", help="write every process's figures to this file")
    args = parser.parse_args()
    prefix = tempfile.TemporaryDirectory(prefix="tftools-bytecode-")
    cached_bytecode(prefix.name)
    bags = {fmt: bag for fmt, bag in write_bags(UNIT_SECONDS, False).items() if fmt in args.formats.split(",")}
    with tempfile.TemporaryDirectory() as tmp:
        sides = {
            "before": side_of(args.before, Path(tmp) / "before"),
            "after": side_of(args.after, Path(tmp) / "after"),
        }
        runs: dict[tuple[str, str], list[dict[str, float]]] = {(s, f): [] for s in sides for f in bags}
        for side in sides.values():
            for bag in bags.values():
                measure(side, bag)  # each side's bytecode written, unmeasured
        loads = [os.getloadavg()[0]]
        for round_ in range(args.rounds):
            for fmt, bag in bags.items():
                order = list(sides.items())
                for name, side in order[::-1] if round_ % 2 else order:  # who goes first swapped every round
                    runs[name, fmt].append(measure(side, bag))
            loads.append(os.getloadavg()[0])
    for fmt in bags:
        for side in sides:
            got = runs[side, fmt]
            figures = "  ".join(f"{k} {1e3 * statistics.median(r[k] for r in got):6.1f}" for k in FIGURES)
            faults = statistics.median(r["faults"] for r in got)
            best, worst = (1e3 * f(r["ingest"] for r in got) for f in (min, max))
            worst_cpu = 1e3 * max(r["cpu"] for r in got)
            worst_insert = 1e3 * max(r["insert_cpu"] for r in got)
            slow_insert = sum(r["insert_cpu"] > SLOW_INSERT_CPU for r in got)
            slow_ingest = sum(r["ingest"] > SLOW_INGEST for r in got)
            # what the wall time would be without the waits another process caused
            unwaited = [r["ingest"] - r["waited"] for r in got]
            slow_unwaited = sum(u > SLOW_INGEST for u in unwaited)
            spares = sum(bool(r.get("spare")) for r in got)
            print(
                f"{fmt:5} {side:6} {figures}  (ms)  faults {faults:,.0f}  ingest best {best:.1f} worst {worst:.1f} ms, "
                f"most CPU {worst_cpu:.1f} ms, insert's most CPU {worst_insert:.1f} ms; ingest less the wait "
                f"{1e3 * statistics.median(unwaited):.1f}, at most {1e3 * max(unwaited):.1f} ms; slow: insert "
                f"{slow_insert}, ingest {slow_ingest} ({slow_unwaited} less the wait) of {len(got)}; a spare made in "
                f"{spares}"
            )
    print(
        f"medians of {args.rounds} processes a side, alternated; load average (1 min) {min(loads):.1f}-{max(loads):.1f}"
    )
    if args.json:
        Path(args.json).write_text(json.dumps({f"{fmt} {side}": runs[side, fmt] for side, fmt in runs}))


if __name__ == "__main__":
    main()
