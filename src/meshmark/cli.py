"""The ``meshmark`` command line. Every subcommand takes ``--json`` for scripts."""
from __future__ import annotations

import json
import os
import sys
import traceback

import click

from ._core import MeshError

# Exit status of every command (implemented once, in _Group; documented in `meshmark --help`).
EXIT_DETECTED, EXIT_NOT_DETECTED, EXIT_INPUT_ERROR, EXIT_INTERNAL_ERROR = 0, 1, 2, 3


def _safe(text) -> str:
    """``text`` printable as UTF-8: bytes from argv that are not UTF-8 (surrogate escapes) are shown
    as \\xNN instead of failing to print."""
    text = str(text)
    try:
        return text.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
    except UnicodeEncodeError:
        return text.encode("utf-8", "backslashreplace").decode("utf-8")


def _emit(result: dict, as_json: bool, text: str) -> None:
    click.echo(json.dumps(result, indent=2, sort_keys=False) if as_json else _safe(text))


def _format_info(path: str, d: dict) -> str:
    sizes = ", ".join(f"{k}-gon x{v}" for k, v in d["face_sizes"].items())
    lo, hi = d["bbox_min"], d["bbox_max"]
    rows = [
        ("mesh", path),
        ("vertices", f"{d['n_vertices']} ({d['n_unreferenced_vertices']} unreferenced)"),
        ("faces", f"{d['n_faces']} ({sizes})" + (f", {d['n_dropped_faces']} collapsed faces dropped" if d.get("n_dropped_faces") else "")),
        ("edges", f"{d['n_edges']}"),
        ("boundary edges", f"{d['n_boundary_edges']}"),
        ("components", f"{d['n_components']}"),
        ("manifold", ("yes" if d["manifold"] else
                      f"no ({d['non_manifold_edges']} non-manifold edges, {d['non_manifold_vertices']} non-manifold vertices)")),
        ("closed", "yes" if d["closed"] else "no"),
        ("degenerate faces", f"{d['n_degenerate_faces']}"),
        ("bounding box", f"[{lo[0]:.6g}, {lo[1]:.6g}, {lo[2]:.6g}] .. [{hi[0]:.6g}, {hi[1]:.6g}, {hi[2]:.6g}]"),
        ("bbox diagonal", f"{d['bbox_diagonal']:.6g}"),
        ("mean edge length", f"{d['mean_edge_length']:.6g}"),
    ]
    w = max(len(k) for k, _ in rows)
    return "\n".join(f"{k:<{w}}  {v}" for k, v in rows)


def _option_name(ctx, param: str) -> str:
    """The command-line spelling of an API parameter name (``n_robust`` -> ``--n-robust``) for the
    command being run, found among its click options."""
    cmd, sub = ctx.command, ctx
    args = list(ctx.protected_args) + list(ctx.args) if hasattr(ctx, "protected_args") else list(ctx.args)
    for a in args:  # walk down nested groups (steganalysis cho, ...)
        nxt = cmd.get_command(ctx, a) if isinstance(cmd, click.Group) else None
        if nxt is None:
            break
        cmd = nxt
    for p in getattr(cmd, "params", []):
        if p.name == param and getattr(p, "opts", None):
            return max(p.opts, key=len)
    return "--" + param.replace("_", "-")


