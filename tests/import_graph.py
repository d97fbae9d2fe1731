"""The import graph of a Python package, read from its source with :mod:`ast` (nothing is imported).

Every import statement counts: at module level, inside functions and methods, under ``if`` and
``try``. An edge goes to the module named by the import: ``from . import x`` and ``from pkg import x``
reach the submodule ``x`` when it is a file of the package, otherwise the package's ``__init__``;
``from .mod import name`` reaches ``mod``; ``__import__("pkg.mod")`` and
``importlib.import_module("pkg.mod")`` with a literal name are imports of that module too (a name built
at run time, as in a lazy ``__getattr__``, cannot be read from the source and is not counted). The implicit import of a module's parent packages (Python
runs ``pkg/__init__.py`` before ``pkg/mod.py``) is not an edge, as in import-linter and pydeps.
"""
from __future__ import annotations

import ast
import pathlib


def modules(root: pathlib.Path, package: str) -> dict:
    """``{dotted name: path}`` of every ``.py`` file under ``root`` (the package directory named
    ``package``); a package's ``__init__`` is named after the package."""
    out = {}
    for p in root.rglob("*.py"):
        parts = [package, *p.relative_to(root).with_suffix("").parts]
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = p
    return out


def imports(name: str, path: pathlib.Path, known: set) -> set:
    """Modules of ``known`` that module ``name`` (file ``path``) imports, itself excluded."""
    base = name.split(".")
    if path.name != "__init__.py":
        base = base[:-1]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
        elif isinstance(node, ast.Call) and _dynamic(node):
            target = node.args[0].value
            if target.startswith("."):
                dots = len(target) - len(target.lstrip("."))
                pkg = base[: len(base) - (dots - 1)]
                target = ".".join(pkg + ([target[dots:]] if target[dots:] else []))
            found.add(target)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                pkg = base[: len(base) - (node.level - 1)]
                mod = ".".join(pkg + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            for a in node.names:
                sub = f"{mod}.{a.name}"
                found.add(sub if sub in known else mod)
    return {m for m in found if m in known and m != name}


def _dynamic(call: ast.Call) -> bool:
    """``__import__("name")`` or ``importlib.import_module("name")`` with a literal module name."""
    f = call.func
    name = f.id if isinstance(f, ast.Name) else f.attr if isinstance(f, ast.Attribute) else None
    return (name in ("__import__", "import_module") and bool(call.args) and isinstance(call.args[0], ast.Constant)
            and isinstance(call.args[0].value, str))


def graph(root: pathlib.Path, package: str, native: tuple = ()) -> dict:
    """``{module: set of imported modules}`` for the package under ``root``; ``native`` names its
    compiled extension modules (``"_core"``: not files of the source tree, and leaves of the graph,
    so that ``from . import _core`` is not an import of the package's ``__init__``)."""
    mods = modules(root, package)
    leaves = {f"{package}.{n}" for n in native}
    known = set(mods) | leaves
    return {n: imports(n, p, known) - leaves for n, p in mods.items()}


def cycles(g: dict, roots: frozenset = frozenset()) -> list:
    """The strongly connected components of ``g`` with more than one module (each a sorted list),
    edges out of the modules in ``roots`` left out (a package ``__init__`` that only registers its
    layers). Tarjan's algorithm, iterative."""
    index, low, on, stack, out = {}, {}, set(), [], []
    counter = [0]

    def edges(n):
        return () if n in roots else sorted(g.get(n, ()))

    for start in sorted(g):
        if start in index:
            continue
        work = [(start, iter(edges(start)))]
        index[start] = low[start] = counter[0]
        counter[0] += 1
        stack.append(start)
        on.add(start)
        while work:
            n, it = work[-1]
            for m in it:
                if m not in index:
                    index[m] = low[m] = counter[0]
                    counter[0] += 1
                    stack.append(m)
                    on.add(m)
                    work.append((m, iter(edges(m))))
                    break
                if m in on:
                    low[n] = min(low[n], index[m])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[n])
                if low[n] == index[n]:
                    comp = []
                    while True:
                        m = stack.pop()
                        on.discard(m)
                        comp.append(m)
                        if m == n:
                            break
                    if len(comp) > 1:
                        out.append(sorted(comp))
    return out


def path_in(g: dict, comp: list) -> list:
    """One cycle through the first module of the component ``comp`` (for the failure message)."""
    inside, start = set(comp), comp[0]
    prev, todo = {start: None}, [start]
    while todo:
        n = todo.pop(0)
        for m in sorted(g[n] & inside):
            if m == start:
                path = [n]
                while prev[path[-1]] is not None:
                    path.append(prev[path[-1]])
                return [*reversed(path), start]
            if m not in prev:
                prev[m] = n
                todo.append(m)
    return comp
