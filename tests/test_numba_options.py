"""The kernel cache key: which sources it covers, and why leaving some out is safe."""

from __future__ import annotations

import ast
from pathlib import Path

import rankedassign
from rankedassign import numba_options
from rankedassign.numba_options import NO_KERNELS, source_digest

ROOT = Path(rankedassign.__file__).resolve().parent


def _left_out(path: Path) -> bool:
    return path.relative_to(ROOT).parts[0] in NO_KERNELS


def test_the_parts_left_out_of_the_key_define_no_kernel():
    """A kernel in a part left out would keep a stale cache after an edit of its file."""
    for path in ROOT.rglob("*.py"):
        if not _left_out(path):
            continue
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                names = [ast.unparse(d) for d in node.decorator_list]
                assert not any("jit" in n or "vectorize" in n for n in names), (path, node.name)
            if isinstance(node, ast.Call):
                assert "jit" not in ast.unparse(node.func), (path, node.lineno)


def test_no_module_in_the_key_imports_a_part_left_out():
    """A kernel reads its module's globals at compile time; none may come from a part whose
    edits do not change the key."""
    left = {p.removesuffix(".py") for p in NO_KERNELS}
    for path in ROOT.rglob("*.py"):
        if _left_out(path):
            continue
        rel = path.relative_to(ROOT)
        depth = len(rel.parts) - 1
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                mod = node.module or ""
                if node.level:  # relative: resolve against the package
                    base = list(rel.parts[:depth - node.level + 1])
                    target = base + (mod.split(".") if mod else [])
                else:
                    parts = mod.split(".")
                    if parts[0] != "rankedassign":
                        continue
                    target = parts[1:]
                names = target[:1] or [a.name for a in node.names]
                assert not set(names) & left, (rel, ast.unparse(node))
            elif isinstance(node, ast.Import):
                for a in node.names:
                    parts = a.name.split(".")
                    assert not (parts[0] == "rankedassign" and len(parts) > 1
                                and parts[1] in left), (rel, a.name)


def test_editing_a_study_keeps_the_key_and_editing_a_kernel_file_changes_it(tmp_path,
                                                                             monkeypatch):
    import shutil
    import sys

    copy = tmp_path / "rankedassign"
    shutil.copytree(ROOT, copy, ignore=shutil.ignore_patterns("__pycache__"))
    fake = type(sys)("rankedassign")
    fake.__file__ = str(copy / "__init__.py")
    monkeypatch.setitem(sys.modules, "rankedassign", fake)

    def key():
        source_digest.cache_clear()
        return source_digest("rankedassign")

    before = key()
    study = copy / "experiments" / "studies" / "table1.py"
    study.write_text(study.read_text() + "\n# an edit\n")
    assert key() == before
    kernel = copy / "single" / "_kernels.py"
    kernel.write_text(kernel.read_text() + "\n# an edit\n")
    assert key() != before
    source_digest.cache_clear()
    assert numba_options.KERNEL_PACKAGES == ("rankedassign", "oracle")
