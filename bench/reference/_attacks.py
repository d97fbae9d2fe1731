"""Attack helpers for the reference experiments (numpy only)."""
import io
import numpy as np
import laplacian_ref as lr


def mean_centroid_dist(X):
    return float(np.linalg.norm(X - X.mean(0), axis=1).mean())


def f32(X):
    """Store as float32 (Blender mesh, glTF, binary PLY/STL) and read back."""
    return X.astype(np.float32).astype(np.float64)


def text_roundtrip(X, fmt="%.6f"):
    """Write the coordinates as OBJ-style text with `fmt` and parse them back
    (exact emulation of an OBJ exporter writing `fmt`)."""
    buf = io.StringIO()
    np.savetxt(buf, X, fmt=fmt)
    buf.seek(0)
    return np.loadtxt(buf).reshape(-1, 3)


def noise(X, rel, rng):
    """Additive uniform noise in [-a, a] per coordinate, a = rel * mean vertex-centroid distance."""
    a = rel * mean_centroid_dist(X)
    return X + rng.uniform(-a, a, X.shape)


def twist(X, deg, axis=1):
    """Mesh-editing surrogate: rotate about `axis` through the centroid by an angle
    growing linearly from 0 to `deg` along that axis (smooth global deformation)."""
    c = X.mean(0)
    Y = X - c
    h = Y[:, axis]
    t = np.deg2rad(deg) * (h - h.min()) / np.ptp(h)
    a, b = [i for i in range(3) if i != axis]
    out = Y.copy()
    out[:, a] = np.cos(t) * Y[:, a] - np.sin(t) * Y[:, b]
    out[:, b] = np.sin(t) * Y[:, a] + np.cos(t) * Y[:, b]
    return out + c


def smooth(X, F, lam=0.1, iters=1):
    """Uniform Laplacian smoothing x <- x - lam * (K x) / deg."""
    Kmat = lr.kirchhoff(len(X), F, 0.0)
    deg = np.maximum(Kmat.diagonal(), 1)[:, None]
    for _ in range(iters):
        X = X - lam * (Kmat @ X) / deg
    return X


def bend(X, deg, axis=1, frac=0.7, band=0.1, rot_axis=2):
    """Mesh-editing surrogate resembling a rigged joint (linear blend skinning):
    the part of the model beyond the plane X[:,axis] = quantile(frac) is rotated by
    `deg` about an axis parallel to `rot_axis` through that plane's centre, with a
    smoothstep blend over a band of width band * extent along `axis`."""
    h = X[:, axis]
    h0 = np.quantile(h, frac)
    wband = band * np.ptp(h)
    t = np.clip((h - h0) / wband + 0.5, 0.0, 1.0)
    w = t * t * (3 - 2 * t)
    p0 = X.mean(0)
    p0[axis] = h0
    a, b = [i for i in range(3) if i != rot_axis]
    th = np.deg2rad(deg)
    Y = X - p0
    R = Y.copy()
    R[:, a] = np.cos(th) * Y[:, a] - np.sin(th) * Y[:, b]
    R[:, b] = np.sin(th) * Y[:, a] + np.cos(th) * Y[:, b]
    return X + w[:, None] * (R - Y)
