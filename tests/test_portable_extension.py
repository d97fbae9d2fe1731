"""The Blender extension is portable (issue 11): its wheel is repaired by auditwheel to a manylinux
tag, the zip installs into a fresh virtual environment that holds only the bpy wheel (and what bpy
itself requires), every library of the installed native module resolves to the wheel's own folder or
to the base system, every operator of the installed add-on runs (Run study included, with the
pyarrow and scikit-learn it brings), ``pip check`` passes over its packages, and a new Blender process
enables it by its module name ``bl_ext.user_default.meshmark``. The legacy Blender 3.x package is
a zip whose single top-level folder is the add-on.

Runtime: the wheel is built in the bootstrap's build tree (nothing recompiled) and the fresh bpy
environment is made once in build/fresh-bpy-venv from the pip cache, then reused; the extension goes
into a throw-away Blender user directory each run.
"""
import json
import os
import pathlib
import re
import subprocess
import sys
import zipfile

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
BASE_SYSTEM = re.compile(r"^(linux-vdso|ld-linux-x86-64|libc|libm|libstdc\+\+|libgcc_s|libpthread|libdl|librt)\.so")

CHECK = r"""
import json, os, subprocess, sys
import bpy
user = os.environ["BLENDER_USER_RESOURCES"]
bpy.ops.extensions.package_install_files(filepath=sys.argv[1], repo="user_default", enable_on_install=True)
import meshmark, meshmark._core
assert meshmark.__file__.startswith(user), meshmark.__file__
so = meshmark._core.__file__
ldd = subprocess.run(["ldd", so], capture_output=True, text=True, check=True).stdout
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(user, "scene.blend"))  # '//' is the user folder
bpy.ops.mesh.primitive_monkey_add()
bpy.ops.object.modifier_add(type="SUBSURF")
bpy.context.object.modifiers[0].levels = 2
bpy.ops.object.modifier_apply(modifier=bpy.context.object.modifiers[0].name)
ran = {}
def op(name, **kw):
    ran[name] = sorted(getattr(bpy.ops.meshmark, name)(**kw))
    return json.loads(bpy.context.scene.meshmark.last_result)
bpy.context.scene.meshmark.key = "portable"
op("capacity", method="cho-mean", message="P")
r = op("embed", message="P", method="cho-mean")  # keyfile //Suzanne.meshmark.json
assert r["keyfile"] == os.path.join(user, "Suzanne.meshmark.json"), r["keyfile"]
v = op("verify")
op("save_keyfile", filepath=os.path.join(user, "copy.json"))
op("load_keyfile", filepath=os.path.join(user, "copy.json"))
op("select_parts") if bpy.ops.meshmark.select_parts.poll() else None
f = op("deformation_study", frame_start=1, frame_end=2, output_dir=os.path.join(user, "frames"))
op("issue_copies", copies=2, registry="//copies.sqlite", output_dir="//copies")
t = op("trace", registry="//copies.sqlite")
bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=5, location=(3, 0, 0))
op("stego_embed", message="bundled")
st = op("stego_extract")
op("analyze")
d = op("steganalysis_detect")  # scikit-learn, bundled
spec = os.path.join(user, "s.toml")
open(spec, "w").write(sys.argv[2])
sr = op("study", spec=spec, out=os.path.join(user, "study"))  # pyarrow, bundled; Blender's own Python
import cryptography, sklearn, pyarrow  # bundled with the extension
for m in (cryptography, sklearn, pyarrow):
    assert m.__file__.startswith(user), m.__file__
from bl_ext.user_default.meshmark import api  # the pipeline API, in the extension's namespace
print("RESULT " + json.dumps({"so": so, "ldd": ldd, "detected": v["detected"], "message": v["message"],
                              "stego_text": st.get("text"), "ran": ran, "frames": f["summary"]["detected_frames"],
                              "trace": t["copy"], "state": d["state"], "study_ok": sr["summary"]["ok"],
                              "study_planned": sr["planned"], "api": api.__name__,
                              "site": os.path.dirname(os.path.dirname(meshmark.__file__))}))
"""
# A new process: the extension installed above is enabled by its module name, then scripted.
AGAIN = r"""
import json, sys, bpy
import addon_utils  # on the path once bpy is imported
addon_utils.enable("bl_ext.user_default.meshmark", default_set=True)
from bl_ext.user_default.meshmark import api
bpy.ops.mesh.primitive_monkey_add()
print("AGAIN " + json.dumps({"capacity": api.capacity(message="P", method="cho-mean").capacity,
                             "operators": hasattr(bpy.ops.meshmark, "embed")}))
"""


