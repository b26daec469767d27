"""The kernel cache key: which sources it covers, and why leaving some out is safe."""

from __future__ import annotations

import ast
from pathlib import Path

import rankedassign
from rankedassign import numba_options
from rankedassign.numba_options import NO_KERNELS, kernel_sources, source_digest

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
        kernel_sources.cache_clear()
        return source_digest("rankedassign")

    before = key()
    study = copy / "experiments" / "studies" / "table1.py"
    study.write_text(study.read_text() + "\n# an edit\n")
    assert key() == before
    # a filter, a model: pure Python that no kernel imports
    for rel in (("tracking", "single", "glmb.py"), ("tracking", "models.py"),
                ("tracking", "association.py")):
        path = copy.joinpath(*rel)
        path.write_text(path.read_text() + "\n# an edit\n")
        assert key() == before, rel
    # a module a kernel imports (the problem records it reads) and a kernel file
    problem = copy / "single" / "problem.py"
    problem.write_text(problem.read_text() + "\n# an edit\n")
    assert key() != before
    before = key()
    kernel = copy / "single" / "_kernels.py"
    kernel.write_text(kernel.read_text() + "\n# an edit\n")
    assert key() != before
    source_digest.cache_clear()
    kernel_sources.cache_clear()
    assert numba_options.KERNEL_PACKAGES == ("rankedassign", "oracle")


