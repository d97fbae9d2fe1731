"""Study specs: the TOML schema (the same thing as a Python dict), validation and expansion.

A spec is read with :func:`load_spec` (a TOML path, TOML text or a dict) into a :class:`Spec`:
the meshes found, the method variants (grid points and random draws), the attack variants (single
attacks or chains, grids and draws) and the measurements, all checked before any task runs. Every
error is a :class:`~meshmark.MeshError` that names the TOML line (``smoke.toml:12: ...``) or, for a
dict, the key path (``methods[1].grid.alpha: ...``). The schema is documented in ``docs/studies.md``.
"""
from __future__ import annotations

import glob
import hashlib
import itertools
import json
import math
import os
import pathlib
import re
from dataclasses import dataclass, field

import numpy as np

from .._core import MeshError

try:  # Python >= 3.11
    import tomllib
except ImportError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

MESH_SUFFIXES = (".obj", ".off", ".ply", ".stl")
TOP_KEYS = {"study", "meshes", "methods", "attacks", "measurements"}
STUDY_KEYS = {"name", "seeds", "payload", "payload_bits", "key", "store", "weld", "distance_seed", "distance_samples", "chunk_size", "description", "plugins"}
MESH_KEYS = {"paths", "root", "exclude", "compact", "limit", "recursive", "min_vertices"}
VARIANT_KEYS = {"name", "params", "grid", "random", "draws", "label", "level", "undo", "chain"}
CHAIN_KEYS = {"name", "params"}
VECTOR_PARAMS = {"axis", "center", "normal", "offset", "scale_range"}
UNDOABLE = {"similarity", "rotate", "reorder"}


# --- line numbers (tomllib gives none: find the key's line in the text) -----------------------------

_HEADER = re.compile(r"^\s*(\[\[?)\s*([^\]]+?)\s*\]\]?\s*(#.*)?$")
_KEYLINE = re.compile(r"^\s*([A-Za-z0-9_\-]+(?:\s*\.\s*[A-Za-z0-9_\-]+)*)\s*=")
_INLINE_KEY = re.compile(r"([A-Za-z0-9_\-]+)\s*=")


class _Lines:
    """Maps key paths (tuples of names and array indices) to 1-based TOML line numbers.

    One pass over the text: ``[[methods]]`` opens ``methods[i]``; a sub-table ``[methods.params]``
    refers to the last ``[[methods]]`` seen; ``key =`` lines and the keys of inline tables on them are
    recorded under the current table."""

    def __init__(self, text: str | None, source: str):
        self.source = source
        self.lines: dict = {}
        self.text = text.splitlines() if text else []
        self._live: dict = {}
        table: tuple = ()
        for no, line in enumerate(self.text, 1):
            h = _HEADER.match(line)
            if h and not _KEYLINE.match(line):
                path = tuple(p.strip().strip('"') for p in h.group(2).split("."))
                base = self._resolve(path)
                if h.group(1) == "[[":
                    i = self._live.get(base, -1) + 1
                    self._live[base] = i
                    table = base + (i,)
                else:
                    table = base
                self.lines.setdefault(table, no)
                continue
            k = _KEYLINE.match(line)
            if k:
                key = tuple(p.strip() for p in k.group(1).split("."))
                self.lines.setdefault(table + key, no)
                rest = line[k.end():]
                if "{" in rest:
                    for inner in _INLINE_KEY.findall(rest):
                        self.lines.setdefault(table + key + (inner,), no)

    def _resolve(self, path: tuple) -> tuple:
        out: tuple = ()
        for p in path:
            out = out + (p,)
            c = self._live.get(out)
            if c is not None and out != tuple(path):
                out = out + (c,)
        return out

    def line(self, path: tuple) -> int | None:
        path = tuple(path)
        for n in range(len(path), 0, -1):
            if path[:n] in self.lines:
                no = self.lines[path[:n]]
                last = path[-1]
                if n < len(path) and isinstance(last, str):  # search forward in that table for the key
                    pat = re.compile(r"(^|[\s{,])" + re.escape(last) + r"\s*=")
                    for j in range(no - 1, len(self.text)):
                        if j > no - 1 and _HEADER.match(self.text[j]) and not _KEYLINE.match(self.text[j]):
                            break
                        if pat.search(self.text[j]):
                            return j + 1
                return no
        return None

    def where(self, path) -> str:
        no = self.line(path) if self.text else None
        name = _path_text(path)
        if no is not None:
            return f"{self.source}:{no}: {name}"
        return f"{self.source}: {name}" if self.source else name


