"""The package's architecture holds: each subpackage imports only from the layers below it,
and no module imports itself back through others.

The layers, from the bottom: the base (configuration, files, units, statistics, the
paper's stated values), the compiled physics (physics/: each equation once, whose
stop schedule and constants the numpy model uses too), the model in numpy and, beside it,
the exact theory of the onsets of motion (neither imports the other), the compiled
loops and their parameter record (kernels/), the solver, figure primitives,
trackers, ensemble backends, sweeps, the decision model, the Python API, the gallery's
library and the command line (README, "Layout").
"""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "pde_rotor"

LAYERS: dict[str, int] = {
    "_version": 0,
    "_lazy": 0,
    "units": 0,
    "paper": 0,
    "io": 0,
    "statistics": 0,
    "collective": 0,
    "config": 1,
    "physics": 2,
    "model": 3,
    "theory": 3,
    "kernels": 4,
    "solver": 5,
    "plotting": 6,
    "trackers": 7,
    "backends": 8,
    "sweep": 9,
    "decision": 10,
    "stability": 10,
    "api": 11,
    "gallery": 12,
    "cli": 13,
    "": 14,  # the package's __init__
}
"""Rank of each subpackage and top-level module: an import may only go to a lower rank
(or stay within its own subpackage)."""


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def imports() -> dict[str, set[str]]:
    """Every pde_rotor module and the pde_rotor modules it imports (lazy imports included)."""
    found: dict[str, set[str]] = defaultdict(set)
    for path in PACKAGE.rglob("*.py"):
        name = module_name(path)
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")[: len(package.split(".")) - node.level + 1]
                    target = ".".join([*base, node.module] if node.module else base)
                else:
                    target = node.module or ""
                targets = [target]
                if not node.module:  # from . import x: x may be a module
                    targets = [f"{target}.{alias.name}" for alias in node.names]
            elif isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            else:
                continue
            found[name] |= {t for t in targets if t.split(".")[0] == "pde_rotor"}
        found.setdefault(name, set())
    return found


def known(module: str, modules: set[str]) -> str:
    """`module`, or the module that defines it (``pkg.mod.name`` -> ``pkg.mod``)."""
    while module not in modules and "." in module:
        module = module.rpartition(".")[0]
    return module


def layer_of(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


def test_every_subpackage_has_a_layer():
    names = {layer_of(m) for m in imports()}
    assert names == set(LAYERS), names ^ set(LAYERS)


def test_no_subpackage_imports_from_a_higher_layer():
    graph = imports()
    modules = set(graph)
    upward = []
    for module, targets in sorted(graph.items()):
        for target in sorted(known(t, modules) for t in targets):
            a, b = layer_of(module), layer_of(target)
            if a != b and LAYERS[b] >= LAYERS[a]:
                upward.append(f"{module} -> {target}")
    assert upward == []


def test_no_import_cycles():
    graph = imports()
    modules = set(graph)
    edges = {m: {known(t, modules) for t in ts} - {m} for m, ts in graph.items()}
    # a package's __init__ that imports its own modules is no cycle: they import siblings
    for module in modules:
        edges[module] = {t for t in edges[module] if not module.startswith(f"{t}.")}
    cycles = []
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(node: str) -> None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(edges[node]):
            if state.get(nxt) == 1:
                cycles.append(" -> ".join([*stack[stack.index(nxt) :], nxt]))
            elif nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = 2

    for module in sorted(modules):
        if module not in state:
            visit(module)
    assert cycles == []


def test_the_package_top_holds_at_most_six_modules():
    top = sorted(p.name for p in PACKAGE.glob("*.py") if p.name != "__init__.py")
    assert len(top) <= 6, top


def test_every_subpackage_says_what_each_of_its_modules_does():
    """A newcomer reads a folder's __init__ first: it names every module and every
    subpackage of the folder (nested folders too)."""
    silent = []
    for init in sorted(PACKAGE.glob("*/**/__init__.py")):
        doc = ast.get_docstring(ast.parse(init.read_text(encoding="utf-8"))) or ""
        modules = [p.stem for p in init.parent.glob("*.py") if p.name != "__init__.py"]
        modules += [p.parent.name for p in init.parent.glob("*/__init__.py")]
        for module in sorted(modules):
            if f":mod:`.{module}`" not in doc:
                silent.append(f"{init.parent.relative_to(PACKAGE)}/{module}")
    assert silent == []


MAX_PARAMETERS = 10
"""The most parameters a function outside cli/ may take (arrays travel as named bundles,
scalars in the parameter record; the command line's options are the exception)."""


def parameter_count(node: ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda) -> int:
    """Every parameter of a function: positional, keyword-only, *args and **kwargs."""
    args = node.args
    starred = (args.vararg is not None) + (args.kwarg is not None)
    return len(args.posonlyargs) + len(args.args) + len(args.kwonlyargs) + starred


def long_signatures(tree: ast.AST, where: str) -> list[str]:
    """``where:line name (count)`` of each function (nested ones and lambdas too) in `tree`
    that takes more than :data:`MAX_PARAMETERS` parameters."""
    return [
        f"{where}:{node.lineno} {getattr(node, 'name', 'lambda')} ({parameter_count(node)})"
        for node in ast.walk(tree)
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda)
        and parameter_count(node) > MAX_PARAMETERS
    ]


def test_the_signature_walk_sees_every_kind_of_parameter():
    source = (
        "def eleven(a, b, /, c, d, *rest, e, f, g, h, i, **more): pass\n"
        "def ten(a, b, c, d, e, f, g, h, i, j): pass\n"
        "class K:\n"
        "    def method(self, a, b, c, d, e, f, g, h, i, j): pass\n"
        "def outer():\n"
        "    return lambda a, b, c, d, e, f, g, h, i, j, k: a\n"
    )
    found = long_signatures(ast.parse(source), "x.py")
    assert found == ["x.py:1 eleven (11)", "x.py:4 method (11)", "x.py:6 lambda (11)"]


def test_no_function_outside_cli_takes_more_than_ten_parameters():
    too_long = []
    for path in sorted(PACKAGE.rglob("*.py")):
        where = path.relative_to(PACKAGE.parent)
        if where.parts[1] != "cli":
            too_long += long_signatures(ast.parse(path.read_text(encoding="utf-8")), str(where))
    assert too_long == []
