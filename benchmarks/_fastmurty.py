"""Optional comparison: Motro's ``fastmurty`` (C) on the benchmark's Murty problems.

``fastmurty`` is not a dependency and nothing of it is shipped here. To include it in the
Murty groups of ``test_bench_oracle.py``, build its shared library yourself from its public
repository (MIT licence), once with sparse input and/or once with dense input (the input kind is
chosen when compiling), and point these variables at the builds::

    RANKEDASSIGN_FASTMURTY_SPARSE=/path/to/mhtda_sparse.so
    RANKEDASSIGN_FASTMURTY_DENSE=/path/to/mhtda_dense.so

The commands are in ``benchmarks/README.md``. Without the variables the two methods are skipped.

How a problem is handed over. ``fastmurty`` solves the data-association form of the ranked
assignment: a row or column may stay unassigned at cost 0.

* When every row's missed cost is 0 and no row has a dead column (the square case of
  ``fastmurty``'s own benchmark), the problem *is* that form: the library receives the
  ``P x M`` measurement block alone, "unassigned" is the missed column, and the costs are the
  same numbers (native input). The dense input needs the block free of ``+inf`` for this.
* Otherwise the ``P x (M + 2P)`` matrix is handed over whole, and since every row must be
  assigned, every finite cost is lowered by one constant ``B``, a power of two above ``P`` times
  the spread of the finite costs plus one: any assignment that leaves a row unassigned then
  costs more than every complete one, and the ``k`` best are the project's ``k`` best with
  ``P * B`` subtracted. Forbidden pairs (``+inf``) are absent entries of the sparse input, and
  ``+B`` (never better than leaving the row out) in the dense input.

:meth:`FastMurty.check` checks that every returned assignment is complete and allowed.
"""

from __future__ import annotations

import ctypes
import os
from ctypes import POINTER, c_bool, c_double, c_int

import numpy as np

ENV = {"sparse": "RANKEDASSIGN_FASTMURTY_SPARSE", "dense": "RANKEDASSIGN_FASTMURTY_DENSE"}


class _CsrMatrix(ctypes.Structure):
    """The sparse build's input: rows in order, ``p`` row pointers, ``i`` column indices."""

    _fields_ = [("nzmax", c_int), ("m", c_int), ("n", c_int), ("p", POINTER(c_int)),
                ("i", POINTER(c_int)), ("x", POINTER(c_double)), ("nz", c_int)]


class _Workspace(ctypes.Structure):
    """The library's workspace record, held opaquely: larger than the record it receives
    (a few pointers and counters) and only ever passed back to the library."""

    _fields_ = [("opaque", ctypes.c_byte * 1024)]


def library_path(kind: str) -> str | None:
    """Path of the build of ``kind`` (``"sparse"`` or ``"dense"``) from the environment."""
    return os.environ.get(ENV[kind]) or None


def shift(cost: np.ndarray) -> float:
    """The constant ``B`` subtracted from every finite cost (see the module docstring)."""
    finite = cost[np.isfinite(cost)]
    spread = float(finite.max() - finite.min())
    return float(2.0 ** np.ceil(np.log2(cost.shape[0] * spread + 1.0)))


