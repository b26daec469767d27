"""The multi-sensor tracking study, registered for ``rankedassign reproduce multisensor_tracking``.

The computation lives in :mod:`rankedassign.tracking.multisensor_study`: on the ``"multi"``
scenario (multi-sensor spec §7.2) the measurements of every sensor are drawn once per run, and
each sensor set (``V = 1, 2, 3``) and association runs on the same data; the study reports
OSPA(2) and the cardinality error per scan, the sampler work (sweeps, row updates, calls), the
short chains' reduction against the long chain of 10 000 sweeps per call, the births per scan
and the targets lost, for the static birth and for adaptive birth (spec §7.2 variant).
The paper reports no multi-sensor numbers ("similar results are expected"), so nothing is
compared with it.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from ..tracking.multisensor_study import (
    MultiSensorStudyConfig,
    multisensor_tracking_table,
    multisensor_tracking_task,
    plot_multisensor_tracking,
    summarise_multisensor_tracking,
)
from .registry import Study, register_study

__all__ = ["MULTISENSOR_TRACKING"]


def _tasks(cfg: MultiSensorStudyConfig, seed: int) -> list[tuple]:
    """One task per (run, sensor set, association, birth); run ``r`` uses seed ``seed + r``."""
    cfg = dataclasses.replace(cfg, seed=int(seed))
    static = [(cfg, r, tuple(sensors), method, cfg.birth) for r in range(cfg.n_mc)
              for sensors in cfg.sensor_sets for method in cfg.methods]
    adaptive = [(cfg, r, tuple(sensors), method, "adaptive") for r in range(cfg.n_mc)
                for sensors in cfg.adaptive_sensor_sets for method in cfg.adaptive_methods]
    return static + adaptive


def _summarise(runs, cfg):
    return summarise_multisensor_tracking(runs)


def _render(summary, cfg) -> str:
    runs = "run" if cfg.n_mc == 1 else "runs"
    return (
        f"The \"multi\" scenario (multi-sensor spec §7.2: the paper's 12 targets seen by position "
        f"sensors of σ = 10, 15, 20 m and P_D = 0.6, 0.7, 0.8, 20 clutter points each), "
        f"{cfg.n_mc} Monte Carlo {runs} of {cfg.n_scans} scans, {cfg.birth} static birth, and "
        f"adaptive birth (μ_0 = 0, P_0 = diag(1000², 50², 1000², 50²), τ_rU = 0.9, n_min = 2, "
        f"r_B,max = 0.03, λ_B = 1; no static birth) on the rows marked adaptive; every "
        f"sensor set runs on the same measurements. The long chain takes {cfg.long_obs} sweeps "
        f"per call; the short chains {cfg.n_chains} × {cfg.chain_length} with τ_stall = "
        f"{cfg.tau_stall}, τ_stale = {cfg.tau_stale}. The paper has no multi-sensor numbers.\n\n"
        + multisensor_tracking_table(summary) + "\n\n![multi-sensor tracking]"
        "(multisensor_tracking.png)\n"
    )


def _plot(summary, directory: Path) -> list[str]:
    name = "multisensor_tracking.png"
    plot_multisensor_tracking(summary, Path(directory) / name)
    return [name]


def _csv_rows(summary) -> list[dict]:
    return [{k: v for k, v in dataclasses.asdict(s).items() if not hasattr(v, "shape")}
            for s in summary]


MULTISENSOR_TRACKING = register_study(Study(
    name="multisensor_tracking",
    title="multi-sensor LMB filter: fusion gain and the associations on the 'multi' scenario",
    config_type=MultiSensorStudyConfig,
    full=MultiSensorStudyConfig,
    quick=MultiSensorStudyConfig.quick,
    tasks=_tasks,
    task=multisensor_tracking_task,
    summarise=_summarise,
    render=_render,
    plot=_plot,
    csv_rows=_csv_rows,
    paper="",
    order=95,
))
