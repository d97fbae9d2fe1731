"""``meshmark stego embed | extract | capacity`` (thesis §4.3.2). Registered by one line in meshmark.cli."""
from __future__ import annotations

import os
import sys

import click

from .. import jsonout
import numpy as np

from .._core import MeshError

_ADAPTIVE = click.Choice(["triangle", "curvature", "global"])
_PRECISION = click.Choice(["fixed32", "float32", "float64"])


def _common(f):
    f = click.option("--tolerance", type=float, default=1.0, show_default=True,
                     help="Mean normal degradation budget, degrees, (0, 180] (eq. 4.3.19).")(f)
    f = click.option("--adaptive", type=_ADAPTIVE, default="triangle", show_default=True,
                     help="Levels: per triangle with eps_j = tolerance (Table 4.4), curvature-dependent "
                          "eps_j (eq. 4.3.24), or one global level (eq. 4.3.21).")(f)
    f = click.option("--level", type=int, default=None,
                     help="Override: keep this many most significant bits everywhere (0..32).")(f)
    return f


def _key_options(f):
    f = click.option("--key", default=None, help="Passphrase (stretched with scrypt).")(f)
    f = click.option("--key-file", type=click.Path(dir_okay=False), default=None,
                     help="Read the key as raw bytes from this file.")(f)
    return f


def _key(key, key_file):
    if (key is None) == (key_file is None):
        raise MeshError("give exactly one of --key TEXT or --key-file F")
    if key_file is not None:
        try:
            with open(key_file, "rb") as fh:
                return fh.read()
        except OSError as exc:
            raise MeshError(f"--key-file {key_file}: {exc.strerror}") from None
    return key


def _check_common(tolerance, level) -> None:
    """--tolerance in (0, 180] degrees and --level in 0..32, before the mesh is read (exit 2 naming
    the option)."""
    from ..ranges import check_float, check_int
    check_float("tolerance", tolerance, 0.0, 180.0, low_open=True)
    if level is not None:
        check_int("level", level, 0, 32)


def _adaptive_arg(adaptive: str):
    return {"triangle": True, "curvature": "curvature", "global": False}[adaptive]


_emit = jsonout.emit


def check_stego_output(path: str, force: bool = False, precision: str | None = None) -> None:
    """MeshError (exit 2) before any work when ``path`` cannot take a stego mesh: an unknown or
    unsuitable format (glTF with a precision other than float32), a missing or read-only folder, or
    an existing file without ``force``."""
    from ..atomic import check_output
    ext = os.path.splitext(path)[1].lower()
    if ext == ".stl":
        raise MeshError("STL cannot carry stego data (it has no shared vertices: the reader welds them); "
                        "use .ply, .obj or .off")
    if ext not in (".ply", ".obj", ".off", ".glb", ".gltf"):
        raise MeshError(f"output {path!r}: unknown mesh format (expected .ply, .obj, .off, .glb or .gltf)")
    check_output(path, force, "stego mesh")
    if ext in (".glb", ".gltf") and precision not in (None, "float32"):
        raise MeshError(f"glTF stores positions as float32: use --precision float32 (got {precision})")


def write_verified(path: str, mesh, V: np.ndarray, precision: str, check, source=None,
                   overwrite: bool = False) -> None:
    """Write ``mesh`` with positions ``V`` to ``path`` so that reading it back gives V exactly, then
    run ``check(read_mesh)`` (True = the message comes back); only then move it into place.
    MeshError (and no file) otherwise; an existing ``path`` is replaced only with ``overwrite=True``."""
    from ..atomic import Staged
    from ..io import read_mesh, write_mesh

    check_stego_output(path, overwrite, precision)
    ext = os.path.splitext(path)[1].lower()
    if ext in (".glb", ".gltf"):  # ``source``: the GltfInfo of the asset read (docs/gltf.md)
        return _write_verified_gltf(path, source, V, precision, check, overwrite)
    with Staged([path], what=["stego mesh"], overwrite=overwrite) as st:
        tmp = st.temps[0]
        # PLY: binary, float for float32 carriers, double otherwise; OBJ/OFF: 17 significant digits
        # (enough for any float64, hence for float32 and fixed32 words).
        write_mesh(tmp, mesh.with_vertices(V), binary=True, float32=(precision == "float32" and ext == ".ply"),
                   precision=17)
        back = read_mesh(tmp)
        if back.V.shape != V.shape or not np.array_equal(back.V, V):
            bad = int(np.argmax(np.any(back.V != V, axis=1))) if back.V.shape == V.shape else -1
            raise MeshError(f"the written file does not store the marked vertices exactly (vertex {bad}); "
                            "nothing was written")
        if not (np.array_equal(back.face_indices, mesh.face_indices)
                and np.array_equal(back.face_offsets, mesh.face_offsets)):
            raise MeshError("the written file does not store the faces as given; nothing was written")
        if not check(back):
            raise MeshError("the message does not come back from the written file; nothing was written")
        st.commit()


