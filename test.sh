#!/usr/bin/env bash
# Runs every test: the C++ unit tests (ctest), the Python tests and the Blender tests.
# Does its own setup the first time (see tools/bootstrap.sh); safe to run again.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export MESHMARK_WITH_TESTS=1
source "$ROOT/tools/bootstrap.sh"   # exits on any setup failure (set -e)
set +e
cd "$ROOT"
status=0
say "C++ tests (ctest)"
ctest --test-dir build/py --output-on-failure -j2 || status=1
say "Python tests"
.venv/bin/python -m pytest tests -q "$@" || status=1
say "Blender tests (bpy)"
.venv/bin/python -m pytest blender_tests -q "$@" || status=1
[ "$status" = 0 ] && say "all test suites passed" || say "SOME TESTS FAILED"
exit $status