class FastMurty:
    """One build of the library, loaded privately (both builds export the same names)."""

    def __init__(self, path: str, kind: str):
        if kind not in ENV:
            raise ValueError(f"kind must be 'sparse' or 'dense', got {kind!r}")
        self.kind = kind
        self.lib = ctypes.CDLL(path, mode=os.RTLD_LOCAL)
        matrix = _CsrMatrix if kind == "sparse" else POINTER(c_double)
        self.lib.allocateWorkvarsforDA.argtypes = [c_int, c_int, c_int]
        self.lib.allocateWorkvarsforDA.restype = _Workspace
        self.lib.deallocateWorkvarsforDA.argtypes = [_Workspace]
        self.lib.deallocateWorkvarsforDA.restype = None
        self.lib.da.argtypes = [matrix, c_int, POINTER(c_bool), POINTER(c_double), c_int,
                                POINTER(c_bool), POINTER(c_double), c_int, POINTER(c_int),
                                POINTER(c_double), POINTER(_Workspace)]
        self.lib.da.restype = c_int

    def prepare(self, problem, k: int):
        """A call ``run()`` returning the ``k`` best costs of ``problem`` (``P x N`` costs).

        Everything is built beforehand (input, workspace, outputs), so ``run`` times the
        library's call alone; ``run`` checks nothing, :meth:`check` does.
        """
        C = np.asarray(problem.cost, dtype=float)
        P, N = C.shape
        M = problem.n_meas
        cc = problem.compact_cost
        self._native = bool((cc[:, M] == 0.0).all() and np.isinf(cc[:, M + 1]).all()
                            and (self.kind == "sparse" or np.isfinite(cc[:, :M]).all()))
        if self._native:  # the measurement block, "unassigned" = missed, no shift
            C, B = np.ascontiguousarray(cc[:, :M]), 0.0
            N = M
        else:
            B = shift(C)
        keep = {}  # arrays the library reads must outlive the call
        if self.kind == "sparse":
            finite = np.isfinite(C)
            rows, cols = np.nonzero(finite)  # row by row, columns increasing
            keep["p"] = np.concatenate([[0], np.cumsum(finite.sum(axis=1))]).astype(np.int32)
            keep["i"] = cols.astype(np.int32)
            keep["x"] = np.ascontiguousarray(C[rows, cols] - B)
            matrix = _CsrMatrix(len(cols), P, N, keep["p"].ctypes.data_as(POINTER(c_int)),
                                keep["i"].ctypes.data_as(POINTER(c_int)),
                                keep["x"].ctypes.data_as(POINTER(c_double)), len(cols))
        else:
            keep["c"] = np.ascontiguousarray(np.where(np.isfinite(C), C - B, B))
            matrix = keep["c"].ctypes.data_as(POINTER(c_double))
        keep["row_prior"] = np.ones(P, dtype=np.bool_)  # one hypothesis: every row, weight 0
        keep["col_prior"] = np.ones(N, dtype=np.bool_)
        keep["weight"] = np.zeros(1)
        keep["assocs"] = np.empty((k, P + N, 2), dtype=np.int32)
        keep["costs"] = np.empty(k)
        work = self.lib.allocateWorkvarsforDA(P, N, k)
        self._keep, self._work = keep, work  # one problem prepared at a time
        args = (matrix, 1, keep["row_prior"].ctypes.data_as(POINTER(c_bool)),
                keep["weight"].ctypes.data_as(POINTER(c_double)), 1,
                keep["col_prior"].ctypes.data_as(POINTER(c_bool)),
                keep["weight"].ctypes.data_as(POINTER(c_double)), k,
                keep["assocs"].ctypes.data_as(POINTER(c_int)),
                keep["costs"].ctypes.data_as(POINTER(c_double)), ctypes.byref(work))
        da, costs, offset = self.lib.da, keep["costs"], P * B

        def run():
            da(*args)
            return costs + offset

        self._problem, self._k = problem, k
        return run

    def check(self):
        """The last run's assignments as ``(k, P)`` columns of the project's layout; raise
        unless each is complete and allowed."""
        P, M = self._problem.n_rows, self._problem.n_meas
        # native input: a row left unassigned took its missed column
        out = np.full((self._k, P), -1, dtype=np.int64)
        if self._native:
            out[:] = M + np.arange(P)
        for s, pairs in enumerate(self._keep["assocs"]):
            matched = pairs[(pairs[:, 0] >= 0) & (pairs[:, 1] >= 0)]
            out[s, matched[:, 0]] = matched[:, 1]
        if (out < 0).any() or not self._problem.is_feasible(out).all():
            raise AssertionError("fastmurty returned an incomplete or forbidden assignment")
        return out

    def close(self):
        """Free the workspace of the prepared problem."""
        if getattr(self, "_work", None) is not None:
            self.lib.deallocateWorkvarsforDA(self._work)
            self._work = None
