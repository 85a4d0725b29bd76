#!/usr/bin/env bash
# Build mf_oracle (the real tf2_ros::MessageFilter on bags) against Debian's ROS 1 packages, which
# scripts/install-reference.sh installs. Usage: bash build.sh OUT_DIR; prints the binary's path.
# Exit 3 (saying what is missing) where a package it needs is not installed.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
out="$1"
debs=(g++ pkg-config libtf2-ros-dev libroscpp-dev libmessage-filters-dev librosbag-dev libsensor-msgs-dev
      libnav-msgs-dev libgeometry-msgs-dev libvisualization-msgs-dev libdiagnostic-msgs-dev)
command -v dpkg >/dev/null || { echo "not a Debian system: no ROS 1 packages to build against" >&2; exit 3; }
need=$(for p in "${debs[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || echo "$p"; done)
if [ -n "$need" ]; then
  echo "missing Debian packages: $(echo $need) (scripts/install-reference.sh installs them)" >&2
  exit 3
fi
mkdir -p "$out"
bin="$out/mf_oracle"
if [ ! -x "$bin" ]; then  # OUT_DIR is named after the source's hash: a binary there is of this source
  # rosbag_storage.pc names pluginlib, which ships no .pc here: rosbag's libraries are named by hand.
  g++ -std=c++17 -O2 -Wall -Wno-deprecated-declarations -o "$bin.tmp" "$here/mf_oracle.cpp" \
      -I/usr/include/pluginlib -I/usr/include/class_loader -I/usr/include/rcpputils -I/usr/include/rcutils \
      -I/usr/include/ament_index_cpp \
      $(pkg-config --cflags --libs tf2_ros message_filters roscpp) \
      -lrosbag -lrosbag_storage -lroslz4 -lclass_loader -lboost_regex -lboost_filesystem -lboost_system -lpthread
  mv "$bin.tmp" "$bin"
fi
echo "$bin"
