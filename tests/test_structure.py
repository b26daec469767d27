"""The package's structure: imports go downwards only.

Walks the import statements of every module of :mod:`rankedassign` and :mod:`oracle` (read with
:mod:`ast`, nothing is imported) and checks the layering rules of the house style:

* no import cycle among the modules of ``rankedassign`` (module-level and function-level
  imports both count: a cycle hidden in a function is still a cycle);
* ``oracle`` — the independent judge — imports only public names of ``rankedassign``;
* a function-local import is only for an optional heavy dependency (matplotlib, distributed).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("rankedassign", "oracle")
# Optional dependencies that may be imported inside a function (import cost or availability).
LAZY_OK = ("matplotlib", "distributed")


def _modules(package: str) -> dict[str, Path]:
    out = {}
    for path in sorted((ROOT / package).rglob("*.py")):
        rel = path.relative_to(ROOT).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


MODULES = {name: path for package in PACKAGES for name, path in _modules(package).items()}


def _resolve(module: str, node: ast.ImportFrom) -> str:
    """Absolute name of the module a ``from ... import`` statement reads from."""
    if node.level == 0:
        return node.module or ""
    is_package = MODULES[module].name == "__init__.py"
    base = module.split(".")
    base = base if is_package else base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _imports(module: str):
    """``(target module, imported name or None, inside a function?)`` for every import."""
    tree = ast.parse(MODULES[module].read_text())
    func_nodes = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            func_nodes.update(id(n) for n in ast.walk(node) if n is not node)
    for node in ast.walk(tree):
        local = id(node) in func_nodes
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, None, local
        elif isinstance(node, ast.ImportFrom):
            target = _resolve(module, node)
            for alias in node.names:
                yield target, alias.name, local


def _edges(module: str) -> set[str]:
    """Modules of the two packages that ``module`` imports (``from pkg import sub`` -> sub)."""
    out = set()
    for target, name, _ in _imports(module):
        if name is not None and f"{target}.{name}" in MODULES:
            out.add(f"{target}.{name}")
        elif target in MODULES:
            out.add(target)
    out.discard(module)
    return out


def _cycles(names):
    graph = {m: sorted(e for e in _edges(m) if e in names) for m in names}
    cycles, state, stack = [], {}, []

    def visit(m):
        state[m] = 1
        stack.append(m)
        for n in graph[m]:
            if state.get(n) == 1:
                cycles.append(stack[stack.index(n):] + [n])
            elif n not in state:
                visit(n)
        stack.pop()
        state[m] = 2

    for m in sorted(graph):
        if m not in state:
            visit(m)
    return cycles


def test_walker_sees_every_module():
    assert "rankedassign.samplers" in MODULES and "oracle.single.murty" in MODULES
    assert "rankedassign.engine._kernels" in _edges("rankedassign.single._kernels")


def test_no_import_cycle_in_rankedassign():
    names = {m for m in MODULES if m.split(".")[0] == "rankedassign"}
    cycles = _cycles(names)
    assert not cycles, "import cycles: " + "; ".join(" -> ".join(c) for c in cycles)


def test_no_import_cycle_between_the_packages():
    cycles = _cycles(set(MODULES))
    assert not cycles, "import cycles: " + "; ".join(" -> ".join(c) for c in cycles)


@pytest.mark.parametrize("module", sorted(m for m in MODULES if m.startswith("oracle")))
def test_oracle_imports_only_public_names(module):
    private = []
    for target, name, _ in _imports(module):
        if not target.startswith("rankedassign"):
            continue
        parts = target.split(".") + ([name] if name else [])
        if any(p.startswith("_") for p in parts):
            private.append(".".join(parts))
    assert not private, f"{module} imports private names of rankedassign: {private}"


@pytest.mark.parametrize("module", sorted(MODULES))
def test_function_local_imports_only_for_optional_dependencies(module):
    bad = sorted({target for target, _, local in _imports(module)
                  if local and target.split(".")[0] not in LAZY_OK})
    assert not bad, f"{module} imports {bad} inside a function"
