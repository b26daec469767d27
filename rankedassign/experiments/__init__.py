"""Reproduction of the studies of Trezza, Bucci & Varshney (2023).

Each study is a plain function returning plain data (lists of dicts or a dict), so the command
line (``rankedassign reproduce``), the documentation and notebooks share one implementation:

* :func:`run_table1` — the paper's Table I (ΔObs, ΔError, with Monte Carlo standard errors);
* :func:`run_sweep` — truncation error against observations for several chain lengths;
* :func:`run_tracking` — the LMB tracking study (OSPA(2), observations, row updates);
* :func:`run_tracking_var` — the same under the reading that reproduces the paper's totals;
* :func:`run_ablation` — Table I under every reading of the stall/stale rules (spec §3.2);
* :func:`run_optimum` — sampled error against the best error for as many distinct solutions;
* :func:`reproduce` — all of the above into a report directory (markdown, PNG, JSON, CSV).

Monte Carlo runs go through a :mod:`concurrent.futures` executor (local processes or a Dask
cluster); run ``r`` draws only from ``np.random.SeedSequence(seed).spawn(n)[r]``, so results do
not depend on where or in which order runs execute.
"""

from ._executor import (
    SchedulerError,
    child_seed,
    dask_executor,
    local_executor,
    run_seed,
    run_tasks,
)
from .ablation import run_ablation
from .config import (
    ALL_FAMILIES,
    CRITERIA,
    FAMILIES,
    STALE_READINGS,
    STALL_READINGS,
    STUDIES,
    AblationConfig,
    Config,
    OptimumConfig,
    SweepConfig,
    Table1Config,
    TrackingConfig,
)
from .optimum import best_error, run_optimum
from .runner import ReproduceError, config_from_dict, reproduce
from .sweep import run_sweep
from .table1 import run_table1
from .tracking import PAPER_TOTALS, run_tracking, run_tracking_var

__all__ = [
    "ALL_FAMILIES",
    "AblationConfig",
    "CRITERIA",
    "Config",
    "FAMILIES",
    "OptimumConfig",
    "PAPER_TOTALS",
    "ReproduceError",
    "STALE_READINGS",
    "STALL_READINGS",
    "STUDIES",
    "SchedulerError",
    "SweepConfig",
    "Table1Config",
    "TrackingConfig",
    "best_error",
    "child_seed",
    "config_from_dict",
    "dask_executor",
    "local_executor",
    "reproduce",
    "run_ablation",
    "run_optimum",
    "run_seed",
    "run_sweep",
    "run_table1",
    "run_tasks",
    "run_tracking",
    "run_tracking_var",
]
