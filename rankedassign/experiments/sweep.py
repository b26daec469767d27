"""Truncation error against the number of observations, without early stopping."""

from __future__ import annotations

import math
from concurrent.futures import Executor

import numpy as np

from ._executor import child_seed, run_seed, run_tasks
from ._synthetic import KEY_SWEEP, family_index, make_problem, record
from .config import Config, SweepConfig, study_config

__all__ = ["run_sweep", "summarise_sweep"]


def _sweep_task(cfg: SweepConfig, seed: int, run: int, family: str) -> dict:
    """Every grid point of one run and family.

    Each sampler keeps one stream across the grid, so a run's curve follows one sampler
    trajectory observed after more and more sweeps (sampler outputs are prefix-consistent).
    """
    from .. import sample_original, sample_short_chains

    s = run_seed(seed, run)
    problem = make_problem(family, s, cfg)
    fi = family_index(family)
    out = {"run": run, "family": family, "points": []}
    for n in cfg.obs_grid:
        res = sample_original(problem, n, rng=child_seed(s, KEY_SWEEP, fi, 0))
        out["points"].append({"sampler": "original", "chain_length": None, "budget": n,
                              **record(problem, res)})
        for L in cfg.chain_lengths:
            if n < L:
                continue
            res = sample_short_chains(problem, n // L, L, rng=child_seed(s, KEY_SWEEP, fi, L))
            out["points"].append({"sampler": f"short-{L}", "chain_length": L, "budget": n,
                                  **record(problem, res)})
    return out


def summarise_sweep(runs: list[dict]) -> list[dict]:
    """Rows ``(family, sampler, budget)``: error statistics over runs (percent)."""
    groups: dict[tuple, list[dict]] = {}
    diffs: dict[tuple, list[float]] = {}
    for r in runs:
        ref = {p["budget"]: p["error"] for p in r["points"] if p["sampler"] == "original"}
        for p in r["points"]:
            key = (r["family"], p["sampler"], p["budget"])
            groups.setdefault(key, []).append(p)
            # Paired with the original sampler of the same run (same matrix) and budget.
            diffs.setdefault(key, []).append(100.0 * (p["error"] - ref[p["budget"]]))
    rows = []
    for (fam, sampler, budget), ps in groups.items():
        e = 100.0 * np.array([p["error"] for p in ps])
        d = np.array(diffs[fam, sampler, budget])
        n = len(ps)
        rows.append(
            {
                "family": fam,
                "sampler": sampler,
                "chain_length": ps[0]["chain_length"],
                "budget": budget,
                "n_obs_mean": float(np.mean([p["n_obs"] for p in ps])),
                "n_unique_mean": float(np.mean([p["n_unique"] for p in ps])),
                "error_pct_mean": float(e.mean()),
                "error_pct_se": float(e.std(ddof=1) / math.sqrt(n)) if n > 1 else None,
                "error_pct_q10": float(np.quantile(e, 0.1)),
                "error_pct_q90": float(np.quantile(e, 0.9)),
                "diff_vs_original_pp_mean": float(d.mean()),
                "diff_vs_original_pp_se": float(d.std(ddof=1) / math.sqrt(n)) if n > 1 else None,
                "n_mc": n,
            }
        )
    return rows


def run_sweep(
    config: SweepConfig | Config | None = None,
    *,
    seed: int = 0,
    executor: Executor | None = None,
    progress: bool = True,
    return_runs: bool = False,
):
    """Truncation error (spec 1.9) against the observation budget, no stall/stale.

    The original sampler runs ``n`` sweeps; the short-chain sampler ``n // L`` chains of length
    ``L`` for every ``L`` in ``config.chain_lengths`` (budgets below ``L`` are skipped).

    Parameters
    ----------
    config : SweepConfig or Config, optional
        Settings (default: 100 runs, 11 budgets from 100 to 250 000, ``L`` = 5 ... 100).
    seed : int, optional
        Study seed; the random family draws the same matrices as :func:`run_table1`.
    executor : concurrent.futures.Executor, optional
        Where to run the Monte Carlo runs (default: in this process).
    progress : bool, optional
        Show a progress bar on stderr.
    return_runs : bool, optional
        Also return the per-run records.

    Returns
    -------
    rows : list of dict
        One row per family, sampler (``"original"`` or ``"short-L"``) and budget with the mean,
        standard error and 10 %/90 % quantiles of the error over runs (percent), and the mean
        paired difference to the original sampler at the same budget in the same run
        (``diff_vs_original_pp_mean``, percentage points).
    runs : list of dict
        Per-run records, only if ``return_runs``.

    Notes
    -----
    With short chains every chain restarts from the all-missed state, so a budget spent on
    short chains revisits the states near it; the curves show what this costs (or saves) in
    error at equal observation counts.

    References
    ----------
    .. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, arXiv:2306.15135, 2023.
    .. [2] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8), 2017.

    Examples
    --------
    >>> from rankedassign.experiments import SweepConfig, run_sweep
    >>> cfg = SweepConfig(n_mc=1, families=("uniform",), obs_grid=(10, 100), chain_lengths=(5,))
    >>> rows = run_sweep(cfg, progress=False)
    >>> [(r["sampler"], r["budget"]) for r in rows]
    [('original', 10), ('short-5', 10), ('original', 100), ('short-5', 100)]
    """
    cfg = study_config(config, "sweep", SweepConfig)
    tasks = [(cfg, seed, r, fam) for fam in cfg.families for r in range(cfg.n_mc)]
    runs = run_tasks(_sweep_task, tasks, executor=executor, progress=progress, desc="sweep")
    rows = summarise_sweep(runs)
    return (rows, runs) if return_runs else rows
