#!/usr/bin/env bash
# Run the test suite (pytest's arguments pass through), installing what it needs first: the project
# with its extras ($TFTOOLS_EXTRAS, default test,ros2) and, as root on Debian, the real ROS 1
# tf2/rosbag/roscore used as the test oracle and Chromium. TFTOOLS_SETUP=done skips the installs.
#   bash scripts/test.sh                                   everything (live and slow too)
#   bash scripts/test.sh -m "not live and not slow"        the quick loop
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${TFTOOLS_SETUP:-}" != done ]; then
  bash scripts/install-reference.sh
  bash scripts/setup.sh "${TFTOOLS_EXTRAS:-test,ros2}"
fi
.venv/bin/python -m tests.corpus.fetch || echo "corpus: not complete; its tests say what is missing"
exec .venv/bin/python -m pytest "$@"
