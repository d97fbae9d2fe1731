#!/usr/bin/env bash
# The main job on a built-in default: for now, meshmark describes its built-in mesh.
# Does its own setup the first time (see tools/bootstrap.sh); safe to run again.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$ROOT/tools/bootstrap.sh"
"$ROOT/.venv/bin/meshmark" info "$@"
