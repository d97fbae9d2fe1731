"""Studies at corpus scale: one engine for method x parameter x attack x mesh grids.

A study spec (TOML or the same dict; schema in ``docs/studies.md``) lists meshes, watermark methods
with parameter grids or random draws, attacks (single, chained, with strengths), measurements and
seeds. :func:`run` expands it into tasks keyed by a hash of their inputs, runs them on a local
process pool or on Dask, and appends the rows to Parquet partitions under ``OUT/results``; rerunning
skips finished keys. ``meshmark study run|status|plot`` is the command line.

* :mod:`.spec` — loading a spec (:func:`load_spec`: TOML, text or dict), every table read and checked;
* :mod:`.model` — the expanded spec (:class:`Spec`, the method and attack variants) and the store key
  of a marked mesh; :mod:`.validation` — TOML line numbers, the checker, the keys each table takes;
  :mod:`.expansion` — grids, random draws, labels and the task plan with its keys;
  :mod:`.meshes` — built-in meshes, loading, content digests;
* :mod:`.task` — what a worker does with a chunk of tasks of one mesh;
* :mod:`.engine` — planning, execution (process pool, Dask), Parquet, resume, status;
* :mod:`.measure` — the measurement registry (:func:`register_measurement`);
* :mod:`.kinds` — method kinds beyond the framework methods (:func:`register_method_kind`: the hook
  another module uses to add a task kind; built in: the thesis' raw-bits uses ``cho-mean-bits``,
  ``cho-variance-bits``, ``radial-bits``);
* :mod:`.store` — the content-addressed store of marked meshes (:class:`Store`);
* :mod:`.plot` — standard figures and the CSV summary;
* :mod:`.deform` — Blender's bend when bpy is present (the skinning bend is :func:`meshmark.attacks.bend`);
* :mod:`.trace_kind` — the copy-tracing method kind ``trace`` and its ``tracing`` measurement.
"""
import importlib

_EXPORTS = {
    "Spec": "model", "load_spec": "spec", "plan": "expansion", "embed_key": "model", "mesh_digest": "meshes",
    "MEASUREMENTS": "measure", "register_measurement": "measure", "Measurement": "measure",
    "register_method_kind": "kinds", "METHOD_KINDS": "kinds", "Marked": "kinds", "Read": "kinds",
    "PLUGIN_MODULES": "kinds",
    "Store": "store", "StoredMesh": "store",
    "run": "engine", "status": "engine", "load_results": "engine", "Summary": "engine",
}
__all__ = list(_EXPORTS)


def __getattr__(name):  # lazy: `meshmark --help` does not import pyarrow
    if name in _EXPORTS:
        return getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
    raise AttributeError(name)