def _path_text(path) -> str:
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (("." if out else "") + str(p))
    return out or "(spec)"


# --- the expanded spec -----------------------------------------------------------------------------

@dataclass(frozen=True)
class MethodVariant:
    name: str            # a key of meshmark.watermark.METHODS, or "none" (attack-only study)
    params: dict
    label: str

    def ident(self) -> dict:
        return {"name": self.name, "params": self.params}


@dataclass(frozen=True)
class AttackVariant:
    label: str
    chain: tuple          # ((name, params), ...): applied in order; () = no attack
    undo: bool = False    # measure distortion after undoing a similarity / rotation / reordering
    level: float | None = None

    def ident(self) -> dict:
        return {"chain": [[n, p] for n, p in self.chain], "undo": self.undo}


@dataclass
class Spec:
    name: str
    source: str
    base: pathlib.Path
    meshes: list               # [(label, absolute path)]
    methods: list              # [MethodVariant]
    attacks: list              # [AttackVariant]
    measurements: list         # [name]
    seeds: list
    payload_bits: int = 16
    payload: str | None = None
    key: str = "seed-{seed}"
    weld: bool = True
    compact: bool = False
    store: bool = False
    distance_seed: int = 0
    distance_samples: int | None = None
    chunk_size: int = 64
    plugins: list = field(default_factory=list)   # modules imported by the driver and every worker
    raw: dict = field(default_factory=dict)

    @property
    def n_tasks(self) -> int:
        return len(self.meshes) * len(self.methods) * len(self.attacks) * len(self.seeds)

    def common(self) -> dict:
        """The inputs every task shares (part of every key)."""
        from .. import __version__
        return {"meshmark": __version__, "format": 1, "measurements": sorted(self.measurements),
                "payload_bits": self.payload_bits, **({"payload": self.payload} if self.payload is not None else {}), "key": self.key, "weld": self.weld, "compact": self.compact,
                "distance_seed": self.distance_seed, "distance_samples": self.distance_samples}


def _canon(x) -> str:
    return json.dumps(x, sort_keys=True, separators=(",", ":"), default=_json_default)


def _json_default(o):
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, tuple):
        return list(o)
    raise TypeError(f"not JSON: {o!r}")


def _digest(x) -> bytes:
    return hashlib.blake2b(_canon(x).encode(), digest_size=16).digest()


# --- validation helpers ----------------------------------------------------------------------------

class _Checker:
    def __init__(self, lines: _Lines):
        self.L = lines

    def fail(self, path, msg):
        raise MeshError(f"{self.L.where(path)}: {msg}")

    def table(self, d, path, allowed):
        if not isinstance(d, dict):
            self.fail(path, f"must be a table, got {type(d).__name__}")
        bad = sorted(set(d) - set(allowed))
        if bad:
            self.fail(tuple(path) + (bad[0],), f"unknown key {bad[0]!r} (expected one of {', '.join(sorted(allowed))})")
        return d


def _attack_kwargs(name):
    from ..attacks import parameters
    return set(parameters(name))


def _all_attacks() -> dict:
    from ..attacks import ATTACKS
    from . import deform
    return {**{k: _attack_kwargs(k) for k in ATTACKS}, **deform.available()}


def _method_params(name) -> set:
    from ..watermark import framework
    import sys
    m = framework.METHODS[name]
    d = getattr(m, "defaults", None)
    if d is None:
        d = getattr(sys.modules[type(m).__module__], "DEFAULTS")
    return set(d) | {"params"}  # plus the framework's parameter mode: "auto" (default) or "thesis"


