"""House rules read from the source (nothing imported): no import cycle among the modules of the
package ``meshmark`` or of the add-on ``meshmark_blender``, and no source file over 500 lines.

Every import counts, at module level and inside functions alike (a cycle hidden in a function is
still a cycle: each side needs the other), and so do ``__import__`` / ``importlib.import_module`` with a
literal name (not names built at run time, as in ``meshmark.study``'s lazy ``__getattr__``); the rules of the graph are in ``tests/import_graph.py``.
"""
import pathlib

import pytest

import import_graph as ig

ROOT = pathlib.Path(__file__).resolve().parents[1]
PACKAGES = {"meshmark": ROOT / "src" / "meshmark", "meshmark_blender": ROOT / "addon" / "meshmark_blender"}
MAX_LINES = 500
SOURCE_DIRS = ("src", "native", "addon", "tests", "examples", "blender_tests", "tools", "bench")
SOURCE_SUFFIXES = {".py", ".cpp", ".h", ".hpp", ".c", ".sh"}
EXEMPT = ("bench/reference/",)  # the literal reference implementations the benchmarks compare against


def _graph(name):
    return ig.graph(PACKAGES[name], name, native=("_core",))


@pytest.mark.parametrize("name", sorted(PACKAGES))
def test_no_import_cycle(name):
    g = _graph(name)
    found = ig.cycles(g)
    assert not found, "import cycles:\n" + "\n".join(" -> ".join(ig.path_in(g, c)) for c in found)


def test_the_graph_sees_every_kind_of_import():
    """The checker is not vacuous: module-level, function-level, relative and absolute imports are
    edges, ``from . import _core`` is not an import of the package's ``__init__``, and a cycle made
    of them is found."""
    g = _graph("meshmark")
    assert "meshmark.watermark.methods" in g["meshmark.watermark.keyfile"]  # inside a function
    assert "meshmark.watermark.framework" in g["meshmark.watermark.cho"]    # from . import framework
    assert "meshmark.study.model" in g["meshmark.study.task"]               # inside a method
    assert "meshmark" not in g["meshmark.geometry"]                         # from . import _core
    addon = _graph("meshmark_blender")
    assert "meshmark_blender.tasks.watermark" in addon["meshmark_blender.operators.watermark"]
    assert ig.cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert ig.path_in({"a": {"b"}, "b": {"c"}, "c": {"a"}}, ["a", "b", "c"]) == ["a", "b", "c", "a"]


def test_imports_resolve_like_python(tmp_path):
    pkg = tmp_path / "p"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("from . import a\n")
    (pkg / "a.py").write_text("from .sub import b\nX = 1\n")
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "sub" / "b.py").write_text("def f():\n    from ..a import X\n    import p.sub\n    from p import a, X\n")
    (pkg / "c.py").write_text('import importlib\nB = importlib.import_module("p.sub.b")\n'
                              'A = __import__("p.a", fromlist=["X"])\nS = importlib.import_module(f"p.{B}")\n')
    g = ig.graph(pkg, "p")
    assert g == {"p": {"p.a"}, "p.a": {"p.sub.b"}, "p.sub": set(), "p.sub.b": {"p.a", "p.sub", "p"},
                 "p.c": {"p.sub.b", "p.a"}}
    assert ig.cycles(g) == [["p", "p.a", "p.sub.b"]]  # p.sub.b -> p (from p import X) -> p.a -> p.sub.b


def test_no_file_over_500_lines():
    long = []
    for d in SOURCE_DIRS:
        for p in sorted((ROOT / d).rglob("*")):
            rel = p.relative_to(ROOT).as_posix()
            if p.suffix not in SOURCE_SUFFIXES or not p.is_file() or rel.startswith(EXEMPT) or "/build/" in rel:
                continue
            n = len(p.read_text(encoding="utf-8", errors="replace").splitlines())
            if n > MAX_LINES:
                long.append(f"{rel}: {n} lines")
    assert not long, f"files over {MAX_LINES} lines:\n" + "\n".join(long)


def test_the_installed_package_is_marked_typed():
    """PEP 561: ``py.typed`` ships in the package (scikit-build-core copies all of src/meshmark into
    the wheel), so type checkers read meshmark's annotations."""
    import importlib.resources

    assert (ROOT / "src" / "meshmark" / "py.typed").is_file()
    assert importlib.resources.files("meshmark").joinpath("py.typed").is_file()
