"""Every public function and method of the Python API is type-hinted and documented with shapes.

The public API is what ``meshmark`` and its subpackages export (``__all__``), with the modules they
export walked the same way (their ``__all__``, else the public names they define). For each function,
method and property: every parameter and the return carry an annotation, the annotations resolve
(``typing.get_type_hints``: a misspelt or unimported name fails), there is a docstring, and a function
that takes or returns arrays (numpy.typing hints, a mesh as ``(V, F)``) states their shapes in it, e.g.
``(n, 3)``; one that takes a physical quantity or a tolerance (an angle, a strength, a length) names
its unit. Removing a hint, a shape or a unit from a docstring fails this test.
"""
from __future__ import annotations

import importlib
import inspect
import re
import types
import typing

import pytest

pytest.importorskip("pygltflib")  # meshmark.gltf's readers and writers
pytest.importorskip("pyarrow")  # meshmark.study's engine

PACKAGES = ["meshmark", "meshmark.mesh", "meshmark.io", "meshmark.metrics", "meshmark.parts", "meshmark.geometry",
            "meshmark.topology", "meshmark.watermark", "meshmark.attacks", "meshmark.analysis", "meshmark.stego",
            "meshmark.steganalysis", "meshmark.study", "meshmark.gltf"]
# names a hint may use that its module imports only for annotations
EXTRA_NAMES = {"Mesh": "meshmark.mesh", "Keyfile": "meshmark.watermark.keyfile", "GltfInfo": "meshmark.gltf.reader",
               "Registry": "meshmark.watermark.registry", "Spec": "meshmark.study.model"}
ARRAY_HINT = re.compile(r"\b(ArrayLike|NDArray|FloatArray|IntArray|UInt8Array|BoolArray|MeshLike|MeshPair|ndarray)\b")
SHAPE = re.compile(r"\((?:[\w+\-*/ ]+,)+[\w+\-*/ ]*\)")  # (n, 3), (n,), (m + 1,), (K, 3, 3)


def _exported(mod):
    if hasattr(mod, "__all__"):
        return list(mod.__all__)
    return [n for n, v in vars(mod).items()
            if not n.startswith("_") and getattr(v, "__module__", None) == mod.__name__]


def public_functions():
    """{qualified name: function} of every public function, method and property getter."""
    found, seen_modules = {}, set()

    def add(name, f):
        if inspect.isfunction(f) and f.__module__.startswith("meshmark") and f not in found.values():
            found[name] = f

    def visit(modname):
        if modname in seen_modules:
            return
        seen_modules.add(modname)
        mod = importlib.import_module(modname)
        for n in _exported(mod):
            obj = getattr(mod, n)
            if isinstance(obj, types.ModuleType):
                if obj.__name__.startswith("meshmark.") and ".cli" not in obj.__name__:
                    visit(obj.__name__)
            elif inspect.isclass(obj) and obj.__module__.startswith("meshmark") and obj.__module__ != "meshmark._core":
                for mn, m in vars(obj).items():
                    if mn.startswith("_") and mn != "__init__":
                        continue
                    f = m.fget if isinstance(m, property) else getattr(m, "__func__", m)
                    add(f"{modname}.{n}.{mn}", f)
            else:
                add(f"{modname}.{n}", obj)

    for p in PACKAGES:
        visit(p)
    return found


FUNCTIONS = public_functions()


def _generated(f) -> bool:
    """A dataclass / NamedTuple __init__, generated from the class's annotated fields."""
    return f.__code__.co_filename == "<string>"


def test_the_walk_finds_the_api():
    names = set(FUNCTIONS)
    for expected in ("meshmark.read_mesh", "meshmark.Mesh.with_vertices", "meshmark.Mesh.n_vertices",
                     "meshmark.watermark.embed", "meshmark.watermark.laplacian.extract_blind",
                     "meshmark.attacks.noise", "meshmark.metrics.hausdorff_distance", "meshmark.stego.chao.embed",
                     "meshmark.steganalysis.cho.analyze", "meshmark.study.run", "meshmark.gltf.write_positions",
                     "meshmark.analysis.quantization_level"):
        assert expected in names
    assert len(FUNCTIONS) > 200


@pytest.mark.parametrize("name", sorted(FUNCTIONS))
def test_fully_annotated(name):
    f = FUNCTIONS[name]
    sig = inspect.signature(f)
    missing = [p for p, v in sig.parameters.items() if v.annotation is inspect.Parameter.empty and p not in ("self", "cls")]
    assert not missing, f"{name}: parameters without a type hint: {missing}"
    assert sig.return_annotation is not inspect.Signature.empty, f"{name}: no return type hint"
    extra = {k: getattr(importlib.import_module(m), k) for k, m in EXTRA_NAMES.items()}
    typing.get_type_hints(f, localns=extra)  # every name in the hints resolves


@pytest.mark.parametrize("name", sorted(n for n, f in FUNCTIONS.items() if not _generated(f)))
def test_documented_with_shapes(name):
    f = FUNCTIONS[name]
    doc = inspect.getdoc(f) if f.__name__ != "__init__" else (inspect.getdoc(f) or _class_doc(name))
    assert doc and doc.strip(), f"{name}: no docstring"
    hints = [str(v.annotation) for v in inspect.signature(f).parameters.values()]
    hints.append(str(inspect.signature(f).return_annotation))
    if any(ARRAY_HINT.search(h) for h in hints):
        assert SHAPE.search(doc), f"{name}: takes or returns arrays but its docstring states no shape like (n, 3)"


def _class_doc(name):
    modname, cls, _ = name.rsplit(".", 2)
    return inspect.getdoc(getattr(importlib.import_module(modname), cls))


# parameters that carry a physical quantity or a tolerance: the docstring must say in what unit
UNIT_PARAMS = {"tolerance", "tolerances", "angle", "degrees", "strength", "edge_length", "translation", "height",
               "radius", "rel_tol", "abs_tol", "factor", "width", "joint", "eps", "l", "lam", "fraction", "offset",
               "center", "wait"}
UNIT = re.compile(r"degree|radian|\bdeg\b|mesh units|model units|\bbits?\b|fraction|seconds|bytes|%|unitless|"
                  r"relative|diagonal|units", re.I)


@pytest.mark.parametrize("name", sorted(n for n, f in FUNCTIONS.items() if not _generated(f)
                                        and set(inspect.signature(f).parameters) & UNIT_PARAMS))
def test_units_stated(name):
    doc = inspect.getdoc(FUNCTIONS[name]) or ""
    assert UNIT.search(doc), f"{name}: takes a quantity but its docstring names no unit (degrees, mesh units, ...)"