def _expand_values(ck: _Checker, entry: dict, path: tuple, known: set | None, what: str, seed_text: str):
    """The parameter dicts of one entry: params (fixed) x grid (product) x random draws."""
    params = entry.get("params", {}) or {}
    grid = entry.get("grid", {}) or {}
    rnd = entry.get("random", {}) or {}
    for k, sub in (("params", params), ("grid", grid), ("random", rnd)):
        if not isinstance(sub, dict):
            ck.fail(path + (k,), f"must be a table of parameter = value, got {type(sub).__name__}")
        if known is not None:
            for p in sub:
                if p not in known:
                    ck.fail(path + (k, p), f"unknown parameter {p!r} for {what} "
                                           f"(known: {', '.join(sorted(known)) or 'none'})")
    seen = {}
    for k, sub in (("params", params), ("grid", grid), ("random", rnd)):
        for p in sub:
            if p in seen:
                ck.fail(path + (k, p), f"parameter {p!r} is given both in {seen[p]} and {k}")
            seen[p] = k
    for p, vals in grid.items():
        if not isinstance(vals, list) or not vals:
            ck.fail(path + ("grid", p), f"a grid axis must be a non-empty list of values, got {vals!r}")
    for p, rng in rnd.items():
        if not (isinstance(rng, list) and len(rng) == 2 and all(isinstance(x, (int, float)) and not isinstance(x, bool)
                                                                 for x in rng)):
            ck.fail(path + ("random", p), f"a random range must be [min, max] (two numbers), got {rng!r}")
        if not (math.isfinite(rng[0]) and math.isfinite(rng[1])):
            ck.fail(path + ("random", p), f"range bounds must be finite, got {rng!r}")
        if rng[0] > rng[1]:
            ck.fail(path + ("random", p), f"range min > max: [{rng[0]}, {rng[1]}]")
    draws = entry.get("draws", 1 if rnd else 0)
    if isinstance(draws, bool) or not isinstance(draws, int) or draws < 0 or (rnd and draws < 1):
        ck.fail(path + ("draws",), f"draws must be an integer >= 1 with random ranges, got {draws!r}")
    if draws and not rnd:
        ck.fail(path + ("draws",), "draws without a [random] table of ranges")
    out = []
    names = list(grid)
    for combo in itertools.product(*(grid[n] for n in names)):
        base = {**params, **dict(zip(names, combo))}
        if not rnd:
            out.append(base)
            continue
        for d in range(draws):
            # deterministic: the draw depends on the entry, the grid point and the draw index only
            h = hashlib.blake2b(_canon([seed_text, base, rnd, d]).encode(), digest_size=8).digest()
            g = np.random.default_rng(int.from_bytes(h, "little"))
            p = dict(base)
            for name in sorted(rnd):
                lo, hi = rnd[name]
                if isinstance(lo, int) and isinstance(hi, int):
                    p[name] = int(g.integers(lo, hi + 1))
                else:
                    p[name] = float(g.uniform(lo, hi))
            out.append(p)
    return out, names + sorted(rnd)


def _fmt_label(ck, path, template, params, default):
    if template is None:
        return default
    try:
        return str(template).format(**params)
    except (KeyError, ValueError, IndexError) as e:
        ck.fail(path + ("label",), f"label template {template!r} cannot be filled from {params}: {e}")


def _auto_label(name, params, varying):
    shown = [k for k in varying if k in params] or []
    if not shown:
        return name
    return name + " " + ",".join(f"{k}={params[k]:g}" if isinstance(params[k], float) else f"{k}={params[k]}"
                                 for k in shown)


def _level(params, varying, level_key):
    k = level_key or next((k for k in varying if isinstance(params.get(k), (int, float))
                           and not isinstance(params.get(k), bool)), None)
    v = params.get(k) if k else None
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else None


def _check_attack_values(ck, path, chain):
    """Run each attack once on a tiny mesh: bad values (negative strength, unknown kind, ...) fail here."""
    from ..attacks import ATTACKS
    from . import deform
    from ..shapes import torus
    probe = torus(12, 6)
    m = probe
    for name, params in chain:
        try:
            if name in ATTACKS:
                m = ATTACKS[name](m, **params)
            else:
                m = deform.apply(name, m, params, seed=0)
        except MeshError as e:
            ck.fail(path, f"attack {name!r} with {params}: {e}")
        except TypeError as e:
            ck.fail(path, f"attack {name!r} with {params}: {e}")


# --- loading ----------------------------------------------------------------------------------------

def load_spec(spec, base=None) -> Spec:
    """A :class:`Spec` from a TOML file path, TOML text, or a dict (relative mesh paths are taken from
    ``base``, default the TOML file's folder or the current directory). MeshError on a bad spec."""
    text, source = None, ""
    if isinstance(spec, dict):
        raw = spec
    else:
        s = str(spec)
        if "\n" not in s and (s.endswith(".toml") or os.path.exists(s)):
            p = pathlib.Path(s)
            if not p.is_file():
                raise MeshError(f"study spec {s}: no such file")
            text, source = p.read_text(), str(p)
            base = base or p.resolve().parent
        else:
            text, source = s, "<spec>"
        try:
            raw = tomllib.loads(text)
        except tomllib.TOMLDecodeError as e:
            raise MeshError(f"{source}: not valid TOML: {e}") from None
    base = pathlib.Path(base or os.getcwd()).resolve()
    L = _Lines(text, source)
    return _build(raw, L, base, source)


