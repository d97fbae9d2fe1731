"""Shared fixtures. Tests that use ../shared/meshes fail (never skip) when the data is missing."""
import os
import pathlib
import re

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
SHARED = pathlib.Path(os.environ.get("MESHMARK_SHARED", ROOT.parent / "shared")) / "meshes"


def shared_mesh(rel: str) -> pathlib.Path:
    p = SHARED / rel
    assert p.is_file(), f"shared mesh {p} is missing: the tests need ../shared/meshes beside the repo"
    return p


def sources_table():
    """Rows (relative path, vertices, faces, topology text) of ../shared/meshes/SOURCES.md."""
    src = SHARED / "SOURCES.md"
    assert src.is_file(), f"{src} is missing: the tests need ../shared/meshes beside the repo"
    rows = []
    for line in src.read_text().splitlines():
        m = re.match(r"\| `([^`]+\.(obj|off|ply|stl))` \| (\d+) \| (\d+) \| ([^|]*) \|", line)
        if m:
            rows.append((m.group(1), int(m.group(3)), int(m.group(4)), m.group(5).strip()))
    assert len(rows) >= 80, "SOURCES.md lists fewer meshes than expected"
    return rows


def random_rotation(rng) -> np.ndarray:
    """A uniformly random proper rotation (QR of a Gaussian matrix, det = +1)."""
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] *= -1
    return q


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


@pytest.fixture
def bunny():
    import meshmark
    return meshmark.read_mesh(shared_mesh("classic/bunny.obj"))
