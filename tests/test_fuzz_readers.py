"""Fuzz test of the mesh readers (issue 11): 2,000 seeded mutations of real files in every format
(OBJ, ASCII/binary OFF, ASCII/binary PLY with float, double, int16 and uint8 coordinates, ASCII/binary
STL), each read in its own forked child process. No case may die of a signal or hang, raise anything
but MeshError, report an allocation failure, give a non-UTF-8 message, or grow its peak RSS by more
than 20 x the file size + 64 MB. The engine is tests/fuzz_readers.py; bench/fuzz_readers.py runs
a larger campaign (more cases, the large Horse/Bunny/Elephant files, mesh_info on what reads).
"""
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def test_fuzz_readers_2000_cases(tmp_path):
    keep = tmp_path / "failures"
    r = subprocess.run([sys.executable, os.path.join(HERE, "fuzz_readers.py"), "--cases", "2000", "--seed", "11",
                        "--keep", str(keep)], capture_output=True, text=True, timeout=600)
    assert r.stdout, r.stderr[-3000:]
    d = json.loads(r.stdout)
    assert d["cases"] == 2000
    assert set(d["per_format"]) == {"obj", "off", "ply", "stl"} and min(d["per_format"].values()) >= 200
    # both outcomes occur: the mutations are not all fatal, and not all harmless
    assert d["counts"].get("ok", 0) >= 50 and d["counts"].get("meshError", 0) >= 1000, d["counts"]
    assert d["failures"] == [], json.dumps(d["failures"][:5], indent=1)
    assert r.returncode == 0
    print(f"fuzz: {d['counts']} in {d['seconds']} s; closest to the budget {d['closest_to_budget']}; "
          f"largest growth per byte (files over 100 kB) {d['largest_growth_per_byte_of_files_over_100kB']}")


def test_fuzz_gltf_readers(tmp_path):
    """glTF (issue 26): 300 seeded cases over Fox.glb and hand-built .glb/.gltf octahedra (interleaved,
    sparse, quantized, strips, morph targets): byte mutations of the container and JSON mutations
    repacked with consistent lengths (hostile counts, offsets, strides, indices, types, node cycles,
    deep nesting, cut JSON; tests/fuzz_gltf.py). Same rules as above."""
    keep = tmp_path / "failures"
    r = subprocess.run([sys.executable, os.path.join(HERE, "fuzz_readers.py"), "--cases", "300", "--seed", "26",
                        "--formats", "glb,gltf", "--keep", str(keep)], capture_output=True, text=True, timeout=600)
    assert r.stdout, r.stderr[-3000:]
    d = json.loads(r.stdout)
    assert d["cases"] == 300 and d["per_format"] == {"glb": 150, "gltf": 150}
    assert d["counts"].get("ok", 0) >= 30 and d["counts"].get("meshError", 0) >= 150, d["counts"]
    assert d["failures"] == [], json.dumps(d["failures"][:5], indent=1)
    assert r.returncode == 0
