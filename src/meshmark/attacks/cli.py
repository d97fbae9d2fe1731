"""``meshmark attack``: one attack (``--type``) or a chain (``--chain``) of meshmark.attacks (registered by
one line in meshmark.cli)."""
from __future__ import annotations

import math

import click

from .. import jsonout
from .._core import MeshError


# CLI option -> keyword of the attack functions (meshmark.attacks); an option given to an attack that
# does not take it is an error, not silently ignored.
_ATTACK_OPTIONS = {
    "strength": "strength", "kind": "kind", "lam": "lam", "iterations": "iterations", "weights": "weights",
    "bits": "bits", "word": "word", "fraction": "fraction", "scheme": "scheme", "levels": "levels",
    "axis": "axis", "angle": "angle", "normal": "normal", "offset": "offset", "factor": "factor",
    "fmt": "format", "decimals": "decimals", "degrees": "degrees", "joint": "joint", "width": "width",
    "along": "along", "absolute": "absolute", "edge_length": "edge_length", "seed": "seed",
}
_OPTION_NAMES = {"lam": "--lambda", "fmt": "--format", "edge_length": "--edge-length"}


def _vec(text, name):
    if text is None:
        return None
    try:
        parts = [float(x) for x in text.replace(",", " ").split()]
    except ValueError:
        parts = []
    if len(parts) != 3:
        raise MeshError(f"--{name} needs 3 numbers like 1,0,0, got {text!r}")
    return parts


_INF = math.inf
# Ranges of the numeric options, checked before the mesh is read (exit 2 naming the option); the
# attack functions check them again for API callers. Per type where the meaning differs.
_FLOAT_RANGES = {  # dest -> (low, high, low_open, high_open)
    "strength": (0.0, _INF, False, True), "lam": (-_INF, _INF, True, True), "edge_length": (0.0, 100.0, True, False),
    "degrees": (-_INF, _INF, True, True), "joint": (-_INF, _INF, True, True), "width": (0.0, _INF, True, True),
    "angle": (-_INF, _INF, True, True), "factor": (0.0, _INF, True, True),
}
_FRACTION = {"simplify": (0.0, 1.0, True, False), "crop": (0.0, 1.0, False, True)}
_INT_RANGES = {"iterations": (0, 10_000), "bits": (1, 52), "levels": (0, 6), "decimals": (0, 17),
               "seed": (0, 2 ** 64 - 1)}
_PER_TYPE_INT = {("remesh", "iterations"): (1, 100)}


def check_options(name, opts: dict) -> None:
    """ParameterError (exit 2, the option named) for a numeric option outside its range."""
    from ..ranges import check_float, check_int
    for k, v in opts.items():
        if v is None:
            continue
        if k in _INT_RANGES:
            check_int(k, v, *_PER_TYPE_INT.get((name, k), _INT_RANGES[k]))
        elif k == "fraction":
            lo, hi, lo_open, hi_open = _FRACTION.get(name, (0.0, 1.0, False, False))
            check_float(k, v, lo, hi, low_open=lo_open, high_open=hi_open)
        elif k in _FLOAT_RANGES:
            lo, hi, lo_open, hi_open = _FLOAT_RANGES[k]
            check_float(k, v, lo, hi, low_open=lo_open, high_open=hi_open)

@click.command()
@click.argument("mesh_in", metavar="IN")
@click.argument("mesh_out", metavar="OUT")
@click.option("--type", "name", default=None, metavar="NAME",
              help="similarity, rotate, translate, scale, reorder, noise, smooth, quantize, dither, simplify, "
                   "subdivide, remesh, crop, bend, float32, roundtrip.")
@click.option("--chain", "chain_text", default=None, metavar="STEPS",
              help="Several attacks in order instead of --type, e.g. \"bend:30,simplify:0.5,noise:0.001,similarity,"
                   "reorder,roundtrip:obj\" (NAME[:VALUE][:KEY=VALUE...], comma-separated; docs/attacks.md). "
                   "Random steps get --seed + their position (from 0).")
@click.option("--strength", type=float, help="noise: amplitude as a fraction of the mean vertex-centroid distance (0.0025 = 0.25 %), >= 0.")
@click.option("--kind", help="noise: uniform (default), gaussian, normal, tangent.")
@click.option("--lambda", "lam", type=float, help="smooth: factor (default 0.02).")
@click.option("--iterations", type=int, help="smooth: iterations, 0..10,000 (default 10); remesh: rounds, 1..100 (default 3).")
@click.option("--weights", help="smooth: uniform (default) or cotangent.")
@click.option("--bits", type=int, help="quantize: bits per coordinate; dither: bits kept; 1..52.")
@click.option("--word", help="dither: fixed32 (default) or float64.")
@click.option("--fraction", type=float, help="simplify: fraction of faces kept, (0, 1]; crop: fraction of the extent removed, [0, 1).")
@click.option("--scheme", help="subdivide: loop (default) or midpoint.")
@click.option("--levels", type=int, help="subdivide: levels, 0..6 (default 1).")
@click.option("--edge-length", "edge_length", type=float,
              help="remesh: target edge length as a multiple of the mean edge length, (0, 100] (default 1).")