def _fresh_bpy_venv() -> pathlib.Path:
    venv = ROOT / "build" / "fresh-bpy-venv"
    py = venv / "bin" / "python"
    if not py.exists():
        subprocess.run([sys.executable, "-m", "venv", "--clear", str(venv)], check=True)
        env = {**os.environ, "PIP_CONSTRAINT": str(ROOT / "tools" / "constraints.txt")}
        subprocess.run([str(py), "-m", "pip", "install", "-q", "bpy==5.0.1"], check=True, env=env)
    names = subprocess.run([str(py), "-m", "pip", "list", "--format=json"], capture_output=True, text=True,
                           check=True).stdout
    pkgs = {p["name"].lower() for p in json.loads(names)}
    assert "bpy" in pkgs and not any("meshmark" in p for p in pkgs), pkgs
    return py


@pytest.fixture(scope="module")
def dist(tmp_path_factory):
    out = tmp_path_factory.mktemp("dist")
    r = subprocess.run([sys.executable, str(ROOT / "addon" / "build_extension.py"), "--reuse-dev-build", "--out", str(out)],
                       capture_output=True, text=True, cwd=ROOT, timeout=1500)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    return out


def test_wheel_is_manylinux(dist):
    wheels = list((ROOT / "build" / "ext-wheels-repaired").glob("meshmark-*manylinux_2_*_x86_64.whl"))
    assert len(wheels) == 1, wheels
    bindir = os.path.dirname(sys.executable)
    r = subprocess.run([sys.executable, "-m", "auditwheel", "show", str(wheels[0])], capture_output=True, text=True,
                       env={**os.environ, "PATH": bindir + os.pathsep + os.environ["PATH"]})
    assert r.returncode == 0, r.stderr
    assert re.search(r'consistent\s+with the following platform tag:\s+"manylinux_2_\d+_x86_64"', r.stdout), r.stdout
    with zipfile.ZipFile(wheels[0]) as z:
        vendored = [n for n in z.namelist() if n.startswith("meshmark.libs/")]
    assert any("cholmod" in n for n in vendored) and any("openblas" in n for n in vendored), vendored
    ext = next(dist.glob("meshmark-*[0-9].zip"))
    with zipfile.ZipFile(ext) as z:
        assert f"wheels/{wheels[0].name}" in z.namelist()
        assert "manylinux" in z.read("blender_manifest.toml").decode()


def test_licence_and_notices_ship_in_wheel_and_zips(dist):
    """GPL-3.0-or-later (CGAL's GPL packages are compiled in), with the licence text and the third-party
    notices inside the wheel's .dist-info, the extension zip and the legacy zip."""
    gpl = (ROOT / "LICENSE").read_text()
    assert "GNU GENERAL PUBLIC LICENSE" in gpl and "Version 3, 29 June 2007" in gpl
    wheel = next((ROOT / "build" / "ext-wheels-repaired").glob("meshmark-*manylinux_2_*_x86_64.whl"))
    with zipfile.ZipFile(wheel) as z:
        names = z.namelist()
        meta = z.read(next(n for n in names if n.endswith(".dist-info/METADATA"))).decode()
        assert "License-Expression: GPL-3.0-or-later" in meta
        lic = [n for n in names if n.endswith(".dist-info/licenses/LICENSE")]
        notices = [n for n in names if n.endswith(".dist-info/licenses/THIRD_PARTY_NOTICES.md")]
        assert lic and notices and z.read(lic[0]).decode() == gpl
        assert "CHOLMOD" in z.read(notices[0]).decode() and "CGAL" in z.read(notices[0]).decode()
    ext = next(dist.glob("meshmark-*[0-9].zip"))
    with zipfile.ZipFile(ext) as z:
        assert z.read("LICENSE").decode() == gpl and "OpenBLAS" in z.read("THIRD_PARTY_NOTICES.md").decode()
        assert 'license = ["SPDX:GPL-3.0-or-later"]' in z.read("blender_manifest.toml").decode()
    legacy = next(dist.glob("meshmark_blender-*-legacy.zip"))
    with zipfile.ZipFile(legacy) as z:
        assert z.read("meshmark_blender/LICENSE").decode() == gpl
        assert "pybind11" in z.read("meshmark_blender/THIRD_PARTY_NOTICES.md").decode()


