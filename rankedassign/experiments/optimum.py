"""How far the samplers are from the best possible truncation error for their sample size.

With ``k`` distinct solutions no method can do better than keeping the ``k`` heaviest
assignments: ``eps*(k) = 1 - best_mass(k)``. This study puts the short-chain sampler's (and the
original sampler's) error next to ``eps*`` at the same ``k``.
"""

from __future__ import annotations

import math
from concurrent.futures import Executor
from functools import lru_cache

import numpy as np

from ._executor import run_seed, run_tasks
from ._synthetic import make_problem, original_seed, proposed_seed, run_original, run_proposed
from .config import STALE_READINGS, STALL_READINGS, Config, OptimumConfig, study_config

__all__ = ["run_optimum", "best_error", "summarise_optimum"]

#: Enumerate (and sort) every feasible assignment up to this many; beyond, ask the oracle.
_ENUMERATION_LIMIT = 2_000_000


def _tail_weights(problem) -> np.ndarray | None:
    """Suffix sums of the sorted normalised weights: ``tail[k] = sum_{i >= k} w_(i) / Z``."""
    import oracle

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
    k : int
        Number of distinct assignments (``k >= |Gamma|`` gives 0).

    Returns
    -------
    float
        ``1 - (sum of the k largest weights) / Z``.

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
        import oracle

        return max(0.0, 1.0 - float(oracle.best_mass(problem, int(k))))
    return float(tail[min(int(k), len(tail) - 1)])


def _optimum_task(cfg: OptimumConfig, seed: int, run: int, family: str) -> dict:
    s = run_seed(seed, run)
    problem = make_problem(family, s, cfg)
    tail = _cached_tail(problem) if family in ("diagonal", "uniform") else _tail_weights(problem)
    stall, stale = STALL_READINGS[0], STALE_READINGS[0]
    out = {"run": run, "family": family}
    for name, rec in (
        ("original", run_original(problem, cfg.original_obs, original_seed(s, family))),
        (
            "proposed",
            run_proposed(
                problem, cfg, proposed_seed(s, family, stall, stale), stall=stall, stale=stale
            ),
        ),
    ):
        rec["best_error"] = best_error(problem, rec["n_unique"], _tail=tail)
        out[name] = rec
    return out


def summarise_optimum(runs: list[dict], families) -> list[dict]:
    """Rows ``(family, sampler)``: mean distinct solutions, error and best error (in %)."""
    rows = []
    for fam in families:
        rs = [r for r in runs if r["family"] == fam]
        n = len(rs)
        for sampler in ("original", "proposed"):
            e = 100.0 * np.array([r[sampler]["error"] for r in rs])
            b = 100.0 * np.array([r[sampler]["best_error"] for r in rs])
            k = np.array([r[sampler]["n_unique"] for r in rs], dtype=float)
            obs = np.array([r[sampler]["n_obs"] for r in rs], dtype=float)

            def se(x, n=n):
                return float(x.std(ddof=1) / math.sqrt(n)) if n > 1 else None

            rows.append(
                {
                    "family": fam,
                    "sampler": sampler,
                    "n_mc": n,
                    "obs_mean": float(obs.mean()),
                    "n_unique_mean": float(k.mean()),
                    "error_pct_mean": float(e.mean()),
                    "error_pct_se": se(e),
                    "best_error_pct_mean": float(b.mean()),
                    "best_error_pct_se": se(b),
                    "excess_error_pp_mean": float((e - b).mean()),
                    "excess_error_pp_se": se(e - b),
                }
            )
    return rows


def run_optimum(
    config: OptimumConfig | Config | None = None,
    *,
    seed: int = 0,
    executor: Executor | None = None,
    progress: bool = True,
    return_runs: bool = False,
):
    """Sampled truncation error against the best error with as many distinct solutions.

    Parameters
    ----------
    config : OptimumConfig or Config, optional
        Settings (default: the paper's per-run settings, 100 runs).
    seed : int, optional
        Study seed (same streams as :func:`run_table1`: the ``"proposed"`` runs are Table I's
        ``"full"`` runs and the ``"original"`` runs its original runs).
    executor : concurrent.futures.Executor, optional
        Where to run the Monte Carlo runs (default: in this process).
    progress : bool, optional
        Show a progress bar on stderr.
    return_runs : bool, optional
        Also return the per-run records.

    Returns
    -------
    rows : list of dict
        One row per family and sampler (``"original"``, ``"proposed"``) with keys
        ``n_unique_mean``, ``error_pct_mean``, ``best_error_pct_mean``,
        ``excess_error_pp_mean`` (and standard errors over runs, ``None`` for one run).
    runs : list of dict
        Per-run records, only if ``return_runs``.

    References
    ----------
    .. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, arXiv:2306.15135, 2023.
    .. [2] K. G. Murty, "An Algorithm for Ranking all the Assignments in Order of Increasing
       Cost", Operations Research 16(3), 1968.

    Examples
    --------
    >>> from rankedassign.experiments import OptimumConfig, run_optimum
    >>> cfg = OptimumConfig(n_mc=1, families=("uniform",), original_obs=200, n_chains=8)
    >>> row = run_optimum(cfg, progress=False)[1]
    >>> row["sampler"], row["error_pct_mean"] >= row["best_error_pct_mean"]
    ('proposed', True)
    """
    cfg = study_config(config, "optimum", OptimumConfig)
    tasks = [(cfg, seed, r, fam) for fam in cfg.families for r in range(cfg.n_mc)]
    runs = run_tasks(_optimum_task, tasks, executor=executor, progress=progress, desc="optimum")
    rows = summarise_optimum(runs, cfg.families)
    return (rows, runs) if return_runs else rows
