"""The one place where numba options live, for :mod:`rankedassign` and :mod:`oracle`.

Every compiled kernel of both packages is made by :func:`jit`, so the options below are
switched in one place:

``RANKEDASSIGN_NUMBA_CACHE``
    ``"1"`` (default) caches compiled kernels on disk (``cache=True``), so a new process, a
    ``multiprocessing`` or Dask worker loads them in milliseconds instead of compiling them
    again (tens of seconds for the samplers); ``"0"`` disables the cache. numbagg defaults to
    no cache because two processes compiling into one cache can race; numba writes each cache
    entry atomically (write then rename), and the worst case of such a race is a second
    compilation, never a wrong kernel, so the cache is on by default here. Turn it off for a
    read-only installation or when numba warns that it cannot write ``__pycache__``.

``OMP_WAIT_POLICY``
    Set to ``"PASSIVE"`` unless already set, before numba first starts its OpenMP thread pool:
    idle workers then sleep instead of spinning. With spinning (GNU OpenMP's default), a
    parallel run on a machine whose other core is busy lost 15-37 % against one worker,
    because the waiting threads burnt the cycles the busy core's share needed. Set the
    variable yourself before importing :mod:`rankedassign` to choose otherwise.

``RANKEDASSIGN_NUMBA_INLINE_COPY``
    ``"1"`` (default) makes numba's inliner copy an inlined function's IR in one deep copy
    instead of one per block (each of which copied every variable of the function again: the
    quadratic cost of numba issue #8989; the multi-sensor herded driver's first compile took
    47 s with it instead of 91 s);
    the code numba compiles is the same. ``"0"`` leaves numba's inliner as it is. Applied only
    to the numba text it was written for: :data:`INLINE_COPY_AT_ONCE` says whether it was.

``fastmath`` is always off: the sampler kernels must agree bit for bit with the pure-Python
reference (:mod:`rankedassign.reference`), and fast-math reassociation would break that.
Setting ``NUMBA_DISABLE_JIT=1`` runs every kernel as plain Python (the coverage run does).

Concurrent compiles. numba's on-disk cache saves without a lock; two processes compiling
different signatures of one kernel at once could leave an index that maps one signature to the
other's machine code (a crash at the next load). Importing this module makes every save take
an exclusive lock of the kernel's index file (POSIX ``flock``).

Cache invalidation across files. numba's cache notices when the file that defines a kernel
changes, but not when a kernel it calls (and has compiled into itself) changes in another
file. :func:`jit` therefore keys every cached kernel by a digest of the sources a kernel can
depend on in both packages, :data:`KERNEL_PACKAGES` (:func:`kernel_sources`: the modules that
define kernels and what they import; ``__qualname__`` gets the digest as a suffix, which names
the cache file): editing any of them recompiles everything, kernels can live in as many files
as their algorithms need, and a kernel of one package may call the other's (the δ-GLMB
filter's per-component loop runs the oracle's Murty search and enumeration). Editing a module
that no kernel imports (a filter, a model, a study) keeps the compiled kernels.

Signals. A compiled kernel runs without looking at signals; Python runs the handler of a
signal that arrived meanwhile (Ctrl-C's ``KeyboardInterrupt``, a SIGTERM handler) at the first
Python code after the kernel. When the kernel returns an array, that first Python code is
inside numba's return path (boxing an array calls ``numba.core.serialize._numba_unpickle``),
and the handler's exception comes out as ``SystemError: CPUDispatcher(<kernel>) returned a
result with an exception set``. Every call of such a kernel from Python runs inside
``with interruptible:``, which raises the handler's exception itself instead. A kernel called
from Python never returns a named tuple: numba boxes one by calling its class, and a handler's
exception raised there crashes the process (a segmentation fault); records cross into Python
as plain tuples. Kernels that can run for long are also cut into slices, so that the
handler runs soon: the chain driver of every sampler (:mod:`rankedassign.engine._kernels`,
"Slices"), the oracle's subset, frontier and multi-sensor row DPs, the surrogate's
matched-subset DP, Murty's search and the counting searches. A slice never splits one sweep,
one DP step or one Murty iteration, which the problem's size bounds. Not sliced, because the
input bounds them: the tracking kernels (one scan's tracks, components and measurements), the
LSAP, and the enumeration of the assignments themselves (run only once their count is known to
be within ``limit``).
"""

