"""The adaptive-birth study: Table I layout on the adaptive-birth families, error vs observations.

A registry wrapper around :mod:`rankedassign.experiments.adaptive_birth_study`, which holds the
computation (problems, one Monte Carlo task, the Table I summary, the curve, the table, the
verdict and the plot); this module only splits the settings into tasks and gives the summary a
typed shape. The paper has no adaptive-birth numbers (multi-sensor spec §5: "similar results
are expected"), so the study has no paper column.

References
----------
.. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
   Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023, Table I.
.. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "Multi-sensor joint adaptive birth sampler
   for labeled random finite set tracking", IEEE Trans. Signal Process. 70, 2022.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from . import _format as fmt
from . import adaptive_birth_study as ab
from .registry import Study, register_study

__all__ = ["ADAPTIVE_BIRTH", "AdaptiveBirthRow", "AdaptiveBirthSummary", "summarise_adaptive_birth"]

StudyConfig = ab.StudyConfig


@dataclass(frozen=True)
class AdaptiveBirthRow:
    """One Table I row of the adaptive-birth study (errors are fractions, Δ in % and pp)."""

    family: str
    V: int
    criterion: str
    n_mc: int
    delta_obs_pct: float
    delta_error_pp: float
    delta_error_se_pp: float | None
    error_original: float
    error_short: float
    obs_original: float
    obs_short: float


@dataclass(frozen=True)
class AdaptiveBirthSummary:
    """The study's summary: the Table I rows, the error-vs-observation curves, the verdict."""

    rows: tuple
    curves: dict
    verdict: str


def adaptive_birth_tasks(cfg: StudyConfig, seed: int) -> list[tuple]:
    """Monte Carlo runs of the table, then one curve task per (family, V)."""
    cells = [(f, V) for f in cfg.families for V in cfg.sensors]
    return ([("run", cfg, seed, r, f, V) for f, V in cells for r in range(cfg.n_mc)]
            + [("curve", cfg, seed, 0, f, V) for f, V in cells])


def adaptive_birth_task(kind: str, cfg: StudyConfig, seed: int, run: int, family: str,
                        V: int) -> dict:
    """One task: a Monte Carlo run (:func:`~.adaptive_birth_study.run_task`) or a curve."""
    if kind == "run":
        return {"kind": "run", **ab.run_task(cfg, seed, run, family, V)}
    return {"kind": "curve", "family": family, "V": V,
            "points": ab.curve(cfg, seed, family, V)}


def summarise_adaptive_birth(runs: list[dict], cfg: StudyConfig) -> AdaptiveBirthSummary:
    """Typed rows of :func:`~.adaptive_birth_study.summarise`, the curves and the verdict.

    Parameters
    ----------
    runs : list of dict
        Records of :func:`adaptive_birth_task`.
    cfg : StudyConfig

    Returns
    -------
    AdaptiveBirthSummary
    """
    table = [{k: v for k, v in r.items() if k != "kind"} for r in runs if r["kind"] == "run"]
    raw = ab.summarise(table)
    rows = tuple(AdaptiveBirthRow(**{**r, "delta_error_se_pp": None if math.isnan(
        r["delta_error_se_pp"]) else r["delta_error_se_pp"]}) for r in raw)
    curves = {f"{r['family']}, V={r['V']}": r["points"] for r in runs if r["kind"] == "curve"}
    return AdaptiveBirthSummary(rows=rows, curves=curves,
                                verdict=ab.verdict(raw) if raw else "")


def _raw(rows) -> list[dict]:
    return [{**r.__dict__, "delta_error_se_pp": math.nan if r.delta_error_se_pp is None
             else r.delta_error_se_pp} for r in rows]


def render_adaptive_birth(summary: AdaptiveBirthSummary, cfg: StudyConfig) -> str:
    """The report section: settings, the Table I layout, the curves and the verdict."""
    n = summary.rows[0].n_mc if summary.rows else 0
    budgets = list(cfg.curve_obs)
    curve_rows = [[key, *(f"{fmt.num(100 * p['error_original'])} / "
                          f"{fmt.num(100 * p['error_short'])}" for p in pts)]
                  for key, pts in summary.curves.items()]
    sizes = ", ".join(f"V = {V}: M = {ab.SIZES.get(V, 4)}" for V in cfg.sensors)
    return f"""## Adaptive birth — original vs short chains on the adaptive-birth sampler

The paper has no adaptive-birth numbers (it only expects "similar results", multi-sensor spec
§5), so there is no paper column. Families of multi-sensor spec §6.5 ({", ".join(cfg.families)};
{sizes}); the original sampler is one chain of {cfg.original_obs:,} sweeps, the short chains
{cfg.n_chains:,} × {cfg.chain_length} sweeps (the same budget), τ_stall = {cfg.tau_stall},
τ_stale = {cfg.tau_stale}, readings S3/T3; {fmt.plural(n, "Monte Carlo run")} per family and V.
The error is the exact truncation error over the birth tuples with at least n_min detections.
ΔObs = 100 (N̄_o − N̄_s)/N̄_o, ΔError = |ε̄_o − ε̄_s| with the standard error of the paired
difference; the last two columns are the signed means.

{ab.format_table(_raw(summary.rows))}

Mean truncation error (%) against the observation budget, "original / short chains" (short
chains of {cfg.chain_length} sweeps without termination rules, the same budget):

{fmt.table(["family, V", *(f"{b:,}" for b in budgets)], curve_rows)}

**Verdict** (judged on the "full" criterion). {summary.verdict}

![Adaptive birth: truncation error against observations](adaptive_birth.png)
"""


def plot_adaptive_birth(summary: AdaptiveBirthSummary, directory: Path) -> list[str]:
    """The error-vs-observations figure of :func:`~.adaptive_birth_study.plot`."""
    curves = {}
    for key, pts in summary.curves.items():
        fam, v = key.split(", V=")
        curves[fam, int(v)] = pts
    ab.plot(curves, Path(directory) / "adaptive_birth.png")
    return ["adaptive_birth.png"]


def _csv(summary: AdaptiveBirthSummary) -> list[dict]:
    return [dict(r.__dict__) for r in summary.rows]


ADAPTIVE_BIRTH = register_study(Study(
    name="adaptive_birth",
    title="adaptive-birth sampler: original vs short chains (Table I layout, error curves)",
    config_type=StudyConfig,
    full=lambda: ab.FULL,
    quick=lambda: ab.QUICK,
    tasks=adaptive_birth_tasks,
    task=adaptive_birth_task,
    summarise=summarise_adaptive_birth,
    render=render_adaptive_birth,
    plot=plot_adaptive_birth,
    csv_rows=_csv,
    order=90,
))
