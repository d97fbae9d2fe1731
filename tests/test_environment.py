"""One consistent environment: what tools/bootstrap.sh installs for ./demo.sh and ./test.sh obeys
tools/constraints.txt (numpy < 2 for the bpy 5.0.1 wheel), and pip finds no broken requirement
(tools/pip_check.py: `pip check`, less bpy's mis-tagged WHEEL file; and it does fail on a real one)."""
import pathlib
import subprocess
import sys
from importlib import metadata

from packaging.requirements import Requirement

ROOT = pathlib.Path(__file__).resolve().parents[1]


def test_pip_check_passes():
    r = subprocess.run([sys.executable, ROOT / "tools" / "pip_check.py"], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr


def test_pip_check_fails_on_a_broken_requirement(tmp_path):
    """A distribution that requires a package nobody installed is reported (exit 1, the line shown)."""
    info = tmp_path / "brokendist-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: brokendist\nVersion: 1.0\n"
                                   "Requires-Dist: no-such-package-meshmark>=1\n")
    r = subprocess.run([sys.executable, ROOT / "tools" / "pip_check.py"], capture_output=True, text=True,
                       env={"PYTHONPATH": str(tmp_path), "PATH": "/usr/bin:/bin"})
    assert r.returncode == 1 and "brokendist 1.0 requires no-such-package-meshmark" in r.stdout, r.stdout + r.stderr


def test_installed_versions_obey_the_constraints():
    lines = [x.split("#")[0].strip() for x in (ROOT / "tools" / "constraints.txt").read_text().splitlines()]
    reqs = [Requirement(x) for x in lines if x]
    assert {r.name for r in reqs} >= {"numpy"}
    for r in reqs:
        try:
            v = metadata.version(r.name)
        except metadata.PackageNotFoundError:
            continue
        assert r.specifier.contains(v, prereleases=True), f"{r.name} {v} outside {r.specifier}"
    import numpy
    assert int(numpy.__version__.split(".")[0]) < 2  # the bpy 5.0.1 wheel's ABI


def test_bpy_imports_beside_meshmark():
    code = "import bpy, numpy, meshmark; print(bpy.app.version_string, numpy.__version__)"
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0 and r.stdout.startswith("5.0.1"), r.stderr[-2000:]
