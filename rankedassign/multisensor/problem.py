"""The multi-sensor ranked-assignment problem (multi-sensor spec §1).

``P`` rows (labels) and ``V`` sensors, sensor ``v`` with ``M_v`` measurements. Row ``n`` takes
``gamma_n = -1`` (dead / not born, every component) or a tuple ``t`` of the tuple space
``{0..M_1} x ... x {0..M_V}``: ``t[v] = 0`` missed by sensor ``v``, ``t[v] = j >= 1`` generated
measurement ``j`` of sensor ``v`` (spec eq. 1.1). Feasible assignments use every measurement of
every sensor at most once (positive one-to-one per sensor, spec eq. 1.2), and

    w(gamma) = prod_n eta_n(gamma_n),   pi(gamma) = w(gamma) / Z        (spec eq. 1.4)

There is no 2-D cost matrix: each row has a dead weight ``eta_n(-1)`` and a ``V``-dimensional
table ``eta_n(t)`` of shape ``(M_1+1, ..., M_V+1)`` (spec §1.7). Weights stay in log space;
``-inf`` marks a forbidden (gated-out) option.
"""

from __future__ import annotations

import math
from functools import cached_property

import numpy as np

from ..single.problem import AssignmentProblem
from ..validation import float_array, format_bytes

__all__ = ["MAX_TABLE_ENTRIES", "MultiSensorProblem", "check_table_size",
           "count_feasible_all_positive"]

#: Largest weight table ``log_eta_alive`` (entries) that :meth:`MultiSensorProblem.from_factors`
#: and the synthetic families build from per-sensor factors: ``2**27`` float64 entries, 1 GiB,
#: as for the single-sensor synthetic matrices. The table has ``P prod_v (M_v + 1)`` entries, so
#: this is what bounds the number of sensors: 27 sensors of one measurement each for one row.
MAX_TABLE_ENTRIES = 2**27
# numpy arrays have at most 64 axes; the table has one for the rows and one per sensor
_MAX_AXES = 64

# Exact counting with forbidden tuples (a DP over the reachable sets of used measurements)
# refuses beyond this many states or this much work.
_COUNT_MAX_STATES = 2**21
_COUNT_MAX_WORK = 5 * 10**6




def _dims_text(dims, noun: str) -> str:
    """A tuple of ints for a message; a long one abbreviated, with its length in ``noun``."""
    dims = tuple(int(m) for m in dims)
    if len(dims) <= 8:
        return str(dims)
    head = ", ".join(str(m) for m in dims[:4])
    return f"({head}, ..., {dims[-1]}) ({len(dims)} {noun})"


def check_table_size(P: int, n_meas) -> None:
    """Refuse, before anything is allocated, a weight table too large to build.

    The table ``log_eta_alive`` of ``P`` rows and ``V`` sensors with ``M_v`` measurements has
    shape ``(P, M_1 + 1, ..., M_V + 1)``.

    Parameters
    ----------
    P : int
    n_meas : sequence of int
        ``(M_1, ..., M_V)``.

    Raises
    ------
    ValueError
        If the table would have more than :data:`MAX_TABLE_ENTRIES` entries or more than the
        64 axes of a numpy array (``V > 63``); the message gives the shape, the entries and
        the bytes.

    Examples
    --------
    >>> check_table_size(4, (4, 4))
    >>> check_table_size(2, (1,) * 40)
    Traceback (most recent call last):
    ...
    ValueError: V = 40 sensors with M = (1, 1, 1, 1, ..., 1) (40 sensors) give a weight table of
    shape (2, 2, 2, 2, ..., 2) (41 axes): 2199023255552 entries, 16.0 TiB (17592186044416
    bytes) of float64, more than MAX_TABLE_ENTRIES = 134217728 entries, 1.0 GiB (1073741824
    bytes)
    """
    M = tuple(int(m) for m in n_meas)
    shape = (int(P), *(m + 1 for m in M))
    entries = math.prod(shape)
    size = (f"V = {len(M)} sensors with M = {_dims_text(M, 'sensors')} give a weight table "
            f"of shape {_dims_text(shape, 'axes')}: {entries} entries, "
            f"{format_bytes(8 * entries)} of float64")
    if entries > MAX_TABLE_ENTRIES:
        raise ValueError(f"{size}, more than MAX_TABLE_ENTRIES = {MAX_TABLE_ENTRIES} entries, "
                         f"{format_bytes(8 * MAX_TABLE_ENTRIES)}")
    if len(shape) > _MAX_AXES:
        raise ValueError(f"{size}, but with {len(shape)} axes, more than the {_MAX_AXES} of a "
                         f"numpy array (at most {_MAX_AXES - 1} sensors)")


def _first(mask: np.ndarray) -> tuple:
    """Index of the first True entry of ``mask`` as a tuple of ints."""
    return tuple(int(v) for v in np.argwhere(mask)[0])


def _check_weights(a: np.ndarray, name: str) -> None:
    """Non-negative finite weights (``0`` = forbidden)."""
    if np.isnan(a).any():
        raise ValueError(f"{name} contains NaN at {_first(np.isnan(a))}")
    if (a < 0).any():
        raise ValueError(f"{name} has a negative entry at {_first(a < 0)}; weights must be >= 0")
    if np.isinf(a).any():
        raise ValueError(f"{name} contains inf at {_first(np.isinf(a))}; weights must be finite")


