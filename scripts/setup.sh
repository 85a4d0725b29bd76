#!/usr/bin/env bash
# Set up tftools in .venv (and, as root on Debian, the system packages it uses).
# Usage: bash scripts/setup.sh [extras]    e.g. bash scripts/setup.sh test
set -euo pipefail
cd "$(dirname "$0")/.."
extras="${1:-}"

as_root() { if [ "$(id -u)" = 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@"; else return 1; fi; }
missing_debs() { for p in "$@"; do dpkg -s "$p" >/dev/null 2>&1 || echo "$p"; done; }

# g++ and Python's headers compile the lookups (native/) when tftools is installed; sqlite's headers
# (optional: without them .db3 files are read through Python's sqlite3, ~2.5x slower) the .db3 reader.
debs=(graphviz g++ python3-dev libsqlite3-dev)
python3 -m venv --help >/dev/null 2>&1 && python3 -c 'import ensurepip' 2>/dev/null || debs+=(python3-venv)
if command -v dpkg >/dev/null; then
  need=$(missing_debs "${debs[@]}")
  if [ -n "$need" ]; then
    echo "setup: installing Debian packages: $need" >&2
    as_root apt-get update -qq && as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $need >/dev/null \
      || echo "setup: could not install $need (not root?); view-frames needs Graphviz's dot, the install g++ and libsqlite3-dev" >&2
  fi
fi

[ -x .venv/bin/python ] || python3 -m venv .venv
.venv/bin/python -m pip install -q --upgrade pip
spec="."
[ -n "$extras" ] && spec=".[${extras}]"
.venv/bin/python -m pip install -q -c scripts/constraints.txt -e "$spec"
echo "setup: ready; run .venv/bin/tfx --help" >&2