from __future__ import annotations

import functools
import hashlib
import importlib.util
import inspect
import linecache
import os
import re
import sys
import textwrap
import types
from contextlib import contextmanager
from pathlib import Path

import numba
from numba.core import caching as _caching
from numba.core import inline_closurecall as _closurecall

__all__ = ["CACHE", "INLINE_COPY_AT_ONCE", "KERNEL_PACKAGES", "jit", "threads", "instantiate",
           "source_digest", "kernel_sources",
           "interruptible", "signal_exception"]

CACHE = os.environ.get("RANKEDASSIGN_NUMBA_CACHE", "1") != "0"

def _locked_save(self, key, data, _save=_caching.IndexDataCacheFile.save):
    """numba's cache save under an exclusive lock of its index file.

    numba reads the index, picks the first free data-file number, writes the index and then
    the data, without a lock: two processes that compile different signatures of one kernel at
    once (the suite's workers, ``rankedassign precompile``'s pool) can both take number ``i``,
    and the index that survives then maps one signature to the other's machine code, which
    crashes the next process that loads it. Under the lock the read-modify-write is one step.
    """
    try:
        fd = os.open(self._index_path + ".lock", os.O_RDWR | os.O_CREAT, 0o644)
    except OSError:  # a read-only cache folder: numba's own behaviour
        return _save(self, key, data)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        return _save(self, key, data)
    finally:
        os.close(fd)  # releases the lock


try:
    import fcntl
except ImportError:  # pragma: no cover (not POSIX: numba's unlocked save)
    pass
else:
    if not getattr(_caching.IndexDataCacheFile.save, "_rankedassign_locked", False):
        _locked_save._rankedassign_locked = True
        _caching.IndexDataCacheFile.save = _locked_save

# numba's inliner copies the callee's IR one block at a time, each block with its own deep copy,
# and a block refers to the function's scope, so every block's copy copies every variable of
# the function again: blocks x variables. For the largest kernels here (the multi-sensor herded
# sweep, 591 blocks and 5 278 variables, written into its driver) those copies took about half
# of the compile time (numba issue #8989; numba-cuda issues #688 and #689 describe the same cost).
# The same copy made with one deep copy of all the blocks shares one copy of the scope, as the
# callee's own blocks do. The rewrite is applied only where numba's text is exactly the one
# below (otherwise numba is left alone), and ``RANKEDASSIGN_NUMBA_INLINE_COPY=0`` leaves it
# alone too. Measured (``rankedassign precompile``, empty cache, 2 cores, ABBA): 203 and 196 s
# before, 147 and 171 s after (``benchmarks/README.md``, "Eleventh pass"); the compiled code is
# the same (the tests compare numba's LLVM IR with and without it, and the suite's digests pin
# every result).
_INLINE_COPY_PER_BLOCK = """        kernel_copy.blocks = {}
        for block_label, block in the_ir.blocks.items():
            new_block = copy.deepcopy(the_ir.blocks[block_label])
            kernel_copy.blocks[block_label] = new_block
        return kernel_copy"""
_INLINE_COPY_AT_ONCE = """        kernel_copy.blocks = copy.deepcopy(the_ir.blocks)
        return kernel_copy"""


def _one_copy_inliner() -> bool:
    """Make numba's inliner copy a callee's blocks in one deep copy; ``True`` if it now does.

    See the comment above. ``False`` when ``RANKEDASSIGN_NUMBA_INLINE_COPY=0`` or when this
    numba's ``InlineWorker.inline_ir`` is not the text the rewrite was made for.
    """
    if os.environ.get("RANKEDASSIGN_NUMBA_INLINE_COPY", "1") == "0":
        return False
    worker = _closurecall.InlineWorker
    if getattr(worker.inline_ir, "_rankedassign_one_copy", False):
        return True
    try:
        text = textwrap.dedent(inspect.getsource(worker.inline_ir))
    except (OSError, TypeError):  # pragma: no cover (numba installed without its sources)
        return False
    if text.count(_INLINE_COPY_PER_BLOCK) != 1 or worker.inline_ir.__code__.co_freevars:
        return False
    text = text.replace(_INLINE_COPY_PER_BLOCK, _INLINE_COPY_AT_ONCE)
    # a file name of its own, its text in linecache: tracebacks show the rewritten lines
    filename = "<numba InlineWorker.inline_ir, copied at once by rankedassign.numba_options>"
    linecache.cache[filename] = (len(text), None, text.splitlines(True), filename)
    namespace: dict = {}
    exec(compile(text, filename, "exec"), vars(_closurecall), namespace)
    inline_ir = namespace["inline_ir"]
    inline_ir.__qualname__ = worker.inline_ir.__qualname__
    inline_ir.__doc__ = worker.inline_ir.__doc__
    inline_ir._rankedassign_one_copy = True
    inline_ir._rankedassign_numba = worker.inline_ir  # numba's own
    worker.inline_ir = inline_ir
    return True


