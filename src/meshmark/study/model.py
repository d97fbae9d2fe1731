"""The expanded study spec, the data every module of a study shares: :class:`Spec` with its
:class:`MethodVariant` and :class:`AttackVariant` lists, the canonical JSON and digests that key
tasks (:func:`canon`, :func:`digest`) and the key of a marked mesh in the store (:func:`embed_key`).

Read and checked by :mod:`.spec` (:func:`~meshmark.study.spec.load_spec`), expanded into tasks by
:mod:`.expansion`, run by :mod:`.task`. Imports nothing of the study package.
"""
from __future__ import annotations

import hashlib
import json
import pathlib
from dataclasses import dataclass, field

import numpy as np


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
        """The number of tasks: meshes x method variants x seeds x attack variants."""
        return len(self.meshes) * len(self.methods) * len(self.attacks) * len(self.seeds)

    def common(self) -> dict:
        """The inputs every task shares (part of every key)."""
        from .. import __version__
        return {"meshmark": __version__, "format": 1, "measurements": sorted(self.measurements),
                "payload_bits": self.payload_bits, **({"payload": self.payload} if self.payload is not None else {}), "key": self.key, "weld": self.weld, "compact": self.compact,
                "distance_seed": self.distance_seed, "distance_samples": self.distance_samples}


def canon(x) -> str:
    return json.dumps(x, sort_keys=True, separators=(",", ":"), default=_json_default)


def _json_default(o):
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, tuple):
        return list(o)
    raise TypeError(f"not JSON: {o!r}")


def digest(x) -> bytes:
    return hashlib.blake2b(canon(x).encode(), digest_size=16).digest()



def embed_key(mesh_digest_hex: str, method: MethodVariant, seed: int, spec: Spec) -> str:
    """Key of a marked mesh in the store: content of the mesh, method, payload, key and seed only, so
    any study with the same inputs (whatever its attacks or mesh names) finds it."""
    from .. import __version__
    return hashlib.blake2b(canon({"mesh": mesh_digest_hex, "method": method.ident(), "seed": seed,
                                   "payload_bits": spec.payload_bits, "key": spec.key,
                                   **({"payload": spec.payload} if spec.payload is not None else {}), "weld": spec.weld,
                                   "compact": spec.compact, "meshmark": __version__}).encode(),
                           digest_size=16).hexdigest()