def _check_log_weights(a: np.ndarray, name: str) -> None:
    """Log-weights: finite or ``-inf`` (forbidden)."""
    if np.isnan(a).any():
        raise ValueError(f"{name} contains NaN at {_first(np.isnan(a))}")
    if np.isposinf(a).any():
        raise ValueError(
            f"{name} contains +inf at {_first(np.isposinf(a))}; a weight must be finite"
        )


def _log(a: np.ndarray) -> np.ndarray:
    with np.errstate(divide="ignore"):
        return np.log(a)


def count_feasible_all_positive(n_rows: int, n_meas) -> int:
    """``|Gamma|`` when every weight is positive (multi-sensor spec eq. 1.7).

    ``|Gamma| = sum_a C(P, a) prod_v N(a, M_v)`` with
    ``N(a, M) = sum_k C(a, k) C(M, k) k!`` the number of partial injections of ``a`` alive
    rows into ``M`` measurements: given the alive set the sensors are independent.

    Parameters
    ----------
    n_rows : int
        ``P``.
    n_meas : sequence of int
        ``(M_1, ..., M_V)``.

    Returns
    -------
    int
        Exact (a Python int).

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019.

    Examples
    --------
    >>> count_feasible_all_positive(4, (4, 4)), count_feasible_all_positive(3, (4, 4, 4))
    (67744, 417176)
    >>> count_feasible_all_positive(4, (16,))      # V = 1: single-sensor eq. (1.3)
    76848
    """
    P = int(n_rows)

    def n_inj(a: int, m: int) -> int:
        return sum(math.comb(a, k) * math.comb(m, k) * math.factorial(k)
                   for k in range(min(a, m) + 1))

    return sum(math.comb(P, a) * math.prod(n_inj(a, int(m)) for m in n_meas)
               for a in range(P + 1))