class _Group(click.Group):
    """Exit status for every command, so new commands inherit it: MeshError (bad input, parameter
    out of range) -> a one-line message and status 2; click usage errors -> 2 (click's own); any other
    exception is a bug -> a short message and status 3, with the traceback only under ``--debug`` (or
    MESHMARK_DEBUG=1). Commands that detect exit 0 (detected) or 1 (not detected) themselves."""

    def invoke(self, ctx):
        debug = bool(ctx.params.get("debug")) or os.environ.get("MESHMARK_DEBUG") == "1"
        try:
            return super().invoke(ctx)
        except MeshError as exc:
            if debug:
                traceback.print_exc()
            param = getattr(exc, "param", None)
            where = f"{_option_name(ctx, param)}: " if param else ""
            click.echo(f"meshmark: error: {where}{_safe(exc)}", err=True)
            sys.exit(EXIT_INPUT_ERROR)
        except (click.exceptions.ClickException, click.exceptions.Exit, click.exceptions.Abort):
            raise
        except Exception as exc:  # a bug: never a bare traceback, never status 1 ("not detected")
            if debug:
                traceback.print_exc()
            msg = _safe(exc)
            msg = msg if len(msg) <= 300 else msg[:300] + "..."
            click.echo(f"meshmark: internal error: {type(exc).__name__}: {msg} (this is a bug; "
                       "'meshmark --debug ...' shows the traceback)", err=True)
            sys.exit(EXIT_INTERNAL_ERROR)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="meshmark")
@click.option("--debug", is_flag=True, help="Show the Python traceback of an error.")
def main(debug):
    """meshmark: hide and detect information in 3D triangle meshes.

    \b
    Exit status (every command):
      0  success; extract, trace, steganalysis: a watermark / hidden data was detected
      1  extract, trace, steganalysis: nothing detected
      2  usage or input error: bad option, unreadable mesh or keyfile, a parameter out of
         its range (the option is named), a keyfile that fails its check
      3  internal error (a bug): a one-line message; --debug shows the traceback
    """


@main.command()
@click.argument("mesh", required=False)
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
def info(mesh, as_json):
    """Counts, boundary, components, manifoldness, bounding box and mean edge length of MESH.

    Without MESH, describes the built-in default mesh.
    """
    from . import read_mesh, mesh_info
    from .shapes import default_mesh

    if mesh is None:
        m, path = default_mesh(), "(built-in default)"
        fmt = {"format": "builtin", "binary": False, "float32": False, "n_file_faces": m.n_faces, "n_dropped_faces": 0}
    else:
        (m, fmt), path = read_mesh(mesh, return_info=True), mesh
    d = mesh_info(m)
    # Counts are of the file's records (as SOURCES.md lists them): faces dropped on reading
    # (collapsed, repeating a vertex) count in n_faces and are reported as n_dropped_faces.
    d["n_faces"] = fmt["n_file_faces"]
    d = {"path": path, **fmt, **d}
    _emit(d, as_json, _format_info(path, d))


# --- watermarking ---------------------------------------------------------------------------
_METHOD_CHOICES = ["laplacian", "cho-mean", "cho-variance", "radial"]