#: Whether numba's inliner copies a callee's blocks in one deep copy (see above).
INLINE_COPY_AT_ONCE = _one_copy_inliner()

# Read by the OpenMP runtime when numba's thread pool starts (on the first parallel call).
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
#: The packages whose kernels may compile one another's into themselves: every cache key
#: digests the sources of both.
KERNEL_PACKAGES = ("rankedassign", "oracle")


#: Parts of :mod:`rankedassign` that define no kernel and that no kernel module imports (the
#: studies, the command line, the Stone Soup plug-in): never part of the key, whatever they
#: import. ``tests/test_numba_options.py`` keeps both conditions.
NO_KERNELS = ("experiments", "stonesoup", "cli.py", "__main__.py")

# A module defines kernels when its text calls jit / instantiate / vectorize; read as text,
# not parsed: this runs at import, and reading the ~130 files as text takes milliseconds where
# parsing them takes most of a second. Broader than the truth is safe (a larger key).
_KERNEL_TEXT = re.compile(r"\bjit\b|\binstantiate\(|\bvectorize\b")
# ``from X import a, b`` / ``from X import (a,\n b)`` / ``import X.y``, at any indentation;
# a doctest's ``>>> from ...`` does not match.
_IMPORT_TEXT = re.compile(
    r"^[ \t]*(?:from[ \t]+(?P<src>\.*[\w.]*)[ \t]+import[ \t]+"
    r"(?P<names>\([^)]*\)|[^\n]*)|import[ \t]+(?P<mods>[\w. \t,]+))", re.M)


def _package_files() -> dict[str, Path]:
    """Every module of :data:`KERNEL_PACKAGES` by dotted name (a package by its own name)."""
    files = {}
    for package in KERNEL_PACKAGES:
        module = sys.modules.get(package)
        origin = (module.__file__ if module is not None
                  else importlib.util.find_spec(package).origin)
        root = Path(origin).parent
        for path in sorted(root.rglob("*.py")):
            rel = path.relative_to(root)
            if package == "rankedassign" and rel.parts[0] in NO_KERNELS:
                continue
            parts = (package, *rel.with_suffix("").parts)
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            files[name] = path
    return files


