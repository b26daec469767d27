"""Table I on the multi-sensor ranked-assignment problem, for each multi-sensor sampler.

The single-sensor Table I study (:mod:`rankedassign.experiments.studies.table1`) carried over to
:class:`~rankedassign.multisensor.MultiSensorProblem` (multi-sensor spec §5): the original
sampler is one chain of ``original_obs`` sweeps, the short-chain sampler ``n_chains`` chains of
``chain_length`` sweeps from the all-missed state (the same budget, ``N_S N_C``), under the
stall rule (S3), the stale rule (T3) or both; ΔObs and ΔError are the single-sensor study's
(:func:`~rankedassign.experiments._synthetic.paired_summary`, spec eq. 1.10). Every row update
of the samplers (``method``) is run: ``"exact"`` (Vo-Vo-Beard Alg. 1), ``"mm"`` and
``"mm-fixed"`` (MM-Gibbs) and ``"componentwise"`` (the collapsed target).

Cases: a canonical size of spec §6.5 with one family each (``"A/random_coupled"``: the size
closest to the single-sensor 4 x 24 with a non-separable target, where MM-Gibbs samples a
surrogate; ``"B/random"``: two rows, clutter-rich, separable, where MM-Gibbs is exact in law;
``"C/uniform"``: the flat target, the hardest to truncate, as the single-sensor uniform family).
The random families are re-drawn every Monte Carlo run.

Errors. For ``"exact"``, ``"mm"`` and ``"mm-fixed"`` the exact truncation error against ``pi``
(:func:`oracle.truncation_error`). The component-wise sampler's states are collapsed (a row at
the all-missed tuple stands for "dead or missed by every sensor", multi-sensor spec §1.6) and
its costs are the collapsed weights, so its error is the ``pi``-mass its unique states do not
cover, ``1 - sum exp(-cost) / Z`` (equal to the truncation error for the other methods).

The paper has no multi-sensor numbers ("similar results are expected", multi-sensor spec §5).

References
----------
.. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
   Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023, Table I.
.. [2] B.-N. Vo, B.-T. Vo, M. Beard, "Multi-Sensor Multi-Object Tracking with the Generalized
   Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 67(23):5952-5967, 2019.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

import oracle

from ... import sample_original, sample_short_chains
from ...multisensor import synthetic as ms_synthetic
from ...validation import check_choice, check_fields, check_int
from .. import _format as fmt
from .._executor import child_seed, run_seed
from .._plots import bar_style, figure, legend_below
from .._records import RunRecord
from .._synthetic import PairedStats, paired_summary
from ..config import CRITERIA
from ..registry import Study, as_rows, register_study
from ..vocabulary import ROW_METHODS

__all__ = ["MULTISENSOR", "MultiSensorConfig", "MultiSensorRow", "MethodAccuracyRow",
           "MultiSensorRun", "MultiSensorCalls", "MultiSensorCall",
           "MultiSensorSummary", "CASES", "METHODS", "summarise_multisensor"]

#: The cases of the study: ``"<size>/<family>"`` (sizes of spec §6.5, families of
#: :mod:`rankedassign.multisensor.synthetic`).
CASES = ("A/random_coupled", "B/random", "C/uniform")
#: Families a case may name.
MS_FAMILIES = ("diagonal", "uniform", "random", "random_coupled", "geometric")
#: Row updates of the multi-sensor samplers (``method``, the row conditional alone), in report
#: order: the samplers' own list (:data:`~rankedassign.experiments.vocabulary.ROW_METHODS`); a
#: run's streams are keyed by the position in it.
METHODS = ROW_METHODS
#: Termination rules of each Table I column (``True`` = rule on), readings S3 / T3.
RULES = {"stall": (True, False), "stale": (False, True), "full": (True, True)}
#: Quick mode: Monte Carlo runs (the per-run settings are the full study's).
QUICK_MC = 3


def _case(case) -> tuple[str, str]:
    if not isinstance(case, str):
        raise TypeError(f"cases: a case must be a str such as 'A/random', got {case!r}")
    size, _, family = case.partition("/")
    check_choice(size, "cases: size", tuple(ms_synthetic.SIZES))
    check_choice(family, "cases: family", MS_FAMILIES)
    return size, family


@dataclass(frozen=True)
class MultiSensorConfig:
    """Settings of the multi-sensor Table I study.

    Attributes
    ----------
    n_mc : int
        Monte Carlo runs per case (the random families are re-drawn every run).
    cases : tuple of str
        ``"<size>/<family>"``, size in ``A, B, C`` (spec §6.5), family a function of
        :mod:`rankedassign.multisensor.synthetic`.
    methods : tuple of str
        Samplers' row updates (:data:`METHODS`).
    original_obs : int
        Sweeps of the original chain (default ``n_chains * chain_length``, the Table I rule).
    n_chains, chain_length, tau_stall, tau_stale : int
        Short-chain settings (multi-sensor spec §5 synthetic defaults).

    Examples
    --------
    >>> MultiSensorConfig().original_obs
    250000
    >>> MultiSensorConfig(methods=("gibbs",))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: unknown methods: method 'gibbs'; expected one of (...)
    """

    n_mc: int = 100
    cases: tuple = CASES
    methods: tuple = METHODS
    original_obs: int = 250_000
    n_chains: int = 10_000
    chain_length: int = 25
    tau_stall: int = 5
    tau_stale: int = 25

    def __post_init__(self):
        check_fields(self)
        for name in ("n_mc", "original_obs", "n_chains", "chain_length", "tau_stall",
                     "tau_stale"):
            check_int(getattr(self, name), name, minimum=1)
        for name, values in (("cases", self.cases), ("methods", self.methods)):
            if not isinstance(values, tuple) or not values:
                raise ValueError(f"{name} must be a non-empty tuple, got {values!r}")
        for c in self.cases:
            _case(c)
        for m in self.methods:
            check_choice(m, "methods: method", METHODS)


def make_problem(case: str, run_ss: np.random.SeedSequence):
    """The problem of ``case`` for one Monte Carlo run (random families re-drawn)."""
    size, family = _case(case)
    P, M = ms_synthetic.SIZES[size]
    build = getattr(ms_synthetic, family)
    if family in ("diagonal", "uniform"):
        return build(P, M)
    return build(P, M, rng=child_seed(run_ss, 0))


@dataclass(frozen=True)
class MultiSensorCall(RunRecord):
    """One sampler call of :func:`multisensor_task`.

    Attributes
    ----------
    n_obs : int
        Observations (sweeps) spent.
    n_unique : int
        Unique assignments found.
    n_chains : int
        Chains run.
    stop_reason : str
        Why the sampler stopped.
    error : float
        Truncation error of the unique assignments, a fraction (``"componentwise"``: one
        minus the exact posterior mass of what it found, clipped to ``[0, 1]``).
    seconds : float
        Wall time of the call.
    """

    n_obs: int
    n_unique: int
    n_chains: int
    stop_reason: str
    error: float
    seconds: float


@dataclass(frozen=True)
class MultiSensorCalls(RunRecord):
    """One row conditional's calls in one run: the original chain and the three criteria.

    Attributes
    ----------
    original : MultiSensorCall
        The original chain (``original_obs`` sweeps).
    stall, stale, full : MultiSensorCall
        The short chains under each criterion (:data:`RULES`).
    """

    original: MultiSensorCall
    stall: MultiSensorCall
    stale: MultiSensorCall
    full: MultiSensorCall

    @classmethod
    def from_dict(cls, data: dict) -> MultiSensorCalls:
        """The record of one method's object of a saved run.

        Parameters
        ----------
        data : dict
            The four calls as objects.

        Returns
        -------
        MultiSensorCalls
        """
        return super().from_dict({k: MultiSensorCall.from_dict(v) for k, v in data.items()})


@dataclass(frozen=True)
class MultiSensorRun(RunRecord):
    """One Monte Carlo run of one case (:func:`multisensor_task`).

    Attributes
    ----------
    run : int
        Monte Carlo run.
    case : str
        The case (:data:`CASES` or ``"<size>/<family>"``).
    methods : dict of str to MultiSensorCalls
        Per row conditional of the settings (:data:`METHODS`), its calls.
    """

    run: int
    case: str
    methods: dict

    @classmethod
    def from_dict(cls, data: dict) -> MultiSensorRun:
        """The record of one object of ``multisensor_runs.json``.

        Parameters
        ----------
        data : dict
            Its fields, the calls as objects.

        Returns
        -------
        MultiSensorRun
        """
        return super().from_dict({**data, "methods": {
            m: MultiSensorCalls.from_dict(c) for m, c in data.get("methods", {}).items()}})


def _record(problem, res, seconds: float, log_z: float, method: str) -> MultiSensorCall:
    if method == "componentwise":
        covered = float(np.exp(-np.asarray(res.costs, dtype=float) - log_z).sum())
        error = min(1.0, max(0.0, 1.0 - covered))
    else:
        error = float(oracle.truncation_error(problem, res.assignments))
    return MultiSensorCall(n_obs=int(res.n_observations), n_unique=int(len(res.costs)),
                           n_chains=int(res.n_chains_run), stop_reason=str(res.stop_reason),
                           error=error, seconds=float(seconds))


def multisensor_tasks(cfg: MultiSensorConfig, seed: int) -> list[tuple]:
    """``(cfg, seed, run, case)`` for every case and Monte Carlo run (case-major)."""
    return [(cfg, seed, r, c) for c in cfg.cases for r in range(cfg.n_mc)]


def multisensor_task(cfg: MultiSensorConfig, seed: int, run: int,
                     case: str) -> MultiSensorRun:
    """One Monte Carlo run of one case: for every method, the original chain and the criteria.

    Returns
    -------
    MultiSensorRun
        Per method its :class:`MultiSensorCalls` (``original``, ``stall``, ``stale``,
        ``full``).

    Examples
    --------
    >>> cfg = MultiSensorConfig(n_mc=1, cases=("A/diagonal",), methods=("mm",),
    ...                         original_obs=100, n_chains=4)
    >>> out = multisensor_task(cfg, 0, 0, "A/diagonal")
    >>> out.methods["mm"].original.n_obs, out.methods["mm"].full.n_obs <= 100
    (100, True)
    """
    s = run_seed(seed, run)
    problem = make_problem(case, s)
    log_z = float(oracle.log_normalizer(problem))
    ci = cfg.cases.index(case)
    methods = {}
    for method in cfg.methods:
        mi = METHODS.index(method)
        t = time.perf_counter()
        res = sample_original(problem, cfg.original_obs, rng=child_seed(s, 1, ci, mi),
                              method=method)
        recs = {"original": _record(problem, res, time.perf_counter() - t, log_z, method)}
        for k, crit in enumerate(CRITERIA):
            stall, stale = RULES[crit]
            t = time.perf_counter()
            res = sample_short_chains(
                problem, cfg.n_chains, cfg.chain_length,
                tau_stall=cfg.tau_stall if stall else None,
                tau_stale=cfg.tau_stale if stale else None,
                rng=child_seed(s, 2, ci, mi, k), method=method)
            recs[crit] = _record(problem, res, time.perf_counter() - t, log_z, method)
        methods[method] = MultiSensorCalls(**recs)
    return MultiSensorRun(run=run, case=case, methods=methods)


@dataclass(frozen=True, kw_only=True)
class MultiSensorRow(PairedStats):
    """One Table I row: a case, a method and a criterion (statistics as the single-sensor's).

    ``eps_o``, ``eps_s`` are one run's errors (module docstring) of the original and of the
    short-chain sampler, ``N_o``, ``N_s`` their observations; standard errors are ``None``
    for one run.

    Attributes
    ----------
    n_mc : int
        Paired Monte Carlo runs of the cell (the same matrix for both samplers in a run).
    obs_original_mean, obs_proposed_mean : float
        Mean observations (sweeps) per run of the original and of the short-chain sampler.
    error_original_mean, error_proposed_mean : float
        Mean exact truncation error (spec eq. 1.9) of each sampler, in percent.
    delta_obs_pct : float
        ΔObs, ``100 (mean N_o - mean N_s) / mean N_o``: the share of the original sampler's
        observations the short chains save, in percent.
    delta_error_pp : float
        ΔError, ``|mean(eps_s - eps_o)|`` (spec eq. 1.10), in percentage points.
    delta_error_signed_pp : float
        ``mean(eps_s - eps_o)`` in percentage points: positive when the short chains leave
        more of the target's mass uncovered.
    mean_abs_delta_error_pp : float
        Mean of the per-run ``|eps_s - eps_o|`` (spec A7), in percentage points.
    unique_original_mean, unique_proposed_mean : float
        Mean number of distinct assignments each sampler found.
    chains_proposed_mean : float
        Mean number of chains the short-chain sampler ran.
    stale_stop_fraction : float
        Fraction of runs in which the stale rule ended the short-chain sampler.
    delta_obs_pct_se : float or None
        Standard error of ``delta_obs_pct`` (delta method for the ratio of the paired means).
    delta_error_pp_se : float or None
        Standard error of the mean paired difference ``mean(eps_s - eps_o)``.
    mean_abs_delta_error_pp_se : float or None
        Standard error of ``mean_abs_delta_error_pp``.
    error_original_se, error_proposed_se : float or None
        Standard errors of ``error_original_mean`` and ``error_proposed_mean``.
    obs_original_se, obs_proposed_se, unique_original_se, unique_proposed_se : float or None
        Standard errors of the mean observations and of the mean distinct assignments of each
        sampler (``None`` for one run, and where a caller built the record without them).
    stale_stop_se : float or None
        Standard error of ``stale_stop_fraction`` (the mean of a 0/1 outcome per run).
    case : str
        ``"<size>/<family>"`` (:data:`CASES`).
    method : str
        Row update of both samplers (:data:`METHODS`).
    criterion : {"stall", "stale", "full"}
        Termination rules of the short chains: stall (S3) only, stale (T3) only, or both.
    """

    case: str
    method: str
    criterion: str


@dataclass(frozen=True, kw_only=True)
class MethodAccuracyRow:
    """A method's original chain at the common budget: its error, against the exact method's.

    Errors in %, ``vs_exact_pp`` the mean paired difference to the ``"exact"`` method's error
    in pp (``None`` without the exact method), ``seconds`` the mean wall time of one chain.

    Attributes
    ----------
    case : str
        ``"<size>/<family>"`` (:data:`CASES`).
    method : str
        Row update of the original chain (:data:`METHODS`).
    n_mc : int
        Monte Carlo runs.
    n_obs : int
        Sweeps of the chain, the common budget (``original_obs`` of the settings).
    error_mean : float
        Mean error of the chain, in percent (the module docstring says which error).
    error_se : float or None
        Its standard error; ``None`` for one run.
    vs_exact_pp : float or None
        Mean paired difference ``error - error of "exact"`` over the runs, in percentage
        points (0 for the exact method itself); ``None`` when ``"exact"`` was not run.
    vs_exact_pp_se : float or None
        Its standard error; ``None`` for one run or without ``"exact"``.
    unique_mean : float
        Mean number of distinct states the chain visited.
    seconds_mean : float
        Mean wall-clock time of one chain, in seconds.
    seconds_min : float or None
        The shortest of those times (the one the machine's load disturbed least: what the
        report shows); ``None`` in records written before it was kept.
    unique_se : float or None
        Standard error of ``unique_mean``; ``None`` for one run (and in older records).
    """

    case: str
    method: str
    n_mc: int
    n_obs: int
    error_mean: float
    error_se: float | None
    vs_exact_pp: float | None
    vs_exact_pp_se: float | None
    unique_mean: float
    seconds_mean: float
    seconds_min: float | None = None
    unique_se: float | None = None


@dataclass(frozen=True)
class MultiSensorSummary:
    """Table I rows, the equal-sweeps accuracy rows and the verdict.

    Attributes
    ----------
    rows : tuple of MultiSensorRow
        Table I rows, case by case, then method by method, then criterion (stall, stale,
        full), in the order of the settings.
    accuracy : tuple of MethodAccuracyRow
        One row per case and method: the original chain's error at the common budget.
    verdict : str
        One paragraph judging "similar results are expected" on the ``"full"`` column
        (:func:`verdict`).
    """

    rows: tuple
    accuracy: tuple
    verdict: str


def _se(x) -> float | None:
    x = np.asarray(x, dtype=float)
    return float(x.std(ddof=1) / math.sqrt(x.size)) if x.size > 1 else None


def summarise_multisensor(runs: list[MultiSensorRun],
                          cfg: MultiSensorConfig) -> MultiSensorSummary:
    """Table I rows (case x method x criterion), accuracy rows (case x method), verdict.

    Parameters
    ----------
    runs : list of MultiSensorRun
        Records of :func:`multisensor_task`.
    cfg : MultiSensorConfig

    Returns
    -------
    MultiSensorSummary
    """
    rows, acc = [], []
    for case in cfg.cases:
        rs = sorted((r for r in runs if r.case == case), key=lambda r: r.run)
        if not rs:
            continue
        exact = ([100 * r.methods["exact"].original.error for r in rs]
                 if "exact" in cfg.methods else None)
        for method in cfg.methods:
            orig = [r.methods[method].original for r in rs]
            for crit in CRITERIA:
                stats = paired_summary(orig, [getattr(r.methods[method], crit) for r in rs])
                rows.append(MultiSensorRow(case=case, method=method, criterion=crit,
                                           **stats.__dict__))
            e = np.array([100 * o.error for o in orig])
            d = None if exact is None else e - np.array(exact)
            acc.append(MethodAccuracyRow(
                case=case, method=method, n_mc=len(rs), n_obs=cfg.original_obs,
                error_mean=float(e.mean()), error_se=_se(e),
                vs_exact_pp=None if d is None else float(d.mean()),
                vs_exact_pp_se=None if d is None else _se(d),
                unique_mean=float(np.mean([o.n_unique for o in orig])),
                seconds_mean=float(np.mean([o.seconds for o in orig])),
                seconds_min=float(np.min([o.seconds for o in orig])),
                unique_se=_se([o.n_unique for o in orig])))
    return MultiSensorSummary(rows=tuple(rows), accuracy=tuple(acc),
                              verdict=verdict(rows))


def verdict(rows) -> str:
    """One paragraph: does "similar results are expected" hold, judged on the "full" column?

    A case and method carry the single-sensor result over when the short chains save
    observations (ΔObs > 0) or, as on the single-sensor uniform family, neither save nor lose,
    with a signed error change (short minus original) no larger than 3 standard errors or
    1 pp.

    Examples
    --------
    >>> verdict([])
    'No case was run.'
    """
    full = [r for r in rows if r.criterion == "full"]
    if not full:
        return "No case was run."
    good, bad = [], []
    for r in full:
        se = r.delta_error_pp_se or 0.0
        ok = r.delta_error_signed_pp <= max(1.0, 3 * se)
        (good if ok else bad).append(r)
    saved = [r.delta_obs_pct for r in full]
    text = (f"With both rules (the proposed sampler) the short chains use "
            f"{min(saved):.1f} % to {max(saved):.1f} % fewer observations than the long chain "
            f"over the {len(full)} (case, method) pairs. ")
    if not bad:
        text += ("In every pair the short chains' error is no worse than the long chain's by "
                 "more than 1 pp or 3 standard errors, so the paper's \"similar results are "
                 "expected\" holds for every multi-sensor sampler at these settings.")
    else:
        text += ("The paper's \"similar results are expected\" holds in "
                 f"{len(good)} of the {len(full)} pairs; the short chains lose accuracy in: "
                 + "; ".join(f"{r.case} {r.method} (signed ΔError "
                             f"{fmt.pm(r.delta_error_signed_pp, r.delta_error_pp_se)} pp)"
                             for r in bad) + ".")
    return text


def render_multisensor(summary: MultiSensorSummary, cfg: MultiSensorConfig) -> str:
    """The report section: the Table I layout per method, the accuracy table, the verdict."""
    n = summary.rows[0].n_mc if summary.rows else 0
    main = [[r.case, r.method, r.criterion,
             fmt.pm(r.delta_obs_pct, r.delta_obs_pct_se, n_runs=r.n_mc),
             fmt.pm(r.delta_error_signed_pp, r.delta_error_pp_se, n_runs=r.n_mc),
             fmt.pm(r.error_original_mean, r.error_original_se, n_runs=r.n_mc),
             fmt.pm(r.error_proposed_mean, r.error_proposed_se, n_runs=r.n_mc),
             fmt.pm_count(r.obs_proposed_mean, r.obs_proposed_se, n_runs=r.n_mc),
             fmt.pm(100 * r.stale_stop_fraction,
                    None if r.stale_stop_se is None else 100 * r.stale_stop_se, 1,
                    n_runs=r.n_mc)]
            for r in summary.rows]
    acc = [[a.case, a.method, fmt.pm(a.error_mean, a.error_se, n_runs=a.n_mc),
            fmt.pm(a.vs_exact_pp, a.vs_exact_pp_se, n_runs=a.n_mc),
            fmt.pm_count(a.unique_mean, a.unique_se, n_runs=a.n_mc),
            fmt.num(a.seconds_min if a.seconds_min is not None else a.seconds_mean, 3)]
           for a in summary.accuracy]
    return f"""## Multi-sensor Table I — original vs short-chain sampler, per multi-sensor sampler

The paper has no multi-sensor numbers (it expects "similar results", multi-sensor spec §5), so
there is no paper column. Cases {", ".join(cfg.cases)} (size/family, spec §6.5; random families
re-drawn every run); methods {", ".join(cfg.methods)}. Original sampler: one chain of
{cfg.original_obs:,} sweeps; short chains: {cfg.n_chains:,} × {cfg.chain_length}, τ_stall =
{cfg.tau_stall}, τ_stale = {cfg.tau_stale}, readings S3/T3, every chain from the all-missed
state; {fmt.plural(n, "Monte Carlo run")}. ΔObs as in the single-sensor Table I (spec eq.
1.10); the error column is the signed paired difference ε̄_s − ε̄_o (the paper's ΔError is its
absolute value), so a positive number is accuracy the short chains lose. Errors are exact
truncation errors against π; the component-wise sampler's is the π-mass its collapsed states
do not cover (its states merge "dead" with "missed by every sensor").
{fmt.runs_note(r.n_mc for r in summary.rows)}

**Verdict.** {summary.verdict} (Judged with {fmt.plural(n, "run")} per case; the full run
has 100.)

{fmt.table(["case", "method", "criterion", "ΔObs (%, > 0: short chains save)",
            "ε̄ short − ε̄ original (pp, > 0: short chains less accurate)", "ε̄ original (%)",
            "ε̄ short (%)", "N̄ short", "stale stops (%)"], main)}

Accuracy and time at equal sweeps: each method's original chain of {cfg.original_obs:,} sweeps
— the comparison is at an equal number of sweeps, which does not depend on the machine; the
wall time of the sampler call alone is a secondary column, the shortest of the
{fmt.plural(n, "run")} (the one the machine's load disturbed least):

{fmt.table(["case", "method", "ε̄ (%)", "ε̄ − ε̄ exact (pp, < 0: more accurate than exact)",
            "unique", "seconds (min over runs)"], acc)}

![Multi-sensor Table I: ΔObs and the error change per case, method and criterion](multisensor.png)
"""


def plot_multisensor(summary: MultiSensorSummary, directory: Path) -> list[str]:
    """One column per case: ΔObs and the signed error change per method and criterion (±1 SE),
    and each method's error at equal sweeps; short method names on the x axes, one legend."""
    cases = list(dict.fromkeys(r.case for r in summary.rows))
    methods = list(dict.fromkeys(r.method for r in summary.rows))
    by = {(r.case, r.method, r.criterion): r for r in summary.rows}
    acc = {(a.case, a.method): a for a in summary.accuracy}
    fig, axes = figure(len(cases), width=3.8, height=2.6, nrows=3, squeeze_row=False)
    x = np.arange(len(methods))
    w = 0.8 / len(CRITERIA)
    metrics = (("delta_obs_pct", "delta_obs_pct_se", "ΔObs (%)"),
               ("delta_error_signed_pp", "delta_error_pp_se", "ε̄ short − ε̄ original (pp)"))
    for col, case in enumerate(cases):
        for row, (key, se_key, label) in enumerate(metrics):
            ax = axes[row, col]
            for j, crit in enumerate(CRITERIA):
                rs = [by.get((case, m, crit)) for m in methods]
                ax.bar(x + (j - 1) * w, [getattr(r, key) if r else np.nan for r in rs], w,
                       yerr=[(getattr(r, se_key) or 0.0) if r else 0.0 for r in rs],
                       capsize=0, ecolor="0.3", label=f"short chains, {crit}",
                       **bar_style(j))
            ax.axhline(0.0, color="0.3", lw=0.6)
            ax.set_ylabel(label if col == 0 else "")
            ax.set_title(case, fontsize=10)
        ax = axes[2, col]
        a = [acc.get((case, m)) for m in methods]
        ax.bar(x, [r.error_mean if r else np.nan for r in a], 0.6,
               yerr=[(r.error_se or 0.0) if r else 0.0 for r in a], capsize=0, ecolor="0.3",
               label=f"original chain, {summary.accuracy[0].n_obs:,} sweeps"
               if summary.accuracy else None, **bar_style(len(CRITERIA)))
        ax.set_ylabel("ε̄ at equal sweeps (%)" if col == 0 else "")
        ax.set_title(case, fontsize=10)
        for row in range(3):
            axes[row, col].set_xticks(x, methods, fontsize=8)
            axes[row, col].grid(True, axis="y", alpha=0.3)
    legend_below(fig, axes.ravel(), ncol=4)
    fig.suptitle("Multi-sensor Table I per case (bars ±1 SE) and each method's error at equal "
                 "sweeps", fontsize=10)
    fig.savefig(Path(directory) / "multisensor.png", dpi=110)
    return ["multisensor.png"]


def _csv(summary: MultiSensorSummary) -> list[dict]:
    return as_rows(list(summary.rows))


MULTISENSOR = register_study(Study(
    name="multisensor",
    title="multi-sensor Table I: original vs short chains for every multi-sensor sampler",
    config_type=MultiSensorConfig,
    full=MultiSensorConfig,
    quick=lambda: MultiSensorConfig(n_mc=QUICK_MC),
    tasks=multisensor_tasks,
    task=multisensor_task,
    run_from_dict=MultiSensorRun.from_dict,
    summarise=summarise_multisensor,
    render=render_multisensor,
    plot=plot_multisensor,
    csv_rows=_csv,
    order=80,
    default_run=False,
    warm=lambda c: replace(c, n_mc=1, original_obs=100, n_chains=4),
))