def _build(raw: dict, L: _Lines, base: pathlib.Path, source: str) -> Spec:
    ck = _Checker(L)
    ck.table(raw, (), TOP_KEYS)
    study = ck.table(raw.get("study", {}), ("study",), STUDY_KEYS)
    # seeds
    seeds = study.get("seeds", [0])
    if isinstance(seeds, int) and not isinstance(seeds, bool):
        if seeds < 1:
            ck.fail(("study", "seeds"), f"seeds must be >= 1 (a count) or a list, got {seeds}")
        seeds = list(range(seeds))
    if not isinstance(seeds, list) or not seeds or not all(isinstance(s, int) and not isinstance(s, bool) and s >= 0
                                                             for s in seeds):
        ck.fail(("study", "seeds"), f"seeds must be a count or a non-empty list of integers >= 0, got {seeds!r}")
    if len(set(seeds)) != len(seeds):
        ck.fail(("study", "seeds"), "seeds repeat")
    opts = {}
    for k, typ, lo in (("payload_bits", int, 1), ("distance_seed", int, 0), ("distance_samples", int, 0),
                         ("chunk_size", int, 1)):
        if k in study:
            v = study[k]
            if isinstance(v, bool) or not isinstance(v, typ) or v < lo:
                ck.fail(("study", k), f"{k} must be an integer >= {lo}, got {v!r}")
            opts[k] = v
    for k in ("store", "weld"):
        if k in study:
            if not isinstance(study[k], bool):
                ck.fail(("study", k), f"{k} must be true or false, got {study[k]!r}")
            opts[k] = study[k]
    if "payload" in study:
        if not isinstance(study["payload"], str) or not study["payload"]:
            ck.fail(("study", "payload"), f"payload must be a non-empty text message, got {study['payload']!r}")
        opts["payload"] = study["payload"]
    if "key" in study:
        if not isinstance(study["key"], str) or not study["key"]:
            ck.fail(("study", "key"), "key must be a non-empty string (may contain {seed})")
        try:
            study["key"].format(seed=0)
        except (KeyError, ValueError, IndexError) as e:
            ck.fail(("study", "key"), f"key template {study['key']!r}: {e} (only {{seed}} is known)")
        opts["key"] = study["key"]

    if "plugins" in study:
        pl = study["plugins"]
        if not isinstance(pl, list) or not all(isinstance(x, str) and x for x in pl):
            ck.fail(("study", "plugins"), f"plugins must be a list of module names, got {pl!r}")
        from .kinds import load_plugins
        try:
            load_plugins(pl)
        except ImportError as e:
            ck.fail(("study", "plugins"), f"cannot import a plugin module: {e}")
        opts["plugins"] = list(pl)
    else:
        from .kinds import load_plugins
        load_plugins()

    meshes, compact = _meshes(ck, raw.get("meshes"), base)
    methods = _methods(ck, raw.get("methods", [{"name": "none"}]))
    attacks = _attacks(ck, raw.get("attacks", [{"name": "none"}]))
    measurements = _measurements(ck, raw.get("measurements", None), methods)
    return Spec(name=str(study.get("name", pathlib.Path(source).stem if source else "study")), source=source,
                base=base, meshes=meshes, methods=methods, attacks=attacks, measurements=measurements, seeds=seeds,
                compact=compact, raw=raw, **opts)


