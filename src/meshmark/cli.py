"""The ``meshmark`` command line. Every subcommand takes ``--json`` for scripts."""
from __future__ import annotations

import os
import sys
import traceback

import click

from . import jsonout
from ._core import MeshError

# Exit status of every command (implemented once, in _Group; documented in `meshmark --help`).
EXIT_DETECTED, EXIT_NOT_DETECTED, EXIT_INPUT_ERROR, EXIT_INTERNAL_ERROR = 0, 1, 2, 3


_safe = jsonout.safe
_emit = jsonout.emit


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
    cmd = ctx.command
    for a in ctx.meta.get("meshmark.args", ()):  # walk down nested groups (steganalysis cho, ...)
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
    MESHMARK_DEBUG=1). Under ``--json`` each failure also prints ``{"ok": false, "error": {...}}`` on
    stdout (jsonout.error_object, docs/json.md). Commands that detect exit 0 (detected) or 1 (not
    detected) themselves."""

    def invoke(self, ctx):
        debug = bool(ctx.params.get("debug")) or os.environ.get("MESHMARK_DEBUG") == "1"
        # the command line below the group, kept for _option_name: click empties ctx.args as it invokes
        ctx.meta["meshmark.args"] = [*getattr(ctx, "_protected_args", ()), *ctx.args]
        try:
            return super().invoke(ctx)
        except MeshError as exc:
            if debug:
                traceback.print_exc()
            param = getattr(exc, "param", None)
            where = f"{_option_name(ctx, param)}: " if param else ""
            _fail(ctx, EXIT_INPUT_ERROR, "input", f"{where}{_safe(exc)}", "error")
        except click.exceptions.ClickException as exc:  # usage errors: click prints them and exits 2
            if _json_wanted(ctx):
                click.echo(jsonout.dumps(jsonout.error_object(exc.exit_code, "usage", exc.format_message())))
            raise
        except (click.exceptions.Exit, click.exceptions.Abort):
            raise
        except KeyboardInterrupt:  # Ctrl-C: the shell's status 130, never 1 ("not detected")
            _fail(ctx, 128 + 2, "interrupted", "interrupted", None)
        except Exception as exc:  # a bug: never a bare traceback, never status 1 ("not detected")
            if debug:
                traceback.print_exc()
            msg = _safe(exc)
            msg = msg if len(msg) <= 300 else msg[:300] + "..."
            _fail(ctx, EXIT_INTERNAL_ERROR, "internal", f"{type(exc).__name__}: {msg} (this is a bug; "
                  "'meshmark --debug ...' shows the traceback)", "internal error")


def _json_wanted(ctx) -> bool:
    """The command's ``--json`` (jsonout.option records it as the options are processed); when the
    command line failed before that, ``--json`` among its words (before a ``--``)."""
    if "meshmark.json" in ctx.meta:
        return ctx.meta["meshmark.json"]
    args = [str(a) for a in ctx.meta.get("meshmark.args", ())]
    return "--json" in (args[:args.index("--")] if "--" in args else args)


def _fail(ctx, code: int, kind: str, message: str, label) -> None:
    """The one failure path of every command: a line on stderr, under ``--json`` also the error
    object on stdout (jsonout.error_object), then exit ``code``."""
    click.echo(f"meshmark: {label}: {message}" if label else f"meshmark: {message}", err=True)
    if _json_wanted(ctx):
        click.echo(jsonout.dumps(jsonout.error_object(code, kind, message)))
    sys.exit(code)


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
    With --json, stdout holds one JSON object: "ok": true and the result, or on
    status 2 or 3 {"ok": false, "error": {"code", "kind", "message"}} (docs/json.md).
    """


@main.command()
@click.argument("mesh", required=False)
@jsonout.option()
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
        fmt = {k: (v.to_dict() if k == "gltf" else v) for k, v in fmt.items()}
    d = mesh_info(m)
    # Counts are of the file's records (as SOURCES.md lists them): faces dropped on reading
    # (collapsed, repeating a vertex) count in n_faces and are reported as n_dropped_faces.
    d["n_faces"] = fmt["n_file_faces"]
    d = {"input": path, **fmt, **d}
    _emit(d, as_json, _format_info(path, d), aliases={"path": "input"})


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


_FLOAT_RANGES = {"eps": (0.0, 1.0, True, False), "alpha": (0.0, 0.5, True, True),  # ranges.py's table;
                 "delta_k": (0.0, 1.0, True, True), "guard": (0.0, 0.25, False, True)}  # alpha refined per method


