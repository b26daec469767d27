"""The truncation contract and one association class per truncation, for every filter.

A filter asks an association one of two kind-agnostic questions about one problem (an
:class:`~rankedassign.AssignmentProblem` of one sensor or a
:class:`~rankedassign.multisensor.MultiSensorProblem` of several):

* *marginals* — ``assoc(problem, rng)``: the association marginals the LMB filters update with
  (:class:`~rankedassign.tracking.marginals.AssociationResult` for one sensor,
  :class:`~rankedassign.tracking.marginals.MultiSensorAssociationResult` for several);
* *hypotheses* — ``assoc.hypotheses(problem, budget, rng)``: the unique assignments a δ-GLMB
  component keeps, for the component's count ``T_h = budget``
  (:class:`~rankedassign.tracking.marginals.Hypotheses`).

The same class serves every filter and sensor count: :class:`OriginalGibbs`,
:class:`ShortChainGibbs`, :class:`HerdedGibbs`, :class:`Murty`, :class:`Exact`, :class:`LBP`.
``method=`` means only the multi-sensor row conditional (:data:`MULTISENSOR_METHODS`, default
:data:`DEFAULT_METHOD`, the samplers' own). What a filter cannot use is refused by
:func:`check_truncation` with the reason, and the hypotheses of an object of one's own are
checked by :func:`check_hypotheses`; both are the only places that do so. A truncation that
the δ-GLMB filters can run for all components in one compiled call says so by
:meth:`Association.batch_plan`; the filters never ask which class they hold.

The ``MultiSensor*`` classes of earlier releases (:class:`MultiSensorOriginalGibbs`,
:class:`MultiSensorShortChainGibbs`, :class:`MultiSensorHerdedGibbs`, :class:`MultiSensorExact`)
are deprecated aliases: constructing one emits a :class:`DeprecationWarning` naming the class
that replaces it; they keep their ``repr`` and their default ``method="exact"``, so that the
numbers of code written for them do not change during the release they remain.
"""

from __future__ import annotations

import types
import warnings
from typing import NamedTuple

import numpy as np

import oracle

from ..engine.herding import DEFAULT_MAX_KEYS, Herding
from ..kinds import kind_of
from ..rows import unique_rows
from ..samplers import sample_herded, sample_original, sample_short_chains, sample_tempered
from ..single.lbp import LBP_MAX_ITER, LBP_TOL, check_lbp_settings, lbp_marginals
from ..validation import check_choice, check_int, check_optional_int
from .marginals import (
    MARGINALS,
    AssociationResult,
    Hypotheses,
    MultiSensorAssociationResult,
    multisensor_marginals,
    single_marginals,
    split_collapsed,
)

__all__ = [
    "DEFAULT_METHOD",
    "EXACT_LIMIT",
    "MULTISENSOR_METHODS",
    "GLMB_METHODS",
    "Association",
    "BATCH_METHODS",
    "BatchPlan",
    "Exact",
    "HerdedGibbs",
    "LBP",
    "LBPConvergenceWarning",
    "Murty",
    "MultiSensorAssociation",
    "MultiSensorExact",
    "MultiSensorHerdedGibbs",
    "MultiSensorOriginalGibbs",
    "MultiSensorShortChainGibbs",
    "OriginalGibbs",
    "ShortChainGibbs",
    "TemperedGibbs",
    "association_name",
    "check_hypotheses",
    "check_truncation",
    "truncate",
]

#: Implementations of Murty's method (``backend=`` of :class:`Murty` and :func:`oracle.murty`).
MURTY_BACKENDS = ("numba", "scipy")
#: Multi-sensor row conditionals (``method=`` of the sampler associations and of
#: :func:`rankedassign.sample_original`).
MULTISENSOR_METHODS = ("exact", "mm", "mm-fixed", "componentwise")
#: The one default ``method``: the samplers' (:func:`rankedassign.sample_original`).
DEFAULT_METHOD = "mm"
#: Row kernels a δ-GLMB component can be truncated with. The sensor-component-wise kernel
#: samples the collapsed target, whose all-missed row stands for "dead or missed": it cannot
#: tell a child's dead rows from its missed ones.
GLMB_METHODS = ("exact", "mm", "mm-fixed")
#: Largest enumeration :class:`Exact` runs on one δ-GLMB component.
EXACT_LIMIT = 200_000
#: Row conditionals the multi-sensor δ-GLMB filter's compiled path runs for all components
#: at once (:meth:`Association.batch_plan`). ``"mm-fixed"`` is left to the per-component path:
#: its dead probability sums a row's factors over the component's own columns and takes their
#: logarithm, and only the sampler's own numpy operations on the component's problem give
#: those bits.
BATCH_METHODS = ("exact", "mm")
#: The filters' two kinds of problems (the ``sensors`` attribute of an association).
SENSORS = ("single-sensor", "multi-sensor")


class BatchPlan(NamedTuple):
    """How a δ-GLMB filter may run a truncation for all components at once.

    Attributes
    ----------
    chains : bool
        The truncation is the chains of :class:`OriginalGibbs` or :class:`ShortChainGibbs`
        with the compiled path's readings (start all missed, the default stall and stale
        rules, the numba backend), so one compiled call runs every component's chains.
    random_scan : bool
        The chains' row order is random (else systematic).
    tau_stall, tau_stale : int
        Their rules (0 disables one).
    start_alone : bool
        A count ``T_h <= 1`` keeps the chains' start state alone (every row missed), without
        building the component's problem.
    ranked : bool
        Murty's ``k`` best (``k >= 1``) or every assignment (``k = 0``) of every component in
        compiled loops over the components.
    k : int
        See ``ranked``.
    marginal_chains : tuple of (int, int) or None
        With ``chains``: the chains and sweeps per chain of one call ``assoc(problem, rng)``
        (the marginals question) when its marginals are the truncated ones, so that the LMB
        filter's cluster path may run the calls of many problems in one compiled call; None
        otherwise.
    method : str or None
        With ``chains`` for the multi-sensor filter: the row conditional the compiled path
        runs, one of :data:`BATCH_METHODS`; None for one sensor.
    """

    chains: bool = False
    random_scan: bool = False
    tau_stall: int = 0
    tau_stale: int = 0
    start_alone: bool = False
    ranked: bool = False
    k: int = 0
    marginal_chains: tuple | None = None
    method: str | None = None


def association_name(association) -> str:
    """How messages name an association: a function by its name, an object by its class.

    Parameters
    ----------
    association : object

    Returns
    -------
    str

    Examples
    --------
    >>> association_name(Exact()), association_name(len)
    ('Exact', 'len')
    """
    if isinstance(association, (types.FunctionType, types.MethodType,
                                types.BuiltinFunctionType)):
        return association.__qualname__
    return type(association).__name__


def _is_multi(problem) -> bool:
    return kind_of(problem).name == "multisensor"


