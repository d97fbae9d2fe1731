#!/usr/bin/env bash
# Idempotent setup shared by ./demo.sh and ./test.sh (sourced, not run):
#   1. Debian packages: compiler, CMake, Eigen, CGAL (+GMP/MPFR/Boost), SuiteSparse, OpenBLAS and the
#      X/GL libraries that the bpy wheel loads; with MESHMARK_WITH_TESTS=1 also GoogleTest and Debian's
#      Blender with numpy for its Python plus Xvfb (blender_tests/test_debian_blender.py); installed only
#      when missing, or always when CI=true;
#   2. a virtual environment in .venv with the build tools (scikit-build-core, pybind11, wheel: an
#      sdist among the test dependencies is built in this venv, without build isolation);
#   3. meshmark built in Release mode into it (rebuilt only when a source file changed; the CMake
#      build tree build/py is kept, so rebuilds are incremental) and, with MESHMARK_WITH_TESTS=1,
#      the C++ tests, the test extras (meshmark[test]) and the bpy wheel; with MESHMARK_WITH_BLENDER=1
#      (./demo.sh) the bpy wheel and meshmark[plot] for the demo's plot.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

# What building and running meshmark needs (./demo.sh included: the X/GL libraries load the bpy wheel).
APT_PACKAGES=(build-essential cmake ninja-build git libeigen3-dev libcgal-dev libgmp-dev libmpfr-dev
  libboost-dev libsuitesparse-dev libopenblas0-pthread python3-venv python3-dev
  libx11-6 libxrender1 libxxf86vm1 libxfixes3 libxi6 libxkbcommon0 libsm6 libice6 libgl1 libegl1
  libxext6 libgomp1 libwayland-client0 libdecor-0-0)
# What only the tests use: GoogleTest for ctest; Debian's Blender 3.4 (with numpy for its Python)
# under Xvfb for the real-window tests (blender_tests/test_debian_blender.py).
if [ "${MESHMARK_WITH_TESTS:-0}" = 1 ]; then
  APT_PACKAGES+=(libgtest-dev blender python3-numpy xvfb xauth)
fi

say() { printf '\033[1mmeshmark:\033[0m %s\n' "$*"; }

missing=()
for p in "${APT_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ] || [ "${CI:-}" = "true" ]; then
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  say "installing Debian packages: ${missing[*]:-(CI: refreshing all)}"
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${APT_PACKAGES[@]}" >/dev/null
fi

PY="${MESHMARK_PYTHON:-python3}"
if [ ! -x .venv/bin/python ]; then
  say "creating .venv with $($PY --version)"
  "$PY" -m venv .venv
fi
VPY="$ROOT/.venv/bin/python"
export PIP_DISABLE_PIP_VERSION_CHECK=1
# Every pip install below obeys tools/constraints.txt (numpy < 2 for the bpy 5.0.1 wheel), so the
# demo and the tests share one consistent environment; `pip check` verifies it at the end.
export PIP_CONSTRAINT="$ROOT/tools/constraints.txt"

stamp=.venv/.meshmark-build-stamp
want_tests="${MESHMARK_WITH_TESTS:-0}"
need_build=0
if [ ! -f "$stamp" ]; then
  need_build=1
elif [ "$want_tests" = 1 ] && [ "$(cat "$stamp")" != "tests=1" ]; then
  need_build=1  # the C++ tests were not built yet
elif [ -n "$(find native src CMakeLists.txt pyproject.toml -newer "$stamp" -type f 2>/dev/null | head -1)" ]; then
  need_build=1  # a source file changed
fi
"$VPY" -c "import meshmark._core" 2>/dev/null || need_build=1

# The venv's own pip (23.2 for Python 3.11.7) predates license expressions (PEP 639): `pip show`
# would print an empty licence. Newer pips read them.
"$VPY" -c "import pip, sys; sys.exit(int(tuple(map(int, pip.__version__.split('.')[:2])) < (25, 1)))" 2>/dev/null ||
  "$VPY" -m pip install -q "pip>=25.1"

if [ "$need_build" = 1 ]; then
  say "building meshmark (Release) into .venv"
  # ccache, when installed, makes a rebuild in a fresh build tree (another checkout) cheap; not needed.
  if command -v ccache >/dev/null 2>&1 && [ -z "${CMAKE_CXX_COMPILER_LAUNCHER:-}" ]; then
    export CMAKE_CXX_COMPILER_LAUNCHER=ccache CCACHE_BASEDIR="$ROOT"
  fi
  "$VPY" -m pip install -q "scikit-build-core>=0.11" "pybind11>=2.12" "numpy>=1.23,<2" click wheel "setuptools>=68"
  extras=""
  [ "${MESHMARK_WITH_BLENDER:-0}" = 1 ] && extras="[plot]"   # ./demo.sh plots its sweep
  [ "$want_tests" = 1 ] && extras="[test]"
  "$VPY" -m pip install -q --no-build-isolation -Cbuild-dir=build/py \
    -Ccmake.define.MESHMARK_BUILD_TESTS="$([ "$want_tests" = 1 ] && echo ON || echo OFF)" ".$extras"
  echo "tests=$want_tests" > "$stamp"
fi

# An environment made before the constraints existed may hold numpy 2 (pulled by plyfile 1.1):
# bring it back within them (a no-op when it already is).
if ! "$VPY" -c "import numpy, sys; sys.exit(int(numpy.__version__.split('.')[0]) >= 2)" 2>/dev/null; then
  say "bringing numpy within tools/constraints.txt (bpy 5.0.1 needs numpy < 2)"
  "$VPY" -m pip install -q "numpy<2" "plyfile<1.1"
fi

want_blender="${MESHMARK_WITH_BLENDER:-$want_tests}"
if [ "$want_blender" = 1 ] && ! "$VPY" -c "import bpy" 2>/dev/null; then
  say "installing the bpy wheel (Blender as a Python module; about 400 MB the first time)"
  "$VPY" -m pip install -q "bpy==5.0.1"
fi
if [ "$want_tests" = 1 ] || [ "$want_blender" = 1 ]; then
  # The bpy 5.0.1 wheel for CPython 3.11 is tagged cp39-cp39 inside its own WHEEL file, so pip >= 24
  # reports "bpy 5.0.1 is not supported on this platform" although it installed and imports; that one
  # line is not an inconsistency (tools/pip_check.py), everything else is.
  "$VPY" "$ROOT/tools/pip_check.py" || { say "pip check failed: the environment is inconsistent"; exit 1; }
fi
