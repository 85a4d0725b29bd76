#!/usr/bin/env bash
# Install the real ROS 1 tf2, rosbag and roscore from Debian (as root, or with sudo): the tests'
# oracle and live peers, and the benchmark's reference; the C++ headers the real tf2_ros::MessageFilter
# is built from (tests/oracle/msgfilter, compiled by the tests into a cache outside the repository);
# Debian's diagnostic_msgs for rospy and rosdiagnostic (independent subscribers of tfx wtf --watch's
# /diagnostics); and Chromium, the browser in which the tests open tfx report's page. Without root, says what will
# be missing.
set -euo pipefail

reference=(python3-tf2 python3-tf2-ros python3-tf2-geometry-msgs python3-sensor-msgs python3-rosbag python3-tf python3-roswtf
           tf2-tools tf-tools ros-core graphviz poppler-utils chromium
           g++ pkg-config libtf2-ros-dev libroscpp-dev libmessage-filters-dev librosbag-dev libsensor-msgs-dev
           libnav-msgs-dev libgeometry-msgs-dev libvisualization-msgs-dev libdiagnostic-msgs-dev
           python3-diagnostic-msgs rosdiagnostic)
command -v dpkg >/dev/null || exit 0
need=$(for p in "${reference[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || echo "$p"; done)
[ -n "$need" ] || exit 0
if [ "$(id -u)" = 0 ] || command -v sudo >/dev/null; then
  sudo_=""; [ "$(id -u)" = 0 ] || sudo_=sudo
  echo "installing the tf2 reference (Debian packages): $(echo $need)" >&2
  $sudo_ apt-get update -qq
  $sudo_ env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $need >/dev/null
else
  echo "not root: what needs the real tf2 or Chromium (tests against them, the benchmark's reference) will be skipped" >&2
fi