def _write_verified_gltf(path: str, info, V: np.ndarray, precision: str, check, overwrite: bool) -> None:
    """write_verified for glTF: the asset the input was read from (``info``, its GltfInfo) with the
    marked positions, written first into a temporary folder beside ``path`` and read back there."""
    from ..atomic import temp_folder
    from ..gltf import plan_write, write_positions
    from ..io import read_mesh

    if info is None:
        raise MeshError("stego into a glTF needs a glTF input (the marked positions are written back into the asset)")
    if precision != "float32":
        raise MeshError(f"glTF stores positions as float32: use --precision float32 (got {precision})")
    with temp_folder(path) as d:
        tmp = os.path.join(d, os.path.basename(path))
        for p, data in plan_write(info, V, tmp):
            with open(p, "wb") as f:
                f.write(data)
        back = read_mesh(tmp)
        if back.V.shape != V.shape or not np.array_equal(back.V, V) or not check(back):
            raise MeshError("the message does not come back from the written asset; nothing was written")
    write_positions(info, V, path, overwrite=overwrite)


@click.group("stego")
def stego():
    """High-capacity steganography in the vertex coordinates (thesis §4.3.2)."""


@stego.command("embed")
@click.argument("inp", metavar="IN")
@click.argument("out", metavar="OUT")
@click.option("--message", default=None, help="Text to hide (UTF-8).")
@click.option("--message-file", type=click.Path(dir_okay=False), default=None, help="Hide the bytes of this file.")
@_key_options
@_common
@click.option("--precision", type=_PRECISION, default="fixed32", show_default=True,
              help="The storage the marked coordinates must survive exactly.")
@click.option("--force", is_flag=True, default=False, help="Overwrite an existing OUT.")
@jsonout.option()
def embed_cmd(inp, out, message, message_file, key, key_file, tolerance, adaptive, level, precision, force, as_json):
    """Hide a message in IN and write OUT (.ply/.obj/.off), verified by reading OUT back.
    An existing OUT is replaced only with --force."""
    from ..io import read_mesh
    from . import embed, extract

    if (message is None) == (message_file is None):
        raise MeshError("give exactly one of --message TEXT or --message-file F")
    _check_common(tolerance, level)  # the options first, then the output, before any work
    check_stego_output(out, force, precision)
    if message_file is not None:
        try:
            with open(message_file, "rb") as fh:
                payload = fh.read()
        except OSError as exc:
            raise MeshError(f"--message-file {message_file}: {exc.strerror}") from None
    else:
        payload = message.encode("utf-8")
    k = _key(key, key_file)
    mesh, fmt = read_mesh(inp, return_info=True)
    kw = dict(tolerance=tolerance, adaptive=_adaptive_arg(adaptive), precision=precision, levels=level)
    res = embed(mesh, payload, k, **kw)

    def check(back):
        r = extract(back, k, **kw)
        return r.found and r.message == payload

    write_verified(out, mesh, res.V, precision, check, source=fmt.get("gltf"), overwrite=force)
    from ..metrics import normal_degradation
    deg = float(normal_degradation(mesh, res.V, degrees=True))
    d = {"input": inp, "output": out, "message_bytes": len(payload), "precision": precision,
         "tolerance_deg": tolerance, "adaptive": adaptive, "capacity_bits": res.capacity_bits,
         "bits_per_vertex": res.bits_per_vertex, "max_message_bytes": res.max_message_bytes,
         "e_nonzero_ratio": res.e_nonzero_ratio, "normal_degradation_deg": deg, "verified": True}
    _emit(d, as_json, f"{out}: {len(payload)} bytes hidden ({precision}, {tolerance} deg, {adaptive}); "
                      f"capacity {res.bits_per_vertex:.2f} bits/vertex, up to {res.max_message_bytes} bytes; "
                      f"mean normal degradation {deg:.3f} deg; read back and verified")