def _meshes(ck, m, base):
    path = ("meshes",)
    if m is None:
        ck.fail((), "no [meshes] table: a study needs meshes (paths = [files, folders or globs])")
    if isinstance(m, list):
        m = {"paths": m}
    ck.table(m, path, MESH_KEYS)
    paths = m.get("paths")
    if isinstance(paths, str):
        paths = [paths]
    if not isinstance(paths, list) or not paths or not all(isinstance(p, str) for p in paths):
        ck.fail(path + ("paths",), f"paths must be a non-empty list of files, folders or globs, got {paths!r}")
    root = base / m["root"] if "root" in m else base
    recursive = m.get("recursive", True)
    exclude = m.get("exclude", [])
    found = []
    for i, p in enumerate(paths):
        if p.startswith("builtin:"):
            from .task import BUILTINS
            if p.split(":", 1)[1] not in BUILTINS:
                ck.fail(path + ("paths",), f"unknown built-in mesh {p!r} (known: {', '.join('builtin:' + b for b in BUILTINS)})")
            found.append((p, p))
            continue
        full = os.path.expanduser(p)
        full = full if os.path.isabs(full) else str(root / full)
        if os.path.isdir(full):
            anchor = full.rstrip("/")
            pattern = os.path.join(full, "**", "*") if recursive else os.path.join(full, "*")
            hits = [h for h in glob.glob(pattern, recursive=recursive) if h.lower().endswith(MESH_SUFFIXES)]
        elif any(c in p for c in "*?["):
            prefix = re.split(r"[*?\[]", full, maxsplit=1)[0]
            anchor = os.path.dirname(prefix) if not prefix.endswith("/") else prefix.rstrip("/")
            hits = [h for h in glob.glob(full, recursive=True) if h.lower().endswith(MESH_SUFFIXES)]
        elif os.path.isfile(full):
            anchor, hits = os.path.dirname(full), [full]
        else:
            ck.fail(path + ("paths",), f"{p!r}: no such file or folder (looked at {full})")
        if not hits:
            ck.fail(path + ("paths",), f"{p!r} matches no mesh file ({', '.join(MESH_SUFFIXES)})")
        # label: the path from the folder the entry names (its parent, so "classic/cow.obj")
        top = os.path.dirname(os.path.abspath(anchor))
        found += [(os.path.relpath(os.path.abspath(h), top), h) for h in sorted(hits)]
    seen, labels, out = set(), set(), []
    for label, h in found:
        if h.startswith("builtin:"):
            if h not in seen:
                seen.add(h)
                out.append((h, h))
            continue
        a = os.path.realpath(h)
        if a in seen or any(pathlib.PurePath(label).match(x) or pathlib.PurePath(h).match(x) for x in exclude):
            continue
        seen.add(a)
        if label in labels:
            label = os.path.relpath(os.path.abspath(h), str(root))
        labels.add(label)
        out.append((label, a))
    if "min_vertices" in m:
        mv = m["min_vertices"]
        if isinstance(mv, bool) or not isinstance(mv, int) or mv < 0:
            ck.fail(path + ("min_vertices",), f"min_vertices must be an integer >= 0, got {mv!r}")
        out = [(label, a) for label, a in out if welded_vertices(a) >= mv]
    if "limit" in m:
        out = out[: int(m["limit"])]
    if not out:
        ck.fail(path + ("paths",), "the mesh set is empty (after exclude / limit)")
    compact = m.get("compact", False)
    if not isinstance(compact, bool):
        ck.fail(path + ("compact",), f"compact must be true or false, got {compact!r}")
    return out, compact


def welded_vertices(path: str) -> int:
    """Vertices the faces use once vertices at equal positions are merged (what the methods see with
    ``weld = true``): the size a spec's ``meshes.min_vertices`` compares. Unreadable files count 0."""
    from ..topology import weld_vertices
    from .task import load_mesh
    try:
        m = weld_vertices(load_mesh(path)).mesh
    except MeshError:
        return 0
    used = np.zeros(m.n_vertices, bool)
    used[m.face_indices] = True
    return int(used.sum())


def _methods(ck, entries):
    from ..watermark import framework
    from .kinds import METHOD_KINDS
    if isinstance(entries, dict):
        entries = [entries]
    if not isinstance(entries, list) or not entries:
        ck.fail(("methods",), "methods must be a non-empty list of [[methods]] tables")
    out = []
    for i, e in enumerate(entries):
        path = ("methods", i)
        if isinstance(e, str):
            e = {"name": e}
        ck.table(e, path, VARIANT_KEYS - {"undo", "chain"})
        name = e.get("name")
        if name is None:
            ck.fail(path, "a method needs a name")
        kind = METHOD_KINDS.get(name)
        if name != "none" and name not in framework.METHODS and kind is None:
            ck.fail(path + ("name",), f"unknown method {name!r} (known: none, "
                                      f"{', '.join(list(framework.METHODS) + list(METHOD_KINDS))})")
        known = set() if name == "none" else set(kind.defaults) if kind is not None else _method_params(name)
        plist, varying = _expand_values(ck, e, path, known, f"the {name} method", f"method/{i}/{name}")
        for p in plist:
            if kind is not None and kind.check is not None:
                try:
                    kind.check(p)
                except MeshError as err:
                    where = next((k for k in ("params", "grid", "random") if e.get(k)), "name")
                    ck.fail(path + (where,), f"method {name!r} with {p}: {err}")
            label = _fmt_label(ck, path, e.get("label"), p, _auto_label(name, p, varying))
            out.append(MethodVariant(name, p, label))
    return _unique(ck, out, "methods", lambda v: v.ident())


