"""The paper's Table I: original vs short-chain sampler on the 4 x 24 synthetic matrices."""

from __future__ import annotations

from concurrent.futures import Executor

from ._executor import run_seed, run_tasks
from ._synthetic import (
    make_problem,
    original_seed,
    paired_summary,
    proposed_seed,
    run_original,
    run_proposed,
)
from .config import CRITERIA, STALE_READINGS, STALL_READINGS, Config, Table1Config, study_config

__all__ = ["run_table1", "summarise_table1"]

#: Active termination rules (stall reading, stale reading) of each Table I column, with the
#: recommended readings S3 / T3 of spec §3.3.
_CRITERION_RULES = {
    "stall": (STALL_READINGS[0], None),
    "stale": (None, STALE_READINGS[0]),
    "full": (STALL_READINGS[0], STALE_READINGS[0]),
}


def _table1_task(cfg: Table1Config, seed: int, run: int, family: str) -> dict:
    """One Monte Carlo run of one family: the original sampler and the three criteria."""
    s = run_seed(seed, run)
    problem = make_problem(family, s, cfg)
    out = {
        "run": run,
        "family": family,
        "original": run_original(problem, cfg.original_obs, original_seed(s, family)),
    }
    for crit in CRITERIA:
        stall, stale = _CRITERION_RULES[crit]
        out[crit] = run_proposed(
            problem, cfg, proposed_seed(s, family, stall, stale), stall=stall, stale=stale
        )
    return out


def summarise_table1(runs: list[dict], families=None) -> list[dict]:
    """Table I rows (one per family x criterion) from per-run records of :func:`run_table1`.

    Parameters
    ----------
    runs : list of dict
        Per-run records (``run_table1(..., return_runs=True)[1]``).
    families : sequence of str, optional
        Row order (default: order of first appearance).

    Returns
    -------
    list of dict
        Keys ``family``, ``criterion`` and those of the paired summary (``delta_obs_pct``,
        ``delta_error_pp``, their ``_se``, raw means, ``mean_abs_delta_error_pp``, ``n_mc``).
    """
    if families is None:
        families = list(dict.fromkeys(r["family"] for r in runs))
    rows = []
    for fam in families:
        rs = sorted((r for r in runs if r["family"] == fam), key=lambda r: r["run"])
        for crit in CRITERIA:
            row = {"family": fam, "criterion": crit}
            row.update(paired_summary([r["original"] for r in rs], [r[crit] for r in rs]))
            rows.append(row)
    return rows


def run_table1(
    config: Table1Config | Config | None = None,
    *,
    seed: int = 0,
    executor: Executor | None = None,
    progress: bool = True,
    return_runs: bool = False,
):
    """Reproduce the paper's Table I.

    For each family and Monte Carlo run the original sampler (one chain of
    ``config.original_obs`` sweeps) and the short-chain sampler (``n_chains`` x
    ``chain_length``) with stall only, stale only and both rules (``tau_stall``,
    ``tau_stale``; readings S3 and T3 of spec §3.3) run on the same matrix with independent
    streams; the truncation error (spec 1.9) of every output is exact (:mod:`oracle`).

    Parameters
    ----------
    config : Table1Config or Config, optional
        Settings (default: the paper's, 100 runs).
    seed : int, optional
        Study seed; run ``r`` uses ``np.random.SeedSequence(seed).spawn(n_mc)[r]``.
    executor : concurrent.futures.Executor, optional
        Where to run the Monte Carlo runs (default: in this process).
    progress : bool, optional
        Show a progress bar on stderr.
    return_runs : bool, optional
        Also return the per-run records.

    Returns
    -------
    rows : list of dict
        One row per family and criterion (:func:`summarise_table1`).
    runs : list of dict
        Per-run records, only if ``return_runs``.

    Notes
    -----
    ``delta_obs_pct = 100 (mean N_o - mean N_s) / mean N_o`` and
    ``delta_error_pp = |mean eps_o - mean eps_s|`` (spec eq. 1.10, percentage points). Standard
    errors: delta method for the ratio of paired means (observations); standard error of the
    mean paired per-run difference (errors).

    References
    ----------
    .. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023, Table I.

    Examples
    --------
    >>> from rankedassign.experiments import Table1Config, run_table1
    >>> cfg = Table1Config(n_mc=1, families=("diagonal",), original_obs=500, n_chains=40)
    >>> rows = run_table1(cfg, seed=1, progress=False)
    >>> [(r["family"], r["criterion"]) for r in rows]
    [('diagonal', 'stall'), ('diagonal', 'stale'), ('diagonal', 'full')]
    """
    cfg = study_config(config, "table1", Table1Config)
    tasks = [(cfg, seed, r, fam) for fam in cfg.families for r in range(cfg.n_mc)]
    runs = run_tasks(_table1_task, tasks, executor=executor, progress=progress, desc="table1")
    rows = summarise_table1(runs, cfg.families)
    return (rows, runs) if return_runs else rows

