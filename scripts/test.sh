#!/usr/bin/env bash
# Run the whole test suite, installing what it needs: the project with its test extras, and
# (as root on Debian) the real ROS 1 tf2/rosbag/roscore used as the test oracle.
set -euo pipefail
cd "$(dirname "$0")/.."

reference=(python3-tf2 python3-tf2-ros python3-rosbag python3-tf python3-roswtf
           tf2-tools tf-tools ros-core graphviz poppler-utils)
if command -v dpkg >/dev/null; then
  need=$(for p in "${reference[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || echo "$p"; done)
  if [ -n "$need" ]; then
    if [ "$(id -u)" = 0 ] || command -v sudo >/dev/null; then
      sudo_=""; [ "$(id -u)" = 0 ] || sudo_=sudo
      echo "test: installing the tf2 reference (Debian packages): $(echo $need)" >&2
      $sudo_ apt-get update -qq
      $sudo_ env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $need >/dev/null
    else
      echo "test: not root: tests against the real tf2 will be skipped" >&2
    fi
  fi
fi

bash scripts/setup.sh test,ros2
exec .venv/bin/python -m pytest "$@"