def _method_options(f):
    """Parameters shared by embed and capacity (names as in the Python API; thesis defaults).

    Each method accepts only its own parameters (an option another method owns is an error)."""
    f = click.option("--weld/--no-weld", "weld", default=True, show_default=True,
                     help="Merge vertices at exactly equal positions before the method runs (split seams, "
                          "non-indexed glTF/STL); stored in the keyfile.")(f)
    f = click.option("--origin-iters", "origin_iters", type=int, default=None,
                     help="radial: re-synchronisation rounds of the origin, 0..1000 (default 0).")(f)
    f = click.option("--origin-mode", "origin_mode", type=click.Choice(["axis", "vertices"]), default=None,
                     help="radial: origin on the principal axis (default) or 3-D mean of the right-most half.")(f)
    f = click.option("--center-iters", "center_iters", type=int, default=None,
                     help="cho-*: re-synchronisation rounds of the centre, 0..1000 (default 20; 0 with --thesis-exact).")(f)
    f = click.option("--guard", type=float, default=None,
                     help="cho-*: keep mapped values this far from the bin ends, [0, 0.25) (default 0.005; 0 with --thesis-exact).")(f)
    f = click.option("--delta-k", "delta_k", type=float, default=None, help="cho-*: step of the exponent k, (0, 1) (default 0.001).")(f)
    f = click.option("--alpha", type=float, default=None,
                     help="cho-*: strength factor, (0, 0.5) mean, (0, 1/3) variance (default 0.04 for cho-mean, 0.16 for cho-variance).")(f)
    f = click.option("--thesis-exact", is_flag=True, default=False,
                     help="laplacian, cho-*: run the published algorithm to the letter (no robustness fixes).")(f)
    f = click.option("--carrier", type=click.Choice(["local", "thesis", "normal", "normal_global", "cot_local", "cot_normal"]),
                     default=None, help="laplacian: the binned scalar (default local: ||L|| over the 1-ring's mean edge "
                                        "length; thesis: over the global mean edge length; docs/carrier.md).")(f)
    f = click.option("--solver", type=click.Choice(["iterative", "direct"]), default=None,
                     help="laplacian: reconstruction, PCG rounds that stop when every carrier holds its margin "
                          "(default iterative) or one exact sparse solve (direct).")(f)
    f = click.option("--eps", type=float, default=None, help="laplacian: regularisation of eq. 7.1.4, (0, 1] (default 1e-5).")(f)
    f = click.option("--n-robust", "n_robust", type=int, default=None, help="laplacian: eq. 7.2.16 margin divisor, 1..10^9 (default 5).")(f)
    f = click.option("--n-thr", "n_thr", type=int, default=None,
                     help="1..10^9. laplacian: minimum elements in a valid bin pair (default 46); "
                          "radial: eq. 6.1.6 count difference (default Table 6.1 / docs/radial.md rule).")(f)
    f = click.option("--K", "K", type=int, default=None,
                     help="Number of histogram bins, 4..1048576 (laplacian ceil(N/70), cho-* 64, radial 400; cho-* and radial: "
                          "at most the referenced vertices).")(f)
    f = click.option("--method", type=click.Choice(_METHOD_CHOICES), default="laplacian", show_default=True)(f)
    f = click.option("--params", "params_mode", type=click.Choice(["auto", "thesis"]), default="auto", show_default=True,
                     help="auto: choose the parameters for this mesh and payload (recorded in the keyfile); "
                          "thesis: the published defaults. Options given explicitly are kept in both.")(f)
    return f


def _params(**kw):
    """The method parameters given on the command line (unset options and a false flag left out)."""
    if not kw.get("thesis_exact"):
        kw.pop("thesis_exact", None)
    return {k: v for k, v in kw.items() if v is not None}


def _progress_bar(as_json: bool):
    """A click progress bar on stderr for interactive use (silent with --json)."""
    if as_json or not sys.stderr.isatty():
        return None, None
    bar = click.progressbar(length=100, label="meshmark", file=sys.stderr)
    bar.__enter__()
    state = {"done": 0}

    def report(fraction, text):
        step = int(100 * fraction) - state["done"]
        if step > 0:
            bar.update(step)
            state["done"] += step
    return report, bar


@main.command()
@click.argument("inp", metavar="IN")
@click.argument("out", metavar="OUT")
@_method_options
@click.option("--message", help="Text message to hide (UTF-8, at most 31 bytes).")
@click.option("--bits", help="Raw bit string to hide, e.g. 0110.")
@click.option("--key", required=True, help="Secret key (keep it; it is also stored in the keyfile unless --no-store-key).")
@click.option("--keyfile", required=True, type=click.Path(dir_okay=False), help="Where to write the keyfile (JSON).")
@click.option("--force", is_flag=True, default=False, help="Overwrite an existing keyfile.")
@click.option("--key-bins", "key_bins", is_flag=True, default=False,
              help="Move the published bin count K by a key-derived 3-12 % so another embedder's bins do not align "
                   "with yours (the mark survives overmarking more often; docs/security.md).")