# ------------------------------------------------------------------------------ the contract
class Association:
    """Base class of association methods: marginals ``assoc(problem, rng)`` and, for the
    δ-GLMB filters, ``assoc.hypotheses(problem, budget, rng)``.

    Subclass it (or pass any callable with that signature) to plug a new method into
    :class:`~rankedassign.tracking.LMBFilter`: return the marginals ``beta`` of shape
    ``(P, M + 2)`` and the accounting. A forbidden pair (cost ``+inf``, outside the gate) must
    have marginal 0; the filter refuses anything else. ``rng`` is a
    :class:`numpy.random.Generator` spawned for this problem alone. Give it a method
    ``hypotheses(problem, budget, rng)`` returning
    :class:`~rankedassign.tracking.Hypotheses` to plug it into the δ-GLMB filters
    (:func:`check_hypotheses` says what is checked).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking import Association, AssociationResult
    >>> from rankedassign.tracking import marginals_from_hypotheses
    >>> class Best(Association):        # the single best hypothesis (a point estimate)
    ...     def __call__(self, problem, rng):
    ...         from scipy.optimize import linear_sum_assignment
    ...         C = np.where(np.isinf(problem.cost), 1e300, problem.cost)
    ...         _, cols = linear_sum_assignment(C)
    ...         beta = marginals_from_hypotheses(problem, cols[None, :])
    ...         return AssociationResult(beta, 1, 0, 0, 1)
    >>> from rankedassign import AssignmentProblem
    >>> p = AssignmentProblem.from_eta([[3.0]], [1.0], [1.0])
    >>> Best()(p, None).beta.tolist()
    [[1.0, 0.0, 0.0]]
    """

    name = "association"
    #: The problems it solves: ``"single-sensor"``, ``"multi-sensor"`` or ``"any"`` (the
    #: library's truncations); :func:`check_truncation` refuses the other kind.
    sensors = "single-sensor"
    #: True for the library's truncations, whose hypotheses come from its own samplers and
    #: searches; the hypotheses of any other object are checked by :func:`check_hypotheses`.
    validated_output = False

    def __call__(self, problem, rng):  # pragma: no cover
        raise NotImplementedError

    def cannot(self, sensors: str, need: str):
        """Why this association cannot serve a filter, or None if it can.

        Parameters
        ----------
        sensors : {"single-sensor", "multi-sensor"}
            The filter's problems.
        need : {"marginals", "hypotheses"}
            What the filter asks (the LMB filters marginals, the δ-GLMB filters hypotheses).

        Returns
        -------
        tuple of (type, str) or None
            The exception class and the reason, for :func:`check_truncation`.

        Examples
        --------
        >>> Exact().cannot("multi-sensor", "hypotheses") is None
        True
        >>> LBP().cannot("single-sensor", "hypotheses")[0].__name__
        'TypeError'
        """
        if self.sensors not in ("any", sensors):
            return TypeError, (f"it solves {self.sensors} problems only (its sensors "
                               f"attribute)")
        if need == "hypotheses" and not callable(getattr(self, "hypotheses", None)):
            return TypeError, _MARGINALS_ONLY
        return None

    def batch_plan(self, sensors: str) -> BatchPlan | None:
        """How the δ-GLMB filter of ``sensors`` may batch this truncation (None: per problem).

        Parameters
        ----------
        sensors : {"single-sensor", "multi-sensor"}

        Returns
        -------
        BatchPlan or None

        Examples
        --------
        >>> ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10).batch_plan("single-sensor").chains
        True
        >>> Association().batch_plan("single-sensor") is None
        True
        """
        return None


class MultiSensorAssociation(Association):
    """Base class of an association of one's own that solves multi-sensor problems only.

    ``assoc(problem, rng) -> MultiSensorAssociationResult``; the library's truncations serve
    both kinds and do not derive from it.
    """

    name = "multisensor-association"
    sensors = "multi-sensor"


_MARGINALS_ONLY = (
    "it returns association marginals only, which suit the LMB filters: a δ-GLMB filter keeps "
    "each hypothesis as a component and cannot be rebuilt from marginals (give it a method "
    "hypotheses(problem, budget, rng), or use OriginalGibbs, ShortChainGibbs, HerdedGibbs, "
    "Murty or Exact)")


def check_truncation(association, filter_name: str, sensors: str, need: str) -> None:
    """Refuse an association a filter cannot use, with the reason: the one place that does.

    Parameters
    ----------
    association : object
        The filter's association.
    filter_name : str
        The filter, for the message.
    sensors : {"single-sensor", "multi-sensor"}
        The filter's problems.
    need : {"marginals", "hypotheses"}
        ``"marginals"`` (the LMB filters call ``association(problem, rng)``) or
        ``"hypotheses"`` (the δ-GLMB filters call ``association.hypotheses(problem, budget,
        rng)``).

    Raises
    ------
    TypeError
        If it cannot be called as the filter needs, solves the other kind of problem, or gives
        marginals only to a δ-GLMB filter.
    ValueError
        If one of its settings does not suit the filter (a multi-sensor row conditional that
        cannot tell dead rows from missed ones, in a δ-GLMB filter).

    Examples
    --------
    >>> check_truncation(LBP(), "GLMBFilter", "single-sensor", "hypotheses")
    Traceback (most recent call last):
    ...
    TypeError: GLMBFilter cannot use LBP: it returns association marginals only, which suit the \
LMB filters: a δ-GLMB filter keeps each hypothesis as a component and cannot be rebuilt from \
marginals (give it a method hypotheses(problem, budget, rng), or use OriginalGibbs, \
ShortChainGibbs, HerdedGibbs, Murty or Exact)
    """
    check_choice(sensors, "sensors", SENSORS)
    check_choice(need, "need", ("marginals", "hypotheses"))
    who = association_name(association)
    cannot = getattr(association, "cannot", None)
    if callable(cannot):  # the library's associations and subclasses of Association
        why = cannot(sensors, need)
        if why is not None:
            exc, reason = why
            raise exc(f"{filter_name} cannot use {who}: {reason}")
        if need == "marginals" or not callable(getattr(association, "hypotheses", None)):
            _check_callable(association)
        return
    # any other object: a function, or a class of one's own with the protocol's methods
    if need == "hypotheses" and callable(getattr(association, "hypotheses", None)):
        kind = getattr(association, "sensors", sensors)
    else:
        _check_callable(association)
        kind = getattr(association, "sensors", sensors)
        if need == "hypotheses" and kind in ("any", sensors):
            raise TypeError(f"{filter_name} cannot use {who}: {_MARGINALS_ONLY}")
    if kind not in ("any", sensors):
        raise TypeError(f"{filter_name} cannot use {who}: it solves {kind} problems only (its "
                        "sensors attribute)")


def _check_callable(association) -> None:
    if not callable(association):
        raise TypeError(
            f"association must be callable as association(problem, rng), got "
            f"{type(association).__name__}"
        )


def truncate(association, problem, budget: int, rng=None, caller: str | None = None
             ) -> Hypotheses:
    """Truncate one component's problem with ``association`` and the count ``budget = T_h``.

    Parameters
    ----------
    association : OriginalGibbs, ShortChainGibbs, HerdedGibbs, Murty, Exact or object
        The library's truncations, or any object with a method
        ``hypotheses(problem, budget, rng)`` returning :class:`Hypotheses` (or anything with
        ``assignments`` and ``costs``).
    problem : AssignmentProblem or MultiSensorProblem
    budget : int
        The component's count ``T_h >= 0`` (spec §2.2): the samplers get ``T_h − 1``
        observations (see :class:`~rankedassign.tracking.GLMBFilter`), Murty
        ``k = max(T_h, 1)``; :class:`Exact` ignores it.
    rng : optional
        Anything :func:`numpy.random.default_rng` accepts.
    caller : str, optional
        The filter that asks (``"GLMBFilter"``), named first in the messages about a custom
        truncation's output.

    Returns
    -------
    Hypotheses
        ``assignments`` of shape ``(n, P)`` (one sensor) or ``(n, P, V)``, and their costs.

    Raises
    ------
    TypeError
        If the association cannot supply hypotheses.
    ValueError
        If :class:`Exact` meets a problem with more than :data:`EXACT_LIMIT` assignments (and
        has no fallback), or a custom association returns bad hypotheses
        (:func:`check_hypotheses`).

    Examples
    --------
    >>> from rankedassign import AssignmentProblem
    >>> p = AssignmentProblem.from_eta([[3.0]], [1.0], [1.0])
    >>> truncate(Exact(), p, 0).assignments.tolist()
    [[0], [1], [2]]
    >>> truncate(Murty(5), p, 2).assignments.tolist()   # k = T_h = 2
    [[0], [1]]
    """
    budget = check_int(budget, "budget")
    method = getattr(association, "hypotheses", None)
    if not callable(method):
        raise TypeError(f"cannot truncate with {association_name(association)}: "
                        f"{_MARGINALS_ONLY}")
    res = method(problem, budget, rng)
    if getattr(association, "validated_output", False):
        return res
    return check_hypotheses(association, problem, res, caller)


