"""``meshmark analyze``: the distortion analysis of thesis ch. 3-5 on a mesh file."""
from __future__ import annotations

import math

import click

from .. import jsonout
from .._core import MeshError


_emit = jsonout.emit


def _tolerances(text: str) -> list[float]:
    try:
        vals = [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise MeshError(f"--tolerance must be a comma-separated list of degrees, got {text!r}") from None
    if not vals:
        raise MeshError("--tolerance needs at least one value")
    for v in vals:
        if not (v > 0 and math.isfinite(v)):
            raise MeshError(f"--tolerance values must be finite numbers > 0 degrees, got {v}")
    return vals


def _check(seed=0, repeats=1, t_min=None) -> None:
    """The numeric options against their ranges before the mesh is read (exit 2 naming the option):
    --seed 0..2^63-1, --repeats 1..1000 (each repeat redoes the whole measurement), --t-min 1..19
    (the levels are t = 1..20 and the fit needs two)."""
    from ..ranges import check_int, check_seed
    check_seed(seed)
    check_int("repeats", repeats, 1, 1000)
    if t_min is not None:
        check_int("t_min", t_min, 1, 19)


def _key(x: float) -> str:
    return f"{x:g}"


@click.group()
def analyze():
    """Normal and curvature degradation, quantization levels (thesis ch. 3-5)."""


@analyze.command()
@click.argument("inp", metavar="IN")
@click.option("--tolerance", default="1,5,10", show_default=True, help="Tolerances in degrees (comma-separated).")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the random low bits.")
@click.option("--repeats", type=int, default=1, show_default=True, help="Dithered samples per level (averaged), 1..1000.")
@jsonout.option()
def degradation(inp, tolerance, seed, repeats, as_json):
    """Normal degradation against the mantissa bits kept.

    Thesis chapter 3: fit D(t) = C / (1 + e^(-a - b t)) (eq. 3.2.1) to dis(M, M^t) at t = 12, 16, 20, 24, 28
    bits of the IEEE-754 double kept, per weighting, and the level t per tolerance (eq. 3.2.6)."""
    from .. import read_mesh
    from .degradation import WEIGHTINGS, degradation_model
    _check(seed=seed, repeats=repeats)
    tols = _tolerances(tolerance)
    r = degradation_model(read_mesh(inp), tols, seed=seed, repeats=repeats)
    d = {"input": inp, "seed": seed, "levels_fitted": r["levels_fitted"], "tolerances_deg": tols}
    for w in WEIGHTINGS:
        f = r[w]
        d[w] = {"a": f["a"], "b": f["b"], "C": f["C"], "t": {_key(k): v for k, v in f["t"].items()},
                "samples": f["samples"]}
    lines = [f"{inp}: logistic model D(t) = C / (1 + exp(-a - b t)), fitted at t = {r['levels_fitted']}"]
    for w in WEIGHTINGS:
        f = d[w]
        lv = ", ".join(f"{k} deg: t = {v}" for k, v in f["t"].items())
        lines.append(f"  {w:<8}  a = {f['a']:8.3f}  b = {f['b']:7.3f}  C = {f['C']:.4f}   {lv}")
    _emit(d, as_json, "\n".join(lines), aliases={"tolerances": "tolerances_deg"})


@analyze.command()
@click.argument("inp", metavar="IN")
@click.option("--tolerance", type=float, required=True, help="Tolerance of the mean normal change, degrees.")
@click.option("--bound", type=click.Choice(["min", "appr", "max", "exact"]), default=None,
              help="Only this estimate of E_mesh (default: all four).")
@click.option("--adaptive", is_flag=True, help="Also the curvature-adaptive per-vertex levels (eqs. 4.3.23-4.3.25).")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the dither that measures psi.")
@jsonout.option()
def quantization(inp, tolerance, bound, adaptive, seed, as_json):
    """Quantization level per normal-degradation bound.

    Thesis chapter 4: the dithered-quantization level i (32-bit fixed point in the bounding cube) per bound
    (eqs. 4.3.19-4.3.21) and the measured psi^i in degrees after dithering at that level (eq. 4.3.22)."""
    from .. import read_mesh
    from .quantization import BOUNDS, quantization_table
    _tolerances(str(tolerance))
    _check(seed=seed)
    mesh = read_mesh(inp)
    bounds = (bound,) if bound else BOUNDS
    t = quantization_table(mesh, (tolerance,), bounds, adaptive=adaptive, seed=seed)
    d = {"input": inp, "tolerance_deg": tolerance, "seed": seed, "n_triangles": t["n_triangles"], "cube": t["cube"],
         "bounds": {}}
    for b in bounds:
        det = t["details"][b][tolerance]
        d["bounds"][b] = {"i": t["levels"][b][tolerance], "psi": t["psi"][b][tolerance],
                          "formula": "exact" if det["used_exact"] else "linear",
                          "e_mesh": math.degrees(det["e_level"])}
    lines = [f"{inp}: {t['n_triangles']} triangles, bounding cube {t['cube']:.6g}, tolerance {tolerance:g} deg"]
    for b, v in d["bounds"].items():
        lines.append(f"  {b:<5}  i = {v['i']:2d}  psi^i = {v['psi']:.4g} deg  (E_mesh {v['e_mesh']:.4g} deg, {v['formula']})")
    if adaptive:
        a = t["adaptive"][tolerance]
        d["adaptive"] = a
        lines.append(f"  adaptive  levels {a['min']}..{a['max']} (mean {a['mean_level']:.2f})  psi = {a['psi']:.4g} deg  "
                     f"bits kept {a['total_bits']} vs {a['global_total_bits']} at the global level {a['global_level']}")
    _emit(d, as_json, "\n".join(lines), aliases={"tolerance": "tolerance_deg"})


@analyze.command()
@click.argument("inp", metavar="IN")
@click.argument("out", metavar="OUT")
@click.option("--tolerance", type=float, required=True, help="Tolerance of the mean normal change, degrees.")
@click.option("--bound", type=click.Choice(["min", "appr", "max", "exact"]), default="appr", show_default=True)
@click.option("--adaptive", is_flag=True, help="Per-vertex curvature-adaptive levels (eqs. 4.3.23-4.3.25).")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the random low bits.")
@jsonout.option()
def quantize(inp, out, tolerance, bound, adaptive, seed, as_json):
    """Write OUT: IN quantized at the level of a bound.

    Thesis chapter 4: OUT is the dithered IN (keep the level's most significant bits of the 32-bit
    fixed-point coordinates, random low bits)."""
    import numpy as np
    from .. import read_mesh, write_mesh
    from ..metrics import normal_degradation
    from .quantization import adaptive_levels, quantization_level, quantize as dither
    _tolerances(str(tolerance))
    _check(seed=seed)
    mesh = read_mesh(inp)
    levels = adaptive_levels(mesh, tolerance) if adaptive else quantization_level(mesh, tolerance, bound)
    q = dither(mesh, levels=levels, seed=seed)
    psi = normal_degradation(mesh, q.V, weighting="mean", degrees=True)
    write_mesh(out, q)
    used = mesh.referenced().astype(bool)
    lv = np.asarray(levels)
    d = {"input": inp, "output": out, "tolerance_deg": tolerance, "adaptive": adaptive, "bound": None if adaptive else bound,
         "levels": {"min": int(lv[used].min()), "max": int(lv[used].max()), "mean": float(lv[used].mean())} if adaptive
         else int(levels), "psi": psi, "seed": seed}
    what = (f"levels {d['levels']['min']}..{d['levels']['max']} (mean {d['levels']['mean']:.2f})" if adaptive
            else f"level i = {levels} ({bound})")
    _emit(d, as_json, f"{out}: dithered at {what}; mean normal change psi = {psi:.4g} deg",
          aliases={"tolerance": "tolerance_deg"})


@analyze.command()
@click.argument("inp", metavar="IN")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the displacements.")
@click.option("--repeats", type=int, default=1, show_default=True, help="Draws per level (averaged), 1..1000.")
@click.option("--t-min", type=int, default=12, show_default=True, help="Smallest level of the linear fit, 1..19.")
@jsonout.option()
def curvature(inp, seed, repeats, t_min, as_json):
    """Gaussian-curvature degradation against the bits kept.

    Thesis chapter 5: mean change of the discrete Gaussian curvature (eq. 5.1.1) of the interior vertices under
    displacements of mean strength 2^-t L (t = 1..20, L the bounding cube) along the vertex normal, a
    tangent or a random direction, and the fit log2 kappa_dif = a t + b over t >= t-min (eq. 5.2.4)."""
    from .. import read_mesh
    from .curvature import DIRECTIONS, curvature_model
    _check(seed=seed, repeats=repeats, t_min=t_min)
    r = curvature_model(read_mesh(inp), seed=seed, repeats=repeats, t_min=t_min)
    d = {"input": inp, "seed": seed, "t": r["t"], "scale": r["scale"], "n_interior": r["n_interior"]}
    lines = [f"{inp}: {r['n_interior']} interior vertices, strength 2^-t x {r['scale']:.6g}, "
             f"fit log2 kappa_dif = a t + b over t >= {t_min}"]
    for k in DIRECTIONS:
        f = r[k]
        d[k] = {"a": f["a"], "b": f["b"], "r2": f["r2"], "kappa_dif": f["kappa_dif"]}
        lines.append(f"  {k:<10}  a = {f['a']:7.3f}  b = {f['b']:6.2f}  (r^2 {f['r2']:.4f})")
    _emit(d, as_json, "\n".join(lines))
