"""One consistent environment (issue 11): tools/constraints.txt keeps numpy < 2 for the bpy 5.0.1
wheel; `pip check` passes; the bootstrap used by ./demo.sh and ./test.sh applies the constraints."""
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]


def test_pip_check_passes():
    r = subprocess.run([sys.executable, "-m", "pip", "check"], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr


def test_numpy_within_constraints():
    import numpy
    assert int(numpy.__version__.split(".")[0]) < 2
    text = (ROOT / "tools" / "constraints.txt").read_text()
    assert "numpy>=1.26,<2" in text
    boot = (ROOT / "tools" / "bootstrap.sh").read_text()
    assert 'export PIP_CONSTRAINT="$ROOT/tools/constraints.txt"' in boot and "pip check" in boot
    for script in ("demo.sh", "test.sh"):
        assert "tools/bootstrap.sh" in (ROOT / script).read_text()