def check_hypotheses(association, problem, res, caller: str | None = None) -> Hypotheses:
    """Check the hypotheses a truncation of one's own returned: the one place that does.

    Every filter that keeps hypotheses (both δ-GLMB filters) reaches this function through
    :func:`truncate`. The rule of :mod:`rankedassign.validation` holds: the wrong kind of value
    is a ``TypeError``, a value of the right kind out of range a ``ValueError``, and every
    message names the truncation, the field and, where there is one, the entry.

    Parameters
    ----------
    association : object
        The truncation (named in the messages).
    problem : AssignmentProblem or MultiSensorProblem
        The problem it was given.
    res : object
        What it returned: anything with ``assignments`` (integers, shape ``(n, P)``, or
        ``(n, P, V)`` for a multi-sensor problem, ``n >= 1``) and ``costs`` (shape ``(n,)``),
        optionally ``sweeps`` and ``row_updates`` (ints).
    caller : str, optional
        The filter that asked, named first in the messages.

    Returns
    -------
    Hypotheses
        The assignments as int64 and their exact costs (recomputed from the problem: the
        given ones must agree to 1e-9).

    Raises
    ------
    TypeError
        If ``res`` has no ``assignments`` and ``costs`` (a plain tuple, an int), the
        assignments are not integers (floats, bools, strings), the costs not real numbers, or
        ``sweeps`` / ``row_updates`` not ints.
    ValueError
        On a wrong shape, an entry out of range, a NaN cost, an infeasible or repeated
        assignment, or costs that are not those of the assignments.

    Examples
    --------
    >>> from rankedassign import AssignmentProblem
    >>> p = AssignmentProblem.from_eta([[3.0]], [1.0], [1.0])
    >>> check_hypotheses("mine", p, Hypotheses([[0], [0]], [0.0, 0.0]))
    Traceback (most recent call last):
    ...
    ValueError: association str returned duplicate assignments (a GLMB component is made of \
unique ones)
    >>> check_hypotheses("mine", p, (np.array([[0]]), np.zeros(1)), "GLMBFilter")
    Traceback (most recent call last):
    ...
    TypeError: GLMBFilter: association str returned a tuple from hypotheses(problem, budget, \
rng), not hypotheses: return Hypotheses(assignments, costs) (an object with the attributes \
assignments and costs)
    """
    who = association_name(association)
    head = (f"{caller}: " if caller else "") + f"association {who} returned"
    if not (hasattr(res, "assignments") and hasattr(res, "costs")):
        kind = type(res).__name__
        article = "an" if kind[:1].lower() in "aeiou" else "a"
        raise TypeError(f"{head} {article} {kind} from hypotheses(problem, budget, rng), "
                        "not hypotheses: return Hypotheses(assignments, costs) (an object with "
                        "the attributes assignments and costs)")
    try:
        a = np.asarray(res.assignments)
        c = np.asarray(res.costs)
    except ValueError:  # numpy: "inhomogeneous shape"
        raise ValueError(f"{head} ragged assignments or costs") from None
    multi = _is_multi(problem)
    P = problem.n_rows
    shape = (P, problem.n_sensors) if multi else (P,)
    want = "(n >= 1, " + ", ".join(str(s) for s in shape) + ")"
    if a.ndim != 1 + len(shape) or a.shape[1:] != shape or a.shape[0] == 0:
        raise ValueError(f"{head} assignments of shape {a.shape}, expected {want}")
    if a.dtype.kind not in "iu":
        # a float is refused even when integral: a truncation that computes its columns in
        # floating point can round them anywhere
        raise TypeError(f"{head} assignments of dtype {a.dtype}, expected integer column "
                        f"indices (e.g. {a.reshape(-1)[:3].tolist()}...)")
    if c.dtype.kind not in "iuf":
        raise TypeError(f"{head} costs of dtype {c.dtype}, expected real numbers")
    if c.shape != (a.shape[0],):
        raise ValueError(f"{head} costs of shape {c.shape}, expected ({a.shape[0]},), one per "
                         "assignment")
    c = c.astype(np.float64)
    if np.isnan(c).any():
        raise ValueError(f"{head} a NaN cost (costs[{int(np.flatnonzero(np.isnan(c))[0])}])")
    # per sensor -1 (dead), 0 (missed) or a measurement 1..M_v; one sensor: a column of the
    # P x (M + 2P) matrix
    if multi:
        lo = np.full(shape[-1], -1, dtype=np.int64)
        hi = np.asarray(problem.n_meas, dtype=np.int64)
    else:
        lo = np.zeros(1, dtype=np.int64)
        hi = np.full(1, problem.n_meas + 2 * P - 1, dtype=np.int64)
    lo = np.broadcast_to(lo, a.shape[-1:])
    hi = np.broadcast_to(hi, a.shape[-1:])
    bad = (a < lo) | (a > hi)
    if bad.any():
        at = tuple(int(i) for i in np.argwhere(bad)[0])
        v = at[-1]
        where = f"row {at[1]}" + (f", sensor {v}" if multi else "")
        raise ValueError(f"{head} an entry out of range: assignments[{', '.join(map(str, at))}] "
                         f"= {int(a[at])} ({where}), expected {int(lo[v])}..{int(hi[v])}")
    a = a.astype(np.int64)
    if unique_rows(a.reshape(a.shape[0], -1)).shape[0] != a.shape[0]:
        raise ValueError(f"{head} duplicate assignments (a GLMB component is made of unique "
                         "ones)")
    feasible = problem.is_feasible(a)
    if not feasible.all():
        raise ValueError(f"{head} an infeasible assignment (assignments[{int(np.argmin(feasible))}]"
                         ": a measurement used twice or a pair outside the gate)")
    exact = -problem.log_weight_of(a) if multi else problem.cost_of(a)
    if not np.allclose(c, exact, rtol=1e-9, atol=1e-9):
        raise ValueError(f"{head} costs that are not those of its assignments")
    sweeps = check_int(getattr(res, "sweeps", 0), f"sweeps of association {who}'s hypotheses")
    row_updates = check_int(getattr(res, "row_updates", 0),
                            f"row_updates of association {who}'s hypotheses")
    return Hypotheses(a, exact, sweeps, row_updates)


# ------------------------------------------------------------------------------ the classes
def _check_marginals(marginals):
    return check_choice(marginals, "marginals", MARGINALS)


