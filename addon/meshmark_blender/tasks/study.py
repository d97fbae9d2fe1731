"""A study spec (meshmark.study) run in its own Python process, with Blender's own Python.

:mod:`..study_runner` runs in that process and prints JSON lines (planned tasks, tasks done, the
summary); :class:`StudyRun` reads them on a thread. The Python is Blender's own interpreter
(:func:`python_executable`): the interpreter of the prefix Blender's Python runs from (the bpy
module's venv; an official build's ``<version>/python/bin/python3.x``; a distribution's Blender, such
as Debian's 3.4, embeds ``/usr/lib/libpython3.x``: ``/usr/bin/python3.x``), else ``sys.executable``
when it is a Python (a Blender without a bundled Python sets it to the first ``python3.x`` on PATH,
which may be another Python altogether). The process gets
Blender's ``sys.path``, so it imports exactly what Blender imports (the extension's bundled packages).
``$MESHMARK_PYTHON`` overrides the choice.
"""
from __future__ import annotations

import importlib.util
import json
import os
import queue
import subprocess
import sys
import threading
import time

from meshmark import MeshError

RUNNER = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "study_runner.py")
NEEDS = ("pyarrow",)  # what meshmark.study imports beyond the Blender Python's own numpy
STUDY = "meshmark.study"
CURRENT = {"run": None}  # the StudyRun in progress (the panel and tests read its counts)


def python_executable() -> str | None:
    """Blender's own Python interpreter (see the module doc), or None if none is found. The prefix
    comes first: a Blender without a bundled Python sets ``sys.executable`` to whatever ``python3.x``
    its PATH finds first, which need not be the interpreter it embeds."""
    env = os.environ.get("MESHMARK_PYTHON")
    if env:
        return env
    v = sys.version_info
    names = [f"python{v.major}.{v.minor}", f"python{v.major}", "python"]
    for prefix in dict.fromkeys((sys.prefix, sys.exec_prefix, sys.base_prefix)):
        for p in [os.path.join(prefix, "bin", n) for n in names] + [os.path.join(prefix, "python.exe")]:
            if os.path.isfile(p) and os.access(p, os.X_OK):
                return p
    exe = sys.executable or ""
    return exe if os.path.basename(exe).lower().startswith("python") else None


def missing_packages() -> list:
    return [n for n in NEEDS if importlib.util.find_spec(n) is None]


def check_can_run() -> str:
    """The Python to run with; MeshError saying what is missing and how to get it."""
    missing = missing_packages()
    py = python_executable()
    if missing:
        how = f"'{py} -m pip install {' '.join(missing)}'" if py else f"pip install {' '.join(missing)}"
        raise MeshError(f"Run study needs the Python package {', '.join(missing)}, which this Blender does not have: "
                        f"install the Meshmark extension (it brings it along), or install it for Blender's Python "
                        f"with {how}")
    if py is None:
        raise MeshError("cannot find Blender's Python interpreter to run the study: set the environment variable "
                        "MESHMARK_PYTHON to a Python 3 that has meshmark's packages")
    return py


class StudyRun:
    """The study process and a thread turning its stdout lines into messages on a queue."""

    def __init__(self, spec: str, out: str):
        py = check_can_run()
        env = dict(os.environ)
        paths = [p for p in sys.path if p and os.path.isdir(p)]  # Blender's own path (extension packages too)
        env["PYTHONPATH"] = os.pathsep.join(dict.fromkeys(paths + env.get("PYTHONPATH", "").split(os.pathsep)))
        env.pop("PYTHONHOME", None)
        self.spec, self.out = spec, out
        self.proc = subprocess.Popen([py, RUNNER, spec, out], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     text=True, env=env, cwd=os.path.dirname(spec))
        self.q: queue.Queue = queue.Queue()
        self.planned = self.todo = self.done = 0
        self.summary = self.error = None
        self.stderr = ""
        self.t0 = time.monotonic()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        for line in self.proc.stdout:
            try:
                self.q.put(json.loads(line))
            except ValueError:
                pass
        self.stderr = self.proc.stderr.read()[-2000:]
        self.q.put(None)  # end of output

    def poll(self) -> bool:
        """Take in what the process said; True once it has finished."""
        finished = False
        while True:
            try:
                d = self.q.get_nowait()
            except queue.Empty:
                break
            if d is None:
                finished = True
                continue
            if "planned" in d:
                self.planned, self.todo = d["planned"], d["todo"]
            self.done = d.get("done", self.done)
            self.summary = d.get("summary", self.summary)
            self.error = d.get("error", self.error)
        if finished:
            self.proc.wait()
            if self.summary is None and self.error is None:
                self.error = f"the study process stopped (exit {self.proc.returncode}): {self.stderr.strip()[-300:]}"
        return finished

    @property
    def fraction(self) -> float:
        return self.done / self.todo if self.todo else (1.0 if self.summary is not None else 0.0)

    def text(self) -> str:
        return f"Study: {self.done} of {self.todo} tasks"

    def cancel(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(5)
            except subprocess.TimeoutExpired:  # pragma: no cover
                self.proc.kill()


def study_paths(spec: str, output_dir: str, resolve) -> tuple:
    """(spec, output folder) as absolute paths, checked; ``resolve``: the panel's path resolver."""
    spec = resolve(spec, "study file") if spec else ""
    if not spec:
        raise MeshError("choose the study file (a .toml file: Study file)")
    if not os.path.isfile(spec):
        raise MeshError(f"the study file '{spec}' does not exist")
    out = resolve(output_dir, "results folder") if output_dir else ""
    if not out:
        raise MeshError("choose the folder for the results (Results to)")
    if not os.path.isdir(os.path.dirname(out.rstrip(os.sep)) or "."):
        raise MeshError(f"the folder '{out}' cannot be made: its parent does not exist")
    return spec, out


def study_steps(spec: str, out: str, poll_seconds: float = 0.05):
    """Run the study; yields progress while the process runs. Returns the result dict (ok, figures)."""
    run = CURRENT["run"] = StudyRun(spec, out)
    try:
        while not run.poll():
            yield run.fraction, run.text()
            if poll_seconds:
                time.sleep(poll_seconds)
    except BaseException:  # stopped (Esc, GeneratorExit) or failed: end the process
        run.cancel()
        raise
    if run.error is not None:
        raise MeshError(run.error)
    s = run.summary or {}
    return {"spec": run.spec, "output_dir": run.out, "results": os.path.join(run.out, "results"),
            "planned": run.planned, "done": run.done, "todo": run.todo, "summary": s,
            "seconds": time.monotonic() - run.t0}