@click.option("--store-key/--no-store-key", "store_key", default=True, show_default=True,
              help="Keep the key in the keyfile; with --no-store-key, extract needs --key (or asks for it).")
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
def embed(inp, out, method, message, bits, key, keyfile, force, store_key, key_bins, as_json, params_mode,
          **method_params):
    """Embed a watermark into IN and write the marked mesh to OUT and the keyfile to --keyfile.

    Both files are written, or neither: the folders are checked before any work, then both go to
    temporary files that are renamed only when both are complete. An existing keyfile is replaced
    only with --force.
    """
    from . import read_mesh, write_mesh
    from .atomic import check_writable, write_all
    from .watermark import METHODS, embed as wm_embed, save_keyfile
    from .watermark.payload import Payload

    if (message is None) == (bits is None):
        raise MeshError("give exactly one of --message TEXT or --bits 0110...")
    check_writable(out, "marked mesh")
    check_writable(keyfile, "keyfile")
    payload = Payload.from_text(message) if message is not None else Payload.from_bits(bits)
    from .watermark.keyfile import refuse_overwrite
    refuse_overwrite(keyfile, force, "--force")  # before any work: nothing is written if it exists
    mesh, fmt = read_mesh(inp, return_info=True)
    report, bar = _progress_bar(as_json)
    try:
        res = wm_embed(mesh, payload=payload, key=key, method=method, progress=report, params=params_mode,
                       store_key=store_key, key_bins=key_bins, **_params(**method_params))
    finally:
        if bar is not None:
            bar.__exit__(None, None, None)
    float32 = bool(fmt["float32"]) and out.lower().endswith(".ply")
    write_all([(out, lambda p: write_mesh(p, res.V, mesh, float32=float32)),
               (keyfile, lambda p: save_keyfile(res.keyfile, p, overwrite=True))],  # checked above (--force)
              what=["marked mesh", "keyfile"])
    d = {"input": inp, "output": out, "keyfile": keyfile, "key_stored": store_key, **res.to_dict()}
    coded = res.keyfile.coding
    how = (f"{coded['info_bits']} with the keyed check" if coded.get("check_bits") else "keyed code")
    text = (f"embedded {payload.data.size} payload bits ({how}, "
            f"coded over {res.capacity} carriers) with the {method} method ({params_mode} parameters: "
            f"{METHODS[method].describe(res.keyfile.params)}) into {out}\nkeyfile: {keyfile} (keep it private"
            + ("" if store_key else "; it does not hold the key: extract needs --key") + ")")
    _emit(d, as_json, text)


@main.command()
@click.argument("inp", metavar="IN")
@click.option("--keyfile", required=True, type=click.Path(dir_okay=False), help="Keyfile written by embed.")
@click.option("--key", default=None, help="Use this key instead of the keyfile's; needed when the keyfile holds "
                                          "no key (asked for on a terminal).")
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
def extract(inp, keyfile, key, as_json):
    """Extract and detect the watermark of --keyfile in IN (blind: the original is not needed).

    The keyfile is checked first (schema, then its HMAC-SHA256 tag): a changed keyfile, or a wrong
    key for a keyfile written with --no-store-key, is an error (status 2).

    Exit status: 0 watermark detected, 1 not detected, 2 usage/input error, 3 internal error.
    """
    from . import read_mesh
    from .watermark import extract as wm_extract, load_keyfile
    from .watermark.keyfile import KeyRequired

    try:
        kf = load_keyfile(keyfile, key=key)
    except KeyRequired:
        if not sys.stdin.isatty():
            raise
        key = click.prompt("key", hide_input=True)
        kf = load_keyfile(keyfile, key=key)
    mesh = read_mesh(inp)
    res = wm_extract(mesh, keyfile=kf, key=key)
    d = {"input": inp, **res.to_dict()}
    lines = [f"watermark {'DETECTED' if res.detected else 'not detected'} in {inp}",
             f"bits matched {res.matches}/{res.n_bits}  NC {res.nc:.3f}  CDR {res.cdr:.3f}  "
             f"P(false alarm) {res.p_false_alarm:.3g}",
             f"message: {res.message!r}" if res.message_ok else f"message not recovered ({res.reason})"]
    lines += [f"warning: {w}" for w in res.warnings]
    _emit(d, as_json, "\n".join(lines))
    sys.exit(EXIT_DETECTED if res.detected else EXIT_NOT_DETECTED)


