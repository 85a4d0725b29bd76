"""Instructions of a first load and of an ingest, which a busy machine does not change: callgrind counts
of issue 41's whole script (start Python, ``import tftools``, load the 300 s robot, no lookup) and of one
ingest with the readers imported (two loads less one: what a load costs once everything is imported),
per format, with cached bytecode (as ``ratios.py`` measures), for one or more interpreters (each its
own checkout's tftools: a "before" beside an "after").

Run: ``python benchmarks/load_instructions.py [--formats ros1,db3,mcap] [PYTHON ...]`` (needs valgrind;
no PYTHON: this one). Prints JSON: per interpreter, bare Python's and ``import numpy, pathlib``'s counts
(what no change to tftools removes), and per format the whole script's and the ingest's.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from ratios import ENV, cached_bytecode
from vs_tf2 import HERE, UNIT_SECONDS, write_bags

SCRIPT = "import tftools; tftools.read_recording([{bag!r}])"
#: ``loads`` loads after the readers are imported (ours_side.py's ``import_readers``, as its ingest).
INGEST = (
    "import sys; sys.path.insert(0, {here!r}); from ours_side import import_readers; import_readers(); "
    "import tftools\nfor _ in range({loads}): tftools.read_recording([{bag!r}])"
)


def instructions(python: str, code: str) -> int:
    """Instructions callgrind counts for a process of ``python`` running ``code``."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "callgrind.out"
        subprocess.run(
            ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", python, "-c", code],
            check=True,
            capture_output=True,
            cwd="/",
            env={**ENV, "PYTHONHASHSEED": "0"},  # the same start-up in every process
        )
        for line in out.read_text().splitlines():
            if line.startswith(("summary:", "totals:")):
                return int(line.split()[1])
    raise RuntimeError("callgrind wrote no totals")


def measured(python: str, bags: dict[str, Path]) -> dict[str, int]:
    """Every count for ``python``, its bytecode written by one unmeasured run of each script first (else
    the first measured process would compile what it imports, and the one after it would not)."""
    for bag in bags.values():
        for code in (SCRIPT.format(bag=str(bag)), INGEST.format(here=str(HERE), loads=1, bag=str(bag))):
            subprocess.run([python, "-c", code], check=True, capture_output=True, cwd="/", env=ENV)
    out = {"python": instructions(python, "pass"), "numpy_pathlib": instructions(python, "import numpy, pathlib")}
    for fmt, bag in bags.items():
        out[f"script {fmt}"] = instructions(python, SCRIPT.format(bag=str(bag)))
        once, twice = (instructions(python, INGEST.format(here=str(HERE), loads=n, bag=str(bag))) for n in (1, 2))
        out[f"ingest {fmt}"] = twice - once
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("pythons", nargs="*", help="interpreters, each with its own tftools (default: this one)")
    parser.add_argument("--formats", default="ros1,db3,mcap", help="comma-separated: ros1, db3, mcap")
    args = parser.parse_args()
    prefix = tempfile.TemporaryDirectory(prefix="tftools-bytecode-")
    cached_bytecode(prefix.name)
    bags = {fmt: bag for fmt, bag in write_bags(UNIT_SECONDS, False).items() if fmt in args.formats.split(",")}
    pythons = [os.path.abspath(p) for p in args.pythons] or [sys.executable]
    print(json.dumps({python: measured(python, bags) for python in pythons}, indent=1))


if __name__ == "__main__":
    main()
