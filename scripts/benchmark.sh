#!/usr/bin/env bash
# Issue 17's goals, each with tftools' figure, tf2's and transform-tree's (benchmarks/goals.py),
# installing all three first. With --vs-tf2, issue 8's side-by-side table instead (benchmarks/vs_tf2.py).
# With --ratios, each measure's ratio against tf2 in one run, fresh processes interleaved (benchmarks/ratios.py).
# Usage: bash scripts/benchmark.sh [--parts calls ingest startup fresh memory] [--runs 5]
#        bash scripts/benchmark.sh --vs-tf2 [--scales 1 4 16] [--images] [--commands]
#        bash scripts/benchmark.sh --ratios [--runs 5] [--against OTHER_PYTHON]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-reference.sh
bash scripts/setup.sh bench
if [ "${1:-}" = "--vs-tf2" ]; then
  shift
  exec .venv/bin/python benchmarks/vs_tf2.py "$@"
fi
if [ "${1:-}" = "--ratios" ]; then
  shift
  exec .venv/bin/python benchmarks/ratios.py "$@"
fi
exec .venv/bin/python benchmarks/goals.py "$@"
