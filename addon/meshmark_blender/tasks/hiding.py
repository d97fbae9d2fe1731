"""Hide and reveal data in a mesh (meshmark.stego), with Blender's float32 storage in mind.

Hide writes the base mesh in float32 (``precision="float32"`` of the core), reads it back and
extracts before it reports success; if the data would not come back, every coordinate array is put
back as it was. Hiding moves every vertex a little, which erases a watermark: Hide refuses a mesh
that carries one (its keyfile reads a mark in it) unless told to replace it (``replace_watermark``).

Nothing hidden or revealed is written into the .blend: the text to hide is a session-only field, the
revealed text is kept in the session's last result (never in scene data), and neither goes into a
report line.
"""
from __future__ import annotations

import os
import time

import numpy as np

from meshmark import MeshError, stego
from meshmark.watermark import extract as wm_extract

from .. import bridge, keyfiles, targets
from .outcome import Outcome
from .watermark import read_keyfile

HIDE, REVEAL = "meshmark.stego_embed", "meshmark.stego_extract"
PRECISION = "float32"  # what Blender stores
SPREADS = ("triangle", "curvature", "global")


def watermark_on(context, obj, key=None) -> str | None:
    """The keyfile whose mark ``obj`` carries now (its base mesh, with the keyfile's other parts), or
    None. A keyfile of the object that cannot be read counts as a mark (better ask than erase)."""
    path = keyfiles.abspath(keyfiles.for_objects([obj]))
    if not path or not os.path.isfile(path):
        return None
    try:
        kf = read_keyfile(path, key)
        target, _ = targets.for_keyfile(context, kf, targets.Target([obj]))
        return path if wm_extract(target.base().mesh, keyfile=kf).detected else None
    except MeshError:
        return path


def _check_settings(tolerance, adaptive):
    if not tolerance or tolerance <= 0:
        raise MeshError(f"Shading change must be more than 0 degrees, got {tolerance}")
    if adaptive not in SPREADS:
        raise MeshError(f"Spread must be one of {', '.join(SPREADS)}, got {adaptive!r}")


def data_to_hide(message=None, message_file=None) -> tuple:
    """(bytes, file name or None) from a text or a file."""
    if message_file:
        path = keyfiles.resolve(message_file, "file to hide")
        if not os.path.isfile(path):
            raise MeshError(f"the file to hide '{path}' does not exist")
        with open(path, "rb") as f:
            data = f.read()
        if not data:
            raise MeshError(f"the file to hide '{path}' is empty")
        return data, os.path.basename(path)
    if not message:
        raise MeshError("the text is empty: type a text to hide")
    return message.encode("utf-8"), None


def hide_steps(context, obj, *, message=None, message_file=None, key=None, tolerance=1.0, adaptive="triangle",
               replace_watermark=False):
    data, fname = data_to_hide(message, message_file)
    if not key:
        raise MeshError("the key is empty: type a secret key")
    _check_settings(tolerance, adaptive)
    marked = watermark_on(context, obj, key)
    if marked and not replace_watermark:
        raise MeshError(f"'{obj.name}' carries a watermark (keyfile {os.path.basename(marked)}): hiding data moves "
                        "every vertex and would erase it. Hide in a copy of the object, or confirm to replace "
                        "the watermark")
    yield 0.1, f"Hiding data in '{obj.name}'"
    me = obj.data
    mesh = bridge.base_mesh(obj)
    t0 = time.perf_counter()
    res = stego.embed(mesh, data, key, tolerance=float(tolerance), adaptive=adaptive, precision=PRECISION)
    t_native = time.perf_counter() - t0
    V32 = res.V.astype(np.float32)
    if not np.array_equal(V32.astype(np.float64), res.V):  # the core promised float32 words
        raise MeshError("the hidden data would not survive Blender's float32 storage; nothing was changed")
    yield 0.6, "Checking that it reads back"
    saved = bridge.snapshot_coords(me)
    bridge.write_base_exact(obj, V32)
    try:  # read back what Blender stores, and extract from it
        t1 = time.perf_counter()
        got = stego.extract(bridge.base_mesh(obj), key, tolerance=float(tolerance), adaptive=adaptive,
                            precision=PRECISION)
        t_check = time.perf_counter() - t1
        if not (got.found and got.message == data):
            raise MeshError("the hidden data would not read back from this mesh as Blender stores it "
                            f"({got.reason or 'different data'}); nothing was changed. Try another Shading change")
    except BaseException:
        bridge.restore_coords(obj, saved)
        raise
    moved = float(np.abs(res.V - mesh.V).max()) / max(bridge.bbox_diagonal(mesh.V), 1e-300)
    d = {"bytes": len(data), "file": fname, "max_bytes": res.max_message_bytes, "capacity_bits": res.capacity_bits,
         "bits_per_vertex": res.bits_per_vertex, "tolerance_deg": float(tolerance), "adaptive": adaptive,
         "precision": PRECISION, "n_vertices": res.n_vertices, "read_back": True, "max_move_rel": moved,
         "replaced_watermark": bool(marked), "seconds_native": t_native + t_check}
    what = f"the file '{fname}'" if fname else f"{len(data)} bytes of text"
    text = f"Hid {what} in '{obj.name}' (room for {res.max_message_bytes} bytes); it reads back as stored"
    warn = [f"the watermark of '{obj.name}' is gone (hidden data replaced it)"] if marked else []
    return Outcome(HIDE, [obj.name], "INFO", text, d, warn)


def reveal_steps(context, obj, *, key=None, tolerance=1.0, adaptive="triangle", out_file=""):
    if not key:
        raise MeshError("the key is empty: type a secret key")
    _check_settings(tolerance, adaptive)
    out = keyfiles.resolve(out_file, "file to save to") if out_file else ""
    if out and not os.path.isdir(os.path.dirname(out)):
        raise MeshError(f"cannot write '{out}': the folder does not exist")
    yield 0.1, f"Reading '{obj.name}'"
    mesh = bridge.base_mesh(obj)
    t0 = time.perf_counter()
    got = stego.extract(mesh, key, tolerance=float(tolerance), adaptive=adaptive, precision=PRECISION)
    t_native = time.perf_counter() - t0
    d = {"found": got.found, "detected": got.found, "reason": got.reason, "tolerance_deg": float(tolerance),
         "adaptive": adaptive, "seconds_native": t_native}
    if not got.found and got.reason == stego.TOO_SMALL:
        raise MeshError(f"mesh too small to hold hidden data ({mesh.n_vertices} vertices)")
    if not got.found:
        return Outcome(REVEAL, [obj.name], "WARNING", f"Nothing hidden found in '{obj.name}' with this key and settings", d)
    data = got.message
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        text = None
    d.update(bytes=len(data), text=text, hex=data[:64].hex())
    if out:
        with open(out, "wb") as f:
            f.write(data)
        d["saved"] = out
    where = f"; saved to {out}" if out else ("; shown in the panel" if text is not None else "")
    return Outcome(REVEAL, [obj.name], "INFO", f"Found {len(data)} bytes hidden in '{obj.name}'{where}", d)