@main.command()
@click.argument("inp", metavar="IN")
@_method_options
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
def capacity(inp, method, as_json, params_mode, **method_params):
    """How many carrier bits IN offers to a method, and the longest message that fits, with the
    published defaults (thesis) and with automatic parameters (auto)."""
    from . import read_mesh, weld_vertices
    from .watermark import METHODS
    from .watermark.auto import choose, longest_payload_bits
    from .watermark.coding import max_data_bits
    from .watermark.payload import MAX_DATA_BITS

    mesh = read_mesh(inp)
    m = METHODS[method]
    params = _params(**method_params)
    weld = params.pop("weld")
    if weld:
        mesh = weld_vertices(mesh).mesh
    p, ids, _, _ = choose(mesh, m, "thesis", params, None)
    cap = int(len(ids))
    fit = min(max_data_bits(cap), MAX_DATA_BITS)
    auto_fit = min(longest_payload_bits(mesh, m, params), MAX_DATA_BITS)
    d = {"input": inp, "method": method, "params": p, "weld": weld, "n_vertices": mesh.n_vertices, "capacity": cap,
         "max_message_bits": fit, "max_text_bytes": fit // 8,
         "auto": {"max_message_bits": auto_fit, "max_text_bytes": auto_fit // 8}}
    _emit(d, as_json, f"{inp}: {cap} carrier bits with the {method} method and the thesis parameters "
                      f"({m.describe(p)}): a message of up to {fit} bits ({fit // 8} text bytes) fits; "
                      f"with --params auto up to {auto_fit} bits ({auto_fit // 8} text bytes)")


# --- attack / compare ---------------------------------------------------------------------------------

# CLI option -> keyword of the attack functions (meshmark.attacks); an option given to an attack that
# does not take it is an error, not silently ignored.
_ATTACK_OPTIONS = {
    "strength": "strength", "kind": "kind", "lam": "lam", "iterations": "iterations", "weights": "weights",
    "bits": "bits", "word": "word", "fraction": "fraction", "scheme": "scheme", "levels": "levels",
    "axis": "axis", "angle": "angle", "normal": "normal", "offset": "offset", "factor": "factor",
    "fmt": "format", "seed": "seed",
}
_OPTION_NAMES = {"lam": "--lambda", "fmt": "--format"}


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


@main.command()
@click.argument("mesh_in", metavar="IN")
@click.argument("mesh_out", metavar="OUT")
@click.option("--type", "name", required=True, metavar="NAME",
              help="similarity, rotate, translate, scale, reorder, noise, smooth, quantize, dither, simplify, "
                   "subdivide, crop, float32, roundtrip.")
@click.option("--strength", type=float, help="noise: amplitude as a fraction of the mean vertex-centroid distance (0.0025 = 0.25 %).")
@click.option("--kind", help="noise: uniform (default), gaussian, normal, tangent.")
@click.option("--lambda", "lam", type=float, help="smooth: factor (default 0.02).")
@click.option("--iterations", type=int, help="smooth: iterations (default 10).")
@click.option("--weights", help="smooth: uniform (default) or cotangent.")
@click.option("--bits", type=int, help="quantize: bits per coordinate; dither: bits kept.")
@click.option("--word", help="dither: fixed32 (default) or float64.")
@click.option("--fraction", type=float, help="simplify: fraction of faces kept; crop: fraction of the extent removed.")
@click.option("--scheme", help="subdivide: loop (default) or midpoint.")
@click.option("--levels", type=int, help="subdivide: levels (default 1).")
@click.option("--axis", help="rotate: axis as x,y,z (default 0,0,1).")
@click.option("--angle", type=float, help="rotate: degrees.")
@click.option("--normal", help="crop: plane normal as x,y,z (default 1,0,0).")
@click.option("--offset", help="translate: x,y,z.")
@click.option("--factor", type=float, help="scale: factor.")
@click.option("--format", "fmt", help="roundtrip: obj (6 decimals, default), ply (float), stl.")
@click.option("--seed", type=int, help="random attacks: seed (default 0).")
@click.option("--json", "as_json", is_flag=True, help="Print a summary (with the distortion) as JSON.")
def attack(mesh_in, mesh_out, name, as_json, **opts):
    """Apply an attack to IN and write the result to OUT (format from the extension, double precision).

    \b
    Examples:
      meshmark attack in.obj out.ply --type noise --strength 0.0025 --seed 1
      meshmark attack in.obj out.ply --type smooth --lambda 0.02 --iterations 30
      meshmark attack in.obj out.ply --type quantize --bits 9
      meshmark attack in.obj out.ply --type simplify --fraction 0.5
      meshmark attack in.obj out.ply --type crop --fraction 0.1
    """
    from . import read_mesh, write_mesh
    from .attacks import ATTACKS, attack as run_attack
    from .metrics import compare

    if name not in ATTACKS:
        raise MeshError(f"unknown attack type {name!r} (expected one of {', '.join(sorted(ATTACKS))})")
    for key in ("axis", "normal", "offset"):
        opts[key] = _vec(opts[key], key)
    params = {_ATTACK_OPTIONS[k]: v for k, v in opts.items() if v is not None}
    import inspect
    accepted = {p.name for p in inspect.signature(ATTACKS[name]).parameters.values() if p.kind == p.KEYWORD_ONLY}
    bad = [_OPTION_NAMES.get(k, "--" + k) for k, v in opts.items() if v is not None and _ATTACK_OPTIONS[k] not in accepted]
    if bad:
        raise MeshError(f"--type {name} does not take {', '.join(bad)}")
    m = read_mesh(mesh_in)
    out = run_attack(m, name=name, **params)
    write_mesh(mesh_out, out)
    d = {"in": mesh_in, "out": mesh_out, "type": name, "params": params,
         "n_vertices": out.n_vertices, "n_faces": out.n_faces}
    text = f"{name}: wrote {mesh_out} ({out.n_vertices} vertices, {out.n_faces} faces)"
    if as_json:
        d["distortion"] = compare(m, out)
    _emit(d, as_json, text)


def _format_compare(a, b, d):
    f = lambda x, spec=".6g": "-" if x is None else format(x, spec)
    rows = [
        ("reference", a), ("attacked", b),
        ("vertex RMSE", f(d["rmse"])),
        ("Hausdorff", f"{f(d['hausdorff'])} ({f(d['hausdorff_rel'], '.4e')} of the bbox diagonal)"
         + ("" if d.get("hausdorff_converged", True) else
            f", at most {f(d['hausdorff_upper'])} (work cap reached, docs/metrics.md)")),
        ("RMS distance", f"{f(d['rms'])} ({f(d['rms_rel'], '.4e')} of the bbox diagonal)"),
        ("normal degradation", "-" if d["normal_deg_mean"] is None else
         f"mean {d['normal_deg_mean']:.4f} deg, area {d['normal_deg_area']:.4f} deg, dihedral {d['normal_deg_dihedral']:.4f} deg"),
    ]
    w = max(len(k) for k, _ in rows)
    return "\n".join(f"{k:<{w}}  {v}" for k, v in rows)


@main.command()
@click.argument("mesh_a", metavar="A")
@click.argument("mesh_b", metavar="B")
@click.option("--samples", type=int, default=None, help="Area samples per direction (default 2 x triangles), plus the vertices.")
@click.option("--seed", type=int, default=0, show_default=True, help="Sampling seed.")
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
def compare(mesh_a, mesh_b, samples, seed, as_json):
    """Distortion of B relative to the reference A: vertex RMSE, Hausdorff and RMS surface distance
    (absolute and relative to A's bounding-box diagonal), normal degradation (eq. 3.2.2) in degrees."""
    from . import read_mesh
    from .metrics import compare as run_compare

    d = run_compare(read_mesh(mesh_a), read_mesh(mesh_b), n_samples=samples, seed=seed)
    d = {"a": mesh_a, "b": mesh_b, **d}
    _emit(d, as_json, _format_compare(mesh_a, mesh_b, d))


# --- steganalysis ---------------------------------------------------------------------------
@main.group()
def steganalysis():
    """Detect hidden information without a key."""


@steganalysis.command("cho")
@click.argument("inp", metavar="IN")
@click.option("--k-min", "K_min", type=int, default=1, show_default=True, help="Smallest bin number tried.")
@click.option("--k-max", "K_max", type=int, default=500, show_default=True, help="Largest bin number tried.")
@click.option("--eps", type=float, default=0.15, show_default=True, help="eq. 6.4.16 tolerance.")
@click.option("--eps2", type=float, default=0.03, show_default=True, help="eq. 6.4.17 balance tolerance (with --thesis-exact).")
@click.option("--thesis-exact", is_flag=True, help="Literal eq. 6.4.17 instead of the binomial balance test.")
@click.option("--false-reject", type=float, default=0.01, show_default=True,
              help="Balance test: rate at which random-message marks are rejected.")
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
def steganalysis_cho(inp, K_min, K_max, eps, eps2, thesis_exact, false_reject, as_json):
    """Does IN carry a watermark of Cho et al.'s mean method? (thesis §6.4)

    Exit status: 0 marked, 1 not marked, 2 usage/input error, 3 internal error.
    """
    from . import read_mesh
    from .steganalysis.cho import analyze

    mesh = read_mesh(inp)
    r = analyze(mesh, K_min=K_min, K_max=K_max, eps=eps, eps2=eps2, thesis_exact=thesis_exact,
                false_reject=false_reject)
    d = {"input": inp, "k_estimate": int(r["k_estimate"]), "bhattacharyya": float(r["bhattacharyya"]),
         "marked": bool(r["marked"]), "eq_6_4_16": bool(r["eq_6_4_16"]), "eq_6_4_17": bool(r["eq_6_4_17"]),
         "min_C": float(r["min_C"]), "max_Ctilde": float(r["max_Ctilde"]), "size_C": int(r["size_C"]),
         "size_Ctilde": int(r["size_Ctilde"]), "balance_test": bool(r["balance_test"]),
         "p_balance": float(r["p_balance"]), "thesis_exact": bool(thesis_exact)}
    rule = "(literal eq. 6.4.17)" if thesis_exact else f"(binomial, p = {d['p_balance']:.3g})"
    text = (f"{inp}: {'MARKED' if d['marked'] else 'clean'} (Cho mean method)\n"
            f"estimated bins K' = {d['k_estimate']}  Bhattacharyya D = {d['bhattacharyya']:.4g}\n"
            f"clusters {d['size_C']} / {d['size_Ctilde']}, min C {d['min_C']:.4f}, max C~ {d['max_Ctilde']:.4f}; "
            f"eq. 6.4.16 {'holds' if d['eq_6_4_16'] else 'fails'}, eq. 6.4.17 {'holds' if d['eq_6_4_17'] else 'fails'}; "
            f"balance rule {rule} {'holds' if d['balance_test'] else 'fails'}")
    _emit(d, as_json, text)
    sys.exit(0 if d["marked"] else 1)

from .stego.cli import stego as _stego_cli; main.add_command(_stego_cli)  # noqa: E402  (meshmark stego ...)


from .analysis.cli import analyze; main.add_command(analyze)  # noqa: E402,E702  (thesis ch. 3-5)

from .steganalysis.cli import add_commands as _steganalysis_commands; _steganalysis_commands(steganalysis)  # noqa: E402,E702


main.add_command(__import__("meshmark.study.cli", fromlist=["study"]).study)

[main.add_command(_c) for _c in __import__("meshmark.cli_tracing", fromlist=["COMMANDS"]).COMMANDS]  # issue, trace

if __name__ == "__main__":  # pragma: no cover
    main()
