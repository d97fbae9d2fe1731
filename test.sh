#!/usr/bin/env bash
# Runs every test: the C++ unit tests (ctest), the Python tests and the Blender tests.
# Does its own setup the first time (see tools/bootstrap.sh); safe to run again.
# Extra arguments go to both pytest runs (e.g. -x, -k NAME).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export MESHMARK_WITH_TESTS=1
source "$ROOT/tools/bootstrap.sh"   # exits on any setup failure (set -e)
set +e
cd "$ROOT"
reports="$ROOT/build/test-reports"
rm -rf "$reports" && mkdir -p "$reports"
status=0
say "C++ tests (ctest)"
ctest --test-dir build/py --output-on-failure -j2 --output-junit "$reports/cpp.xml" || status=1
say "Python tests"
.venv/bin/python -m pytest tests -q --junitxml="$reports/python.xml" "$@" || status=1
say "Blender tests (bpy)"
.venv/bin/python -m pytest blender_tests -q --junitxml="$reports/blender.xml" "$@" || status=1
.venv/bin/python tools/junit_summary.py "$reports/cpp.xml" "$reports/python.xml" "$reports/blender.xml" || status=1
exit $status
