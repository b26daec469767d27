"""The ranked-assignment problem of the joint GLMB/LMB prediction/update.

One prior component with ``P`` labels (rows) and ``M`` measurements gives a cost matrix
``C`` of shape ``(P, M + 2P)`` in the paper's layout (spec §1.5, eq. 1.7)::

    C[i, j]         = -ln eta_i(j)    j = 0..M-1   (label i generates measurement j+1)
    C[i, M + i]     = -ln eta_i(0)                 (label i survives / is born, missed)
    C[i, M + P + i] = -ln eta_i(-1)                (label i dies / is not born)
    C[i, c]         = +inf            every other c

An assignment is an integer vector of column indices, one per row (like the ``col_ind`` of
:func:`scipy.optimize.linear_sum_assignment`); no two rows may share a column. The paper's
labels ``gamma`` (-1 dead, 0 missed, j >= 1 measurement j) are a view of the same thing.

Weights stay in log space: ``log w(gamma) = -cost(gamma)``; costs may be negative.
"""

from __future__ import annotations

import math
import numbers
from functools import cached_property

import numpy as np

from ..validation import float_array

__all__ = ["AssignmentProblem", "COST_LIMIT"]

# The finite costs of a problem are refused when the rows' largest |finite cost| sum beyond
# this: then the cost of every assignment, and the difference of any two, stays finite
# (<= 2**1021 < the largest double), so sums, log-sum-exps and ratios of weights never overflow.
COST_LIMIT = 2.0**1020

# Column indices and gamma labels beyond this magnitude cannot index anything; they are refused
# before the cast to int64 (which would wrap them around).
_INDEX_LIMIT = 2**62

# Exact counting (n_feasible on a problem with forbidden pairs) refuses beyond this work.
_COUNT_MAX_SUBSET_BITS = 22
_COUNT_MAX_WORK = 2 * 10**8




def _first(mask: np.ndarray) -> tuple:
    """Index of the first True entry of ``mask`` as a tuple of ints."""
    return tuple(int(v) for v in np.argwhere(mask)[0])