def _attacks(ck, entries):
    if isinstance(entries, dict):
        entries = [entries]
    if not isinstance(entries, list) or not entries:
        ck.fail(("attacks",), "attacks must be a non-empty list of [[attacks]] tables")
    known_all = _all_attacks()
    out = []
    for i, e in enumerate(entries):
        path = ("attacks", i)
        if isinstance(e, str):
            e = {"name": e}
        ck.table(e, path, VARIANT_KEYS)
        undo = e.get("undo", False)
        if not isinstance(undo, bool):
            ck.fail(path + ("undo",), f"undo must be true or false, got {undo!r}")
        if "chain" in e:
            chain = e["chain"]
            if "name" in e or "params" in e or "grid" in e or "random" in e:
                ck.fail(path + ("chain",), "a chain entry takes chain = [...] and a label, not name/params/grid")
            if isinstance(chain, str):  # the chain text of `meshmark attack --chain` (meshmark.attacks.parse_chain)
                from ..attacks import parse_chain
                try:
                    chain = [{"name": n, "params": p} for n, p in parse_chain(chain)]
                except MeshError as err:
                    ck.fail(path + ("chain",), str(err))
                if "label" not in e:
                    e = {**e, "label": e["chain"]}
            if not isinstance(chain, list) or not chain:
                ck.fail(path + ("chain",), "chain must be a chain text (\"bend:30,noise:0.001\") or a non-empty list of "
                                           "{name = ..., params = {...}}")
            steps = []
            for j, st in enumerate(chain):
                sp = path + ("chain", j)
                if not isinstance(st, dict):
                    ck.fail(path + ("chain",), f"chain step {j} must be an inline table, got {st!r}")
                bad = sorted(set(st) - CHAIN_KEYS)
                if bad:
                    ck.fail(path + ("chain", bad[0]), f"chain step {j}: unknown key {bad[0]!r} (expected name, params)")
                nm = st.get("name")
                if nm not in known_all:
                    ck.fail(path + ("chain", "name"), f"chain step {j}: unknown attack {nm!r} "
                                                      f"(known: none, {', '.join(sorted(known_all))})")
                pr = st.get("params", {})
                for p in pr:
                    if p not in known_all[nm]:
                        ck.fail(path + ("chain", p), f"chain step {j}: unknown parameter {p!r} for the {nm} attack "
                                                     f"(known: {', '.join(sorted(known_all[nm])) or 'none'})")
                steps.append((nm, dict(pr)))
            if undo:
                ck.fail(path + ("undo",), "undo is only for a single similarity, rotate or reorder attack")
            _check_attack_values(ck, path + ("chain",), steps)
            label = e.get("label") or " + ".join(_auto_label(n, p, list(p)) for n, p in steps)
            out.append(AttackVariant(str(label), tuple(steps), False, None))
            continue
        name = e.get("name")
        if name is None:
            ck.fail(path, "an attack needs a name (or a chain)")
        if name != "none" and name not in known_all:
            ck.fail(path + ("name",), f"unknown attack {name!r} (known: none, {', '.join(sorted(known_all))})")
        if undo and name not in UNDOABLE:
            ck.fail(path + ("undo",), f"undo is only for {', '.join(sorted(UNDOABLE))}, not {name!r}")
        known = set() if name == "none" else known_all[name]
        plist, varying = _expand_values(ck, e, path, known, f"the {name} attack", f"attack/{i}/{name}")
        for p in plist:
            chain = () if name == "none" else ((name, p),)
            if chain:
                where = next((k for k in ("params", "grid", "random") if e.get(k)), "name")
                _check_attack_values(ck, path + (where,), chain)
            label = _fmt_label(ck, path, e.get("label"), p, _auto_label(name, p, varying))
            out.append(AttackVariant(label, chain, undo, _level(p, varying, e.get("level"))))
    return _unique(ck, out, "attacks", lambda v: v.ident())