def _imports(name: str, path: Path, text: str):
    """``(module, names)`` for each import of the module (``names`` None for ``import X``)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    for m in _IMPORT_TEXT.finditer(text):
        if m["mods"] is not None:
            for mod in m["mods"].split(","):
                yield mod.split()[0] if mod.split() else "", None
            continue
        src = m["src"]
        dots = len(src) - len(src.lstrip("."))
        if dots:
            base = package.split(".")
            base = base[:len(base) - (dots - 1)]
            src = ".".join(base + ([src[dots:]] if src[dots:] else []))
        names = m["names"].split("#")[0].strip("() \t\\").replace("\n", " ")
        yield src, [n.split()[0] for n in names.split(",") if n.split()]


@functools.cache
def kernel_sources() -> tuple[Path, ...]:
    """The files a compiled kernel can depend on: the modules that define kernels, and what
    they import, name by name, across :data:`KERNEL_PACKAGES`.

    A kernel compiles into itself the kernels it calls and reads the globals of its module at
    compile time, so these files are all the sources its machine code depends on. A module
    imported as a whole (``from . import _kernels``) counts with everything it imports; a
    name taken from a package's ``__init__`` counts only through the module it comes from,
    so the pure-Python layers (the filters, their associations, the models) are outside, and
    editing them does not recompile the kernels.

    Returns
    -------
    tuple of pathlib.Path
        Sorted.

    Examples
    --------
    >>> names = {p.name for p in kernel_sources()}
    >>> "_kernels.py" in names and "glmb.py" not in names
    True
    """
    files = _package_files()
    texts = {name: path.read_text(encoding="utf-8") for name, path in files.items()}
    seen: set = set()
    todo = [(name, None) for name, text in texts.items() if _KERNEL_TEXT.search(text)]
    while todo:
        name, names = todo.pop()
        if name not in files or (name, names) in seen:
            continue
        seen.add((name, names))
        whole = names is None or files[name].name != "__init__.py"
        for src, taken in _imports(name, files[name], texts[name]):
            if taken is None:
                todo.append((src, None))
                continue
            for n in taken:
                if not whole and n not in names and n != "*":
                    continue
                todo.append((f"{src}.{n}", None) if f"{src}.{n}" in files else (src, (n,)))
    return tuple(sorted({files[name] for name, _ in seen}))


@functools.cache
def source_digest(package: str) -> str:
    """Digest of the files of ``package`` a kernel can depend on (first 10 hex digits).

    The files are those of :func:`kernel_sources` within ``package``; the parts of
    :mod:`rankedassign` in :data:`NO_KERNELS` are never among them.

    Parameters
    ----------
    package : str
        A top-level package name (``"rankedassign"``, ``"oracle"``); it is found without
        being imported.

    Examples
    --------
    >>> len(source_digest("rankedassign"))
    10
    """
    module = sys.modules.get(package)
    origin = module.__file__ if module is not None else importlib.util.find_spec(package).origin
    root = Path(origin).parent
    h = hashlib.sha1(numba.__version__.encode())
    for path in kernel_sources():
        if root not in path.parents:
            continue
        h.update(str(path.relative_to(root)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:10]


@functools.cache
def _kernel_digest() -> str:
    """Digest of the sources of every package of :data:`KERNEL_PACKAGES` (10 hex digits)."""
    parts = "".join(source_digest(p) for p in KERNEL_PACKAGES)
    return hashlib.sha1(parts.encode()).hexdigest()[:10]


def _keyed(func, qualname: str | None = None):
    """``func`` renamed so that its cache file is specific to the sources of both packages."""
    func.__qualname__ = f"{qualname or func.__qualname__}__{_kernel_digest()}"
    return func


def jit(*, parallel: bool = False, cache: bool | None = None, inline: str = "never",
        nrt: bool = True):
    """Return numba's ``njit`` decorator with the project's options.

    Parameters
    ----------
    parallel : bool, optional
        Compile with ``parallel=True`` (``prange`` loops run on numba's thread pool).
    cache : bool, optional
        Override the on-disk cache setting (default: ``RANKEDASSIGN_NUMBA_CACHE``).
    inline : {"never", "always"}, optional
        numba's ``inline`` option: ``"always"`` writes the function into each compiled caller
        (at numba's IR level), which saves a call whose arguments are many arrays.
    nrt : bool, optional
        False compiles without numba's reference counting (its runtime, NRT): the kernel may
        then allocate nothing, and every array it touches must be kept alive by its caller.
        For a loop that hands named records of arrays to phases inlined into it: each record
        bound to a phase's argument, and each array read from one, would otherwise cost an
        atomic reference count update per array, on every pass of the loop.

    Returns
    -------
    callable
        A decorator.

    Examples
    --------
    >>> from rankedassign.numba_options import jit
    >>> @jit(cache=False)
    ... def add(a, b):
    ...     return a + b
    >>> add(1, 2)
    3
    """
    use_cache = CACHE if cache is None else cache

    def decorate(func):
        if use_cache:
            func = _keyed(func)
        extra = {} if nrt else {"_nrt": False}  # (numba's option for it is private)
        return numba.njit(cache=use_cache, fastmath=False, nogil=True, parallel=parallel,
                          inline=inline, error_model="numpy", **extra)(func)

    return decorate


def instantiate(template, name: str, bindings: dict, *, parallel: bool = False,
                cache: bool | None = None, nrt: bool = True, inline: str = "never"):
    """Compile a copy of the plain function ``template`` whose globals include ``bindings``.

    This is how one generic kernel (the chain driver of :mod:`rankedassign.engine._kernels`) is
    compiled once per problem type: the template refers to the problem's row update by a
    global name, and each instantiation binds that name to another compiled function. numba
    freezes global functions at compile time, so the instantiation calls the bound function
    directly (no function-pointer indirection), and each instantiation has its own cache file
    (``name``).

    Parameters
    ----------
    template : function
        A plain (not compiled) Python function.
    name : str
        The instantiation's qualified name (must be unique per binding).
    bindings : dict
        Global names to add or override for this instantiation.
    parallel, cache, nrt : bool
        As in :func:`jit`.
    inline : {"never", "always"}, optional
        As in :func:`jit`.

    Returns
    -------
    numba dispatcher (or the plain copy when ``NUMBA_DISABLE_JIT=1``)

    Examples
    --------
    >>> def twice(x):
    ...     return step(step(x))
    >>> inc = jit(cache=False)(lambda x: x + 1)
    >>> twice_inc = instantiate(twice, "twice_inc", {"step": inc}, cache=False)
    >>> twice_inc(1)
    3
    """
    g = dict(template.__globals__)
    g.update(bindings)
    func = types.FunctionType(template.__code__, g, template.__name__, template.__defaults__,
                              template.__closure__)
    func.__doc__ = template.__doc__
    func.__module__ = template.__module__
    func.__qualname__ = name
    func.__kwdefaults__ = template.__kwdefaults__
    return jit(parallel=parallel, cache=cache, nrt=nrt, inline=inline)(func)


@contextmanager
def threads(n: int):
    """Run the enclosed block with numba's thread pool limited to ``n`` threads.

    Parameters
    ----------
    n : int
        Number of threads, clipped to ``numba.config.NUMBA_NUM_THREADS``.

    Examples
    --------
    >>> from rankedassign.numba_options import threads
    >>> with threads(1):
    ...     pass
    """
    old = numba.get_num_threads()
    numba.set_num_threads(max(1, min(int(n), numba.config.NUMBA_NUM_THREADS)))
    try:
        yield
    finally:
        numba.set_num_threads(old)


# What CPython says when a C function returns a value with an exception set (Objects/call.c).
_RESULT_WITH_EXCEPTION = "returned a result with an exception set"


def signal_exception(exc: BaseException) -> BaseException | None:
    """The exception a signal handler raised inside numba's return path, or None.

    Parameters
    ----------
    exc : BaseException
        An exception raised by a call of a compiled kernel.

    Returns
    -------
    BaseException or None
        When ``exc`` is a ``SystemError`` "returned a result with an exception set" whose
        chain of causes runs through such ``SystemError`` s down to another exception, that
        exception (the ``KeyboardInterrupt``, or whatever a signal handler raised while numba
        boxed the kernel's result); else None.

    Examples
    --------
    >>> inner = KeyboardInterrupt()
    >>> outer = SystemError("CPUDispatcher(<f>) returned a result with an exception set")
    >>> outer.__cause__ = inner
    >>> signal_exception(outer) is inner, signal_exception(SystemError("other"))
    (True, None)
    """
    seen = set()
    e = exc
    while isinstance(e, SystemError) and _RESULT_WITH_EXCEPTION in str(e) and id(e) not in seen:
        seen.add(id(e))
        e = e.__cause__ if e.__cause__ is not None else e.__context__
    if e is None or e is exc or isinstance(e, SystemError):
        return None
    return e


class _Interruptible:
    """``with interruptible:`` raises a signal handler's exception as itself (module docstring).

    Stateless and re-entrant: one shared instance, entered around each call of a kernel
    that returns arrays. Costs about a tenth of a microsecond.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.numba_options import interruptible, jit
    >>> @jit(cache=False)
    ... def ones(n):
    ...     return np.ones(n)
    >>> with interruptible:
    ...     a = ones(3)
    >>> a.tolist()
    [1.0, 1.0, 1.0]
    """

    __slots__ = ()

    def __enter__(self):
        return self

    def __exit__(self, typ, exc, tb):
        if typ is not None and issubclass(typ, SystemError):
            root = signal_exception(exc)
            if root is not None:
                raise root.with_traceback(root.__traceback__) from None
        return False

    def __repr__(self):
        return "interruptible"


#: Context manager around calls of compiled kernels from Python: a signal handler's exception
#: raised while numba boxes the result (``KeyboardInterrupt``, a SIGTERM handler's exception)
#: comes out as itself instead of a ``SystemError`` (see the module docstring, "Signals").
interruptible = _Interruptible()