class AssignmentProblem:
    """A ``P x (M + 2P)`` ranked-assignment problem in the paper's layout.

    Build one with :meth:`from_eta`, :meth:`from_log_eta`, :meth:`from_cost` or
    :meth:`from_vo_layout`; the constructor validates once, so every solver, sampler and
    oracle function can trust the matrix.

    Parameters
    ----------
    cost : array_like, shape (P, M + 2P)
        Cost matrix in the paper's layout. Prefer the ``from_*`` constructors.

    Attributes
    ----------
    n_rows : int
        ``P``, the number of labels (rows).
    n_meas : int
        ``M``, the number of measurements.
    n_cols : int
        ``M + 2P``.
    cost : ndarray, shape (P, M + 2P)
        Read-only float64 C-contiguous cost matrix; ``+inf`` marks a forbidden pair.

    Notes
    -----
    The target distribution of both Gibbs samplers is (spec eq. 1.6)
    ``pi(gamma) = w(gamma) / Z`` with ``w(gamma) = prod_i eta_i(gamma_i)`` on the feasible
    set ``Gamma`` (no measurement used twice) and ``Z = sum_Gamma w``. Here
    ``-ln w(gamma)`` is the sum of the chosen cost entries (:meth:`cost_of`).

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8), 2017.
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign import AssignmentProblem
    >>> prob = AssignmentProblem.from_eta([[2.0, 0.5], [0.1, 3.0]], [0.2, 0.3], [0.1, 0.1])
    >>> prob.n_rows, prob.n_meas, prob.cost.shape
    (2, 2, (2, 6))
    >>> prob.n_feasible()
    14
    >>> best = np.array([0, 1])          # row 0 -> measurement 1, row 1 -> measurement 2
    >>> prob.cols_to_gamma(best)
    array([1, 2])
    >>> float(np.exp(prob.log_weight_of(best)))   # 2.0 * 3.0
    6.0
    """

    def __init__(self, cost):
        C = float_array(cost, "cost matrix")
        if C.ndim != 2:
            raise ValueError(
                f"cost matrix must be 2-D with shape (P, M + 2P), got {C.ndim}-D shape {C.shape}"
            )
        P, N = C.shape
        M = N - 2 * P
        if M < 0:
            raise ValueError(
                f"cost matrix of shape {C.shape} is not (P, M + 2P): with P = {P} rows it needs "
                f"at least 2P = {2 * P} columns (M measurement columns, then P missed and P dead "
                "columns)"
            )
        if np.isnan(C).any():
            raise ValueError(f"cost matrix contains NaN at {_first(np.isnan(C))}")
        if np.isneginf(C).any():
            raise ValueError(
                f"cost matrix contains -inf at {_first(np.isneginf(C))}; a cost must be finite "
                "or +inf (forbidden)"
            )
        allowed = np.zeros((P, N), dtype=bool)
        allowed[:, :M] = True
        rows = np.arange(P)
        allowed[rows, M + rows] = True
        allowed[rows, M + P + rows] = True
        bad = np.isfinite(C) & ~allowed
        if bad.any():
            i, c = _first(bad)
            kind = "missed" if c < M + P else "dead"
            owner = c - M if c < M + P else c - M - P
            raise ValueError(
                f"cost matrix has a finite entry at ({i}, {c}) where the layout requires +inf: "
                f"column {c} is the {kind} column of row {owner}, not of row {i}"
            )
        finite = np.isfinite(C)
        empty = ~finite.any(axis=1)
        if empty.any():
            i = int(np.flatnonzero(empty)[0])
            raise ValueError(
                f"row {i} has no finite entry: it can be neither detected, missed nor dead, so "
                "no assignment is feasible"
            )
        _check_cost_range(C, finite)
        C.setflags(write=False)
        self._cost = C
        self._check_feasible()

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_cost(cls, cost) -> AssignmentProblem:
        """Build a problem from a cost matrix in the paper's layout.

        Parameters
        ----------
        cost : array_like, shape (P, M + 2P)
            ``-ln eta``; ``+inf`` = forbidden. Must be ``+inf`` outside the measurement
            columns, the row's own missed column ``M + i`` and its dead column ``M + P + i``.

        Returns
        -------
        AssignmentProblem

        Raises
        ------
        ValueError
            On a wrong shape, NaN, ``-inf``, a finite entry where the layout requires ``+inf``,
            a row with no finite entry, a problem with no feasible assignment, or finite costs
            so large that an assignment's cost could overflow: the rows' largest ``|cost|``
            must sum to at most :data:`COST_LIMIT` ``= 2**1020``.
        TypeError
            On non-numeric input (strings, ``None``, complex numbers, dates, ragged lists).

        Examples
        --------
        >>> import numpy as np
        >>> inf = np.inf
        >>> C = [[1.0, -0.5, 2.0, inf, 3.0, inf],   # row 0: 2 measurements, missed, dead
        ...      [0.5, inf, inf, 1.0, inf, 0.1]]    # row 1 cannot take measurement 2
        >>> p = AssignmentProblem.from_cost(C)
        >>> p.n_rows, p.n_meas
        (2, 2)
        """
        return cls(cost)

    @classmethod
    def from_log_eta(cls, log_eta_detect, log_eta_missed, log_eta_dead) -> AssignmentProblem:
        """Build a problem from log-weights (``-inf`` = weight zero = forbidden).

        Parameters
        ----------
        log_eta_detect : array_like, shape (P, M)
            ``ln eta_i(j)`` for measurement ``j`` (0-based column ``j - 1``).
        log_eta_missed : array_like, shape (P,)
            ``ln eta_i(0)``.
        log_eta_dead : array_like, shape (P,)
            ``ln eta_i(-1)``.

        Returns
        -------
        AssignmentProblem

        Examples
        --------
        >>> p = AssignmentProblem.from_log_eta([[0.0]], [-1.0], [-2.0])
        >>> p.cost.tolist()
        [[-0.0, 1.0, 2.0]]
        """
        D = float_array(log_eta_detect, "log_eta_detect")
        m = float_array(log_eta_missed, "log_eta_missed")
        d = float_array(log_eta_dead, "log_eta_dead")
        D, m, d = cls._check_eta_shapes(D, m, d, "log_eta")
        for name, a in (("log_eta_detect", D), ("log_eta_missed", m), ("log_eta_dead", d)):
            if np.isnan(a).any():
                raise ValueError(f"{name} contains NaN at {_first(np.isnan(a))}")
            if np.isposinf(a).any():
                raise ValueError(
                    f"{name} contains +inf at {_first(np.isposinf(a))}; a weight must be finite"
                )
        return cls(cls._assemble(-D, -m, -d))

    @classmethod
    def from_eta(cls, eta_detect, eta_missed, eta_dead) -> AssignmentProblem:
        """Build a problem from the non-negative weights ``eta`` of spec eq. (1.4).

        Parameters
        ----------
        eta_detect : array_like, shape (P, M)
            ``eta_i(j)``, label ``i`` generates measurement ``j`` (0-based column ``j - 1``).
        eta_missed : array_like, shape (P,)
            ``eta_i(0)``, label ``i`` exists and is missed.
        eta_dead : array_like, shape (P,)
            ``eta_i(-1)``, label ``i`` dies or is not born.

        Returns
        -------
        AssignmentProblem
            With ``C = -ln eta`` (``eta = 0`` gives ``+inf``, a forbidden pair).

        Raises
        ------
        ValueError
            On mismatched shapes, NaN, negative or infinite weights, or a row whose weights
            are all zero.

        Examples
        --------
        >>> p = AssignmentProblem.from_eta([[1.0, 0.0]], [0.5], [0.25])
        >>> p.cost
        array([[-0.        ,         inf,  0.69314718,  1.38629436]])
        """
        D = float_array(eta_detect, "eta_detect")
        m = float_array(eta_missed, "eta_missed")
        d = float_array(eta_dead, "eta_dead")
        D, m, d = cls._check_eta_shapes(D, m, d, "eta")
        for name, a in (("eta_detect", D), ("eta_missed", m), ("eta_dead", d)):
            if np.isnan(a).any():
                raise ValueError(f"{name} contains NaN at {_first(np.isnan(a))}")
            if (a < 0).any():
                raise ValueError(
                    f"{name} has a negative entry at {_first(a < 0)}; weights must be >= 0"
                )
            if np.isinf(a).any():
                raise ValueError(
                    f"{name} contains inf at {_first(np.isinf(a))}; weights must be finite"
                )
        with np.errstate(divide="ignore"):
            return cls(cls._assemble(-np.log(D), -np.log(m), -np.log(d)))

    @staticmethod
    def _check_eta_shapes(D, m, d, prefix):
        if D.ndim != 2:
            raise ValueError(
                f"{prefix}_detect must be 2-D with shape (P, M), got {D.ndim}-D shape {D.shape}"
            )
        P = D.shape[0]
        for name, a in ((f"{prefix}_missed", m), (f"{prefix}_dead", d)):
            if a.shape != (P,):
                raise ValueError(
                    f"{name} must have shape (P,) = ({P},) to match {prefix}_detect of shape "
                    f"{D.shape}, got shape {a.shape}"
                )
        return D, m, d

    @staticmethod
    def _assemble(cost_detect, cost_missed, cost_dead) -> np.ndarray:
        P, M = cost_detect.shape
        C = np.full((P, M + 2 * P), np.inf)
        C[:, :M] = cost_detect
        rows = np.arange(P)
        C[rows, M + rows] = cost_missed
        C[rows, M + P + rows] = cost_dead
        return C

    @classmethod
    def from_vo_layout(cls, P0) -> AssignmentProblem:
        """Build a problem from a cost matrix in Vo's MATLAB column order.

        Vo's ``gibbswrap_jointpredupdt_custom.m`` uses columns ``[dead | missed |
        measurements]``, each of the first two blocks ``P`` wide with ``+inf`` off the diagonal.

        Parameters
        ----------
        P0 : array_like, shape (P, 2P + M)

        Returns
        -------
        AssignmentProblem

        Examples
        --------
        >>> import numpy as np
        >>> vo = np.array([[2.0, 1.0, 0.5]])     # dead, missed, measurement 1
        >>> AssignmentProblem.from_vo_layout(vo).cost.tolist()
        [[0.5, 1.0, 2.0]]
        """
        A = float_array(P0, "Vo-layout cost matrix")
        if A.ndim != 2 or A.shape[1] < 2 * A.shape[0]:
            raise ValueError(
                "Vo-layout cost matrix must be 2-D with shape (P, 2P + M) "
                f"([dead | missed | measurements]), got shape {A.shape}"
            )
        P = A.shape[0]
        return cls(np.hstack([A[:, 2 * P :], A[:, P : 2 * P], A[:, :P]]))

    def to_vo_layout(self) -> np.ndarray:
        """Return the cost matrix in Vo's MATLAB column order ``[dead | missed | meas]``.

        Returns
        -------
        ndarray, shape (P, 2P + M)

        Examples
        --------
        >>> p = AssignmentProblem.from_cost([[0.5, 1.0, 2.0]])
        >>> p.to_vo_layout().tolist()
        [[2.0, 1.0, 0.5]]
        """
        P, M = self.n_rows, self.n_meas
        C = self._cost
        return np.hstack([C[:, M + P :], C[:, M : M + P], C[:, :M]])

    # ------------------------------------------------------------------ properties
    @property
    def cost(self) -> np.ndarray:
        """Read-only ``(P, M + 2P)`` float64 cost matrix (``+inf`` = forbidden)."""
        return self._cost

    @property
    def n_rows(self) -> int:
        """Number of rows (labels) ``P``."""
        return int(self._cost.shape[0])

    @property
    def n_cols(self) -> int:
        """Number of columns ``M + 2P``."""
        return int(self._cost.shape[1])

    @property
    def n_meas(self) -> int:
        """Number of measurements ``M``."""
        return int(self._cost.shape[1] - 2 * self._cost.shape[0])

    @property
    def shape(self) -> tuple[int, int]:
        """``(P, M + 2P)``."""
        return self._cost.shape

    @cached_property
    def compact_cost(self) -> np.ndarray:
        """Per-row costs in compact form, shape ``(P, M + 2)``.

        Columns ``0..M-1`` are the measurements, column ``M`` the row's missed entry and
        column ``M + 1`` its dead entry. Read-only. This is the form the kernels use: a row can
        only ever take one of these ``M + 2`` values.
        """
        P, M = self.n_rows, self.n_meas
        rows = np.arange(P)
        out = np.empty((P, M + 2))
        out[:, :M] = self._cost[:, :M]
        out[:, M] = self._cost[rows, M + rows]
        out[:, M + 1] = self._cost[rows, M + P + rows]
        out.setflags(write=False)
        return out

    def eta(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Return the weights ``(eta_detect (P, M), eta_missed (P,), eta_dead (P,))``.

        ``exp(-cost)``; may overflow to ``inf`` for very negative costs, in which case use
        :attr:`compact_cost` and work in log space.

        Returns
        -------
        eta_detect : ndarray of float64, shape (P, M)
            ``eta_i(j)``, the weight of row ``i`` taking measurement ``j + 1``; 0 where the
            pair is forbidden.
        eta_missed : ndarray of float64, shape (P,)
            ``eta_i(0)``, the weight of row ``i`` surviving undetected.
        eta_dead : ndarray of float64, shape (P,)
            ``eta_i(-1)``, the weight of row ``i`` not surviving (dead or not born).

        All three are new writable arrays.

        Examples
        --------
        >>> p = AssignmentProblem.from_eta([[2.0]], [0.5], [0.25])
        >>> [a.tolist() for a in p.eta()]
        [[[2.0]], [0.5], [0.25]]
        """
        cc = self.compact_cost
        M = self.n_meas
        with np.errstate(over="ignore"):
            e = np.exp(-cc)
        return e[:, :M].copy(), e[:, M].copy(), e[:, M + 1].copy()

    def __repr__(self) -> str:
        return f"AssignmentProblem(P={self.n_rows}, M={self.n_meas})"

    def __eq__(self, other) -> bool:
        if not isinstance(other, AssignmentProblem):
            return NotImplemented
        return self.shape == other.shape and bool(np.array_equal(self._cost, other._cost))

    def __hash__(self) -> int:
        return hash((self.shape, self._cost.tobytes()))

    # ------------------------------------------------------------------ assignments
    def all_missed(self) -> np.ndarray:
        """The all-missed assignment ``gamma = (0, ..., 0)``: column ``M + i`` for row ``i``.

        Returns
        -------
        ndarray of int64, shape (P,)
            The column indices ``M, M + 1, ..., M + P - 1`` (the samplers' default start).

        Examples
        --------
        >>> AssignmentProblem.from_cost([[0.5, 1.0, 2.0]]).all_missed()
        array([1])
        """
        return self.n_meas + np.arange(self.n_rows, dtype=np.int64)

    def all_dead(self) -> np.ndarray:
        """The all-dead assignment ``gamma = (-1, ..., -1)``: column ``M + P + i`` for row ``i``.

        Returns
        -------
        ndarray of int64, shape (P,)
            The column indices ``M + P, ..., M + 2P - 1``.

        Examples
        --------
        >>> AssignmentProblem.from_cost([[0.5, 1.0, 2.0]]).all_dead()
        array([2])
        """
        return self.n_meas + self.n_rows + np.arange(self.n_rows, dtype=np.int64)

    def _as_assignments(self, assignments, name="assignments") -> tuple[np.ndarray, bool]:
        """Validate an ``(n, P)`` or ``(P,)`` integer array; return 2-D int64 and a 1-D flag.

        Integer dtypes and Python ints are accepted, and so are floats holding whole numbers
        (``2.0``); any other kind of value is a ``TypeError``. A value beyond ``+-2**62`` (no
        column index or label reaches it) is a ``ValueError``, raised before the cast to int64
        could wrap it around.
        """
        kind = f"{name} must be an integer array of column indices"
        try:
            a = np.asarray(assignments)
        except Exception as exc:  # ragged lists and the like
            raise TypeError(f"{kind}, could not convert: {exc}") from None
        shape = a.shape
        if a.dtype.kind == "f" and a.size and not isinstance(assignments, np.ndarray):
            # numpy turns a list mixing ints beyond int64 with small ones into floats; keep
            # the Python ints exact instead
            b = np.array(assignments, dtype=object)
            if all(isinstance(v, numbers.Integral) for v in b.reshape(-1)):
                a = b
        if a.dtype == object:
            flat = a.reshape(-1)
            if not all(isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in flat):
                raise TypeError(f"{kind}, got dtype object")
            bad = [int(v) for v in flat if abs(int(v)) > _INDEX_LIMIT]
            if bad:
                raise ValueError(f"{name} contains {bad[0]}, beyond any index (|value| <= 2**62)")
            a = np.array([int(v) for v in flat], dtype=np.int64).reshape(a.shape)
        elif a.size == 0 and a.dtype.kind in "biuf":
            a = a.astype(np.int64)
        elif a.dtype.kind == "f":
            if not (np.isfinite(a).all() and np.all(a == np.round(a))):
                raise TypeError(f"{kind}, got dtype {a.dtype} with non-integer values")
        elif a.dtype.kind not in "iu":
            raise TypeError(f"{kind}, got dtype {a.dtype}")
        if a.size and (a.max() > _INDEX_LIMIT or a.min() < -_INDEX_LIMIT):
            bad = a[(a > _INDEX_LIMIT) | (a < -_INDEX_LIMIT)].reshape(-1)[0]
            bad = int(bad) if a.dtype.kind in "iu" else float(bad)
            raise ValueError(f"{name} contains {bad}, beyond any index (|value| <= 2**62)")
        a = a.astype(np.int64, copy=False)
        P = self.n_rows
        single = a.ndim == 1
        if single:
            a = a[None, :]
        if a.ndim != 2 or a.shape[1] != P:
            raise ValueError(
                f"{name} must have shape (n, P) = (n, {P}) or (P,) = ({P},), got shape "
                f"{shape}"
            )
        return a, single

    def _check_range(self, a: np.ndarray, name: str = "assignments") -> None:
        if a.size and (a.min() < 0 or a.max() >= self.n_cols):
            bad = a[(a < 0) | (a >= self.n_cols)][0]
            raise ValueError(
                f"{name} contains column index {int(bad)} outside [0, {self.n_cols}) "
                f"(M + 2P = {self.n_cols})"
            )

    def cost_of(self, assignments) -> np.ndarray | float:
        """Cost ``-ln w(gamma)`` of each assignment.

        Parameters
        ----------
        assignments : array_like of int, shape (n, P) or (P,)
            Column indices.

        Returns
        -------
        ndarray, shape (n,), or float
            The sum of the chosen entries, accumulated row by row in order ``0..P-1``;
            ``+inf`` for an infeasible assignment (a forbidden pair or a measurement used
            twice), whose weight is zero.

        Examples
        --------
        >>> p = AssignmentProblem.from_eta([[2.0, 0.5], [0.1, 3.0]], [0.2, 0.3], [0.1, 0.1])
        >>> p.cost_of([[0, 1], [1, 0]]).round(6).tolist()
        [-1.791759, 2.995732]
        >>> float(p.cost_of([0, 0]))      # both rows on measurement 1: infeasible
        inf
        """
        a, single = self._as_assignments(assignments)
        self._check_range(a)
        out = self._sum_costs(a)
        if a.shape[1]:
            out[self._has_duplicate_measurement(a)] = np.inf
        return float(out[0]) if single else out

    def _sum_costs(self, a: np.ndarray) -> np.ndarray:
        """Row-by-row sums of the chosen entries of valid ``(n, P)`` int64 column indices.

        The arithmetic of :meth:`cost_of` without its checks, for callers that built ``a``
        themselves (the samplers, whose states are feasible by construction).
        """
        n, P = a.shape
        out = np.zeros(n)
        if P:
            picked = self._cost[np.arange(P)[None, :], a]
            for i in range(P):  # fixed left-to-right order: reproducible to the last bit
                out += picked[:, i]
        return out

    def log_weight_of(self, assignments) -> np.ndarray | float:
        """Log-weight ``ln w(gamma) = -cost`` of each assignment (``-inf`` if infeasible).

        Parameters
        ----------
        assignments : array_like of int, shape (n, P) or (P,)
            Column indices, one per row, as for :meth:`cost_of`.

        Returns
        -------
        ndarray of float64, shape (n,), or float
            ``-self.cost_of(assignments)``: a float for a single ``(P,)`` assignment, else one
            entry per assignment; ``-inf`` where an assignment is infeasible.

        Examples
        --------
        >>> p = AssignmentProblem.from_eta([[2.0]], [0.5], [0.25])
        >>> float(p.log_weight_of([0]))
        0.6931471805599453
        """
        c = self.cost_of(assignments)
        return -c

    def _has_duplicate_measurement(self, a: np.ndarray) -> np.ndarray:
        M = self.n_meas
        if a.shape[1] < 2:
            return np.zeros(a.shape[0], dtype=bool)
        s = np.sort(a, axis=1)
        dup = (s[:, 1:] == s[:, :-1]) & (s[:, 1:] < M)
        # A row-specific column can only be shared if a row took another row's column; those
        # entries are +inf already, so only measurement columns matter here.
        return dup.any(axis=1)

    def is_feasible(self, assignments) -> np.ndarray | bool:
        """Whether each assignment is feasible (finite cost, no measurement used twice).

        Parameters
        ----------
        assignments : array_like of int, shape (n, P) or (P,)

        Returns
        -------
        ndarray of bool, shape (n,), or bool
            Column indices outside ``[0, M + 2P)`` are infeasible, not an error (but a value
            beyond ``+-2**62``, which no index can reach, is a ``ValueError``).

        Examples
        --------
        >>> p = AssignmentProblem.from_eta([[2.0, 0.5], [0.1, 3.0]], [0.2, 0.3], [0.1, 0.1])
        >>> p.is_feasible([[0, 1], [0, 0], [4, 3]]).tolist()
        [True, False, True]
        """
        a, single = self._as_assignments(assignments)
        in_range = ((a >= 0) & (a < self.n_cols)).all(axis=1)
        ok = in_range.copy()
        if a.shape[0] and ok.any():
            ok[ok] = np.isfinite(self.cost_of(a[ok]))
        return bool(ok[0]) if single else ok

    def cols_to_gamma(self, cols) -> np.ndarray:
        """Convert column indices to the paper's labels ``gamma``.

        Column ``c < M`` is ``gamma = c + 1``; the row's missed column ``M + i`` is ``0``;
        its dead column ``M + P + i`` is ``-1`` (spec §1.5).

        Parameters
        ----------
        cols : array_like of int, shape (n, P) or (P,)

        Returns
        -------
        ndarray of int64, same shape

        Raises
        ------
        ValueError
            If a column is out of range or is the missed/dead column of another row.

        Examples
        --------
        >>> p = AssignmentProblem.from_eta([[2.0, 0.5], [0.1, 3.0]], [0.2, 0.3], [0.1, 0.1])
        >>> p.cols_to_gamma([[1, 5], [2, 0]]).tolist()
        [[2, -1], [0, 1]]
        """
        a, single = self._as_assignments(cols, "cols")
        self._check_range(a, "cols")
        P, M = self.n_rows, self.n_meas
        rows = np.arange(P)[None, :]
        g = np.where(a < M, a + 1, 0)
        miss = a == M + rows
        dead = a == M + P + rows
        wrong = (a >= M) & ~miss & ~dead
        if wrong.any():
            r, k = _first(wrong)
            raise ValueError(
                f"cols[{r}, {k}] = {int(a[r, k])} is the missed/dead column of another row; "
                f"row {k} may use measurement columns, {M + k} (missed) or {M + P + k} (dead)"
            )
        g = np.where(dead, -1, g).astype(np.int64)
        return g[0] if single else g

    def gamma_to_cols(self, gamma) -> np.ndarray:
        """Convert the paper's labels ``gamma`` (-1, 0, 1..M) to column indices.

        Parameters
        ----------
        gamma : array_like of int, shape (n, P) or (P,)

        Returns
        -------
        ndarray of int64, same shape

        Examples
        --------
        >>> p = AssignmentProblem.from_eta([[2.0, 0.5], [0.1, 3.0]], [0.2, 0.3], [0.1, 0.1])
        >>> p.gamma_to_cols([[2, -1], [0, 1]]).tolist()
        [[1, 5], [2, 0]]
        """
        g, single = self._as_assignments(gamma, "gamma")
        P, M = self.n_rows, self.n_meas
        if g.size and (g.min() < -1 or g.max() > M):
            bad = g[(g < -1) | (g > M)][0]
            raise ValueError(f"gamma contains {int(bad)} outside [-1, M] = [-1, {M}]")
        rows = np.arange(P)[None, :]
        c = np.where(g >= 1, g - 1, np.where(g == 0, M + rows, M + P + rows)).astype(np.int64)
        return c[0] if single else c

    # ------------------------------------------------------------------ counting
    def n_feasible(self) -> int:
        """Exact number of feasible (finite-cost) assignments ``|Gamma|``.

        Returns
        -------
        int
            A Python int (exact at any size).

        Raises
        ------
        ValueError
            When some allowed entry is ``+inf`` and the exact count would need more work than
            the subset dynamic programme allows (the message states the size).

        Notes
        -----
        When every entry that the layout allows is finite, spec eq. (1.3):
        ``|Gamma| = sum_k C(P,k) C(M,k) k! 2^(P-k)``. Otherwise an exact integer subset
        dynamic programme (spec §5.2 on 0/1 weights) over subsets of the smaller of rows and
        measurements: ``O(2^min(P,M) * min(P,M) * max(P,M))``.

        Examples
        --------
        >>> from rankedassign import synthetic
        >>> synthetic.uniform().n_feasible()
        76848
        """
        P, M = self.n_rows, self.n_meas
        cc = self.compact_cost
        finite = np.isfinite(cc)
        if finite.all():
            return sum(
                math.comb(P, k) * math.comb(M, k) * math.factorial(k) * 2 ** (P - k)
                for k in range(min(P, M) + 1)
            )
        a = finite[:, M].astype(np.int64) + finite[:, M + 1].astype(np.int64)
        B = finite[:, :M]
        # Drop measurements no row can take; they do not change the count.
        B = B[:, B.any(axis=0)]
        M2 = B.shape[1]
        k, n = min(P, M2), max(P, M2)
        work = (1 << k) * max(k, 1) * max(n, 1)
        if k > _COUNT_MAX_SUBSET_BITS or work > _COUNT_MAX_WORK:
            raise ValueError(
                f"problem too large to count exactly: P = {P} rows and {M2} reachable "
                f"measurements with forbidden pairs need a subset DP over 2^{k} states "
                f"(~{work:.2e} steps, limit {_COUNT_MAX_WORK:.0e})"
            )
        bound = sum(
            math.comb(P, t) * math.comb(M2, t) * math.factorial(t) * 2 ** (P - t)
            for t in range(k + 1)
        )
        dtype = np.int64 if bound < 2**62 else object
        if P <= M2:
            return _count_rows_small(B, a, dtype)
        return _count_meas_small(B, a, dtype)

    def _check_feasible(self) -> None:
        """Raise if no assignment is feasible (rows with neither missed nor dead entry)."""
        M = self.n_meas
        cc = self.compact_cost
        must = ~(np.isfinite(cc[:, M]) | np.isfinite(cc[:, M + 1]))
        if not must.any():
            return
        B = np.where(np.isfinite(cc[must, :M]), 0.0, np.inf)
        try:
            if B.shape[0] > B.shape[1]:  # more rows that need a measurement than measurements
                raise ValueError
            from scipy.optimize import linear_sum_assignment  # (0.3 s to import: here)

            linear_sum_assignment(B)  # raises "cost matrix is infeasible" otherwise
        except ValueError:
            rows = np.flatnonzero(must).tolist()
            raise ValueError(
                f"no feasible assignment: rows {rows} can be neither missed nor dead and cannot "
                "all be given distinct measurements"
            ) from None


def _check_cost_range(C: np.ndarray, finite: np.ndarray) -> None:
    """Refuse finite costs whose assignment sums could overflow (see :data:`COST_LIMIT`)."""
    big = np.where(finite, np.abs(C), 0.0).max(axis=1, initial=0.0)
    # summed in units of 2**-64, so that the sum itself cannot overflow
    total = float(np.sum(big * 2.0**-64))
    if total > COST_LIMIT * 2.0**-64:
        i = int(np.argmax(big))
        log10 = math.log10(total) + 64 * math.log10(2.0)
        e = math.floor(log10)
        raise ValueError(
            f"cost matrix has finite costs too large to add up: the rows' largest |finite "
            f"cost| sum to {10 ** (log10 - e):.3f}e+{e} (row {i}: {big[i]:.6g}), beyond "
            "COST_LIMIT = 2**1020 = 1.124e+307, the bound that keeps every assignment's cost "
            "finite; a forbidden pair is +inf"
        )


def _count_rows_small(B: np.ndarray, a: np.ndarray, dtype) -> int:
    """Count over subsets S of rows matched so far, measurement by measurement (spec 5.1)."""
    P, M = B.shape
    S = np.arange(1 << P)
    f = np.zeros(1 << P, dtype=dtype)
    f[0] = 1
    for j in range(M):
        g = f.copy()
        for i in range(P):
            if B[i, j]:
                has = (S >> i) & 1 == 1
                g[has] += f[S[has] ^ (1 << i)]
        f = g
    # multiply by prod_{i not in S} a_i
    weight = np.ones(1 << P, dtype=dtype)
    for i in range(P):
        weight = weight * np.where((S >> i) & 1 == 1, 1, int(a[i])).astype(dtype)
    return int((f * weight).sum())


def _count_meas_small(B: np.ndarray, a: np.ndarray, dtype) -> int:
    """Count over subsets T of measurements used so far, row by row."""
    P, M = B.shape
    T = np.arange(1 << M)
    g = np.zeros(1 << M, dtype=dtype)
    g[0] = 1
    for i in range(P):
        h = g * int(a[i])
        for j in range(M):
            if B[i, j]:
                has = (T >> j) & 1 == 1
                h[has] += g[T[has] ^ (1 << j)]
        g = h
    return int(g.sum())
