"""The package layout of docs/architecture.md, read from the source with ``ast`` (nothing is
imported): no import cycle between the modules of ``gearrotor``, every room imports only the
rooms below it, and the command line only in ``gearrotor/cli/``.

Which imports count. Every ``import``/``from ... import`` of a ``gearrotor`` module anywhere in a
file: at module level, under ``if TYPE_CHECKING:``, and inside functions. The lazy imports inside
functions (the analyses the commands import when they run, so that ``gearrotor --help`` starts
fast; matplotlib-free modules that import a plotting helper when asked for a figure) are counted
like the others: deferring an import changes when a module is loaded, not which module depends
on which, so a cycle through a lazy import is still a cycle. A separate check of the module-level
graph alone names the cycles Python would meet while importing.

An edge ``a -> b`` means that module ``a`` imports module ``b``: ``from x.y import z`` is an
edge to ``x.y.z`` when that is a module, and to ``x.y`` otherwise (``z`` is then a name its
``__init__`` defines) or when ``x.y`` is not a package ``a`` belongs to (its ``__init__`` runs
first). A package's ``__init__`` importing its own modules, and a module importing a sibling
through ``from . import sibling``, are the ordinary layout of a package, not cycles.
"""

from __future__ import annotations

import ast
import functools
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src"
PACKAGE = SRC / "gearrotor"


def _modules() -> dict[str, tuple[Path, bool]]:
    """Dotted name -> (file, is a package ``__init__``) of every module of gearrotor."""
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = list(path.relative_to(SRC).with_suffix("").parts)
        is_pkg = parts[-1] == "__init__"
        if is_pkg:
            parts = parts[:-1]
        out[".".join(parts)] = (path, is_pkg)
    return out


MODULES = _modules()


@functools.cache
def _parse(path: Path) -> ast.Module:
    """A source file's syntax tree, parsed once (the tests below read every file several
    times; not changed by them)."""
    return ast.parse(path.read_text(encoding="utf-8"))


def _owner(name: str) -> str:
    """The longest prefix of a dotted name that is a module of the package."""
    while name not in MODULES:
        name = name.rsplit(".", 1)[0]
    return name


def _imports(tree: ast.AST, *, lazy: bool):
    """The import statements of a module; without ``lazy``, those run while it is imported
    (not inside function bodies)."""
    todo = list(ast.iter_child_nodes(tree))
    while todo:
        node = todo.pop()
        if isinstance(node, ast.Import | ast.ImportFrom):
            yield node
        if not lazy and isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda):
            continue
        todo.extend(ast.iter_child_nodes(node))


def _graph(*, lazy: bool) -> dict[str, set[str]]:
    graph: dict[str, set[str]] = {}
    for name, (path, is_pkg) in MODULES.items():
        package = name if is_pkg else name.rsplit(".", 1)[0]
        edges: set[str] = set()
        for node in _imports(_parse(path), lazy=lazy):
            if isinstance(node, ast.Import):
                edges |= {_owner(a.name) for a in node.names if a.name.split(".")[0] == "gearrotor"}
                continue
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(base + ([node.module] if node.module else []))
            else:
                base = node.module or ""
            if base.split(".")[0] != "gearrotor":
                continue
            own_package = name == base or name.startswith(base + ".")
            for alias in node.names:
                target = f"{base}.{alias.name}"
                if target in MODULES:
                    edges.add(target)
                    if not own_package:
                        edges.add(_owner(base))
                else:
                    edges.add(_owner(base))
        edges.discard(name)
        graph[name] = edges
    return graph


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_the_graph_sees_the_imports():
    """The graph is not empty by construction: known edges are found, lazy ones only with
    ``lazy``."""
    lazy, eager = _graph(lazy=True), _graph(lazy=False)
    assert "gearrotor.analyses.transient.forces" in eager["gearrotor.analyses.transient.results"]
    assert "gearrotor.signals" in eager["gearrotor.analyses.transient.results"]
    assert "gearrotor.studies.cases" in eager["gearrotor.studies.collection"]
    # `gearrotor modal` imports the analysis when it runs
    assert "gearrotor.analyses" in lazy["gearrotor.cli.modal"]
    assert "gearrotor.analyses" not in eager["gearrotor.cli.modal"]
    # a cycle is found when there is one
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


@pytest.mark.parametrize("lazy", [False, True], ids=["module-level", "with-lazy-imports"])
def test_no_import_cycle(lazy):
    cycles = _cycles(_graph(lazy=lazy))
    assert not cycles, "import cycles between modules of gearrotor: " + "; ".join(
        " <-> ".join(c) for c in cycles
    )


def test_command_line_only_in_cli():
    """Typer is imported by the command-line package only, and no module outside it is a
    command-line module."""
    cli = PACKAGE / "cli"
    offenders = []
    for name, (path, _) in MODULES.items():
        if path.is_relative_to(cli):
            continue
        if "cli" in name.rsplit(".", 1)[-1]:
            offenders.append(f"{name}: a command-line module outside gearrotor/cli/")
        for node in _imports(_parse(path), lazy=True):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module]
            if any((n or "").split(".")[0] in ("typer", "click") for n in names):
                offenders.append(f"{name}: imports {', '.join(n for n in names if n)}")
    assert not offenders, "\n".join(offenders)
    assert (cli / "__init__.py").exists()


