#!/usr/bin/env bash
# First use after a fresh install: tftools installed non-editable into a throwaway venv, its
# site-packages then made read-only (a CI container, a system install); times its first
# `tfx echo --all` on BAG, then RUNS later ones. Prints one JSON object.
# Usage: bash benchmarks/fresh_install.sh BAG [RUNS]   (root ignores the read-only bits)
set -euo pipefail
bag="$1"; runs="${2:-3}"
repo="$(cd "$(dirname "$0")/.." && pwd)"
tmp="$(mktemp -d)"
trap 'chmod -R u+w "$tmp"; rm -rf "$tmp"' EXIT
python3 -m venv "$tmp/venv"
"$tmp/venv/bin/python" -m pip install -q "$repo" >&2
site="$("$tmp/venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')"
chmod -R a-w "$site"
seconds() {  # wall seconds of one `tfx echo --all` run from an empty working directory
  local began ended
  began=$(date +%s.%N)
  (cd "$tmp" && "$tmp/venv/bin/tfx" echo map arm_link6 -b "$bag" --all >/dev/null)
  ended=$(date +%s.%N)
  python3 -c "print($ended - $began)"
}
first=$(seconds)
later=()
for _ in $(seq "$runs"); do later+=("$(seconds)"); done
python3 -c "import json, statistics, sys; later = [float(x) for x in sys.argv[2:]]
print(json.dumps({'first_s': float(sys.argv[1]), 'later_s': statistics.median(later)}))" "$first" "${later[@]}"