def _parsed_closure() -> set:
    """The files a kernel can depend on, found by parsing (the key reads the files as text)."""
    import oracle

    files = {}
    for pkg in (rankedassign, oracle):
        root = Path(pkg.__file__).resolve().parent
        for path in root.rglob("*.py"):
            parts = (pkg.__name__, *path.relative_to(root).with_suffix("").parts)
            if pkg is rankedassign and parts[1] in {p.removesuffix(".py") for p in NO_KERNELS}:
                continue
            files[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    trees = {name: ast.parse(path.read_text()) for name, path in files.items()}

    def imports(name):
        pkg = name if files[name].name == "__init__.py" else name.rpartition(".")[0]
        for node in ast.walk(trees[name]):
            if isinstance(node, ast.ImportFrom):
                base = pkg.split(".")[:len(pkg.split(".")) - node.level + 1] if node.level else []
                src = ".".join(base + ([node.module] if node.module else []))
                yield src, [a.name for a in node.names]
            elif isinstance(node, ast.Import):
                for a in node.names:
                    yield a.name, None

    def defines_kernel(name):
        for node in ast.walk(trees[name]):
            if isinstance(node, ast.FunctionDef) and any(
                    "jit" in ast.unparse(d) for d in node.decorator_list):
                return True
            if isinstance(node, ast.Call) and any(
                    w in ast.unparse(node.func) for w in ("jit", "instantiate", "vectorize")):
                return True
        return False

    seen, todo = set(), [(n, None) for n in files if defines_kernel(n)]
    while todo:
        name, names = todo.pop()
        if name not in files or (name, names) in seen:
            continue
        seen.add((name, names))
        whole = names is None or files[name].name != "__init__.py"
        for src, taken in imports(name):
            for n in taken or [None]:
                if n is None:
                    todo.append((src, None))
                elif whole or n in names:
                    todo.append((f"{src}.{n}", None) if f"{src}.{n}" in files else (src, (n,)))
    return {files[n] for n, _ in seen}


def test_the_key_covers_every_file_a_kernel_can_depend_on():
    """The key reads imports as text; parsing must not find a file it misses (a missed file
    would keep a stale kernel after its edit)."""
    parsed = _parsed_closure()
    keyed = {p.resolve() for p in kernel_sources()}
    assert parsed - keyed == set()
    # what is outside: the pure-Python layers above the kernels
    names = {str(p.relative_to(ROOT.parent)) for p in keyed}
    for outside in ("rankedassign/tracking/single/glmb.py", "rankedassign/tracking/models.py",
                    "rankedassign/samplers.py", "oracle/single/murty.py"):
        assert outside not in names
    assert "rankedassign/tracking/single/_glmb_kernels.py" in names


def _save_many(path, who, n):
    from numba.core.caching import IndexDataCacheFile

    import rankedassign.numba_options  # noqa: F401  (installs the locked save)

    cache = IndexDataCacheFile(str(path), "kernel-1.py311", (1.0, 1))
    for i in range(n):
        cache.save((who, i), f"{who}-{i}".encode() * 50)


def test_concurrent_saves_of_one_kernels_cache_keep_every_signature_with_its_own_code(tmp_path):
    """Two processes saving different signatures of one kernel at once (the suite's workers)
    must not leave an index that maps a signature to another's machine code."""
    import multiprocessing

    from numba.core.caching import IndexDataCacheFile

    ctx = multiprocessing.get_context("fork")
    procs = [ctx.Process(target=_save_many, args=(tmp_path, who, 150)) for who in ("a", "b")]
    for p in procs:
        p.start()
    for p in procs:
        p.join(timeout=120)
        assert p.exitcode == 0
    cache = IndexDataCacheFile(str(tmp_path), "kernel-1.py311", (1.0, 1))
    for who in ("a", "b"):
        for i in range(150):
            assert cache.load((who, i)) == f"{who}-{i}".encode() * 50, (who, i)


_INLINED_KERNEL = '''
import hashlib, json, sys
import numpy as np
from numba import njit

import rankedassign.numba_options as options


@njit(inline="always")
def inner(a, i):
    s = 0.0
    for j in range(a.shape[1]):
        if a[i, j] > 0.5:
            s += a[i, j] * j
        else:
            s -= a[i, j] ** 2
    return s


@njit(inline="always")
def middle(a):
    t = 0.0
    for i in range(a.shape[0]):
        t += inner(a, i) / (i + 1.0)
    return t


@njit
def outer(a):
    return middle(a) - 2.0 * middle(a[::-1])


a = np.random.default_rng(0).random((5, 7))
value = outer(a)
llvm = "".join(outer.inspect_llvm().values())
print(json.dumps({"one_copy": options.INLINE_COPY_AT_ONCE, "value": float(value).hex(),
                  "llvm": hashlib.sha1(llvm.encode()).hexdigest(), "llvm_chars": len(llvm)}))
'''


def _inlined_kernel(tmp_path, one_copy: str) -> dict:
    import json
    import os
    import subprocess
    import sys

    script = tmp_path / f"inlined_{one_copy}.py"
    script.write_text(_INLINED_KERNEL)
    env = {**os.environ, "RANKEDASSIGN_NUMBA_INLINE_COPY": one_copy,
           "RANKEDASSIGN_NUMBA_CACHE": "0", "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    out = subprocess.run([sys.executable, str(script)], env=env, capture_output=True, text=True,
                         timeout=300, cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_the_inliner_copied_at_once_compiles_the_same_code_as_numbas_own(tmp_path):
    """``RANKEDASSIGN_NUMBA_INLINE_COPY``: numba's inliner copies a callee's blocks in one deep
    copy instead of one per block; nested ``inline="always"`` functions compile to the same
    LLVM IR and the same result as with numba's own inliner."""
    ours = _inlined_kernel(tmp_path, "1")
    numbas = _inlined_kernel(tmp_path, "0")
    assert numbas["one_copy"] is False
    assert ours["one_copy"] is True, "numba's inliner text changed"
    assert ours["llvm_chars"] > 1000
    assert (ours["llvm"], ours["value"]) == (numbas["llvm"], numbas["value"])


def test_the_inliner_is_rewritten_on_this_numba_and_left_alone_on_another_text(monkeypatch):
    """The rewrite applies to the numba text it was made for (this numba's), and leaves an
    ``inline_ir`` of any other text as it is."""
    import inspect
    import textwrap

    from numba.core import inline_closurecall as closurecall

    def text(f):
        return textwrap.dedent(inspect.getsource(f))

    import os

    # at import: rewritten unless the opt-out was set; here, without it, it always applies
    opted_out = os.environ.get("RANKEDASSIGN_NUMBA_INLINE_COPY") == "0"
    assert numba_options.INLINE_COPY_AT_ONCE is not opted_out, "numba's inliner text changed"
    monkeypatch.delenv("RANKEDASSIGN_NUMBA_INLINE_COPY", raising=False)
    monkeypatch.setattr(closurecall.InlineWorker, "inline_ir",
                        closurecall.InlineWorker.inline_ir)  # restored after the test
    assert numba_options._one_copy_inliner() is True, "numba's inliner text changed"
    patched = closurecall.InlineWorker.inline_ir
    assert patched._rankedassign_one_copy
    assert numba_options._INLINE_COPY_PER_BLOCK in text(patched._rankedassign_numba)
    assert numba_options._INLINE_COPY_PER_BLOCK not in text(patched)
    assert numba_options._INLINE_COPY_AT_ONCE in text(patched)

    def inline_ir(self, caller_ir, block, i, callee_ir, callee_freevars, arg_typs=None):
        return None  # another numba's text

    monkeypatch.setattr(closurecall.InlineWorker, "inline_ir", inline_ir)
    assert numba_options._one_copy_inliner() is False
    assert closurecall.InlineWorker.inline_ir is inline_ir
    monkeypatch.setenv("RANKEDASSIGN_NUMBA_INLINE_COPY", "0")
    monkeypatch.setattr(closurecall.InlineWorker, "inline_ir", patched._rankedassign_numba)
    assert numba_options._one_copy_inliner() is False