#: The rooms of docs/architecture.md by layer: a module may import its own room and the rooms of
#: lower layers, not a room of its own layer or above.
LAYERS = {
    "errors": 0,
    "units": 0,
    "signals": 0,
    "elements": 1,
    "inputs": 1,
    "files": 1,
    "threads": 1,
    "progress": 0,
    "model": 1,
    "bearings": 2,
    "cache": 2,
    "seals": 2,
    "gears": 2,
    "io": 2,
    "assembly": 3,
    "analyses": 4,
    "interop": 4,
    "plots": 5,
    "studies": 5,
    "cli": 6,
    "__main__": 7,
}


def _room(module: str) -> str | None:
    """``gearrotor.analyses.transient.driver`` -> ``analyses``; None for the package root, whose
    ``__init__`` only gathers the public names (and ``__version__``)."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else None


def test_rooms_import_only_lower_layers():
    assert {_room(m) for m in MODULES} - {None} == set(LAYERS), "a room is missing from LAYERS"
    wrong = []
    for a, targets in _graph(lazy=True).items():
        ra = _room(a)
        for b in sorted(targets):
            rb = _room(b)
            if ra is None or rb is None or ra == rb:
                continue
            if LAYERS[rb] >= LAYERS[ra]:
                wrong.append(f"{a} imports {b} ({ra}, layer {LAYERS[ra]} -> {rb}, {LAYERS[rb]})")
    assert not wrong, "imports against the layering of docs/architecture.md:\n" + "\n".join(wrong)


def test_test_modules_have_unique_names():
    """pytest imports test modules by basename (rootdir-relative, no packages): two
    ``test_x.py`` in different folders stop the whole run at collection."""
    tests = Path(__file__).resolve().parent
    seen: dict[str, Path] = {}
    clashes = []
    for p in sorted(tests.rglob("test_*.py")):
        if "data" in p.relative_to(tests).parts:
            continue
        if p.name in seen:
            clashes.append(f"{seen[p.name].relative_to(tests)} and {p.relative_to(tests)}")
        seen[p.name] = p
    assert not clashes, "test modules with the same name: " + "; ".join(clashes)


# Former module names (issue 26): a 0.1 package with no external users keeps no aliases. Each
# old name now reads as one of the analyses' rooms (static, lateral, audit, torsional,
# transient) or the model.
FORMER = {
    "gearrotor.analyses.parametric": "gearrotor.analyses.lateral.floquet",
    "gearrotor.analyses.transient.integrators": "gearrotor.analyses.transient",
    "gearrotor.plots.interactive": "gearrotor.plots.report.sections",
    "gearrotor.analyses.operating": "gearrotor.model.speed_range",
    "gearrotor.analyses.static.operating": "gearrotor.analyses.static.operating_point",
    "gearrotor.analyses.api617": "gearrotor.analyses.audit.api_unbalance",
    "gearrotor.model.audit": "gearrotor.model.api_audit",
    "gearrotor.analyses.modal": "gearrotor.analyses.lateral.modal",
    "gearrotor.analyses.campbell": "gearrotor.analyses.lateral.campbell",
    "gearrotor.analyses.unbalance": "gearrotor.analyses.lateral.unbalance",
    "gearrotor.analyses.stability": "gearrotor.analyses.audit.stability",
    "gearrotor.analyses.ucs": "gearrotor.analyses.audit.ucs",
}


def _is_alias(path: Path) -> bool:
    """A module whose body is only imports and ``__all__``: names re-exported from elsewhere."""
    body = [
        n
        for n in _parse(path).body
        if not (isinstance(n, ast.Expr) and isinstance(n.value, ast.Constant))
    ]

    def reexport(n: ast.stmt) -> bool:
        if isinstance(n, ast.Import | ast.ImportFrom):
            return True
        return isinstance(n, ast.Assign) and all(
            isinstance(t, ast.Name) and t.id == "__all__" for t in n.targets
        )

    return bool(body) and all(reexport(n) for n in body)


def test_no_alias_module():
    """No module re-exports names under a former name (a package's ``__init__`` gathering its
    own modules' names is its ordinary layout), no former module name is back, and no file of
    the repository imports one."""
    aliases = [m for m, (p, is_pkg) in MODULES.items() if not is_pkg and _is_alias(p)]
    assert not aliases, f"alias modules (only imports and __all__): {aliases}"
    back = sorted(set(FORMER) & set(MODULES))
    assert not back, f"former module names are back: {back}"
    root = SRC.parent
    users = []
    for folder in ("src", "tests", "benchmarks", "examples"):
        for p in sorted((root / folder).rglob("*.py")):
            for node in _imports(_parse(p), lazy=True):
                names = (
                    [a.name for a in node.names]
                    if isinstance(node, ast.Import)
                    else [node.module or ""]
                )
                users += [f"{p.relative_to(root)}: {n}" for n in names if n in FORMER]
    assert not users, "imports of former module names:\n" + "\n".join(users)
