"""The package's structure: imports go downwards only.

Walks the import statements of every module of :mod:`rankedassign` and :mod:`oracle` (read with
:mod:`ast`, nothing is imported) and checks the layering rules of the house style:

* no import cycle among the modules of ``rankedassign`` (module-level and function-level
  imports both count: a cycle hidden in a function is still a cycle);
* ``oracle`` — the independent judge — imports only public names of ``rankedassign``;
* a function-local import is only for an optional heavy dependency (matplotlib, distributed)
  or a SciPy subpackage that is slow to import (scipy.optimize, scipy.stats).
"""

from __future__ import annotations

import ast
import functools
import subprocess
import sys
from pathlib import Path

import pytest

from rankedassign.kinds import KINDS

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("rankedassign", "oracle")
# Optional dependencies that may be imported inside a function (import cost or availability),
# and the two SciPy subpackages whose import would be most of the package's own import time
# (scipy.optimize for linear_sum_assignment, scipy.stats for chi2 and t: about 0.5 s of
# `rankedassign reproduce`'s 1.6 s start, test_import_cost below).
LAZY_OK = ("matplotlib", "distributed", "scipy.optimize", "scipy.stats")


def _lazy_ok(target: str) -> bool:
    return any(target == m or target.startswith(m + ".") for m in LAZY_OK)


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


@functools.cache
def _imports(module: str) -> tuple[tuple[str, str | None, bool], ...]:
    """``(target module, imported name or None, inside a function?)`` for every import.

    Each module is parsed once per process (every rule below reads the same statements).
    """
    out = []

    def visit(node, local):
        if isinstance(node, ast.Import):
            out.extend((alias.name, None, local) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            target = _resolve(module, node)
            out.extend((target, alias.name, local) for alias in node.names)
        inner = local or isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))
        for child in ast.iter_child_nodes(node):
            visit(child, inner)

    visit(ast.parse(MODULES[module].read_text()), False)
    return tuple(out)


@functools.cache
def _edges(module: str) -> frozenset[str]:
    """Modules of the two packages that ``module`` imports (``from pkg import sub`` -> sub)."""
    out = set()
    for target, name, _ in _imports(module):
        if name is not None and f"{target}.{name}" in MODULES:
            out.add(f"{target}.{name}")
        elif target in MODULES:
            out.add(target)
    out.discard(module)
    return frozenset(out)


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
                  if local and not _lazy_ok(target)})
    assert not bad, f"{module} imports {bad} inside a function"


def test_import_cost():
    """Importing the package and its command line does not import scipy.optimize or
    scipy.stats (they are imported where they are first used)."""
    code = ("import sys, rankedassign, rankedassign.experiments, rankedassign.cli\n"
            "print(sorted(m for m in ('scipy.optimize', 'scipy.stats') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "[]"


# ------------------------------------------------------------------------------ layers
#: The layers, bottom up: a module imports only modules of its own layer or of lower ones.
#: Longest prefix wins. The three kinds are separate layers so that none imports a later one
#: (the multi-sensor problem converts to and from the single-sensor one, which it may import).
RANKS = {
    "rankedassign._version": 0, "rankedassign.validation": 0, "rankedassign.numba_options": 0,
    "rankedassign.engine": 1,
    # the kinds, in the order of KINDS: none imports a later one (the list is derived, so a new
    # kind gets its layer without an edit here)
    **{f"rankedassign.{k.name}": 2.0 + i / 10 for i, k in enumerate(KINDS)},
    "rankedassign.kinds": 3.0, "rankedassign.metrics": 3.0,
    "rankedassign.samplers": 3.1, "rankedassign.reference": 3.1,
    "rankedassign": 3.2,
    "oracle": 4,
    "rankedassign.tracking.": 5.0, "rankedassign.tracking.single": 5.1,
    "rankedassign.tracking.runner": 5.05, "rankedassign.tracking.clustered": 5.15,
    "rankedassign.tracking.multisensor": 5.2, "rankedassign.tracking.filters": 5.2,
    "rankedassign.tracking.run": 5.3,
    "rankedassign.tracking.io": 5.3, "rankedassign.tracking": 5.4,
    "rankedassign.stonesoup": 5.6,
    "rankedassign.experiments": 6,
    "rankedassign.cli": 7, "rankedassign.__main__": 7,
}
LAYER_NAMES = {0: "utilities", 1: "engine",
               **{2.0 + i / 10: f"{k.name} kind" for i, k in enumerate(KINDS)},
               3.0: "kind registry and metrics",
               3.1: "samplers", 3.2: "package API", 4: "oracle", 5.0: "tracking models",
               5.05: "the scan loop",
               5.1: "single-sensor filters", 5.15: "clustered δ-GLMB filter",
               5.2: "multi-sensor filters",
               5.3: "scenario runners and files", 5.4: "tracking API",
               5.6: "Stone Soup plug-in", 6: "experiments", 7: "CLI"}
KIND_FILES = ("__init__.py", "problem.py", "synthetic.py", "prepare.py", "reference.py",
              "_kernels.py")


def rank(module: str) -> float:
    best, key = None, ""
    for prefix, r in RANKS.items():
        exact = module == prefix.rstrip(".")
        inside = module.startswith(prefix if prefix.endswith(".") else prefix + ".")
        if (exact and not prefix.endswith(".")) or inside:
            if len(prefix) > len(key):
                best, key = r, prefix
    assert best is not None, f"{module} is in no layer of RANKS"
    return best


@pytest.mark.parametrize("module", sorted(MODULES))
def test_imports_go_down_the_layers(module):
    """engine -> kinds -> samplers/oracle -> filters -> experiments -> CLI, never upward."""
    here = rank(module)
    up = sorted(f"{m} ({LAYER_NAMES[rank(m)]})" for m in _edges(module) if rank(m) > here)
    assert not up, f"{module} ({LAYER_NAMES[here]}) imports upward: {up}"


def test_every_kind_is_one_folder_with_the_same_files():
    from rankedassign.kinds import KINDS

    names = [kind.name for kind in KINDS]
    for name in names:
        folder = ROOT / "rankedassign" / name
        missing = [f for f in KIND_FILES if not (folder / f).is_file()]
        assert not missing, f"kind {name!r}: rankedassign/{name}/ lacks {missing}"
        assert (ROOT / "oracle" / name / "__init__.py").is_file(), f"no oracle/{name}/"
    assert len(set(names)) == len(names)


def test_the_engine_imports_no_kind():
    kinds = ("rankedassign.single", "rankedassign.multisensor", "rankedassign.adaptive_birth",
             "rankedassign.kinds")
    for module in (m for m in MODULES if m.startswith("rankedassign.engine")):
        bad = sorted(e for e in _edges(module) if e.startswith(kinds))
        assert not bad, f"{module} imports the kinds {bad}"
