#!/usr/bin/env bash
# Issue 17's goals, each with tftools' figure, tf2's and transform-tree's (benchmarks/goals.py),
# installing all three first. With --vs-tf2, issue 8's side-by-side table instead (benchmarks/vs_tf2.py).
# Usage: bash scripts/benchmark.sh [--parts calls ingest startup fresh memory] [--runs 5]
#        bash scripts/benchmark.sh --vs-tf2 [--scales 1 4 16] [--images] [--commands]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-reference.sh
bash scripts/setup.sh bench
if [ "${1:-}" = "--vs-tf2" ]; then
  shift
  exec .venv/bin/python benchmarks/vs_tf2.py "$@"
fi
exec .venv/bin/python benchmarks/goals.py "$@"