def _params(**kw):
    """The method parameters given on the command line (unset options and a false flag left out),
    each checked against its range of meshmark.ranges before any mesh is read."""
    from .ranges import RANGES, check_float, check_int
    if not kw.get("thesis_exact"):
        kw.pop("thesis_exact", None)
    out = {k: v for k, v in kw.items() if v is not None}
    for k, v in out.items():
        if k in RANGES:
            check_int(k, v)
        elif k in _FLOAT_RANGES:
            lo, hi, lo_open, hi_open = _FLOAT_RANGES[k]
            check_float(k, v, lo, hi, low_open=lo_open, high_open=hi_open)
    return out


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
@click.option("--force", is_flag=True, default=False, help="Overwrite an existing marked mesh and keyfile.")
@click.option("--key-bins", "key_bins", is_flag=True, default=False,
              help="Move the bin count K (of the automatic or the published parameters) by a key-derived 3-12 % so "
                   "another embedder's bins do not align with yours: your mark then survives most re-embeddings "
                   "by someone else (overmarking; docs/security.md).")
@click.option("--store-key/--no-store-key", "store_key", default=True, show_default=True,
              help="Keep the key in the keyfile; with --no-store-key, extract needs --key (or asks for it).")
@jsonout.option()
def embed(inp, out, method, message, bits, key, keyfile, force, store_key, key_bins, as_json, params_mode,
          **method_params):
    """Embed a watermark into IN and write the marked mesh to OUT and the keyfile to --keyfile.

    Both files are written, or neither: the folders are checked before any work, then both go to
    private temporary files that are renamed only when both are complete, the keyfile first, so a
    marked mesh never stands at OUT without its keyfile, even if the process is killed (docs/cli.md).
    An existing OUT or keyfile is replaced only with --force.
    """
    from .atomic import check_output, text_writer, write_all
    from .io import mesh_outputs, read_mesh
    from .watermark import METHODS, embed as wm_embed
    from .watermark.payload import Payload

    if (message is None) == (bits is None):
        raise MeshError("give exactly one of --message TEXT or --bits 0110...")
    if os.path.realpath(out) == os.path.realpath(keyfile):
        raise MeshError(f"OUT and --keyfile are the same file '{_safe(out)}'; give the keyfile its own name")
    check_output(out, force, "marked mesh")  # before any work: nothing is written if one exists
    check_output(keyfile, force, "keyfile")
    payload = Payload.from_text(message) if message is not None else Payload.from_bits(bits)
    method_kw = _params(**method_params)  # ranges checked before the mesh is read
    mesh, fmt = read_mesh(inp, return_info=True)
    report, bar = _progress_bar(as_json)
    try:
        res = wm_embed(mesh, payload=payload, key=key, method=method, progress=report, params=params_mode,
                       store_key=store_key, key_bins=key_bins, **method_kw)
    finally:
        if bar is not None:
            bar.__exit__(None, None, None)
    items = mesh_outputs(out, res.V, mesh, fmt)  # a glTF asset: only its positions change (docs/gltf.md)
    # the keyfile is renamed into place first, the mesh after it (atomic.py)
    write_all([(keyfile, text_writer(res.keyfile.to_json()))] + items, what=["keyfile"] + ["marked mesh"] * len(items),
              private=[True] + [False] * len(items), overwrite=force)
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
@jsonout.option()
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
    d = {("n_carriers" if k == "bits" else k): v for k, v in d.items()}  # the coded bits read, one per carrier
    lines = [f"watermark {'DETECTED' if res.detected else 'not detected'} in {inp}",
             f"bits matched {res.matches}/{res.n_bits}  NC {res.nc:.3f}  CDR {res.cdr:.3f}  "
             f"P(false alarm) {res.p_false_alarm:.3g}",
             f"message: {res.message!r}" if res.message_ok else f"message not recovered ({res.reason})"]
    lines += [f"warning: {w}" for w in res.warnings]
    _emit(d, as_json, "\n".join(lines), aliases={"bits": "n_carriers"})
    sys.exit(EXIT_DETECTED if res.detected else EXIT_NOT_DETECTED)


@main.command()
@click.argument("inp", metavar="IN")
@_method_options
@click.option("--key-bins", "key_bins", is_flag=True, default=False,
              help="The bins embed --key-bins uses with --key (the capacity then depends on the key).")