def _unique(ck, variants, what, ident):
    seen = {}
    for v in variants:
        k = _canon(ident(v))
        if k in seen:
            ck.fail((what,), f"two {what} entries expand to the same setting ({v.label!r}); results are keyed by "
                             "their inputs, so each setting must be listed once")
        seen[k] = v
    return variants


def _measurements(ck, m, methods):
    from .measure import MEASUREMENTS, DEFAULT
    path = ("measurements",)
    marked = any(v.name != "none" for v in methods)
    if m is None:
        names = [n for n in DEFAULT if marked or not MEASUREMENTS[n].needs_mark]
    else:
        if isinstance(m, dict):
            ck.table(m, path, {"list"})
            m, path = m.get("list"), path + ("list",)
        if not isinstance(m, list) or not all(isinstance(x, str) for x in m):
            ck.fail(path, f"measurements must be a list of names, got {m!r}")
        names = list(dict.fromkeys(m))
    for n in names:
        if n not in MEASUREMENTS:
            ck.fail(path, f"unknown measurement {n!r} (known: {', '.join(MEASUREMENTS)})")
    for n in names:
        if MEASUREMENTS[n].needs_mark and not marked:
            ck.fail(path, f"measurement {n!r} needs a watermark method, but every method is 'none'")
    return names


# --- tasks and keys ---------------------------------------------------------------------------------

def mesh_digest(path: str) -> str:
    """blake2b-128 of a file's bytes (hex); of the vertex and face arrays for ``builtin:NAME``."""
    h = hashlib.blake2b(digest_size=16)
    if path.startswith("builtin:"):
        from .task import builtin_mesh
        m = builtin_mesh(path.split(":", 1)[1])
        for a in (m.V, m.face_indices, m.face_offsets):
            h.update(np.ascontiguousarray(a).tobytes())
        return h.hexdigest()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def plan(spec: Spec, mesh_digests=None):
    """Every task of the spec, mesh-major: ``(keys (T,) list of 32-hex str, index (T, 4) int32 array of
    (mesh, method, seed, attack) indices, mesh digests)``.

    A key is blake2b-128 over the common inputs (meshmark version, measurements, payload, key
    template, weld, compaction), the mesh's label and content digest, the method variant, the attack
    variant and the seed: a pure function of the task's inputs, whatever runs it.
    """
    digests = mesh_digests or [mesh_digest(p) for _, p in spec.meshes]
    common = _digest(spec.common())
    mh = [hashlib.blake2b(common + _canon([lab, d]).encode(), digest_size=16).digest()
          for (lab, _), d in zip(spec.meshes, digests)]
    meth = [_digest(v.ident()) for v in spec.methods]
    att = [_digest(v.ident()) for v in spec.attacks]
    seeds = [int(s).to_bytes(8, "little") for s in spec.seeds]
    nM, nm, ns, na = len(mh), len(meth), len(seeds), len(att)
    keys = []
    append = keys.append
    b2 = hashlib.blake2b
    for a in mh:
        for b in meth:
            ab = a + b
            for s in seeds:
                abs_ = ab + s
                for c in att:
                    append(b2(abs_ + c, digest_size=16).hexdigest())
    idx = np.stack(np.meshgrid(np.arange(nM), np.arange(nm), np.arange(ns), np.arange(na), indexing="ij"),
                   -1).reshape(-1, 4).astype(np.int32)
    return keys, idx, digests


def embed_key(mesh_digest_hex: str, method: MethodVariant, seed: int, spec: Spec) -> str:
    """Key of a marked mesh in the store: content of the mesh, method, payload, key and seed only, so
    any study with the same inputs (whatever its attacks or mesh names) finds it."""
    from .. import __version__
    return hashlib.blake2b(_canon({"mesh": mesh_digest_hex, "method": method.ident(), "seed": seed,
                                   "payload_bits": spec.payload_bits, "key": spec.key,
                                   **({"payload": spec.payload} if spec.payload is not None else {}), "weld": spec.weld,
                                   "compact": spec.compact, "meshmark": __version__}).encode(),
                           digest_size=16).hexdigest()
