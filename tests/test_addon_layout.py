"""The add-on's house rules, read from its source (no Blender needed): no import cycle among its
modules (every import counted, also those inside functions), no file over 500 lines, the bpy-free
modules free of bpy, operators, properties and panels apart (no panel imports an operator module, no
operator module imports a panel), and the package ``meshmark`` never imports the add-on."""
import ast
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[1]
ADDON = ROOT / "addon" / "meshmark_blender"
PKG = "meshmark_blender"
BPY_FREE = {"params", "messages", "words", "session", "study", "study_runner", "tasks.outcome"}


def _modules() -> dict:
    out = {}
    for p in ADDON.rglob("*.py"):
        rel = p.relative_to(ADDON).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = p
    return out


def _imports(name: str, path: pathlib.Path, known: set) -> set:
    """Add-on modules imported by module ``name`` (relative imports resolved; ``from . import x``
    counts as an import of the submodule x)."""
    is_pkg = path.name == "__init__.py"
    base = name.split(".") if name else []
    if not is_pkg:
        base = base[:-1]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level:
            pkg = base[: len(base) - (node.level - 1)] if node.level > 1 else base
            mod = ".".join(pkg + ([node.module] if node.module else []))
            for alias in node.names:
                sub = f"{mod}.{alias.name}" if mod else alias.name
                found.add(sub if sub in known else mod)
        elif isinstance(node, ast.ImportFrom) and node.module and node.module.startswith(PKG):
            found.add(node.module[len(PKG) + 1:])
    return {m for m in found if m in known and m != name}


def _graph():
    mods = _modules()
    return {n: _imports(n, p, set(mods)) for n, p in mods.items()}, mods


def test_no_import_cycle():
    g, _ = _graph()
    state, stack = {}, []

    def visit(n):
        state[n] = 1
        stack.append(n)
        for m in sorted(g[n]):
            if m == "" or n == "":  # the package's __init__ registers the layers: it is the root
                continue
            if state.get(m) == 1:
                raise AssertionError("import cycle: " + " -> ".join(stack[stack.index(m):] + [m]))
            if m not in state:
                visit(m)
        stack.pop()
        state[n] = 2

    for n in sorted(g):
        if n not in state:
            visit(n)
    # the graph is not empty nonsense: the operators do import the tasks, the panels the session
    assert "tasks.watermark" in g["operators.watermark"] and "session" in g["panels.results"]


def test_layers_apart_and_small_files():
    g, mods = _graph()
    for n, deps in g.items():
        if n.startswith("panels"):
            assert not any(d.startswith("operators") for d in deps), (n, deps)
        if n.startswith("operators"):
            assert not any(d.startswith("panels") for d in deps), (n, deps)
        if n.startswith("tasks") or n in ("bridge", "targets", "keyfiles", "api"):
            assert not any(d.startswith(("operators", "panels")) or d == "properties" for d in deps), (n, deps)
    for n, p in mods.items():
        lines = len(p.read_text().splitlines())
        assert lines <= 500, f"{p.relative_to(ROOT)} has {lines} lines"
        if n in BPY_FREE:
            tree = ast.parse(p.read_text())
            names = {a.name.split(".")[0] for x in ast.walk(tree) if isinstance(x, ast.Import) for a in x.names}
            names |= {x.module.split(".")[0] for x in ast.walk(tree) if isinstance(x, ast.ImportFrom) and x.module}
            assert not names & {"bpy", "bmesh", "mathutils", "blf"}, (n, names)

