"""Checking a study spec: where a key is in the TOML text (:class:`Lines`, for errors that name the
line), the :class:`Checker` that raises them, the keys each table takes, and the attack and method
parameters a spec may name (an attack's values are tried once on a small torus)."""
from __future__ import annotations

import re

from .._core import MeshError
from .model import canon

TOP_KEYS = {"study", "meshes", "methods", "attacks", "measurements"}
STUDY_KEYS = {"name", "seeds", "payload", "payload_bits", "key", "store", "weld", "distance_seed", "distance_samples", "chunk_size", "description", "plugins"}
MESH_KEYS = {"paths", "root", "exclude", "compact", "limit", "recursive", "min_vertices"}
VARIANT_KEYS = {"name", "params", "grid", "random", "draws", "label", "level", "undo", "chain"}
CHAIN_KEYS = {"name", "params"}
UNDOABLE = {"similarity", "rotate", "reorder"}


# --- line numbers (tomllib gives none: find the key's line in the text) -----------------------------

_HEADER = re.compile(r"^\s*(\[\[?)\s*([^\]]+?)\s*\]\]?\s*(#.*)?$")
_KEYLINE = re.compile(r"^\s*([A-Za-z0-9_\-]+(?:\s*\.\s*[A-Za-z0-9_\-]+)*)\s*=")
_INLINE_KEY = re.compile(r"([A-Za-z0-9_\-]+)\s*=")


class Lines:
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
        name = path_text(path)
        if no is not None:
            return f"{self.source}:{no}: {name}"
        return f"{self.source}: {name}" if self.source else name


def path_text(path) -> str:
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (("." if out else "") + str(p))
    return out or "(spec)"



class Checker:
    def __init__(self, lines: Lines):
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


def all_attacks() -> dict:
    from ..attacks import ATTACKS
    from . import deform
    return {**{k: _attack_kwargs(k) for k in ATTACKS}, **deform.available()}


def method_params(name) -> set:
    from ..watermark import framework
    import sys
    m = framework.METHODS[name]
    d = getattr(m, "defaults", None)
    if d is None:
        d = getattr(sys.modules[type(m).__module__], "DEFAULTS")
    return set(d) | {"params"}  # plus the framework's parameter mode: "auto" (default) or "thesis"


def check_attack_values(ck, path, chain):
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



def check_unique(ck, variants, what, ident):
    seen = {}
    for v in variants:
        k = canon(ident(v))
        if k in seen:
            ck.fail((what,), f"two {what} entries expand to the same setting ({v.label!r}); results are keyed by "
                             "their inputs, so each setting must be listed once")
        seen[k] = v
    return variants


