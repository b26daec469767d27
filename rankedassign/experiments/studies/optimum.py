"""How far the samplers are from the best possible truncation error for their sample size.

With ``k`` distinct solutions no method can do better than keeping the ``k`` heaviest
assignments: ``eps*(k) = 1 - best_mass(k)``. This study puts the short-chain sampler's (and the
original sampler's) error next to ``eps*`` at the same ``k``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

import oracle

from .. import _format as fmt
from .._plots import bar_style, figure, legend_below
from .._records import RunRecord
from .._synthetic import (
    SamplerRun,
    paired_calls,
    tiny_synthetic,
)
from ..config import STALE_READINGS, STALL_READINGS, SyntheticConfig
from ..registry import Study, as_rows, per_family_tasks, register_study


@dataclass(frozen=True)
class OptimumConfig(SyntheticConfig):
    """Sampled truncation error next to the best error with as many distinct solutions.

    The short-chain sampler runs with both rules under the recommended readings (S3, T3).

    Attributes
    ----------
    n_mc, families, original_obs, n_chains, chain_length
        As in :class:`~rankedassign.experiments.config.SyntheticConfig`.
    tau_stall, tau_stale, pbar_d, granularity, diagonal_pbar_d
        As in :class:`~rankedassign.experiments.config.SyntheticConfig`.

    Examples
    --------
    >>> from rankedassign.experiments import OptimumConfig
    >>> OptimumConfig().tau_stale
    25
    """

__all__ = ["OPTIMUM", "OptimumRow", "OptimumRun", "OptimumCall", "best_error", "summarise_optimum"]

#: Quick mode: Monte Carlo runs (the per-run settings are the paper's).
QUICK_MC = 20

#: Enumerate (and sort) every feasible assignment up to this many; beyond, ask the oracle.
_ENUMERATION_LIMIT = 2_000_000


def _tail_weights(problem) -> np.ndarray | None:
    """Suffix sums of the sorted normalised weights: ``tail[k] = sum_{i >= k} w_(i) / Z``."""
    if problem.n_feasible() > _ENUMERATION_LIMIT:
        return None
    costs = oracle.enumerate_assignments(problem, limit=_ENUMERATION_LIMIT).costs
    logw = -np.asarray(costs, dtype=float)
    w = np.exp(logw - logw.max())  # sorted by cost = by decreasing weight
    # Sum from the light end so small tails keep their relative precision.
    tail = np.concatenate([np.cumsum(w[::-1])[::-1], [0.0]])
    return tail / tail[0]


_cached_tail = lru_cache(maxsize=4)(_tail_weights)


def best_error(problem, k: int, *, _tail=None) -> float:
    """Smallest truncation error (spec 1.9) of any set of ``k`` distinct assignments.

    Parameters
    ----------
    problem : AssignmentProblem
        The single-sensor problem whose target ``pi = w / Z`` the error is measured against.
    k : int
        Number of distinct assignments (``k >= |Gamma|`` gives 0).
    _tail : ndarray of float64, shape (|Gamma| + 1,), optional
        Internal: the suffix sums ``tail[k] = sum_{i >= k} w_(i) / Z`` of the sorted
        normalised weights, when the caller already enumerated them (the study computes them
        once per problem for both samplers). Leave it ``None``.

    Returns
    -------
    float
        ``1 - (sum of the k largest weights) / Z``, in ``[0, 1]``.

    Raises
    ------
    ValueError
        If ``k`` is not a non-negative integer.

    Notes
    -----
    Exact: every feasible assignment is enumerated and sorted
    (:func:`oracle.enumerate_assignments`) when there are at most two million of them,
    otherwise :func:`oracle.best_mass` (Murty's k-best) is used. On the uniform family the
    answer is ``1 - k / |Gamma|``.

    References
    ----------
    .. [1] K. G. Murty, "An Algorithm for Ranking all the Assignments in Order of Increasing
       Cost", Operations Research 16(3), 1968.

    Examples
    --------
    >>> from rankedassign import synthetic
    >>> from rankedassign.experiments import best_error
    >>> round(best_error(synthetic.uniform(), 76848 // 2), 6)
    0.5
    """
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 0:
        raise ValueError(f"k must be a non-negative integer, got {k!r}")
    tail = _tail if _tail is not None else _tail_weights(problem)
    if tail is None:
        return max(0.0, 1.0 - float(oracle.best_mass(problem, int(k))))
    return float(tail[min(int(k), len(tail) - 1)])


@dataclass(frozen=True)
class OptimumCall(SamplerRun):
    """One sampler's call with the best error for as many distinct assignments.

    Attributes
    ----------
    n_obs, n_row_updates, n_unique, n_chains, stop_reason, error
        As in ``SamplerRun`` (``rankedassign.experiments._synthetic``).
    best_error : float
        ``eps*(k)`` for ``k = n_unique`` (:func:`best_error`), a fraction.
    """

    best_error: float


@dataclass(frozen=True)
class OptimumRun(RunRecord):
    """One run of one family: both samplers, each beside its best error.

    Attributes
    ----------
    run : int
        Monte Carlo run.
    family : str
        Matrix family.
    original, proposed : OptimumCall
        The original sampler and the short chains with both rules (S3, T3).
    """

    run: int
    family: str
    original: OptimumCall
    proposed: OptimumCall

    @classmethod
    def from_dict(cls, data: dict) -> OptimumRun:
        """The record of one object of ``optimum_runs.json``.

        Parameters
        ----------
        data : dict
            Its fields, each sampler's call as an object.

        Returns
        -------
        OptimumRun
        """
        calls = {k: OptimumCall.from_dict(data[k]) for k in ("original", "proposed")
                 if k in data}
        return super().from_dict({**data, **calls})


def optimum_task(cfg: OptimumConfig, seed: int, run: int, family: str) -> OptimumRun:
    """One run of one family: both samplers and the best error for their distinct count."""
    problem, original, proposed = paired_calls(cfg, seed, run, family)
    tail = _cached_tail(problem) if family in ("diagonal", "uniform") else _tail_weights(problem)
    out = {}
    for name, rec in (("original", original),
                      ("proposed", proposed(STALL_READINGS[0], STALE_READINGS[0]))):
        out[name] = OptimumCall(**rec.to_dict(),
                                best_error=best_error(problem, rec.n_unique, _tail=tail))
    return OptimumRun(run=run, family=family, **out)


@dataclass(frozen=True)
class OptimumRow:
    """One family and sampler: mean distinct solutions, error and best error (percent).

    Standard errors are ``None`` for one run.

    Attributes
    ----------
    family : str
        Matrix family (:data:`~rankedassign.experiments.config.ALL_FAMILIES`).
    sampler : {"original", "proposed"}
        The original sampler or the short-chain sampler with both rules (S3, T3).
    n_mc : int
        Monte Carlo runs.
    obs_mean : float
        Mean observations (sweeps) per run.
    n_unique_mean : float
        Mean number ``k`` of distinct assignments found.
    error_pct_mean : float
        Mean truncation error ``eps`` (spec eq. 1.9), in percent.
    error_pct_se : float or None
        Its standard error.
    best_error_pct_mean : float
        Mean best error ``eps*(k)`` with the same number of distinct assignments
        (:func:`best_error`), in percent.
    best_error_pct_se : float or None
        Its standard error.
    excess_error_pp_mean : float
        Mean per-run excess ``eps - eps*(k)``, in percentage points.
    excess_error_pp_se : float or None
        Its standard error.
    obs_se, n_unique_se : float or None
        Standard errors of ``obs_mean`` and ``n_unique_mean``; ``None`` for one run.
    """

    family: str
    sampler: str
    n_mc: int
    obs_mean: float
    n_unique_mean: float
    error_pct_mean: float
    error_pct_se: float | None
    best_error_pct_mean: float
    best_error_pct_se: float | None
    excess_error_pp_mean: float
    excess_error_pp_se: float | None
    # last and with defaults, so a record built with the fields above stays valid
    obs_se: float | None = None
    n_unique_se: float | None = None


def summarise_optimum(runs: list[OptimumRun], families) -> list[OptimumRow]:
    """Rows ``(family, sampler)``: mean distinct solutions, error and best error (in %).

    Parameters
    ----------
    runs : list of OptimumRun
        Per-run records of the study's task, each sampler's call holding ``n_obs``,
        ``n_unique``, ``error`` and ``best_error`` (fractions).
    families : sequence of str
        Families to summarise, in report order.

    Returns
    -------
    list of OptimumRow
        Per family the ``"original"`` row then the ``"proposed"`` row.
    """
    rows = []
    for fam in families:
        rs = [r for r in runs if r.family == fam]
        n = len(rs)
        for sampler in ("original", "proposed"):
            calls = [getattr(r, sampler) for r in rs]
            e = 100.0 * np.array([c.error for c in calls])
            b = 100.0 * np.array([c.best_error for c in calls])
            k = np.array([c.n_unique for c in calls], dtype=float)
            obs = np.array([c.n_obs for c in calls], dtype=float)

            def se(x, n=n):
                return float(x.std(ddof=1) / math.sqrt(n)) if n > 1 else None

            rows.append(OptimumRow(
                family=fam,
                sampler=sampler,
                n_mc=n,
                obs_mean=float(obs.mean()),
                n_unique_mean=float(k.mean()),
                error_pct_mean=float(e.mean()),
                error_pct_se=se(e),
                best_error_pct_mean=float(b.mean()),
                best_error_pct_se=se(b),
                excess_error_pp_mean=float((e - b).mean()),
                excess_error_pp_se=se(e - b),
                obs_se=se(obs),
                n_unique_se=se(k),
            ))
    return rows


_HEADER = ["family", "sampler", "observations", "unique k", "ε (%)", "ε*(k) (%)",
           "ε − ε* (pp, > 0: above the best possible)"]


def _verdict(rows: list[OptimumRow]) -> str:
    """How far each sampler's unique set is from the best set of the same size, per family."""
    parts = []
    for fam in dict.fromkeys(r.family for r in rows):
        cells = []
        for r in (r for r in rows if r.family == fam):
            who = "the short chains" if r.sampler == "proposed" else "the original chain"
            cells.append(f"{who} {fmt.pm(r.excess_error_pp_mean, r.excess_error_pp_se, 4)} pp "
                         f"above the best error for {fmt.integer(r.n_unique_mean)} "
                         f"solutions ({fmt.pm(r.error_pct_mean, r.error_pct_se)} % against "
                         f"{fmt.pm(r.best_error_pct_mean, r.best_error_pct_se)} %)")
        parts.append(f"{fam}: " + ", ".join(cells))
    return ("A sampler's error exceeds the smallest possible for as many distinct solutions "
            "by: " + "; ".join(parts) + ". The excess is the mass the sampled solutions miss "
            "among the heaviest ones; where it is near zero the sampler finds the best "
            "solutions first.")


def render_optimum(rows: list[OptimumRow], cfg: OptimumConfig) -> str:
    """The optimum section (the paper has no such study)."""
    body = [
        [r.family, r.sampler, fmt.pm_count(r.obs_mean, r.obs_se, n_runs=r.n_mc),
         fmt.pm_count(r.n_unique_mean, r.n_unique_se, n_runs=r.n_mc),
         fmt.pm(r.error_pct_mean, r.error_pct_se, n_runs=r.n_mc),
         fmt.pm(r.best_error_pct_mean, r.best_error_pct_se, n_runs=r.n_mc),
         fmt.pm(r.excess_error_pp_mean, r.excess_error_pp_se, n_runs=r.n_mc)]
        for r in rows
    ]
    n = rows[0].n_mc if rows else 0
    return f"""## Optimum — sampled error against the best error for the same number of solutions

For k distinct solutions the smallest possible truncation error is that of the k heaviest
assignments, ε*(k) = 1 − best_mass(k) (exact: all 76,848 feasible assignments enumerated and
sorted). Proposed = the Table I "full" runs (same streams), {fmt.plural(n, "Monte Carlo run")}.
The paper has no such study. {fmt.runs_note(r.n_mc for r in rows)}

**Verdict.** {_verdict(rows)}

{fmt.table(_HEADER, body)}

![optimum](optimum.png)
"""


def plot_optimum(rows: list[OptimumRow], directory: Path) -> list[str]:
    """Sampled error vs the best error at the same number of distinct solutions."""
    fams = list(dict.fromkeys(r.family for r in rows))
    fig, (ax,) = figure()
    x = np.arange(len(fams))
    by = {(r.family, r.sampler): r for r in rows}
    series = [("original", "error_pct_mean", "original ε"),
              ("original", "best_error_pct_mean", "ε*(k original)"),
              ("proposed", "error_pct_mean", "short-chain ε"),
              ("proposed", "best_error_pct_mean", "ε*(k short-chain)")]
    w = 0.8 / len(series)
    for j, (s, key, label) in enumerate(series):
        v = [max(getattr(by[f, s], key), 1e-12) for f in fams]
        ax.bar(x + (j - 1.5) * w, v, w, label=label, **bar_style(j))
    ax.set_yscale("log")
    ax.set_xticks(x, fams)
    ax.set_ylabel("truncation error (%)")
    ax.set_title("Sampled error against the best error for as many solutions")
    ax.grid(True, axis="y", which="both", alpha=0.3)
    legend_below(fig, [ax], ncol=2)
    fig.savefig(directory / "optimum.png", dpi=110)
    return ["optimum.png"]


OPTIMUM = register_study(Study(
    name="optimum",
    title="sampled error against the best error for as many distinct solutions",
    config_type=OptimumConfig,
    full=OptimumConfig,
    quick=lambda: OptimumConfig(n_mc=QUICK_MC),
    tasks=per_family_tasks,
    task=optimum_task,
    run_from_dict=OptimumRun.from_dict,
    summarise=lambda runs, cfg: summarise_optimum(runs, cfg.families),
    render=render_optimum,
    plot=plot_optimum,
    csv_rows=as_rows,
    order=60,
    warm=tiny_synthetic,
    warm_after="table1",  # Table I's samplers, compiled by its first tiny task
))
