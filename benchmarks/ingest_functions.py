"""Where one ingest's instructions moved between two checkouts, function by function: callgrind's counts of a
process loading the 300 s robot twice less one loading it once (``load_instructions.py``'s ingest), for each
checkout's Python sources beside this environment's compiled extensions, so that whatever differs is the
sources' doing (an extension function counts alike on both sides to the instruction where it is not changed).

Run: ``python benchmarks/ingest_functions.py BEFORE [AFTER] [--formats ros1,db3,mcap] [--top 25]``, BEFORE
and AFTER git revisions (AFTER: the working tree). Needs valgrind. Prints, per format, both ingests' totals
and the functions whose counts differ most (self counts, ``callgrind_annotate --inclusive=no``).
"""

from __future__ import annotations

import argparse
import collections
import re
import shutil
import subprocess
import sys
import sysconfig
import tempfile
from pathlib import Path

from load_instructions import INGEST
from ratios import ENV, cached_bytecode
from vs_tf2 import HERE, UNIT_SECONDS, write_bags

REPO = HERE.parent
#: A line of ``callgrind_annotate``: a count, its share, and the function with its object file.
LINE = re.compile(r"\s*([\d,]+)\s+\([^)]*\)\s+(.*)")


def checkout(revision: str | None, into: Path) -> Path:
    """``tftools/`` of ``revision`` (None: the working tree) in ``into``, with this environment's extensions."""
    into.mkdir(parents=True)
    if revision is None:
        shutil.copytree(REPO / "tftools", into / "tftools", ignore=shutil.ignore_patterns("__pycache__"))
    else:
        archive = subprocess.run(["git", "archive", revision, "tftools"], cwd=REPO, check=True, capture_output=True)
        subprocess.run(["tar", "-x", "-C", str(into)], input=archive.stdout, check=True)
    installed = Path(sysconfig.get_paths()["purelib"]) / "tftools"
    for built in [*installed.rglob("*.so"), installed / "_version.py"]:
        shutil.copy(built, into / "tftools" / built.relative_to(installed))
    return into


def functions(tree: Path, code: str) -> collections.Counter[str]:
    """Self instructions per function of a ``python -S`` process running ``code`` with ``tree`` first on its path."""
    env = {**ENV, "PYTHONHASHSEED": "0", "PYTHONPATH": f"{tree}:{sysconfig.get_paths()['purelib']}"}
    command = [sys.executable, "-S", "-c", code]
    subprocess.run(command, check=True, capture_output=True, cwd="/", env=env)  # its bytecode written first
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "callgrind.out"
        valgrind = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}"]
        subprocess.run(valgrind + command, check=True, capture_output=True, cwd="/", env=env)
        annotated = subprocess.run(
            ["callgrind_annotate", "--inclusive=no", "--threshold=100", str(out)],
            check=True,
            capture_output=True,
            text=True,
        ).stdout
    counts: collections.Counter[str] = collections.Counter()
    for line in annotated.splitlines():
        if found := LINE.match(line):
            counts[found.group(2).strip().replace(str(tree), "TREE")] += int(found.group(1).replace(",", ""))
    return counts


def ingest(tree: Path, bag: Path) -> dict[str, int]:
    """Each function's instructions of one load once the readers are imported: two loads less one."""
    once, twice = (functions(tree, INGEST.format(here=str(HERE), loads=n, bag=str(bag))) for n in (1, 2))
    return {name: twice[name] - once[name] for name in set(once) | set(twice)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("before", help="a git revision")
    parser.add_argument("after", nargs="?", help="a git revision (default: the working tree)")
    parser.add_argument("--formats", default="ros1,db3,mcap", help="comma-separated: ros1, db3, mcap")
    parser.add_argument("--top", type=int, default=25, help="functions listed per format")
    args = parser.parse_args()
    prefix = tempfile.TemporaryDirectory(prefix="tftools-bytecode-")
    cached_bytecode(prefix.name)
    bags = {fmt: bag for fmt, bag in write_bags(UNIT_SECONDS, False).items() if fmt in args.formats.split(",")}
    with tempfile.TemporaryDirectory(prefix="tftools-ingest-functions-") as tmp:
        trees = [checkout(args.before, Path(tmp) / "before"), checkout(args.after, Path(tmp) / "after")]
        for fmt, bag in bags.items():
            before, after = (ingest(tree, bag) for tree in trees)
            total = "PROGRAM TOTALS"
            print(f"{fmt}: ingest {before[total] / 1e6:.1f}M -> {after[total] / 1e6:.1f}M instructions")
            moved = {name: after.get(name, 0) - before.get(name, 0) for name in set(before) | set(after)}
            for name, change in sorted(moved.items(), key=lambda kv: -abs(kv[1]))[: args.top]:
                if name != total:
                    was, now = before.get(name, 0) / 1e6, after.get(name, 0) / 1e6
                    print(f"  {change / 1e6:+8.2f}M  {was:8.2f} -> {now:8.2f}  {name[:150]}")


if __name__ == "__main__":
    main()
