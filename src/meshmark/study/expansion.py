"""Expanding a study spec: an entry's parameter dicts (fixed params x grid product x keyed random
draws), the labels and levels of the variants, and the task plan (every task's key, mesh-major)."""
from __future__ import annotations

import hashlib
import itertools
import math

import numpy as np

from .meshes import mesh_digest
from .model import Spec, canon, digest
from .validation import Checker
from .._typing import IntArray
from typing import Sequence


def expand_values(ck: Checker, entry: dict, path: tuple, known: set | None, what: str, seed_text: str):
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
            h = hashlib.blake2b(canon([seed_text, base, rnd, d]).encode(), digest_size=8).digest()
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


def fmt_label(ck, path, template, params, default):
    if template is None:
        return default
    try:
        return str(template).format(**params)
    except (KeyError, ValueError, IndexError) as e:
        ck.fail(path + ("label",), f"label template {template!r} cannot be filled from {params}: {e}")


def auto_label(name, params, varying):
    shown = [k for k in varying if k in params] or []
    if not shown:
        return name
    return name + " " + ",".join(f"{k}={params[k]:g}" if isinstance(params[k], float) else f"{k}={params[k]}"
                                 for k in shown)


def level(params, varying, level_key):
    k = level_key or next((k for k in varying if isinstance(params.get(k), (int, float))
                           and not isinstance(params.get(k), bool)), None)
    v = params.get(k) if k else None
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else None



def plan(spec: Spec, mesh_digests: Sequence[str] | None = None) -> tuple[list[str], IntArray, list[str]]:
    """Every task of the spec, mesh-major: ``(keys (T,) list of 32-hex str, index (T, 4) int32 array of
    (mesh, method, seed, attack) indices, mesh digests)``.

    A key is blake2b-128 over the common inputs (meshmark version, measurements, payload, key
    template, weld, compaction), the mesh's label and content digest, the method variant, the attack
    variant and the seed: a pure function of the task's inputs, whatever runs it.
    """
    digests = mesh_digests or [mesh_digest(p) for _, p in spec.meshes]
    common = digest(spec.common())
    mh = [hashlib.blake2b(common + canon([lab, d]).encode(), digest_size=16).digest()
          for (lab, _), d in zip(spec.meshes, digests)]
    meth = [digest(v.ident()) for v in spec.methods]
    att = [digest(v.ident()) for v in spec.attacks]
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