class _Sampled(Association):
    """What the sampler truncations share: the marginals, the method, the sampler options."""

    sensors = "any"
    validated_output = True
    #: ``method`` a bare construction uses (the deprecated aliases keep their own).
    _default_method = DEFAULT_METHOD

    def _settings(self, marginals, method, options):
        self.marginals = _check_marginals(marginals)
        if method is None:
            method = self._default_method
        self.method = check_choice(method, "method", MULTISENSOR_METHODS)
        self.options = dict(options)

    def _options(self, problem) -> dict:
        """The sampler's keyword arguments: ``method`` on a multi-sensor problem only."""
        if _is_multi(problem):
            return {"method": self.method, **self.options}
        return self.options

    def _extra(self) -> str:
        out = "" if self.method == self._default_method else f", method={self.method!r}"
        out += "" if self.marginals == "truncated" else f", marginals={self.marginals!r}"
        return out + "".join(f", {k}={v!r}" for k, v in self.options.items())

    def _result(self, problem, res):
        """Marginals of a sampler's result, of the problem's kind."""
        if _is_multi(problem):
            dead, tup = multisensor_marginals(problem, res.assignments, res.costs,
                                              self.marginals)
            if self.method == "componentwise" and self.marginals == "truncated":
                dead, tup = split_collapsed(problem, dead, tup)
            return MultiSensorAssociationResult(
                dead=dead, tuples=tup, invocations=1, sweeps=int(res.n_observations),
                row_updates=int(res.n_row_updates), n_unique=int(len(res.costs)))
        beta = single_marginals(problem, res.assignments, res.costs, self.marginals)
        return AssociationResult(
            beta=beta, invocations=1, sweeps=int(res.n_observations),
            row_updates=int(res.n_row_updates), n_unique=int(len(res.costs)))

    def cannot(self, sensors: str, need: str):
        if need == "hypotheses" and sensors == "multi-sensor" and self.method not in GLMB_METHODS:
            return ValueError, (
                f"the δ-GLMB filters truncate with method in {GLMB_METHODS}, got "
                f"{self.method!r}: the component-wise kernel samples the collapsed target, whose "
                "all-missed row stands for dead or missed, so a child's dead rows cannot be told "
                "from its missed ones")
        return None

    def _chain_plan(self, sensors: str, tau_stall, tau_stale, call=None) -> BatchPlan:
        """The chains' plan: compiled with the kernels' readings (for several sensors with a
        row conditional of :data:`BATCH_METHODS`); ``call`` is ``(chains, sweeps per chain)``
        of one marginals call."""
        multi = sensors == "multi-sensor"
        if multi and self.method not in BATCH_METHODS:
            return BatchPlan(start_alone=True)
        opts = dict(self.options)
        if opts.pop("stall", "global-consecutive") != "global-consecutive" or \
                opts.pop("stale", "consecutive") != "consecutive":
            return BatchPlan(start_alone=True)
        opts.pop("workers", None)  # the result does not depend on the threads
        scan = opts.pop("scan", "systematic")
        if (opts.pop("start", "all_missed") != "all_missed"
                or opts.pop("backend", "numba") != "numba"
                or scan not in ("systematic", "random") or opts):
            return BatchPlan(start_alone=True)
        if multi:  # the δ-GLMB question only: the multi-sensor LMB filter asks per problem
            return BatchPlan(chains=True, random_scan=scan == "random",
                             tau_stall=tau_stall or 0, tau_stale=tau_stale or 0,
                             start_alone=True, method=self.method)
        return BatchPlan(chains=True, random_scan=scan == "random", tau_stall=tau_stall or 0,
                         tau_stale=tau_stale or 0, start_alone=True,
                         marginal_chains=call if self.marginals == "truncated" else None)


class OriginalGibbs(_Sampled):
    """The original long-chain Gibbs sampler (Vo, Vo & Hoang 2017; Vo, Vo & Beard 2019).

    One chain of ``n_obs`` observations on a problem of one sensor or several.

    Parameters
    ----------
    n_obs : int
        Observations (full sweeps) per call (the paper: 10 000).
    method : {"exact", "mm", "mm-fixed", "componentwise"}, optional
        The multi-sensor row conditional of :func:`rankedassign.sample_original` (Alg. 1,
        MM-Gibbs with the exclusion-aware or the fixed proposal, sensor-component-wise; default
        :data:`DEFAULT_METHOD`); ignored on a single-sensor problem. The component-wise kernel
        samples the collapsed target (spec §1.6), whose all-missed tuple stands for "dead or
        missed"; its truncated marginals split that mass ``η(−1) : η(0, ..., 0)``.
    marginals : {"truncated", "rao-blackwell"}, optional
        How the unique hypotheses become association marginals
        (:func:`~rankedassign.tracking.marginals_from_hypotheses`); ``"truncated"`` is the
        paper's construction.
    **sampler_options
        Passed to :func:`rankedassign.sample_original` (e.g. ``start``, ``scan``, ``backend``).

    Examples
    --------
    >>> from rankedassign.tracking import OriginalGibbs
    >>> OriginalGibbs(10_000)
    OriginalGibbs(10000)
    >>> OriginalGibbs(10_000, method="exact")
    OriginalGibbs(10000, method='exact')
    """

    name = "original"

    def __init__(self, n_obs: int, *, method: str | None = None, marginals: str = "truncated",
                 **sampler_options):
        self.n_obs = check_int(n_obs, "n_obs", minimum=1)
        self._settings(marginals, method, sampler_options)

    def __repr__(self):
        return f"{type(self).__name__}({self.n_obs}{self._extra()})"

    def __call__(self, problem, rng):
        res = sample_original(problem, self.n_obs, rng=rng, **self._options(problem))
        return self._result(problem, res)

    def budget(self, counts: np.ndarray):
        """Chains and sweeps per chain of every component for its count ``T_h``.

        ``T_h`` counts stored solutions with the start state (Vo's ``T``, spec A20), so the
        chain gets ``T_h − 1`` observations, at most ``n_obs``: one chain of
        ``min(T_h − 1, n_obs)`` sweeps. A count of 0 or 1 gives the start state alone.

        Parameters
        ----------
        counts : ndarray of int64, shape (H,)

        Returns
        -------
        chains, length : ndarray of int64, shape (H,)

        Examples
        --------
        >>> import numpy as np
        >>> [x.tolist() for x in OriginalGibbs(500).budget(np.array([0, 1, 2, 1000]))]
        [[0, 0, 1, 1], [0, 0, 1, 500]]
        """
        n_obs = np.maximum(counts - 1, 0)
        length = np.minimum(n_obs, self.n_obs)
        return (length > 0).astype(np.int64), length.astype(np.int64)

    def hypotheses(self, problem, budget: int, rng) -> Hypotheses:
        """The δ-GLMB truncation of one component's problem with the count ``budget = T_h``.

        Parameters
        ----------
        problem : AssignmentProblem or MultiSensorProblem
        budget : int
            The component's count ``T_h >= 0`` (:meth:`budget`).
        rng : optional
            Anything :func:`numpy.random.default_rng` accepts.

        Returns
        -------
        Hypotheses

        Examples
        --------
        >>> from rankedassign import synthetic
        >>> OriginalGibbs(1000).hypotheses(synthetic.random(rng=0), 51, rng=0).sweeps
        50
        """
        _, length = self.budget(np.array([budget]))
        res = sample_original(problem, int(length[0]), rng=rng, **self._options(problem))
        return Hypotheses(res.assignments, res.costs, int(res.n_observations),
                          int(res.n_row_updates))

    def batch_plan(self, sensors: str) -> BatchPlan | None:
        # a call is sample_original(problem, n_obs): one chain of n_obs sweeps, no rules
        return self._chain_plan(sensors, None, None, (1, self.n_obs))


