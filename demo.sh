#!/usr/bin/env bash
# The main job on a built-in default: a character rigged in Blender is watermarked, animated through
# a pose sweep and verified at every frame (summary table, CSV and plot in ./meshmark-demo).
# Options: --mesh FILE|.blend [--object NAME] [--keyfile K.json] [--message TEXT] ... (--help).
# Does its own setup the first time (see tools/bootstrap.sh); safe to run again.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export MESHMARK_WITH_BLENDER=1
source "$ROOT/tools/bootstrap.sh"
exec "$ROOT/.venv/bin/python" "$ROOT/examples/blender_demo.py" "$@"
