"""Reproduction of the studies of Trezza, Bucci & Varshney (2023).

Every study is described once, by a :class:`Study` in the registry (:func:`get_study`,
:func:`study_names`), and run by :func:`run_study`, which returns typed summary records; the
command line (``rankedassign reproduce``), :func:`reproduce` and the report read the same
registry:

* ``table1`` — the paper's Table I (ΔObs, ΔError, with Monte Carlo standard errors), beside the
  paper's numbers;
* ``sweep`` — truncation error against observations for several chain lengths;
* ``tracking`` — the LMB tracking study (OSPA(2), observations, row updates);
* ``tracking_var`` — the same under the reading that reproduces the paper's totals;
* ``ablation`` — Table I under every reading of the stall/stale rules (spec §3.2);
* ``optimum`` — sampled error against the best error for as many distinct solutions;
* ``random_readings`` — Table I under every reading of the random family (spec A2, A5);
* ``multisensor`` — Table I for every multi-sensor sampler, and each one's error at equal
  sweeps (no paper numbers);
* ``adaptive_birth`` — Table I and error curves of the adaptive-birth sampler (no paper
  numbers);
* ``tempering_herding`` — herded, tempered and LBP association graded by the exact oracle on
  every problem kind, and in the LMB filter (the paper's future work; no paper numbers).

Adding a study is adding one module that registers a :class:`Study` and importing it below.

Monte Carlo runs go through a :mod:`concurrent.futures` executor (local processes or a Dask
cluster); run ``r`` draws only from ``np.random.SeedSequence(seed).spawn(n)[r]``, so results do
not depend on where or in which order runs execute.
"""

# Importing a study module registers its studies (run order: each Study's ``order``).
from ._executor import (
    SchedulerError,
    child_seed,
    dask_executor,
    local_executor,
    run_seed,
    run_tasks,
)
from ._synthetic import Table1Row
from .config import (
    ALL_FAMILIES,
    CRITERIA,
    FAMILIES,
    STALE_READINGS,
    STALL_READINGS,
)
from .paper import PAPER_TABLE1, PAPER_TOTALS
from .registry import (
    Config,
    ReproduceError,
    Study,
    config_from_dict,
    default_study_names,
    get_study,
    register_study,
    run_study,
    study_names,
    warm_plan,
    warm_study,
)
from .runner import StudyFailed, check_output, reproduce
from .studies import (  # noqa: F401  (each module registers its study)
    ablation,
    adaptive_birth,
    glmb_tracking,
    multisensor,
    multisensor_tracking,
    nonlinear_tracking,
    optimum,
    readings,
    scaling,
    sweep,
    table1,
    tempering_herding,
    tracking,
)
from .studies.ablation import AblationConfig, AblationRow
from .studies.optimum import OptimumConfig, OptimumRow, best_error
from .studies.readings import ReadingRow
from .studies.sweep import ChainLengthCheck, SweepConfig, SweepRow
from .studies.table1 import Table1Config
from .studies.tracking import TrackingConfig, TrackingSummary

#: The built-in studies, in run order (:func:`study_names` also lists studies registered later).
STUDIES = study_names()

__all__ = [
    "ALL_FAMILIES",
    "AblationConfig",
    "AblationRow",
    "CRITERIA",
    "ChainLengthCheck",
    "Config",
    "FAMILIES",
    "OptimumConfig",
    "OptimumRow",
    "PAPER_TABLE1",
    "PAPER_TOTALS",
    "ReadingRow",
    "ReproduceError",
    "StudyFailed",
    "STALE_READINGS",
    "STALL_READINGS",
    "STUDIES",
    "SchedulerError",
    "Study",
    "SweepConfig",
    "SweepRow",
    "Table1Config",
    "Table1Row",
    "TrackingConfig",
    "TrackingSummary",
    "best_error",
    "check_output",
    "child_seed",
    "config_from_dict",
    "default_study_names",
    "dask_executor",
    "get_study",
    "local_executor",
    "register_study",
    "reproduce",
    "run_seed",
    "run_study",
    "run_tasks",
    "study_names",
    "warm_study",
    "warm_plan",
]