class ShortChainGibbs(_Sampled):
    """The short-chain sampler with stall/stale termination (Trezza et al. 2023).

    Parameters
    ----------
    n_chains, chain_length : int
        ``N_S`` chains of ``N_C`` observations (the paper: 400 × 25).
    tau_stall, tau_stale : int or None
        Termination thresholds (the paper: 5 and 10); None disables a rule.
    method : {"exact", "mm", "mm-fixed", "componentwise"}, optional
        The multi-sensor row conditional (see :class:`OriginalGibbs`); ignored on a
        single-sensor problem.
    marginals : {"truncated", "rao-blackwell"}, optional
        How the unique hypotheses become association marginals
        (:func:`~rankedassign.tracking.marginals_from_hypotheses`); ``"truncated"`` is the
        paper's construction. The short chains stop after a few dozen sweeps and miss
        hypotheses of a few per mille, e.g. a newborn track that exists but was not detected;
        ``"rao-blackwell"`` restores their weight (the Tracking page of the documentation shows
        what that changes).
    **sampler_options
        Passed to :func:`rankedassign.sample_short_chains` (``stall``, ``stale``, ``start``,
        ``scan``, ``backend``, ``workers``).

    Examples
    --------
    >>> from rankedassign.tracking import ShortChainGibbs
    >>> ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)
    ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)
    >>> ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, marginals="rao-blackwell")
    ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, marginals='rao-blackwell')
    """

    name = "short-chain"

    def __init__(self, n_chains: int, chain_length: int, *, tau_stall=None, tau_stale=None,
                 method: str | None = None, marginals: str = "truncated", **sampler_options):
        self.n_chains = check_int(n_chains, "n_chains", minimum=1)
        self.chain_length = check_int(chain_length, "chain_length", minimum=1)
        self.tau_stall = check_optional_int(tau_stall, "tau_stall", minimum=1)
        self.tau_stale = check_optional_int(tau_stale, "tau_stale", minimum=1)
        self._settings(marginals, method, sampler_options)

    def __repr__(self):
        return (f"{type(self).__name__}({self.n_chains}, {self.chain_length}, "
                f"tau_stall={self.tau_stall}, tau_stale={self.tau_stale}{self._extra()})")

    def __call__(self, problem, rng):
        res = sample_short_chains(
            problem, self.n_chains, self.chain_length, tau_stall=self.tau_stall,
            tau_stale=self.tau_stale, rng=rng, **self._options(problem),
        )
        return self._result(problem, res)

    def budget(self, counts: np.ndarray):
        """Chains and sweeps per chain of every component for its count ``T_h``.

        Chains of ``L = min(N_C, T_h − 1)`` sweeps, ``min(N_S, ⌈(T_h − 1) / L⌉)`` of them; a
        count of 0 or 1 gives the start state alone (the all-missed solution).

        Parameters
        ----------
        counts : ndarray of int64, shape (H,)

        Returns
        -------
        chains, length : ndarray of int64, shape (H,)

        Examples
        --------
        >>> import numpy as np
        >>> [x.tolist() for x in ShortChainGibbs(10, 25).budget(np.array([0, 5, 101, 1000]))]
        [[0, 1, 4, 10], [0, 4, 25, 25]]
        """
        n_obs = np.maximum(counts - 1, 0)
        length = np.minimum(n_obs, self.chain_length)
        safe = np.maximum(length, 1)
        chains = np.where(length > 0, np.minimum(-(-n_obs // safe), self.n_chains), 0)
        return chains.astype(np.int64), length.astype(np.int64)

    def hypotheses(self, problem, budget: int, rng) -> Hypotheses:
        """The δ-GLMB truncation of one component's problem with the count ``budget = T_h``.

        Parameters
        ----------
        problem : AssignmentProblem or MultiSensorProblem
        budget : int
            The component's count ``T_h >= 0`` (:meth:`budget`).
        rng : optional
            Anything :func:`numpy.random.default_rng` accepts.

        Returns
        -------
        Hypotheses

        Examples
        --------
        >>> from rankedassign import synthetic
        >>> hyp = ShortChainGibbs(4, 5).hypotheses(synthetic.random(rng=0), 1, rng=0)
        >>> hyp.sweeps, hyp.assignments.shape[0]
        (0, 1)
        """
        chains, length = self.budget(np.array([budget]))
        res = sample_short_chains(problem, int(chains[0]), int(length[0]),
                                  tau_stall=self.tau_stall, tau_stale=self.tau_stale, rng=rng,
                                  **self._options(problem))
        return Hypotheses(res.assignments, res.costs, int(res.n_observations),
                          int(res.n_row_updates))

    def batch_plan(self, sensors: str) -> BatchPlan | None:
        return self._chain_plan(sensors, self.tau_stall, self.tau_stale,
                                (self.n_chains, self.chain_length))


class HerdedGibbs(_Sampled):
    """Herded Gibbs (Chen et al. 2016, :func:`rankedassign.sample_herded`) as association.

    One deterministic herded chain of ``n_obs`` sweeps, or, with ``n_chains``, herded short
    chains with seeded initial weights and the paper's stall/stale rules
    (:func:`rankedassign.sample_short_chains` with ``herding=``), on a problem of one sensor or
    several.

    Parameters
    ----------
    n_obs : int
        Sweeps of the one chain, or the length ``N_C`` of each short chain.
    keys : {"shared", "full"}
        The herding keys (:class:`rankedassign.Herding`;
        :func:`rankedassign.multisensor.reference.herd_key` says what they are per method).
    init : {"conditional", "zero", "uniform"} or None
        Initial weights; None (default): ``"conditional"`` for one chain, ``"uniform"`` for
        short chains (so that they differ).
    max_keys : int
        Bound of each chain's key table.
    n_chains : int or None
        None (default): one chain. Otherwise ``N_S`` short chains of ``n_obs`` sweeps.
    tau_stall, tau_stale : int or None
        The short chains' rules (ignored for one chain).
    method : {"exact", "mm", "mm-fixed", "componentwise"}, optional
        The multi-sensor row conditional (see :class:`OriginalGibbs`); every one herds.
    marginals : {"truncated", "rao-blackwell"}, optional
        How the unique hypotheses become association marginals
        (:func:`~rankedassign.tracking.marginals_from_hypotheses`).
    **sampler_options
        Passed to the sampler (``start``, ``scan``, ``beta``, ``backend``, ``workers`` for
        short chains).

    Examples
    --------
    >>> from rankedassign.tracking import HerdedGibbs
    >>> HerdedGibbs(1000)
    HerdedGibbs(1000)
    >>> HerdedGibbs(25, n_chains=400, tau_stall=5, tau_stale=10, keys="full")
    HerdedGibbs(25, keys='full', n_chains=400, tau_stall=5, tau_stale=10)
    >>> from rankedassign.multisensor import synthetic
    >>> out = HerdedGibbs(200)(synthetic.random(3, (2, 2), rng=0), 1)
    >>> out.sweeps, out.tuples.shape
    (200, (3, 3, 3))
    """

    name = "herded"

    def __init__(self, n_obs: int, *, keys: str = "shared", init=None,
                 max_keys: int = DEFAULT_MAX_KEYS, n_chains=None, tau_stall=None,
                 tau_stale=None, method: str | None = None, marginals: str = "truncated",
                 **sampler_options):
        self.n_obs = check_int(n_obs, "n_obs", minimum=1)
        self.n_chains = check_optional_int(n_chains, "n_chains", minimum=1)
        default_init = "conditional" if self.n_chains is None else "uniform"
        self.herding = Herding(keys=keys, init=default_init if init is None else init,
                               max_keys=max_keys)
        self.init_given = init
        self.tau_stall = check_optional_int(tau_stall, "tau_stall", minimum=1)
        self.tau_stale = check_optional_int(tau_stale, "tau_stale", minimum=1)
        self._settings(marginals, method, sampler_options)

    def __repr__(self):
        h = self.herding
        parts = [str(self.n_obs)]
        if h.keys != "shared":
            parts.append(f"keys={h.keys!r}")
        if self.init_given is not None:
            parts.append(f"init={h.init!r}")
        if h.max_keys != DEFAULT_MAX_KEYS:
            parts.append(f"max_keys={h.max_keys}")
        if self.n_chains is not None:
            parts.append(f"n_chains={self.n_chains}, tau_stall={self.tau_stall}, "
                         f"tau_stale={self.tau_stale}")
        return f"{type(self).__name__}({', '.join(parts)}{self._extra()})"

    def __call__(self, problem, rng):
        res = self._sample(problem, self.n_chains or 1, self.n_obs, rng)
        return self._result(problem, res)

    def _sample(self, problem, n_chains: int, length: int, rng):
        h = self.herding
        opts = self._options(problem)
        if self.n_chains is None:
            return sample_herded(problem, length, keys=h.keys, init=h.init,
                                 max_keys=h.max_keys, rng=rng, **opts)
        return sample_short_chains(problem, n_chains, length, tau_stall=self.tau_stall,
                                   tau_stale=self.tau_stale, rng=rng, herding=h, **opts)

    def hypotheses(self, problem, budget: int, rng) -> Hypotheses:
        """The δ-GLMB truncation of one component's problem with the count ``budget = T_h``.

        The rule of the Gibbs truncations (:class:`~rankedassign.tracking.GLMBFilter`): ``T_h``
        counts stored solutions with the start state, so the herded draw gets ``n = T_h − 1``
        observations, at most its own budget: one chain of ``min(n, n_obs)`` sweeps, or
        ``min(n_chains, ⌈n / L⌉)`` short chains of ``L = min(n_obs, n)``. ``n = 0`` gives
        the start state alone. The costs are recomputed from the problem.

        Parameters
        ----------
        problem : AssignmentProblem or MultiSensorProblem
        budget : int
            The component's count ``T_h >= 0``.
        rng : optional
            Anything :func:`numpy.random.default_rng` accepts.

        Returns
        -------
        Hypotheses
            The unique assignments, their costs, and the sweeps and row updates spent.

        Examples
        --------
        >>> from rankedassign import synthetic
        >>> from rankedassign.tracking import HerdedGibbs
        >>> hyp = HerdedGibbs(1000).hypotheses(synthetic.random(rng=0), 51, rng=0)
        >>> hyp.sweeps, len(hyp.costs) <= 51
        (50, True)
        >>> HerdedGibbs(25, n_chains=4).hypotheses(synthetic.random(rng=0), 1, rng=0).sweeps
        0
        """
        n = max(check_int(budget, "budget", minimum=0) - 1, 0)
        if n == 0:
            one = {k: v for k, v in self._options(problem).items() if k != "workers"}
            res = sample_herded(problem, 0, rng=rng, **one)  # the start state alone
        elif self.n_chains is None:
            res = self._sample(problem, 1, min(n, self.n_obs), rng)
        else:
            length = min(self.n_obs, n)
            res = self._sample(problem, min(self.n_chains, -(-n // length)), length, rng)
        a = np.asarray(res.assignments, dtype=np.int64)
        # the exact costs of the assignments, as the filters have always used for the herded
        # draw (its own sums may differ in the last bits)
        costs = -problem.log_weight_of(a) if _is_multi(problem) else problem.cost_of(a)
        return Hypotheses(a, costs, int(res.n_observations), int(res.n_row_updates))


class TemperedGibbs(_Sampled):
    """Tempered Gibbs sampling as association: a chain at inverse temperature β, or the
    importance tempering of Zanella & Roberts (2019).

    Two samplers of the same idea, flattening the target so that a chain leaves the modes it
    would stick in:

    * ``scheme="beta"``: one long chain whose row conditionals are ``π_i^β``
      (:func:`rankedassign.sample_original` with ``beta``); its unique assignments are kept
      with their exact costs, as every Gibbs truncation's are;
    * ``scheme="zanella-roberts"``: tempered Gibbs sampling (:func:`rankedassign.sample_tempered`),
      ``n_obs`` times the rows' count of moves (one sweep's worth of row updates per
      observation); its marginals are importance-weighted (weights ``1/Z(x)``), which makes them
      consistent for the exact posterior ``π`` itself, and its target is ``π``, so on several
      sensors its row conditional is always the exact one (``method="exact"``).

    Parameters
    ----------
    n_obs : int
        Observations (sweeps, or a sweep's worth of moves) per call.
    beta : float
        Inverse temperature in ``(0, 1]`` (``1``: plain Gibbs).
    scheme : {"beta", "zanella-roberts"}
        See above.
    method : {"exact", "mm", "mm-fixed", "componentwise"}, optional
        The multi-sensor row conditional of the β-chain (see :class:`OriginalGibbs`); the
        Zanella–Roberts scheme takes ``"exact"`` only.
    marginals : {"truncated", "rao-blackwell", "importance"}, optional
        How the LMB filters get association marginals: from the unique hypotheses
        (:func:`~rankedassign.tracking.marginals_from_hypotheses`), or the Zanella–Roberts
        importance-weighted estimate (``"importance"``, that scheme's default and only there).
    **sampler_options
        Passed to the sampler (``start``; ``scan`` and ``backend`` for the β-chain).

    Raises
    ------
    ValueError
        If ``beta`` is outside ``(0, 1]``, ``scheme`` unknown, ``"importance"`` marginals
        are asked of the β-chain, or the Zanella–Roberts scheme is given a ``method`` other
        than ``"exact"``.

    References
    ----------
    .. [1] G. Zanella, G. Roberts, "Scalable importance tempering and Bayesian variable
       selection", J. R. Stat. Soc. B 81(3):489-517, 2019.

    Examples
    --------
    >>> from rankedassign import synthetic
    >>> from rankedassign.tracking import TemperedGibbs
    >>> TemperedGibbs(200, beta=0.5)
    TemperedGibbs(200, beta=0.5)
    >>> zr = TemperedGibbs(50, beta=0.5, scheme="zanella-roberts")
    >>> zr(synthetic.random(rng=0), 1).beta.shape
    (4, 18)
    >>> zr.hypotheses(synthetic.random(rng=0), 11, rng=0).sweeps   # T_h - 1 = 10 sweeps' worth
    10
    """

    name = "tempered"
    SCHEMES = ("beta", "zanella-roberts")

    def __init__(self, n_obs: int, *, beta: float, scheme: str = "beta",
                 method: str | None = None, marginals: str | None = None,
                 **sampler_options):
        self.n_obs = check_int(n_obs, "n_obs", minimum=1)
        if isinstance(beta, bool) or not isinstance(beta, (int, float, np.floating)) \
                or not 0.0 < float(beta) <= 1.0:
            raise ValueError(f"beta must be a number in (0, 1], got {beta!r}")
        self.beta = float(beta)
        self.scheme = check_choice(scheme, "scheme", self.SCHEMES)
        zr = self.scheme == "zanella-roberts"
        if marginals is None:
            marginals = "importance" if zr else "truncated"
        if marginals == "importance":
            if not zr:
                raise ValueError("marginals='importance' are the Zanella-Roberts scheme's "
                                 "(importance-weighted states); the beta-chain's marginals come "
                                 "from its hypotheses: 'truncated' or 'rao-blackwell'")
            self.importance = True
            marginals = "truncated"
        else:
            self.importance = False
        if zr and method not in (None, "exact"):
            raise ValueError(f"method={method!r} does not apply to the Zanella-Roberts scheme: "
                             "its target is the exact posterior, whose row conditional is "
                             "method='exact'")
        self._default_method = "exact" if zr else DEFAULT_METHOD
        self._settings(marginals, method, sampler_options)

    def __repr__(self):
        parts = [str(self.n_obs), f"beta={self.beta!r}"]
        if self.scheme != "beta":
            parts.append(f"scheme={self.scheme!r}")
        if self.method != self._default_method:
            parts.append(f"method={self.method!r}")
        shown = "importance" if self.importance else self.marginals
        if shown != ("importance" if self.scheme == "zanella-roberts" else "truncated"):
            parts.append(f"marginals={shown!r}")
        parts += [f"{k}={v!r}" for k, v in self.options.items()]
        return f"{type(self).__name__}({', '.join(parts)})"

    def _sample(self, problem, n: int, rng):
        opts = self._options(problem)
        if self.scheme == "beta":
            return sample_original(problem, n, beta=self.beta, rng=rng, **opts)
        opts.pop("method", None)  # "exact": the tempered samplers' own conditional
        res = sample_tempered(problem, n * problem.n_rows, beta=self.beta, rng=rng, **opts)
        return res

    def __call__(self, problem, rng):
        res = self._sample(problem, self.n_obs, rng)
        if not self.importance:
            return self._result(problem, _as_sampled(res, self.n_obs))
        n_unique = int(len(res.costs))
        if _is_multi(problem):
            dead, tup = res.marginals.dead, res.marginals.tuples
            return MultiSensorAssociationResult(dead=dead, tuples=tup, invocations=1,
                                                sweeps=self.n_obs, row_updates=int(res.n_steps),
                                                n_unique=n_unique)
        return AssociationResult(beta=res.marginals, invocations=1, sweeps=self.n_obs,
                                 row_updates=int(res.n_steps), n_unique=n_unique)

    def hypotheses(self, problem, budget: int, rng) -> Hypotheses:
        """The δ-GLMB truncation of one component's problem with the count ``budget = T_h``.

        As for the other chains (:class:`OriginalGibbs`): ``n = min(T_h − 1, n_obs)``
        observations (sweeps, or a sweep's worth of moves), ``n = 0`` the start state alone;
        the unique states are kept with their exact costs.

        Parameters
        ----------
        problem : AssignmentProblem or MultiSensorProblem
        budget : int
            The component's count ``T_h >= 0``.
        rng : optional
            Anything :func:`numpy.random.default_rng` accepts.

        Returns
        -------
        Hypotheses

        Examples
        --------
        >>> from rankedassign import synthetic
        >>> TemperedGibbs(1000, beta=0.7).hypotheses(synthetic.random(rng=0), 51, rng=0).sweeps
        50
        """
        n = min(max(check_int(budget, "budget", minimum=0) - 1, 0), self.n_obs)
        res = _as_sampled(self._sample(problem, n, rng), n)
        a = np.asarray(res.assignments, dtype=np.int64)
        costs = -problem.log_weight_of(a) if _is_multi(problem) else problem.cost_of(a)
        return Hypotheses(a, costs, int(res.n_observations), int(res.n_row_updates))


class _TemperedAsSampled(NamedTuple):
    assignments: np.ndarray
    costs: np.ndarray
    n_observations: int
    n_row_updates: int


def _as_sampled(res, n_obs: int):
    """A sampler's result, or a tempered one with ``n_obs`` observations of its moves."""
    if hasattr(res, "n_observations"):
        return res
    return _TemperedAsSampled(res.assignments, res.costs, n_obs, int(res.n_steps))


class Murty(Association):
    """Murty's k best assignments (Murty 1968; the oracle's implementation) as association.

    A ranked search of one sensor's problem: a filter of several sensors refuses it (there is
    no ranked multi-sensor search in the library).

    Parameters
    ----------
    k : int
        Number of best hypotheses per call.
    backend : {"numba", "scipy"}
        The implementation of :func:`oracle.murty`.
    marginals : {"truncated", "rao-blackwell"}, optional
        How the k best hypotheses become association marginals
        (:func:`~rankedassign.tracking.marginals_from_hypotheses`).

    Examples
    --------
    >>> from rankedassign.tracking import Murty
    >>> Murty(1000)
    Murty(1000)
    """

    name = "murty"
    validated_output = True

    def __init__(self, k: int, *, backend: str = "numba", marginals: str = "truncated"):
        self.k = check_int(k, "k", minimum=1)
        self.backend = check_choice(backend, "backend", MURTY_BACKENDS)
        self.marginals = _check_marginals(marginals)

    def __repr__(self):
        extra = "" if self.backend == "numba" else f", backend={self.backend!r}"
        mar = "" if self.marginals == "truncated" else f", marginals={self.marginals!r}"
        return f"Murty({self.k}{extra}{mar})"

    def cannot(self, sensors: str, need: str):
        if sensors == "multi-sensor":
            return TypeError, ("Murty's ranked search solves one sensor's problem; there is no "
                               "ranked multi-sensor search (use Exact or a sampler truncation)")
        return None

    def __call__(self, problem, rng):
        ranked = oracle.murty(problem, self.k, backend=self.backend)
        beta = single_marginals(problem, ranked.assignments, ranked.costs, self.marginals)
        return AssociationResult(beta=beta, invocations=1, sweeps=0, row_updates=0,
                                 n_unique=int(len(ranked.costs)))

    def hypotheses(self, problem, budget: int, rng) -> Hypotheses:
        """The ``min(k, max(T_h, 1))`` best assignments of one component's problem.

        Parameters
        ----------
        problem : AssignmentProblem
        budget : int
            The component's count ``T_h >= 0``.
        rng : optional
            Unused (the search is deterministic).

        Returns
        -------
        Hypotheses

        Examples
        --------
        >>> from rankedassign import AssignmentProblem
        >>> p = AssignmentProblem.from_eta([[3.0]], [1.0], [1.0])
        >>> Murty(5).hypotheses(p, 2, None).assignments.tolist()
        [[0], [1]]
        """
        ranked = oracle.murty(problem, min(self.k, max(budget, 1)), backend=self.backend)
        return Hypotheses(ranked.assignments, ranked.costs)

    def batch_plan(self, sensors: str) -> BatchPlan | None:
        return BatchPlan(ranked=True, k=self.k) if self.backend == "numba" else None


class Exact(Association):
    """Every assignment: exact association marginals (spec §5.2, :func:`oracle.marginals`),
    the exact LMB update, or every hypothesis of a δ-GLMB component.

    On one sensor the oracle solves each connected component of the gated problem
    separately, densely when ``min(P_c, M_c) <= 20`` and otherwise by a frontier DP over the
    measurements (at most ``2^20`` states); on several sensors the row DP over used-measurement
    sets accepts at most :data:`oracle.multisensor.dp.MAX_MASK_BITS` reachable measurements
    over all sensors. A δ-GLMB component is enumerated up to :data:`EXACT_LIMIT` assignments.
    The problems of the paper's preset (one group of some 20 rows and 60 gated measurements
    per scan) are within the frontier DP's reach (sizes and times on the Tracking page of the
    documentation); the filter's grouping (spec §6.5a) keeps problems small on presets with
    narrow births.

    Parameters
    ----------
    fallback : association or None, optional
        Association used on a problem beyond the oracle (marginals) or :data:`EXACT_LIMIT`
        (hypotheses). None (default): such a problem raises ``ValueError``. Problems solved by
        the fallback are counted in :attr:`n_fallback`.

    Raises
    ------
    TypeError
        If ``fallback`` is not callable.

    Examples
    --------
    >>> from rankedassign.tracking import Exact, ShortChainGibbs
    >>> Exact()
    Exact()
    >>> Exact(fallback=ShortChainGibbs(400, 25))
    Exact(fallback=ShortChainGibbs(400, 25, tau_stall=None, tau_stale=None))
    """

    name = "exact"
    sensors = "any"
    validated_output = True

    def __init__(self, fallback=None):
        if fallback is not None and not callable(fallback) and not callable(
                getattr(fallback, "hypotheses", None)):
            raise TypeError(
                f"fallback must be an association or None, got {type(fallback).__name__}"
            )
        self.fallback = fallback
        self.n_fallback = 0

    def __repr__(self):
        name = type(self).__name__
        return f"{name}()" if self.fallback is None else f"{name}(fallback={self.fallback!r})"

    def cannot(self, sensors: str, need: str):
        if self.fallback is None:
            return None
        inner = getattr(self.fallback, "cannot", None)
        return inner(sensors, need) if callable(inner) else None

    def __call__(self, problem, rng):
        multi = _is_multi(problem)
        try:
            m = oracle.marginals(problem)
        except ValueError as exc:
            if self.fallback is None:
                if not multi:
                    raise
                raise ValueError(
                    f"{type(self).__name__}: a group of P = {problem.n_rows} tracks with "
                    f"M = {problem.n_meas} gated measurements is beyond the exact DP ({exc}); "
                    "enable grouping, narrow the gate, or pass fallback=<a sampler association>"
                ) from None
            self.n_fallback += 1
            return self.fallback(problem, rng)
        if multi:
            return MultiSensorAssociationResult(
                dead=np.asarray(m.dead, dtype=np.float64),
                tuples=np.asarray(m.tuples, dtype=np.float64), invocations=1, sweeps=0,
                row_updates=0, n_unique=0)
        return AssociationResult(beta=np.array(m, dtype=np.float64), invocations=1, sweeps=0,
                                 row_updates=0, n_unique=0)

    def hypotheses(self, problem, budget: int, rng) -> Hypotheses:
        """Every assignment of one component's problem (the count is ignored).

        Parameters
        ----------
        problem : AssignmentProblem or MultiSensorProblem
        budget : int
            The component's count (passed to the fallback, if it runs).
        rng : optional
            Passed to the fallback, if it runs.

        Returns
        -------
        Hypotheses

        Raises
        ------
        ValueError
            On a problem of more than :data:`EXACT_LIMIT` assignments without a fallback.

        Examples
        --------
        >>> from rankedassign import AssignmentProblem
        >>> p = AssignmentProblem.from_eta([[3.0]], [1.0], [1.0])
        >>> Exact().hypotheses(p, 0, None).assignments.tolist()
        [[0], [1], [2]]
        """
        try:
            ranked = oracle.enumerate_assignments(problem, limit=EXACT_LIMIT)
        except ValueError as err:
            if self.fallback is not None:
                self.n_fallback += 1
                return truncate(self.fallback, problem, budget, rng)
            name = type(self).__name__
            if _is_multi(problem):
                raise ValueError(
                    f"{name}() cannot enumerate a component's problem of {problem.n_rows} rows "
                    f"and M = {problem.n_meas} measurements within {EXACT_LIMIT} assignments "
                    f"(EXACT_LIMIT): {err}; pass fallback=<a multi-sensor sampler association> "
                    "or use the chains for problems of this size") from None
            raise ValueError(
                f"{name}() cannot enumerate a component's problem of {problem.n_rows} rows and "
                f"{problem.n_meas} measurements within {EXACT_LIMIT} assignments "
                f"(EXACT_LIMIT): {err}; use Murty(k) or a sampler for problems of this size"
            ) from None
        return Hypotheses(ranked.assignments, ranked.costs)

    def batch_plan(self, sensors: str) -> BatchPlan | None:
        return BatchPlan(ranked=True, k=0) if sensors == "single-sensor" else None


class LBPConvergenceWarning(RuntimeWarning):
    """Loopy belief propagation stopped at ``max_iter`` before its messages settled."""


class LBP(Association):
    """Loopy belief propagation (Williams & Lau 2014, :func:`rankedassign.lbp_marginals`).

    Approximate association marginals from message passing, without sampling or
    enumeration: exact when no two tracks gate the same measurement, at most 0.002 from the
    exact marginals on 200 of the paper's random ``4 x 24`` matrices (0.071 on one gated
    30-track problem with a tight loop), and tens of times faster than :class:`Exact` on a
    30-track problem (the Herding, tempering and belief propagation page of the documentation
    has the measurements). It gives marginals of one sensor's problem only, so it serves the
    LMB filter, not the δ-GLMB filters (which need hypotheses) nor the multi-sensor ones.

    Parameters
    ----------
    tol : float, optional
        Stop when no message changes by more than ``tol`` (default ``1e-9``).
    max_iter : int, optional
        Iteration cap (default 1000). A call that reaches it keeps its last beliefs, emits an
        :class:`LBPConvergenceWarning` naming the problem's size and the last change, and is
        counted in :attr:`n_unconverged`.

    Attributes
    ----------
    n_calls, n_unconverged : int
        Calls made and calls that stopped at ``max_iter`` (in this process).
    iterations : int
        Iterations over all calls.

    References
    ----------
    .. [1] J. Williams, R. Lau, "Approximate evaluation of marginal association probabilities
       with belief propagation", IEEE Trans. Aerosp. Electron. Syst. 50(4):2942-2959, 2014.

    Examples
    --------
    >>> from rankedassign import AssignmentProblem
    >>> from rankedassign.tracking import LBP
    >>> assoc = LBP()
    >>> assoc
    LBP()
    >>> p = AssignmentProblem.from_eta([[2.0]], [0.5], [0.25])
    >>> assoc(p, None).beta.round(6).tolist()
    [[0.727273, 0.181818, 0.090909]]
    >>> assoc.n_calls, assoc.n_unconverged
    (1, 0)
    """

    name = "lbp"

    def __init__(self, *, tol: float = LBP_TOL, max_iter: int = LBP_MAX_ITER):
        self.tol, self.max_iter = check_lbp_settings(tol, max_iter)
        self.n_calls = 0
        self.n_unconverged = 0
        self.iterations = 0

    def __repr__(self):
        parts = []
        if self.tol != LBP_TOL:
            parts.append(f"tol={self.tol!r}")
        if self.max_iter != LBP_MAX_ITER:
            parts.append(f"max_iter={self.max_iter!r}")
        return f"LBP({', '.join(parts)})"

    def cannot(self, sensors: str, need: str):
        if need == "hypotheses":
            return TypeError, _MARGINALS_ONLY
        if sensors == "multi-sensor":
            return TypeError, ("loopy belief propagation is written for one sensor's "
                               "problem (use Exact or a sampler truncation)")
        return None

    def __call__(self, problem, rng) -> AssociationResult:
        res = lbp_marginals(problem, tol=self.tol, max_iter=self.max_iter)
        self.n_calls += 1
        self.iterations += res.iterations
        if not res.converged:
            self.n_unconverged += 1
            warnings.warn(
                f"loopy belief propagation did not converge within max_iter={self.max_iter} "
                f"iterations on a {problem.n_rows} x {problem.n_meas} problem (last message "
                f"change {res.change:.3g} > tol={self.tol:g}); its last beliefs are used",
                LBPConvergenceWarning, stacklevel=2,
            )
        return AssociationResult(beta=res.marginals, invocations=1, sweeps=0, row_updates=0,
                                 n_unique=0)


# ------------------------------------------------------------------------------ deprecated
def _deprecated(old: str, new: type):
    """A deprecated alias of ``new``: warns on construction, keeps ``repr`` and
    ``method="exact"`` (the multi-sensor associations' default before the merge)."""

    def __init__(self, *args, **kwargs):
        warnings.warn(f"{old} is deprecated and will be removed in the next release; use "
                      f"{new.__name__} (the same class serves every filter and sensor count; "
                      f"its default method is {DEFAULT_METHOD!r}, pass method='exact' for the "
                      f"numbers of {old})", DeprecationWarning, stacklevel=2)
        new.__init__(self, *args, **kwargs)

    doc = (f"Deprecated alias of :class:`{new.__name__}` (one release), with "
           "``method=\"exact\"`` by default.\n\n    Parameters\n    ----------\n"
           f"    *args, **kwargs\n        Those of :class:`{new.__name__}`.\n")
    return type(old, (new,), {"__init__": __init__, "__doc__": doc, "__module__": __name__,
                              "_default_method": "exact"})


MultiSensorOriginalGibbs = _deprecated("MultiSensorOriginalGibbs", OriginalGibbs)
MultiSensorShortChainGibbs = _deprecated("MultiSensorShortChainGibbs", ShortChainGibbs)
MultiSensorHerdedGibbs = _deprecated("MultiSensorHerdedGibbs", HerdedGibbs)
MultiSensorExact = _deprecated("MultiSensorExact", Exact)
