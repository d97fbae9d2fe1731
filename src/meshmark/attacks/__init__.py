"""Attacks: the operations a watermark must survive (or that a steganalyzer must not be fooled by).

Every attack takes a :class:`~meshmark.Mesh` or ``(V, F)`` and returns a new :class:`~meshmark.Mesh`;
the input is never modified. The per-element work is native (``meshmark._core``). Units: positions
in model units, angles in degrees, strengths as fractions (``strength=0.0025`` is the thesis'
A = 0.25 %). See ``docs/attacks.md`` for the definitions, the choices made where the thesis is vague,
the chain grammar, and tables of the distortion each attack causes and of what each method survives.

Randomness: every random attack takes ``seed`` (an integer >= 0) and is deterministic: the native
core draws from ``std::mt19937_64(seed)`` with meshmark's own uniform/normal transforms (not the
standard library's distributions), so the same seed gives the same mesh on every machine. Bend and
remesh are deterministic without a seed.

Polygons: attacks defined on positions or on the edge graph keep the faces as stored (quads stay
quads): similarity, reorder, noise, smoothing, quantization, dithering, crop, bend, float32 and file
round trips. Vertex normals (normal/tangent noise) and cotangent weights are computed on the
deterministic triangulation, but the polygons are kept. Simplification, subdivision and remeshing
triangulate first and return triangles.

Groups (the ``--type`` names of ``meshmark attack`` are the keys of :data:`ATTACKS`):

* similarity: :func:`rotate`, :func:`translate`, :func:`scale`, :func:`similarity` (random), :func:`random_rotation`;
* reordering: :func:`reorder` (vertices and faces, faces re-indexed consistently);
* noise: :func:`noise` with ``kind`` uniform (eq. 6.3.12), gaussian, normal, tangent;
* smoothing: :func:`smooth` (uniform Laplacian, or cotangent weights);
* quantization: :func:`quantize` (2^b levels over the bounding box), :func:`dither` and the reusable
  :func:`dithered_quantize` / :func:`dither_bits` of ch. 3-4;
* connectivity: :func:`simplify` (CGAL edge collapse), :func:`subdivide` (midpoint, Loop),
  :func:`remesh` (CGAL isotropic remeshing), :func:`crop`;
* deformation: :func:`bend` (two-bone linear blend skinning);
* storage: :func:`float32_cast`, :func:`file_roundtrip` (OBJ with 6 decimals, float PLY, STL);
* several at once: :func:`chain` (``"bend:30,simplify:0.5,noise:0.001,similarity,reorder,roundtrip:obj"``).
"""
from .basic import (  # noqa: F401
    NOISE_KINDS, _seed, crop, dither, dither_bits, dithered_quantize, file_roundtrip, float32_cast,
    mean_centroid_distance, noise, quantize, random_rotation, reorder, rotate, scale, similarity, simplify,
    smooth, subdivide, translate, vertex_normals,
)
from .bend import bend  # noqa: F401
from .chain import POSITIONAL, chain, format_chain, parse_chain  # noqa: F401
from .registry import ATTACKS, attack, parameters  # noqa: F401
from .remesh import remesh  # noqa: F401

__all__ = [
    "rotate", "translate", "scale", "similarity", "random_rotation", "reorder", "noise", "smooth",
    "quantize", "dither", "dithered_quantize", "dither_bits", "simplify", "subdivide", "remesh", "crop", "bend",
    "float32_cast", "file_roundtrip", "mean_centroid_distance", "vertex_normals", "attack", "chain",
    "parse_chain", "format_chain", "parameters", "ATTACKS", "POSITIONAL", "NOISE_KINDS",
]
