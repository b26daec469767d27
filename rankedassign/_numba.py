"""The one place where numba options live.

Every kernel of :mod:`rankedassign` and :mod:`oracle` is compiled through :func:`jit` so that
the options below are switched in one place:

``RANKEDASSIGN_NUMBA_CACHE``
    ``"1"`` (default) caches compiled kernels on disk (``cache=True``); ``"0"`` disables it.

``fastmath`` is always off: the sampler kernels must agree bit for bit with the pure-Python
reference (:mod:`rankedassign.reference`), and fast-math reassociation would break that.
Setting ``NUMBA_DISABLE_JIT=1`` runs every kernel as plain Python (for coverage of kernel lines).
"""

from __future__ import annotations

import os
from contextlib import contextmanager

import numba

CACHE = os.environ.get("RANKEDASSIGN_NUMBA_CACHE", "1") != "0"


def jit(*, parallel: bool = False, cache: bool | None = None):
    """Return numba's ``njit`` decorator with the project's options.

    Parameters
    ----------
    parallel : bool, optional
        Compile with ``parallel=True`` (``prange`` loops run on numba's thread pool).
    cache : bool, optional
        Override the on-disk cache setting (default: ``RANKEDASSIGN_NUMBA_CACHE``).

    Returns
    -------
    callable
        A decorator.

    Examples
    --------
    >>> from rankedassign._numba import jit
    >>> @jit(cache=False)
    ... def add(a, b):
    ...     return a + b
    >>> add(1, 2)
    3
    """
    return numba.njit(
        cache=CACHE if cache is None else cache,
        fastmath=False,
        nogil=True,
        parallel=parallel,
        error_model="numpy",
    )


@contextmanager
def threads(n: int):
    """Run the enclosed block with numba's thread pool limited to ``n`` threads.

    Parameters
    ----------
    n : int
        Number of threads, clipped to ``numba.config.NUMBA_NUM_THREADS``.

    Examples
    --------
    >>> from rankedassign._numba import threads
    >>> with threads(1):
    ...     pass
    """
    old = numba.get_num_threads()
    numba.set_num_threads(max(1, min(int(n), numba.config.NUMBA_NUM_THREADS)))
    try:
        yield
    finally:
        numba.set_num_threads(old)