@stego.command("extract")
@click.argument("inp", metavar="IN")
@_key_options
@_common
@click.option("--precision", type=_PRECISION, default="fixed32", show_default=True)
@click.option("--out-file", type=click.Path(dir_okay=False), default=None, help="Write the message bytes here.")
@click.option("--force", is_flag=True, default=False, help="Overwrite an existing --out-file.")
@jsonout.option()
def extract_cmd(inp, key, key_file, tolerance, adaptive, level, precision, out_file, force, as_json):
    """Recover the message hidden in IN. Exit status: 0 found, 1 no message (wrong key, damaged, clean).
    A UTF-8 message is printed; binary bytes go to --out-file or a redirected output, never to a
    terminal. An existing --out-file is replaced only with --force."""
    from ..atomic import check_output, write_bytes
    from ..io import read_mesh
    from . import extract

    _check_common(tolerance, level)
    if out_file is not None:
        check_output(out_file, force, "message file")  # before any work
    k = _key(key, key_file)
    mesh = read_mesh(inp)
    r = extract(mesh, k, tolerance=tolerance, adaptive=_adaptive_arg(adaptive), precision=precision, levels=level)
    if not r.found:
        _emit({"input": inp, "detected": False, "message": None, "reason": r.reason}, as_json,
              f"{inp}: no message ({r.reason})", aliases={"found": "detected"})
        sys.exit(1)
    if out_file is not None:
        write_bytes(out_file, r.message, what="message file", overwrite=force)
    try:
        text = r.message.decode("utf-8")
    except UnicodeDecodeError:
        text = None
    d = {"input": inp, "detected": True, "message_bytes": len(r.message), "message": text if out_file is None else None,
         "out_file": out_file}
    if as_json:
        _emit(d, True, "", aliases={"found": "detected"})
    elif out_file is not None:
        click.echo(f"{inp}: {len(r.message)} bytes written to {out_file}")
    elif text is not None:
        click.echo(text)
    elif sys.stdout.isatty():  # binary bytes would garble the terminal: say where they can go instead
        click.echo(f"{inp}: a binary message of {len(r.message)} bytes was found; it is not printed to a "
                   "terminal: use --out-file FILE or redirect the output (> FILE)", err=True)
    else:
        sys.stdout.buffer.write(r.message)
        sys.stdout.buffer.flush()
    sys.exit(0)


@stego.command("capacity")
@click.argument("inp", metavar="IN")
@_common
@click.option("--precision", type=click.Choice(["all", "fixed32", "float32", "float64"]), default="all",
              show_default=True)
@jsonout.option()
def capacity_cmd(inp, tolerance, adaptive, level, precision, as_json):
    """Hiding capacity of IN per storage precision (bits per vertex, longest message)."""
    from ..io import read_mesh
    from . import capacity

    _check_common(tolerance, level)
    mesh = read_mesh(inp)
    precs = ["fixed32", "float32", "float64"] if precision == "all" else [precision]
    rows = [capacity(mesh, tolerance=tolerance, adaptive=_adaptive_arg(adaptive), precision=p, levels=level)
            for p in precs]
    lines = [f"{inp}: {mesh.n_vertices} vertices, tolerance {tolerance} deg ({adaptive}), levels "
             f"{rows[0]['level_min']}..{rows[0]['level_max']}, thesis 32-bit count "
             f"{rows[0]['thesis_bits_per_vertex']:.2f} bits/vertex",
             f"{'precision':<10} {'bits':>12} {'bits/vertex':>12} {'max message bytes':>18}"]
    lines += [f"{r['precision']:<10} {r['capacity_bits']:>12} {r['bits_per_vertex']:>12.2f} {r['max_message_bytes']:>18}"
              for r in rows]
    _emit({"input": inp, "tolerance_deg": tolerance, "adaptive": adaptive, "rows": rows}, as_json, "\n".join(lines))
