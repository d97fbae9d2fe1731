"""Study specs: reading the TOML schema (the same thing as a Python dict) into an expanded spec.

A spec is read with :func:`load_spec` (a TOML path, TOML text or a dict) into a :class:`Spec`:
the meshes found, the method variants (grid points and random draws), the attack variants (single
attacks or chains, grids and draws) and the measurements, all checked before any task runs. Every
error is a :class:`~meshmark.MeshError` that names the TOML line (``smoke.toml:12: ...``) or, for a
dict, the key path (``methods[1].grid.alpha: ...``). The schema is documented in ``docs/studies.md``.

This module reads each table; what it builds is in :mod:`.model`, the checks it applies in
:mod:`.validation`, grids, draws, labels and the task plan in :mod:`.expansion`, mesh loading and digests
in :mod:`.meshes` (their public names are importable from here too).
"""
from __future__ import annotations

import glob
import os
import pathlib
import re

from .._core import MeshError
from .expansion import auto_label, expand_values, fmt_label, level, plan  # noqa: F401  (plan: re-exported)
from .meshes import BUILTINS, MESH_SUFFIXES, mesh_digest, welded_vertices  # noqa: F401  (re-exported)
from .model import AttackVariant, MethodVariant, Spec, embed_key  # noqa: F401  (re-exported)
from .validation import (CHAIN_KEYS, MESH_KEYS, STUDY_KEYS, TOP_KEYS, UNDOABLE, VARIANT_KEYS, Checker, Lines,
                         all_attacks, check_attack_values, check_unique, method_params)
from .._typing import PathLike
from typing import Any

try:  # Python >= 3.11
    import tomllib
except ImportError:  # pragma: no cover - Python 3.10
    import tomli as tomllib


# --- loading ----------------------------------------------------------------------------------------

def load_spec(spec: PathLike | dict[str, Any], base: PathLike | None = None) -> Spec:
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
    L = Lines(text, source)
    return _build(raw, L, base, source)


def _build(raw: dict, L: Lines, base: pathlib.Path, source: str) -> Spec:
    ck = Checker(L)
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
        known = set() if name == "none" else set(kind.defaults) if kind is not None else method_params(name)
        plist, varying = expand_values(ck, e, path, known, f"the {name} method", f"method/{i}/{name}")
        for p in plist:
            if kind is not None and kind.check is not None:
                try:
                    kind.check(p)
                except MeshError as err:
                    where = next((k for k in ("params", "grid", "random") if e.get(k)), "name")
                    ck.fail(path + (where,), f"method {name!r} with {p}: {err}")
            label = fmt_label(ck, path, e.get("label"), p, auto_label(name, p, varying))
            out.append(MethodVariant(name, p, label))
    return check_unique(ck, out, "methods", lambda v: v.ident())


def _attacks(ck, entries):
    if isinstance(entries, dict):
        entries = [entries]
    if not isinstance(entries, list) or not entries:
        ck.fail(("attacks",), "attacks must be a non-empty list of [[attacks]] tables")
    known_all = all_attacks()
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
            check_attack_values(ck, path + ("chain",), steps)
            label = e.get("label") or " + ".join(auto_label(n, p, list(p)) for n, p in steps)
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
        plist, varying = expand_values(ck, e, path, known, f"the {name} attack", f"attack/{i}/{name}")
        for p in plist:
            chain = () if name == "none" else ((name, p),)
            if chain:
                where = next((k for k in ("params", "grid", "random") if e.get(k)), "name")
                check_attack_values(ck, path + (where,), chain)
            label = fmt_label(ck, path, e.get("label"), p, auto_label(name, p, varying))
            out.append(AttackVariant(label, chain, undo, level(p, varying, e.get("level"))))
    return check_unique(ck, out, "attacks", lambda v: v.ident())


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
