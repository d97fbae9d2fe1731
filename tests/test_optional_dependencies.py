"""Optional dependencies: a feature whose extra is not installed is a user error (exit 2) that gives the
exact pip line, raised before any work starts. The child processes hide the package from the import
system (a meta-path finder that refuses it), as in an environment where it was never installed."""
import os
import pathlib
import subprocess
import sys

import pytest

from meshmark.optional import MissingDependency, install_line, require

ROOT = pathlib.Path(__file__).resolve().parents[1]
HIDE = """
import sys
class _Hide:
    def find_spec(self, name, path=None, target=None):
        if name.split('.')[0] in {hidden!r}:
            raise ImportError(f"No module named {{name!r}}")
sys.meta_path.insert(0, _Hide())
from meshmark.cli import main
sys.exit(main())
"""


def _run_without(hidden, *args, cwd=None):
    code = HIDE.format(hidden=set(hidden))
    return subprocess.run([sys.executable, "-c", code, *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=300)


def test_dask_study_without_distributed_is_exit_2_with_the_install_line(tmp_path):
    out = tmp_path / "out"
    r = _run_without({"distributed", "dask"}, "study", "run", ROOT / "examples/studies/smoke.toml",
                     "--out", out, "--dask", "local:2")
    assert r.returncode == 2, r.stderr
    assert "pip install 'meshmark[study]'" in r.stderr and "internal error" not in r.stderr
    assert not out.exists()  # refused before anything was planned or written


def test_study_plot_without_matplotlib_is_exit_2_with_the_install_line(tmp_path):
    out = tmp_path / "o"
    spec = tmp_path / "s.toml"
    spec.write_text('[study]\nname = "t"\nseeds = [0]\n[meshes]\npaths = ["builtin:torus"]\n'
                    '[[methods]]\nname = "none"\n[[attacks]]\nname = "noise"\nparams = { strength = 0.001 }\n'
                    '[measurements]\nlist = ["rmse"]\n')
    r = subprocess.run([sys.executable, "-m", "meshmark.cli", "study", "run", spec, "--out", out], capture_output=True,
                       text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    r = _run_without({"matplotlib"}, "study", "plot", out)
    assert r.returncode == 2, r.stderr
    assert "pip install 'meshmark[plot]'" in r.stderr


def test_require_names_feature_and_extra():
    assert require("matplotlib", "plots").__name__ == "matplotlib"  # installed with meshmark[test]
    with pytest.raises(MissingDependency, match=r"--dask needs .*dask\[distributed\].*meshmark\[study\]"):
        try:
            sys.modules["distributed"] = None  # an import of it fails, as when it is not installed
            require("distributed", "--dask")
        finally:
            del sys.modules["distributed"]
    assert install_line("auditwheel") == "pip install 'meshmark[build]'  (or: pip install 'auditwheel')"


def test_obj_copies_need_no_gltf_library(tmp_path):
    """pygltflib is needed for glTF files only: issuing and tracing OBJ copies work without it (the add-on
    in an interpreter that lacks it issued copies with 'internal error: No module named pygltflib')."""
    from conftest import shared_mesh
    reg, out = tmp_path / "r.sqlite", tmp_path / "copies"
    r = _run_without({"pygltflib"}, "issue", shared_mesh("classic/cow.obj"), out, "--copies", "2", "--key", "k",
                     "--registry", reg)
    assert r.returncode == 0, r.stderr
    copies = sorted(out.iterdir())
    assert len(copies) == 2
    r = _run_without({"pygltflib"}, "trace", copies[1], "--registry", reg)
    assert r.returncode == 0 and "0002" in r.stdout, r.stdout + r.stderr