@click.option("--degrees", type=float, help="bend: angle in degrees (default 30).")
@click.option("--joint", type=float, help="bend: joint position, a fraction of the extent along the bone (default 0.5).")
@click.option("--width", type=float, help="bend: half-width of the blend zone, a fraction of the extent (default 0.1).")
@click.option("--along", type=click.Choice(["x", "y", "z"]), default=None,
              help="bend: the bone axis (default z; the bend turns about the next axis: z->x, x->y, y->z).")
@click.option("--absolute", is_flag=True, default=None, help="bend: --joint and --width in model units, not fractions.")
@click.option("--axis", help="rotate: axis as x,y,z (default 0,0,1).")
@click.option("--angle", type=float, help="rotate: degrees.")
@click.option("--normal", help="crop: plane normal as x,y,z (default 1,0,0).")
@click.option("--offset", help="translate: x,y,z.")
@click.option("--factor", type=float, help="scale: factor, > 0.")
@click.option("--format", "fmt", help="roundtrip: obj (6 decimals, default), ply (float), stl.")
@click.option("--decimals", type=int, help="roundtrip obj: decimals written, 0..17 (default 6).")
@click.option("--seed", type=int, help="random attacks: seed, 0..2^64-1 (default 0).")
@click.option("--force", is_flag=True, default=False, help="Overwrite an existing OUT.")
@jsonout.option("Print a summary (with the distortion) as JSON.")
def attack(mesh_in, mesh_out, name, chain_text, force, as_json, **opts):
    """Apply an attack (--type) or a chain of attacks (--chain) to IN and write the result to OUT
    (format from the extension, double precision).

    \b
    Examples:
      meshmark attack in.obj out.ply --type noise --strength 0.0025 --seed 1
      meshmark attack in.obj out.ply --type smooth --lambda 0.02 --iterations 30
      meshmark attack in.obj out.ply --type quantize --bits 9
      meshmark attack in.obj out.ply --type simplify --fraction 0.5
      meshmark attack in.obj out.ply --type remesh --edge-length 1
      meshmark attack in.obj out.ply --type bend --degrees 60
      meshmark attack in.obj out.ply --chain "bend:30,simplify:0.5,noise:0.001,similarity,reorder,roundtrip:obj" --seed 2
    """
    import numpy as np
    from ..atomic import check_output, write_all
    from ..io import mesh_outputs, read_mesh
    from . import ATTACKS, attack as run_attack, chain as run_chain, parameters, parse_chain
    from ..metrics import compare

    if (name is None) == (chain_text is None):
        raise MeshError("give exactly one of --type NAME or --chain STEPS")
    if chain_text is not None:
        given = [_OPTION_NAMES.get(k, "--" + k) for k, v in opts.items() if v is not None and k != "seed"]
        if given:
            raise MeshError(f"--chain takes only --seed; give the other parameters in the steps ({', '.join(given)})")
        check_options(None, {"seed": opts["seed"]})
        steps = parse_chain(chain_text)  # bad text: exit 2 naming the step, before the mesh is read
        seed = 0 if opts["seed"] is None else opts["seed"]
        check_output(mesh_out, force, "attacked mesh")  # after the options, before any work
        m, fmt = read_mesh(mesh_in, return_info=True)
        out = run_chain(m, steps, seed=seed)
        params = {"chain": chain_text, "seed": seed, "steps": [[n, p] for n, p in steps]}
        label = "chain"
    else:
        if name not in ATTACKS:
            raise MeshError(f"unknown attack type {name!r} (expected one of {', '.join(sorted(ATTACKS))})")
        for key in ("axis", "normal", "offset"):
            opts[key] = _vec(opts[key], key)
        params = {_ATTACK_OPTIONS[k]: v for k, v in opts.items() if v is not None}
        accepted = set(parameters(name))
        bad = [_OPTION_NAMES.get(k, "--" + k) for k, v in opts.items() if v is not None and _ATTACK_OPTIONS[k] not in accepted]
        if bad:
            raise MeshError(f"--type {name} does not take {', '.join(bad)}")
        check_options(name, opts)
        check_output(mesh_out, force, "attacked mesh")  # after the options, before any work
        m, fmt = read_mesh(mesh_in, return_info=True)
        out = run_attack(m, name=name, **params)
        label = name
    # the faces unchanged (glTF: the asset written back with only its positions changed), else a new mesh
    same = np.array_equal(out.face_indices, m.face_indices) and np.array_equal(out.face_offsets, m.face_offsets)
    write_all(mesh_outputs(mesh_out, out.V, m if same else out, fmt if same else None), what=["attacked mesh"],
              overwrite=force)
    d = {"input": mesh_in, "output": mesh_out, "type": label, "params": params,
         "n_vertices": out.n_vertices, "n_faces": out.n_faces}
    text = f"{label}: wrote {mesh_out} ({out.n_vertices} vertices, {out.n_faces} faces)"
    if as_json:
        d["distortion"] = compare(m, out)
    jsonout.emit(d, as_json, text, aliases={"in": "input", "out": "output"})