@click.option("--key", default=None, help="The key, with --key-bins.")
@jsonout.option()
def capacity(inp, method, key_bins, key, as_json, params_mode, **method_params):
    """How many carrier bits IN offers to a method and the longest message that fits, with the
    parameters of --params (auto, the default, as in the Python API's capacity(); or thesis), and the
    longest message under each of the two. With --key-bins and --key: the key-dependent bins of
    embed --key-bins (the thesis figures stay the published ones)."""
    from . import read_mesh, weld_vertices
    from .watermark import METHODS
    from .watermark.auto import choose, longest_payload_bits
    from .watermark.coding import max_data_bits
    from .watermark.framework import moved_bins
    from .watermark.payload import MAX_DATA_BITS

    if key_bins and key is None:
        raise MeshError("--key-bins needs --key: the bins depend on the key")
    params = _params(**method_params)  # ranges checked before the mesh is read
    mesh = read_mesh(inp)
    m = METHODS[method]
    weld = params.pop("weld")
    if weld:
        mesh = weld_vertices(mesh).mesh
    move_K, given = moved_bins(mesh, m, params_mode, params, key, key_bins)
    p, ids, _, _ = choose(mesh, m, params_mode, given, None, move_K=move_K)  # = watermark.capacity(params=...)
    cap = int(len(ids))
    thesis_p, ids_t, _, _ = choose(mesh, m, "thesis", params, None)
    thesis_cap = int(len(ids_t))
    thesis_fit = min(max_data_bits(thesis_cap), MAX_DATA_BITS)
    auto_move = moved_bins(mesh, m, "auto", params, key, key_bins)[0]
    auto_fit = min(longest_payload_bits(mesh, m, params, auto_move), MAX_DATA_BITS)
    fit = min(max_data_bits(cap), MAX_DATA_BITS) if params_mode == "thesis" else auto_fit
    d = {"input": inp, "method": method, "params_mode": params_mode, "params": p, "weld": weld, "key_bins": key_bins,
         "n_vertices": mesh.n_vertices, "capacity": cap, "max_message_bits": fit, "max_text_bytes": fit // 8,
         "thesis": {"params": thesis_p, "capacity": thesis_cap, "max_message_bits": thesis_fit,
                    "max_text_bytes": thesis_fit // 8},
         "auto": {"max_message_bits": auto_fit, "max_text_bytes": auto_fit // 8}}
    _emit(d, as_json, f"{inp}: {cap} carrier bits with the {method} method and --params {params_mode} "
                      f"({m.describe(p)}); the longest message: {auto_fit} bits ({auto_fit // 8} text bytes) "
                      f"with --params auto, {thesis_fit} bits ({thesis_fit // 8} text bytes) with the thesis "
                      f"parameters ({thesis_cap} carrier bits)")


# --- attack (meshmark/attacks/cli.py) / compare ---------------------------------------------------------

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
@click.option("--samples", type=int, default=None, help="Area samples per direction, 0..10,000,000 (default 2 x triangles), plus the vertices.")
@click.option("--seed", type=int, default=0, show_default=True, help="Sampling seed, 0..2^63-1.")
@jsonout.option()
def compare(mesh_a, mesh_b, samples, seed, as_json):
    """Distortion of B relative to the reference A: vertex RMSE, Hausdorff and RMS surface distance
    (absolute and relative to A's bounding-box diagonal), normal degradation (eq. 3.2.2) in degrees."""
    from . import read_mesh
    from .metrics import compare as run_compare
    from .ranges import check_int, check_seed

    if samples is not None:  # before the meshes are read; 10^7 samples hold 240 MB of points
        check_int("samples", samples, 0, 10_000_000)
    check_seed(seed)
    d = run_compare(read_mesh(mesh_a), read_mesh(mesh_b), n_samples=samples, seed=seed)
    d = {"reference": mesh_a, "input": mesh_b, **d}
    _emit(d, as_json, _format_compare(mesh_a, mesh_b, d), aliases={"a": "reference", "b": "input"})


# --- steganalysis ---------------------------------------------------------------------------
@main.group()
def steganalysis():
    """Detect hidden information without a key."""


from .steganalysis.cho_cli import add_command as _cho_command; _cho_command(steganalysis)  # noqa: E402,E702 (steganalysis cho)


from .stego.cli import stego as _stego_cli; main.add_command(_stego_cli)  # noqa: E402  (meshmark stego ...)
from .analysis.cli import analyze; main.add_command(analyze)  # noqa: E402,E702  (thesis ch. 3-5)
from .steganalysis.cli import add_commands as _steganalysis_commands; _steganalysis_commands(steganalysis)  # noqa: E402,E702
main.add_command(__import__("meshmark.study.cli", fromlist=["study"]).study)
[main.add_command(_c) for _c in __import__("meshmark.watermark.cli", fromlist=["COMMANDS"]).COMMANDS]  # issue, trace

main.add_command(__import__("meshmark.attacks.cli", fromlist=["attack"]).attack)  # attack

if __name__ == "__main__":  # pragma: no cover
    main()
