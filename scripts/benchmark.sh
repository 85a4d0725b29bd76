#!/usr/bin/env bash
# tftools against rosbag + tf2, side by side (benchmarks/vs_tf2.py), installing both first.
# Usage: bash scripts/benchmark.sh [--scales 1 4 16] [--images] [--commands]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-reference.sh
bash scripts/setup.sh
exec .venv/bin/python benchmarks/vs_tf2.py "$@"
