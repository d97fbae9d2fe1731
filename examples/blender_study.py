"""Run a study spec with the add-on's study operator (from a script it waits; from the panel it runs
in the background with a progress bar, Esc stops it).

    python examples/blender_study.py --spec examples/studies/smoke.toml --out out/smoke
"""
import argparse

from _blender_common import argv, result, start

import bpy

ap = argparse.ArgumentParser()
ap.add_argument("--spec", required=True, help="a study spec (.toml, docs/studies.md)")
ap.add_argument("--out", required=True, help="folder for the results")
a = ap.parse_args(argv())
start()
bpy.ops.meshmark.study(spec=a.spec, out=a.out)
r = result()
s = r["summary"]
print(f"study: {s['ok']} ok, {s['mesh_error']} mesh errors, {s['failed']} failed of {r['planned']}; results in {r['results']}")