def test_legacy_zip_has_one_top_level_folder(dist):
    legacy = next(dist.glob("meshmark_blender-*-legacy.zip"))
    with zipfile.ZipFile(legacy) as z:
        names = z.namelist()
    assert {n.split("/")[0] for n in names} == {"meshmark_blender"}
    assert "meshmark_blender/__init__.py" in names and not any("__pycache__" in n for n in names)


def test_installs_in_fresh_bpy_venv_and_embeds(dist, tmp_path):
    py = _fresh_bpy_venv()
    ext = next(dist.glob("meshmark-*[0-9].zip"))
    user = tmp_path / "user"
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env["BLENDER_USER_RESOURCES"] = str(user)
    spec = ('[study]\nname = "portable"\nseeds = [0]\npayload_bits = 8\n[meshes]\npaths = ["builtin:default"]\n'
            '[[methods]]\nname = "cho-mean"\n[[attacks]]\nname = "none"\n[measurements]\nlist = ["nc"]\n')
    r = subprocess.run([str(py), "-c", CHECK, str(ext), spec], capture_output=True, text=True, env=env, cwd=tmp_path,
                       timeout=900)
    line = [x for x in r.stdout.splitlines() if x.startswith("RESULT ")]
    assert r.returncode == 0 and line, r.stdout[-3000:] + r.stderr[-3000:]
    d = json.loads(line[0][7:])
    assert d["detected"] is True and d["message"] == "P"
    assert d["stego_text"] == "bundled" and d["frames"] == 2 and d["trace"] is None
    assert d["state"] in ("marked", "clean", "cannot_judge") and d["study_ok"] == d["study_planned"] == 1
    every = {"capacity", "embed", "verify", "save_keyfile", "load_keyfile", "deformation_study", "issue_copies",
             "trace", "stego_embed", "stego_extract", "analyze", "steganalysis_detect", "study"}
    assert every <= set(d["ran"]) and all(v == ["FINISHED"] for v in d["ran"].values()), d["ran"]
    # every package the extension brings is consistent with what it runs beside (bpy's numpy)
    pc = subprocess.run([str(py), "-m", "pip", "check"], capture_output=True, text=True,
                        env={**env, "PYTHONPATH": d["site"]})
    assert pc.returncode == 0, pc.stdout + pc.stderr
    listed = subprocess.run([str(py), "-m", "pip", "list", "--path", d["site"], "--format=json"], capture_output=True,
                            text=True, check=True).stdout
    assert {"meshmark", "scipy", "scikit-learn", "pyarrow", "cryptography", "click", "tqdm"} <= \
        {p["name"].lower() for p in json.loads(listed)}
    # a new Blender process: enabled by its module name, scripted through its API
    a = subprocess.run([str(py), "-c", AGAIN], capture_output=True, text=True, env=env, cwd=tmp_path, timeout=300)
    again = [x for x in a.stdout.splitlines() if x.startswith("AGAIN ")]
    assert a.returncode == 0 and again, a.stdout[-2000:] + a.stderr[-2000:]
    assert json.loads(again[0][6:]) == {"capacity": json.loads(again[0][6:])["capacity"], "operators": True}
    site = d["site"]
    for row in d["ldd"].splitlines():
        row = row.strip()
        if not row:
            continue
        name = row.split()[0]
        target = row.split("=>")[1].split("(")[0].strip() if "=>" in row else name
        assert "not found" not in row, row
        ok = target.startswith(site) or BASE_SYSTEM.match(os.path.basename(name))
        assert ok, f"{row}: neither in the wheel ({site}) nor a base-system library"