class MultiSensorProblem:
    """A multi-sensor ranked-assignment problem: ``P`` rows, ``V`` sensors, ``M_v`` each.

    Build one with :meth:`from_eta`, :meth:`from_log_eta`, :meth:`from_factors` or (``V = 1``)
    :meth:`from_assignment_problem`; the constructors validate once, so samplers and oracle
    functions can trust the arrays. Instances are immutable; every array attribute is
    read-only, float64 and C-contiguous.

    Parameters
    ----------
    log_eta_dead : array_like, shape (P,)
        ``ln eta_n(-1)``; ``-inf``: the row cannot be dead.
    log_eta_alive : array_like, shape (P, M_1+1, ..., M_V+1)
        ``ln eta_n(t)``; ``-inf``: forbidden tuple. Index 0 on axis ``v`` is "missed by sensor
        ``v``", index ``j >= 1`` is measurement ``j`` of sensor ``v``.
    log_s, log_theta : optional
        The separable factors of :meth:`from_factors` (both or neither). Prefer the
        ``from_*`` constructors.

    Attributes
    ----------
    n_rows : int
        ``P``.
    n_sensors : int
        ``V``.
    n_meas : tuple of int
        ``(M_1, ..., M_V)``.
    shape : tuple of int
        ``(P, M_1, ..., M_V)``.
    log_eta_dead : ndarray, shape (P,)
    log_eta_alive : ndarray, shape (P, M_1+1, ..., M_V+1)
    log_s : ndarray, shape (P,), or None
        ``ln s_n`` of the separable surrogate (spec eq. 3.2), when built by
        :meth:`from_factors`.
    log_theta : tuple of V ndarrays, shape (P, M_v+1), or None
        ``ln theta_n^(v)(j)`` (spec eq. 3.1), when built by :meth:`from_factors`.

    Notes
    -----
    An assignment ``gamma`` is an int array of shape ``(P, V)`` (batched: ``(n, P, V)``): a
    dead row is all ``-1``; otherwise each entry is ``0`` (missed by that sensor) or
    ``j >= 1``. Mixed rows (some ``-1``, some not) do not exist (spec §1.2). The weight is
    ``w(gamma) = prod_n eta_n(gamma_n)`` on the feasible set (no measurement of any sensor used
    by two rows) and the target ``pi = w / Z`` (spec eq. 1.4). With ``V = 1`` this is the
    single-sensor :class:`~rankedassign.AssignmentProblem` (:meth:`from_assignment_problem`,
    :meth:`to_assignment_problem`).

    References
    ----------
    .. [1] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the
       Generalized Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23), 2019
       (arXiv:1702.08849).
    .. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.multisensor import MultiSensorProblem
    >>> eta_alive = np.ones((2, 2, 3))          # P = 2 rows, M = (1, 2)
    >>> p = MultiSensorProblem.from_eta([0.5, 0.5], eta_alive)
    >>> p.n_rows, p.n_sensors, p.n_meas, p.shape
    (2, 2, (1, 2), (2, 1, 2))
    >>> p.n_feasible()
    34
    >>> gamma = np.array([[1, 2], [0, 1]])      # row 0: z1 of sensor 1, z2 of sensor 2
    >>> float(p.log_weight_of(gamma)), bool(p.is_feasible([[1, 2], [1, 0]]))
    (0.0, False)
    """

    def __init__(self, log_eta_dead, log_eta_alive, log_s=None, log_theta=None):
        d = float_array(log_eta_dead, "log_eta_dead")
        a = float_array(log_eta_alive, "log_eta_alive")
        if a.ndim < 2:
            raise ValueError(
                "log_eta_alive must have shape (P, M_1+1, ..., M_V+1) with at least one "
                f"sensor, got {a.ndim}-D shape {a.shape}"
            )
        P = a.shape[0]
        if d.shape != (P,):
            raise ValueError(
                f"log_eta_dead must have shape (P,) = ({P},) to match log_eta_alive of shape "
                f"{a.shape}, got shape {d.shape}"
            )
        if 0 in a.shape[1:]:
            raise ValueError(
                f"log_eta_alive of shape {a.shape} has an empty sensor axis; axis v has "
                "length M_v + 1 >= 1 (index 0 is 'missed by sensor v')"
            )
        _check_log_weights(d, "log_eta_dead")
        _check_log_weights(a, "log_eta_alive")
        if (log_s is None) != (log_theta is None):
            raise ValueError("log_s and log_theta must be given together or not at all")
        if log_s is not None:
            log_s = float_array(log_s, "log_s")
            if log_s.shape != (P,):
                raise ValueError(f"log_s must have shape (P,) = ({P},), got {log_s.shape}")
            _check_log_weights(log_s, "log_s")
            thetas = []
            if len(log_theta) != a.ndim - 1:
                raise ValueError(
                    f"log_theta must hold one array per sensor (V = {a.ndim - 1}), got "
                    f"{len(log_theta)}"
                )
            for v, th in enumerate(log_theta):
                th = float_array(th, f"log_theta[{v}]")
                if th.shape != (P, a.shape[v + 1]):
                    raise ValueError(
                        f"log_theta[{v}] must have shape (P, M_{v + 1}+1) = "
                        f"({P}, {a.shape[v + 1]}), got {th.shape}"
                    )
                _check_log_weights(th, f"log_theta[{v}]")
                th.setflags(write=False)
                thetas.append(th)
            log_s.setflags(write=False)
            log_theta = tuple(thetas)
        flat = a.reshape(P, math.prod(a.shape[1:]))
        empty = np.isneginf(d) & np.isneginf(flat).all(axis=1)
        if empty.any():
            n = int(np.flatnonzero(empty)[0])
            raise ValueError(
                f"row {n} has no positive weight: it can be neither dead nor alive, so no "
                "assignment is feasible"
            )
        d.setflags(write=False)
        a.setflags(write=False)
        self._log_eta_dead = d
        self._log_eta_alive = a
        self._log_s = log_s
        self._log_theta = log_theta
        self._check_feasible()

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_log_eta(cls, log_eta_dead, log_eta_alive) -> MultiSensorProblem:
        """Build a problem from log-weights (``-inf`` = weight zero = forbidden).

        Parameters
        ----------
        log_eta_dead : array_like, shape (P,)
            ``ln eta_n(-1)``.
        log_eta_alive : array_like, shape (P, M_1+1, ..., M_V+1)
            ``ln eta_n(t)``.

        Returns
        -------
        MultiSensorProblem
            Without separable factors (``log_s`` and ``log_theta`` are ``None``).

        Raises
        ------
        ValueError
            On mismatched shapes, NaN, ``+inf``, or a row that can be neither dead nor alive.
        TypeError
            On non-numeric input.

        Examples
        --------
        >>> p = MultiSensorProblem.from_log_eta([0.0], [[[-1.0, -2.0], [-3.0, -4.0]]])
        >>> p.shape, p.log_s is None
        ((1, 1, 1), True)
        """
        return cls(log_eta_dead, log_eta_alive)

    @classmethod
    def from_eta(cls, eta_dead, eta_alive) -> MultiSensorProblem:
        """Build a problem from the non-negative weights ``eta`` of spec eq. (1.3).

        Parameters
        ----------
        eta_dead : array_like, shape (P,)
            ``eta_n(-1)``, e.g. ``1 - Pbar_S`` (``1 - r_B`` for a newborn row).
        eta_alive : array_like, shape (P, M_1+1, ..., M_V+1)
            ``eta_n(t) = Pbar_S psibar_n(t)``; ``0`` = forbidden tuple.

        Returns
        -------
        MultiSensorProblem

        Raises
        ------
        ValueError
            On mismatched shapes, NaN, negative or infinite weights, or a row whose weights
            are all zero.
        TypeError
            On non-numeric input.

        Examples
        --------
        >>> import numpy as np
        >>> p = MultiSensorProblem.from_eta([0.5], np.full((1, 3), 2.0))   # V = 1, M = 2
        >>> p.n_meas, p.n_feasible()
        ((2,), 4)
        """
        d = float_array(eta_dead, "eta_dead")
        a = float_array(eta_alive, "eta_alive")
        _check_weights(d, "eta_dead")
        _check_weights(a, "eta_alive")
        return cls(_log(d), _log(a))

    @classmethod
    def from_factors(cls, eta_dead, pbar_s, theta, coupling=None) -> MultiSensorProblem:
        """Build a problem from the separable factors of spec §3.1.

        ``eta_n(t) = s_n prod_v theta_n^(v)(t[v]) c_n(t)`` with ``s_n = pbar_s[n]`` and
        ``c = coupling`` (``None``: ``c = 1``, a sensor-separable problem).

        Parameters
        ----------
        eta_dead : array_like, shape (P,)
            ``eta_n(-1)``.
        pbar_s : array_like, shape (P,)
            ``s_n``: ``Pbar_S`` of a persisting row, ``r_B`` of a newborn row.
        theta : sequence of V array_like, shape (P, M_v+1)
            ``theta_n^(v)(0) = 1 - Pbar_D^(v)``, ``theta_n^(v)(j)`` the single-sensor
            likelihood ratio of row ``n`` and measurement ``j`` of sensor ``v`` (spec eq. 3.1).
        coupling : array_like, shape (P, M_1+1, ..., M_V+1), optional
            Non-negative factor ``c_n(t)`` that couples the sensors (a common state makes
            ``psibar_n(t) != prod_v theta_n^(v)(t[v])``).

        Returns
        -------
        MultiSensorProblem
            With ``log_s = ln s`` and ``log_theta = ln theta``: the surrogate of MM-Gibbs is
            ``eta~_n(t) = s_n prod_v theta_n^(v)(t[v])`` (spec eq. 3.2), which equals ``eta``
            when ``coupling`` is ``None``.

        Raises
        ------
        ValueError
            On mismatched shapes, NaN, negative or infinite weights, a row whose weights
            are all zero, or a table ``(P, M_1+1, ..., M_V+1)`` of more than
            :data:`MAX_TABLE_ENTRIES` ``= 2**27`` entries (1 GiB) or more than 63 sensors
            (:func:`check_table_size`, before anything is allocated).
        TypeError
            On non-numeric input or a ``theta`` that is not a sequence.

        Examples
        --------
        >>> p = MultiSensorProblem.from_factors([0.1], [0.9], [[[0.2, 3.0]], [[0.5, 1.0, 2.0]]])
        >>> p.shape
        (1, 1, 2)
        >>> import numpy as np
        >>> np.exp(p.log_eta_alive[0]).round(3).tolist()   # 0.9 * theta1 (x) theta2
        [[0.09, 0.18, 0.36], [1.35, 2.7, 5.4]]
        """
        d = float_array(eta_dead, "eta_dead")
        s = float_array(pbar_s, "pbar_s")
        if isinstance(theta, np.ndarray) or not hasattr(theta, "__len__"):
            raise TypeError(
                "theta must be a sequence of V arrays of shape (P, M_v+1), one per sensor, "
                f"got {type(theta).__name__}"
            )
        if len(theta) == 0:
            raise ValueError("theta must hold at least one sensor's (P, M_v+1) array, got none")
        P = d.shape[0] if d.ndim == 1 else None
        if d.ndim != 1:
            raise ValueError(f"eta_dead must be 1-D with shape (P,), got shape {d.shape}")
        if s.shape != (P,):
            raise ValueError(
                f"pbar_s must have shape (P,) = ({P},) to match eta_dead, got shape {s.shape}"
            )
        thetas = []
        for v, th in enumerate(theta):
            th = float_array(th, f"theta[{v}]")
            if th.ndim != 2 or th.shape[0] != P or th.shape[1] < 1:
                raise ValueError(
                    f"theta[{v}] must have shape (P, M_{v + 1}+1) with P = {P}, got shape "
                    f"{th.shape}"
                )
            thetas.append(th)
        check_table_size(P, [th.shape[1] - 1 for th in thetas])
        _check_weights(d, "eta_dead")
        _check_weights(s, "pbar_s")
        for v, th in enumerate(thetas):
            _check_weights(th, f"theta[{v}]")
        log_s = _log(s)
        log_theta = [_log(th) for th in thetas]
        V = len(thetas)
        shape = (P, *(th.shape[1] for th in thetas))
        # ln eta_n(t) = ln s_n + ln theta^(1) + ... + ln theta^(V) (+ ln c), in this order
        la = np.broadcast_to(log_s.reshape((P,) + (1,) * V), shape).copy()
        for v, lt in enumerate(log_theta):
            idx = [slice(None)] + [None] * V
            idx[v + 1] = slice(None)
            la = la + lt[tuple(idx)]
        if coupling is not None:
            c = float_array(coupling, "coupling")
            if c.shape != shape:
                raise ValueError(
                    f"coupling must have shape (P, M_1+1, ..., M_V+1) = {shape}, got shape "
                    f"{c.shape}"
                )
            _check_weights(c, "coupling")
            la = la + _log(c)
        return cls(_log(d), la, log_s, log_theta)

    @classmethod
    def from_assignment_problem(cls, problem: AssignmentProblem) -> MultiSensorProblem:
        """The ``V = 1`` multi-sensor form of a single-sensor problem.

        ``log_eta_alive[n, 0]`` is row ``n``'s missed weight, ``log_eta_alive[n, j]`` its
        weight of measurement ``j``; a single-sensor ``gamma`` of shape ``(P,)`` is the
        multi-sensor ``gamma[:, None]``. The separable factors are ``s = 1`` and
        ``theta^(1) = eta`` (a one-sensor problem is trivially separable).

        Parameters
        ----------
        problem : AssignmentProblem

        Returns
        -------
        MultiSensorProblem

        Examples
        --------
        >>> from rankedassign import AssignmentProblem
        >>> sp = AssignmentProblem.from_eta([[2.0, 0.5]], [0.2], [0.1])
        >>> mp = MultiSensorProblem.from_assignment_problem(sp)
        >>> mp.shape, mp.n_feasible() == sp.n_feasible()
        ((1, 2), True)
        """
        if not isinstance(problem, AssignmentProblem):
            raise TypeError(
                f"problem must be a rankedassign.AssignmentProblem, got {type(problem).__name__}"
            )
        cc = problem.compact_cost
        M = problem.n_meas
        P = problem.n_rows
        la = np.empty((P, M + 1))
        la[:, 0] = -cc[:, M]
        la[:, 1:] = -cc[:, :M]
        return cls(-cc[:, M + 1], la, np.zeros(P), (la,))

    def to_assignment_problem(self) -> AssignmentProblem:
        """The single-sensor :class:`~rankedassign.AssignmentProblem` of a ``V = 1`` problem.

        Returns
        -------
        AssignmentProblem

        Raises
        ------
        ValueError
            If ``V != 1``.

        Examples
        --------
        >>> p = MultiSensorProblem.from_eta([0.5], [[0.25, 2.0]])
        >>> p.to_assignment_problem().cost.round(4).tolist()
        [[-0.6931, 1.3863, 0.6931]]
        """
        if self.n_sensors != 1:
            raise ValueError(
                f"only a one-sensor problem converts to an AssignmentProblem, this one has "
                f"V = {self.n_sensors} sensors"
            )
        la = self._log_eta_alive
        return AssignmentProblem.from_log_eta(la[:, 1:], la[:, 0], self._log_eta_dead)

    # ------------------------------------------------------------------ properties
    @property
    def n_rows(self) -> int:
        """Number of rows (labels) ``P``."""
        return int(self._log_eta_alive.shape[0])

    @property
    def n_sensors(self) -> int:
        """Number of sensors ``V``."""
        return self._log_eta_alive.ndim - 1

    @property
    def n_meas(self) -> tuple[int, ...]:
        """Measurement counts ``(M_1, ..., M_V)``."""
        return tuple(int(m) - 1 for m in self._log_eta_alive.shape[1:])

    @property
    def shape(self) -> tuple[int, ...]:
        """``(P, M_1, ..., M_V)``."""
        return (self.n_rows, *self.n_meas)

    @property
    def n_tuples(self) -> int:
        """Size of the tuple space ``prod_v (M_v + 1)``."""
        return math.prod(self._log_eta_alive.shape[1:])

    @property
    def log_eta_dead(self) -> np.ndarray:
        """Read-only ``(P,)`` array of ``ln eta_n(-1)`` (``-inf``: the row cannot be dead)."""
        return self._log_eta_dead

    @property
    def log_eta_alive(self) -> np.ndarray:
        """Read-only ``(P, M_1+1, ..., M_V+1)`` array of ``ln eta_n(t)`` (``-inf``: forbidden)."""
        return self._log_eta_alive

    @property
    def log_s(self) -> np.ndarray | None:
        """``ln s_n`` of the separable surrogate, shape ``(P,)``; ``None`` without factors."""
        return self._log_s

    @property
    def log_theta(self) -> tuple[np.ndarray, ...] | None:
        """``ln theta^(v)``, one ``(P, M_v+1)`` array per sensor; ``None`` without factors."""
        return self._log_theta

    @cached_property
    def tuples(self) -> np.ndarray:
        """Every tuple ``t`` of the tuple space, shape ``(prod_v (M_v+1), V)``, int64.

        Row ``k`` is the tuple at flat (C-order) index ``k`` of an ``eta_n`` table, so
        ``log_eta_alive.reshape(P, T)[:, k]`` is the weight of ``tuples[k]``. Read-only.

        Examples
        --------
        >>> import numpy as np
        >>> MultiSensorProblem.from_eta([1.0], np.ones((1, 2, 2))).tuples.tolist()
        [[0, 0], [0, 1], [1, 0], [1, 1]]
        """
        dims = self._log_eta_alive.shape[1:]
        t = np.indices(dims).reshape(len(dims), -1).T
        t = np.ascontiguousarray(t, dtype=np.int64)
        t.setflags(write=False)
        return t

    def eta(self) -> tuple[np.ndarray, np.ndarray]:
        """Return the weights ``(eta_dead (P,), eta_alive (P, M_1+1, ..., M_V+1))``.

        ``exp`` of the log-weights; may overflow to ``inf`` for huge weights, in which case
        work with the log arrays.

        Returns
        -------
        eta_dead : ndarray of float64, shape (P,)
            ``eta_n(-1)``, the weight of row ``n`` being dead (0 where it cannot be).
        eta_alive : ndarray of float64, shape (P, M_1+1, ..., M_V+1)
            ``eta_n(t)`` for every tuple ``t`` (index 0 on axis ``v``: missed by sensor ``v``);
            0 for a forbidden tuple.

        Both are new writable arrays.

        Examples
        --------
        >>> p = MultiSensorProblem.from_eta([0.5], [[0.25, 2.0]])
        >>> [a.tolist() for a in p.eta()]
        [[0.5], [[0.25, 2.0]]]
        """
        with np.errstate(over="ignore"):
            return np.exp(self._log_eta_dead), np.exp(self._log_eta_alive)

    def surrogate(self) -> MultiSensorProblem:
        """The separable surrogate problem of MM-Gibbs (spec eq. 3.2).

        ``eta~_n(-1) = eta_n(-1)``, ``eta~_n(t) = s_n prod_v theta_n^(v)(t[v])``; its target
        is ``pi~``.

        Returns
        -------
        MultiSensorProblem
            With the same factors.

        Raises
        ------
        ValueError
            If the problem has no separable factors (it was not built by
            :meth:`from_factors`).

        Examples
        --------
        >>> import numpy as np
        >>> c = np.ones((1, 2, 2)); c[0, 1, 1] = 3.0
        >>> p = MultiSensorProblem.from_factors([0.1], [1.0], [[[1.0, 2.0]], [[1.0, 2.0]]], c)
        >>> np.exp(p.log_eta_alive[0]).tolist(), np.exp(p.surrogate().log_eta_alive[0]).tolist()
        ([[1.0, 2.0], [2.0, 12.0]], [[1.0, 2.0], [2.0, 4.0]])
        """
        self._require_factors("the surrogate problem")
        P, V = self.n_rows, self.n_sensors
        la = np.broadcast_to(self._log_s.reshape((P,) + (1,) * V),
                             self._log_eta_alive.shape).copy()
        for v, lt in enumerate(self._log_theta):
            idx = [slice(None)] + [None] * V
            idx[v + 1] = slice(None)
            la = la + lt[tuple(idx)]
        return MultiSensorProblem(self._log_eta_dead, la, self._log_s, self._log_theta)

    def _require_factors(self, what: str) -> None:
        if self._log_s is None:
            raise ValueError(
                f"{what} needs the separable factors s and theta (spec §3.1); build the problem "
                "with MultiSensorProblem.from_factors"
            )

    def __repr__(self) -> str:
        return f"MultiSensorProblem(P={self.n_rows}, M={self.n_meas})"

    def __eq__(self, other) -> bool:
        """Equal weights and equal separable factors (both absent, or equal arrays)."""
        if not isinstance(other, MultiSensorProblem):
            return NotImplemented
        same = (self._log_eta_alive.shape == other._log_eta_alive.shape
                and bool(np.array_equal(self._log_eta_dead, other._log_eta_dead))
                and bool(np.array_equal(self._log_eta_alive, other._log_eta_alive)))
        if not same or (self._log_s is None) != (other._log_s is None):
            return False
        if self._log_s is None:
            return True
        return bool(np.array_equal(self._log_s, other._log_s)) and all(
            np.array_equal(a, b) for a, b in zip(self._log_theta, other._log_theta, strict=True))

    def __reduce__(self):
        # rebuild through the validating constructor, so an unpickled problem is read-only too
        return (MultiSensorProblem,
                (self._log_eta_dead, self._log_eta_alive, self._log_s, self._log_theta))

    def __hash__(self) -> int:
        return hash((self._log_eta_alive.shape, self._log_eta_dead.tobytes(),
                     self._log_eta_alive.tobytes()))

    # ------------------------------------------------------------------ assignments
    def all_missed(self) -> np.ndarray:
        """The all-missed assignment: every row the tuple ``(0, ..., 0)``, shape ``(P, V)``.

        Returns
        -------
        ndarray of int64, shape (P, V)
            All zeros (the samplers' default start).

        Examples
        --------
        >>> MultiSensorProblem.from_eta([1.0], [[[1.0]]]).all_missed().tolist()
        [[0, 0]]
        """
        return np.zeros((self.n_rows, self.n_sensors), dtype=np.int64)

    def all_dead(self) -> np.ndarray:
        """The all-dead assignment: every entry ``-1``, shape ``(P, V)``.

        Returns
        -------
        ndarray of int64, shape (P, V)
            All ``-1``.

        Examples
        --------
        >>> MultiSensorProblem.from_eta([1.0], [[[1.0]]]).all_dead().tolist()
        [[-1, -1]]
        """
        return np.full((self.n_rows, self.n_sensors), -1, dtype=np.int64)

    def _as_gamma(self, gamma, name: str = "gamma") -> tuple[np.ndarray, bool]:
        """Validate an ``(n, P, V)`` or ``(P, V)`` integer array; 3-D int64 and a 2-D flag."""
        g = np.asarray(gamma)
        if g.dtype == bool or not (np.issubdtype(g.dtype, np.integer) or g.size == 0):
            if np.issubdtype(g.dtype, np.floating) and g.size and np.all(g == np.round(g)):
                g = g.astype(np.int64)
            else:
                raise TypeError(
                    f"{name} must be an integer array of shape (P, V) or (n, P, V), got dtype "
                    f"{g.dtype}"
                )
        g = g.astype(np.int64, copy=False)
        P, V = self.n_rows, self.n_sensors
        single = g.ndim == 2
        if single:
            g = g[None]
        if g.ndim != 3 or g.shape[1:] != (P, V):
            raise ValueError(
                f"{name} must have shape (P, V) = ({P}, {V}) or (n, P, V) = (n, {P}, {V}), got "
                f"shape {np.shape(gamma)}"
            )
        return g, single

    def _valid_rows(self, g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(in_range (n, P, V), consistent (n, P))``: entries in ``[-1, M_v]``; rows that
        are all ``-1`` or all ``>= 0``."""
        hi = np.asarray(self.n_meas, dtype=np.int64)
        in_range = (g >= -1) & (g <= hi)
        dead = g == -1
        consistent = dead.all(axis=2) | ~dead.any(axis=2)
        return in_range, consistent

    def _check_gamma_values(self, g: np.ndarray, name: str = "gamma") -> None:
        in_range, consistent = self._valid_rows(g)
        if not in_range.all():
            k, n, v = _first(~in_range)
            raise ValueError(
                f"{name}[{k}, {n}, {v}] = {int(g[k, n, v])} is outside [-1, M_{v + 1}] = "
                f"[-1, {self.n_meas[v]}] for sensor {v}"
            )
        if not consistent.all():
            k, n = _first(~consistent)
            raise ValueError(
                f"{name}[{k}, {n}] = {g[k, n].tolist()} mixes -1 with other values: a row is "
                "either dead (every entry -1) or alive (every entry >= 0)"
            )

    def _row_log_weights(self, g: np.ndarray) -> np.ndarray:
        """``ln eta_n(gamma_n)`` for every assignment and row, shape ``(n, P)`` (no 1-1 check)."""
        n, P, V = g.shape
        dims = np.asarray(self._log_eta_alive.shape[1:], dtype=np.int64)
        strides = np.ones(V, dtype=np.int64)
        for v in range(V - 2, -1, -1):
            strides[v] = strides[v + 1] * dims[v + 1]
        dead = g[:, :, 0] == -1 if V else np.zeros((n, P), dtype=bool)
        flat = np.where(dead, 0, (np.maximum(g, 0) * strides).sum(axis=2))
        table = self._log_eta_alive.reshape(P, self.n_tuples)
        alive = table[np.arange(P)[None, :], flat]
        return np.where(dead, self._log_eta_dead[None, :], alive)

    def _reuses_measurement(self, g: np.ndarray) -> np.ndarray:
        """Whether some sensor's measurement is taken by two rows, shape ``(n,)``."""
        n, P, V = g.shape
        out = np.zeros(n, dtype=bool)
        if P < 2:
            return out
        s = np.sort(g, axis=1)
        dup = (s[:, 1:, :] == s[:, :-1, :]) & (s[:, 1:, :] > 0)
        return dup.any(axis=(1, 2))

    def log_weight_of(self, gamma) -> np.ndarray | float:
        """Log-weight ``ln w(gamma) = sum_n ln eta_n(gamma_n)`` of each assignment.

        Parameters
        ----------
        gamma : array_like of int, shape (P, V) or (n, P, V)
            A dead row is all ``-1``; otherwise each entry is ``0`` (missed) or ``j >= 1``.

        Returns
        -------
        ndarray, shape (n,), or float
            The sum accumulated row by row in order ``0..P-1``; ``-inf`` for an infeasible
            assignment (a forbidden option, or a measurement of some sensor used twice).

        Raises
        ------
        TypeError
            If ``gamma`` is not an integer array.
        ValueError
            On a wrong shape, an entry outside ``[-1, M_v]``, or a row mixing ``-1`` with
            other values.

        Examples
        --------
        >>> import numpy as np
        >>> p = MultiSensorProblem.from_eta([0.5, 0.25], np.full((2, 2, 2), 2.0))
        >>> p.log_weight_of([[[1, 1], [-1, -1]], [[1, 0], [0, 1]]]).round(6).tolist()
        [-0.693147, 1.386294]
        >>> float(p.log_weight_of([[1, 0], [1, 1]]))       # z1 of sensor 1 used twice
        -inf
        """
        g, single = self._as_gamma(gamma)
        self._check_gamma_values(g)
        n, P, _ = g.shape
        out = np.zeros(n)
        if P:
            rows = self._row_log_weights(g)
            for i in range(P):  # fixed left-to-right order: reproducible to the last bit
                out += rows[:, i]
            out[self._reuses_measurement(g)] = -np.inf
        return float(out[0]) if single else out

    def cost_of(self, gamma) -> np.ndarray | float:
        """Cost ``-ln w(gamma)`` of each assignment (``+inf`` if infeasible).

        Parameters
        ----------
        gamma : array_like of int, shape (P, V) or (n, P, V)
            Labels, as for :meth:`log_weight_of`: a dead row is all ``-1``, otherwise each
            entry is ``0`` (missed by that sensor) or ``j >= 1`` (its measurement ``j``).

        Returns
        -------
        ndarray of float64, shape (n,), or float
            ``-self.log_weight_of(gamma)``: a float for a single ``(P, V)`` assignment, else
            one entry per assignment; ``+inf`` where an assignment is infeasible.

        Raises
        ------
        TypeError, ValueError
            As :meth:`log_weight_of`.

        Examples
        --------
        >>> p = MultiSensorProblem.from_eta([0.5], [[2.0, 4.0]])
        >>> float(p.cost_of([[1]]))
        -1.3862943611198906
        """
        return -self.log_weight_of(gamma)

    def is_feasible(self, gamma) -> np.ndarray | bool:
        """Whether each assignment is feasible (positive weight, measurements used once).

        Parameters
        ----------
        gamma : array_like of int, shape (P, V) or (n, P, V)

        Returns
        -------
        ndarray of bool, shape (n,), or bool
            Entries outside ``[-1, M_v]`` and rows mixing ``-1`` with other values are
            infeasible, not an error.

        Examples
        --------
        >>> import numpy as np
        >>> p = MultiSensorProblem.from_eta([0.5, 0.0], np.ones((2, 2, 2)))
        >>> p.is_feasible([[[1, 0], [0, 1]], [[1, 0], [-1, -1]], [[1, 0], [1, 1]],
        ...                [[-1, 0], [0, 0]]]).tolist()
        [True, False, False, False]
        """
        g, single = self._as_gamma(gamma)
        in_range, consistent = self._valid_rows(g)
        ok = in_range.all(axis=(1, 2)) & consistent.all(axis=1)
        if g.shape[0] and ok.any():
            ok[ok] = np.isfinite(self.log_weight_of(g[ok]))
        return bool(ok[0]) if single else ok

    # ------------------------------------------------------------------ counting
    def n_feasible(self) -> int:
        """Exact number of feasible (positive-weight) assignments ``|Gamma|``.

        Returns
        -------
        int
            A Python int.

        Raises
        ------
        ValueError
            When some weight is zero and the exact count would need more states or work
            than the counting DP allows (the message states the size).

        Notes
        -----
        When every weight is positive, spec eq. (1.7) (:func:`count_feasible_all_positive`).
        Otherwise an exact integer DP over rows whose state is the set of measurements (of all
        sensors) used so far, keeping only reachable sets: row ``n`` keeps the set (dead or
        all-missed, if allowed) or adds the measurements of an allowed tuple disjoint from it.

        Examples
        --------
        >>> from rankedassign.multisensor import synthetic
        >>> synthetic.uniform(4, (4, 4)).n_feasible()
        67744
        """
        P = self.n_rows
        d = np.isfinite(self._log_eta_dead)
        a = np.isfinite(self._log_eta_alive.reshape(P, self.n_tuples))
        if d.all() and a.all():
            return count_feasible_all_positive(P, self.n_meas)
        return self._count_dp(d, a)

    def _count_dp(self, d: np.ndarray, a: np.ndarray) -> int:
        P = self.n_rows
        tuples = self.tuples
        used = np.zeros(self.n_tuples, dtype=bool)  # measurements some row can take
        for n in range(P):
            used |= a[n]
        # bits only for measurements some allowed tuple uses
        bit = 0
        bits_of = []
        for v, m in enumerate(self.n_meas):
            reach = np.zeros(m + 1, dtype=bool)
            reach[tuples[used, v]] = True
            reach[0] = False
            b = np.full(m + 1, -1, dtype=np.int64)
            b[np.flatnonzero(reach)] = bit + np.arange(int(reach.sum()))
            bit += int(reach.sum())
            bits_of.append(b)
        if bit > 62:
            raise ValueError(
                f"problem too large to count exactly: {bit} reachable measurements with "
                "forbidden tuples exceed the 62-bit state of the counting DP"
            )
        masks = np.zeros(self.n_tuples, dtype=np.int64)
        for v, b in enumerate(bits_of):
            col = tuples[:, v]
            masks |= np.where(col > 0, np.left_shift(1, np.maximum(b[col], 0)), 0)
        bound = count_feasible_all_positive(P, self.n_meas)
        dtype = np.int64 if bound < 2**62 else object
        states = np.zeros(1, dtype=np.int64)
        counts = np.ones(1, dtype=dtype)
        work = 0
        for n in range(P):
            keep = int(d[n]) + int(a[n, 0])
            opts = masks[a[n]]
            opts = opts[opts != 0]
            work += states.size * (opts.size + 1)
            if work > _COUNT_MAX_WORK:
                raise ValueError(
                    f"problem too large to count exactly: the counting DP over used "
                    f"measurements needs more than {_COUNT_MAX_WORK:.0e} steps"
                )
            new_s = [states] if keep else []
            new_c = [counts * keep] if keep else []
            for m in opts:
                free = (states & m) == 0
                new_s.append(states[free] | m)
                new_c.append(counts[free])
            if not new_s:
                return 0
            s = np.concatenate(new_s)
            c = np.concatenate(new_c)
            states, inv = np.unique(s, return_inverse=True)
            counts = np.zeros(states.size, dtype=dtype)
            np.add.at(counts, inv, c)
            if states.size > _COUNT_MAX_STATES:
                raise ValueError(
                    f"problem too large to count exactly: more than {_COUNT_MAX_STATES} "
                    "reachable sets of used measurements"
                )
        return int(counts.sum())

    def _check_feasible(self) -> None:
        """Raise if no assignment is feasible.

        A row with a dead or all-missed option uses no measurement, so only the rows that must
        detect can conflict; a depth-first search gives them pairwise disjoint tuples.
        """
        P = self.n_rows
        if P == 0:
            return
        flat = self._log_eta_alive.reshape(P, self.n_tuples)
        must = ~(np.isfinite(self._log_eta_dead) | np.isfinite(flat[:, 0]))
        if not must.any():
            return
        tuples = self.tuples
        rows = np.flatnonzero(must)
        options = [[tuple((v, int(j)) for v, j in enumerate(tuples[k]) if j > 0)
                    for k in np.flatnonzero(np.isfinite(flat[n]))] for n in rows]
        order = sorted(range(len(rows)), key=lambda i: len(options[i]))

        def search(i: int, taken: frozenset) -> bool:
            if i == len(order):
                return True
            for det in options[order[i]]:
                if taken.isdisjoint(det) and search(i + 1, taken | frozenset(det)):
                    return True
            return False

        if not search(0, frozenset()):
            raise ValueError(
                f"no feasible assignment: rows {rows.tolist()} can be neither dead nor missed by "
                "every sensor and cannot all be given tuples with distinct measurements"
            )
