"""The paper's Table I: original vs short-chain sampler on the 4 x 24 synthetic matrices."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...validation import check_choice
from .. import _format as fmt
from .._plots import bar_style, figure, legend_below
from .._records import RunRecord
from .._synthetic import (
    SamplerRun,
    Table1Row,
    paired_calls,
    paired_summary,
    paper_settings,
    tiny_synthetic,
    with_paper,
)
from ..config import (
    CRITERIA,
    FAMILIES,
    OTHER_RANDOM,
    STALE_READINGS,
    STALL_READINGS,
    SyntheticConfig,
)
from ..paper import Z_LIMIT
from ..registry import Study, as_rows, per_family_tasks, register_study


@dataclass(frozen=True)
class Table1Config(SyntheticConfig):
    """Table I: original vs short-chain sampler with stall only, stale only and both.

    By default the random family is also run under the other reading of ``Pbar_D``
    (:data:`OTHER_RANDOM`), so the report shows both readings beside the paper's row.

    Attributes
    ----------
    n_mc, families, original_obs, n_chains, chain_length
        As in :class:`~rankedassign.experiments.config.SyntheticConfig`.
    tau_stall, tau_stale, pbar_d, granularity, diagonal_pbar_d
        As in :class:`~rankedassign.experiments.config.SyntheticConfig`.

    Examples
    --------
    >>> from rankedassign.experiments import Table1Config
    >>> Table1Config(n_mc=2).n_chains
    10000
    """

    families: tuple[str, ...] = (*FAMILIES, OTHER_RANDOM)

__all__ = ["TABLE1", "Table1Run", "summarise_table1", "family_label"]

#: Active termination rules (stall reading, stale reading) of each Table I column, with the
#: recommended readings S3 / T3 of spec §3.3.
CRITERION_RULES = {
    "stall": (STALL_READINGS[0], None),
    "stale": (None, STALE_READINGS[0]),
    "full": (STALL_READINGS[0], STALE_READINGS[0]),
}
#: Quick mode: Monte Carlo runs (the per-run settings are the paper's).
QUICK_MC = 40


@dataclass(frozen=True)
class Table1Run(RunRecord):
    """One Monte Carlo run of one family: the original sampler and the three criteria.

    Attributes
    ----------
    run : int
        Monte Carlo run.
    family : str
        Matrix family.
    original : SamplerRun
        The original sampler (``original_obs`` sweeps).
    stall, stale, full : SamplerRun
        The short chains under each Table I criterion (:data:`CRITERION_RULES`).
    """

    run: int
    family: str
    original: SamplerRun
    stall: SamplerRun
    stale: SamplerRun
    full: SamplerRun

    @classmethod
    def from_dict(cls, data: dict):
        """The record of one object of ``table1_runs.json``.

        Parameters
        ----------
        data : dict
            Its fields, each sampler's call as an object.

        Returns
        -------
        Table1Run
            (or the subclass it is called on).
        """
        calls = {k: SamplerRun.from_dict(data[k]) for k in ("original", *CRITERIA) if k in data}
        return super().from_dict({**data, **calls})

    def criterion(self, crit: str) -> SamplerRun:
        """The short chains' call under one Table I criterion.

        Parameters
        ----------
        crit : {"stall", "stale", "full"}
            The criterion (:data:`~rankedassign.experiments.CRITERIA`).

        Returns
        -------
        SamplerRun
            Its field of that name.

        Raises
        ------
        ValueError
            For another criterion.
        """
        return getattr(self, check_choice(crit, "criterion", CRITERIA))


def table1_task(cfg: Table1Config, seed: int, run: int, family: str) -> Table1Run:
    """One Monte Carlo run of one family: the original sampler and the three criteria."""
    _, original, proposed = paired_calls(cfg, seed, run, family)
    return Table1Run(run=run, family=family, original=original,
                     **{crit: proposed(*CRITERION_RULES[crit]) for crit in CRITERIA})


def summarise_table1(runs: list[Table1Run], cfg: Table1Config) -> list[Table1Row]:
    """Table I rows (one per family x criterion) from per-run records, with the paper's cells.

    Parameters
    ----------
    runs : list of Table1Run
        Per-run records (``run_study("table1", ..., return_runs=True)[1]``).
    cfg : Table1Config
        The settings of the runs (row order: ``cfg.families``; the cells are judged against
        the paper's only under the paper's per-run settings).

    Returns
    -------
    list of Table1Row
        Per family of ``cfg.families`` the ``"stall"``, ``"stale"`` and ``"full"`` rows.
    """
    rows = []
    judge = paper_settings(cfg)
    for fam in cfg.families:
        rs = sorted((r for r in runs if r.family == fam), key=lambda r: r.run)
        for crit in CRITERIA:
            stats = paired_summary([r.original for r in rs], [r.criterion(crit) for r in rs])
            rows.append(with_paper(fam, crit, stats, judge=judge))
    return rows


def family_label(family: str, cfg) -> str:
    """The family with the reading of P̄_D and of the P_s, P_d draws it uses (spec A2, A5).

    Parameters
    ----------
    family : str
        A family name (:data:`~rankedassign.experiments.config.ALL_FAMILIES`).
    cfg : object
        The study's settings: ``pbar_d`` and ``granularity`` are read for the random
        families, ``diagonal_pbar_d`` (if the settings have it) for the diagonal one.

    Returns
    -------
    str
        The label of a report row, e.g. ``"random: P̄_D = P_d, matrix P_s, P_d"`` or
        ``"diagonal: P̄_D = r·P_d"``; the family itself for the uniform family.
    """
    def pbar(p):
        return "r·P_d" if p == "r_pd" else "P_d"

    if family.startswith("random"):
        p = cfg.pbar_d if family == "random" else family.split("-", 1)[1]
        return f"{family}: P̄_D = {pbar(p)}, {cfg.granularity} P_s, P_d"
    if family == "diagonal" and hasattr(cfg, "diagonal_pbar_d"):
        return f"diagonal: P̄_D = {pbar(cfg.diagonal_pbar_d)}"
    return family


def _cell(ours, se, paper) -> list[str]:
    if paper is None:
        return [fmt.pm(ours, se), "–", "–"]
    return [fmt.pm(ours, se), fmt.num(paper, 2), fmt.versus(ours, se, paper)]


def disagreements(rows, label=lambda f: f) -> list[str]:
    """Cells more than :data:`~rankedassign.experiments.paper.Z_LIMIT` SE from the paper's."""
    out = []
    for r in rows:
        if r.paper_delta_obs_pct is None or r.agrees_with_paper is not False:
            continue
        for what, ours, se, paper, unit in (
            ("ΔObs", r.delta_obs_pct, r.delta_obs_pct_se, r.paper_delta_obs_pct, "%"),
            ("ΔError", r.delta_error_pp, r.delta_error_pp_se, r.paper_delta_error_pp, "pp"),
        ):
            v = fmt.versus(ours, se, paper)
            if "differs" in v:
                out.append(
                    f"{label(r.family)}, {r.criterion}: {what} {fmt.pm(ours, se)} {unit} "
                    f"against the paper's {paper:.2f} {unit} ({v.split(' —')[0]})"
                )
    return out


def render_table1(rows: list[Table1Row], cfg: Table1Config) -> str:
    """The Table I section of the report: ours beside the paper's, cell by cell."""
    n = rows[0].n_mc if rows else 0

    def label(f):
        return family_label(f, cfg)

    main = [
        [label(r.family), r.criterion,
         *_cell(r.delta_obs_pct, r.delta_obs_pct_se, r.paper_delta_obs_pct),
         *_cell(r.delta_error_pp, r.delta_error_pp_se, r.paper_delta_error_pp)]
        for r in rows
    ]
    details = [
        [label(r.family), r.criterion,
         fmt.pm(r.error_original_mean, r.error_original_se, n_runs=r.n_mc),
         fmt.pm(r.error_proposed_mean, r.error_proposed_se, n_runs=r.n_mc),
         fmt.pm(r.mean_abs_delta_error_pp, r.mean_abs_delta_error_pp_se, n_runs=r.n_mc),
         fmt.pm_count(r.obs_original_mean, r.obs_original_se, n_runs=r.n_mc),
         fmt.pm_count(r.obs_proposed_mean, r.obs_proposed_se, n_runs=r.n_mc),
         fmt.pm_count(r.unique_proposed_mean, r.unique_proposed_se, n_runs=r.n_mc),
         fmt.pm(100 * r.stale_stop_fraction,
                None if r.stale_stop_se is None else 100 * r.stale_stop_se, 1, n_runs=r.n_mc)]
        for r in rows
    ]
    if not paper_settings(cfg):
        verdict = ("These settings are not the paper's (spec §3.4), so the cells are not judged "
                   "against the paper's; its numbers are shown for reference.")
    elif not any(r.agrees_with_paper is not None for r in rows):
        verdict = ("No cell can be compared with the paper's: one Monte Carlo run has no "
                   "standard error.")
    else:
        parts = []
        for title, group in (
            ("the default readings", [r for r in rows if r.family in FAMILIES]),
            ("the other reading of the random family",
             [r for r in rows if r.family not in FAMILIES]),
        ):
            compared = [r for r in group if r.agrees_with_paper is not None]
            if not compared:
                continue
            off = disagreements(compared, label)
            if not off:
                parts.append(f"Under {title}, all {2 * len(compared)} numbers of the "
                             f"{len(compared)} compared cells lie within {Z_LIMIT:g} standard "
                             "errors of the paper's.")
            else:
                parts.append(f"Under {title}, {fmt.plural(len(off), 'number')} of the "
                             f"{2 * len(compared)} compared lie more than {Z_LIMIT:g} standard "
                             "errors from the paper's:\n\n"
                             + "\n".join(f"- {line}" for line in off))
        verdict = "\n\n".join(parts)
    checks = _reference_checks(rows, cfg)
    return f"""## Table I — original vs short-chain sampler, beside the paper's

Original sampler: one chain of {cfg.original_obs:,} observations. Short-chain sampler:
{cfg.n_chains:,} chains × {cfg.chain_length}, τ_stall = {cfg.tau_stall}, τ_stale = {cfg.tau_stale},
readings S3 (stall: consecutive observations new to the global set) and T3 (stale: consecutive
completed chains without a new solution), spec §3.3. Families of spec §1.6, the random family
re-drawn every run; {fmt.plural(n, "Monte Carlo run")}. Errors are exact truncation errors
(spec eq. 1.9).

**Verdict.** {verdict}

{fmt.table(["family", "criterion", "ΔObs (%, > 0: short chains save) ours", "paper",
            "ours − paper", "ΔError (pp, 0 = no accuracy lost) ours", "paper",
            "ours − paper"], main)}

ΔObs = 100 (N̄_o − N̄_s)/N̄_o and ΔError = |ε̄_o − ε̄_s| (spec eq. 1.10). `±` is one Monte
Carlo standard error (SE): the delta method for the ratio of paired means (ΔObs), the standard
error of the mean per-run paired difference (ΔError). "ours − paper" is the difference in our
standard errors; a cell more than {Z_LIMIT:g} SE away from the paper's rounding interval (its
value ± half a unit of its last printed digit) is flagged in words. Rows of a
family's alternative reading are compared with the paper's row of that family.
{fmt.runs_note(r.n_mc for r in rows)}

Details (errors in %, differences in pp; "stale stops" is the percentage of runs the stale
rule ended):

{fmt.table(["family", "criterion", "ε̄ original (%)", "ε̄ proposed (%)", "mean |Δε| (pp)",
            "N̄ original", "N̄ proposed", "unique (proposed)", "stale stops (%)"], details)}

Reference magnitudes of the specification:

{checks}

![Table I: ours (bars, ±1 SE) and the paper's (black marks)](table1.png)
"""


def _reference_checks(rows, cfg) -> str:
    by = {(r.family, r.criterion): r for r in rows}
    lines = []
    if ("uniform", "stall") in by and cfg.original_obs == 250_000:
        r = by["uniform", "stall"]
        expect = 100 * math.exp(-250_000 / 76_848)
        eo = fmt.pm(r.error_original_mean, r.error_original_se)
        lines.append(
            f"- uniform, original sampler: ε̄_o = {eo} % (spec §3.5, §10.4: ≈ 3.8 %, "
            f"e^(−250000/76848) = {expect:.2f} %)"
        )
    if ("diagonal", "stall") in by:
        r = by["diagonal", "stall"]
        eo = fmt.pm(r.error_original_mean, r.error_original_se)
        lines.append(
            f"- diagonal, original sampler: ε̄_o = {eo} % (spec §10.5: about 1e−5, i.e. "
            "0.001 %, or below)"
        )
    return "\n".join(lines) if lines else "- (no family with a reference value was run)"


def plot_table1(rows: list[Table1Row], directory: Path) -> list[str]:
    """ΔObs and ΔError per family and criterion (±1 SE bars), the paper's values marked."""
    fams = list(dict.fromkeys(r.family for r in rows))
    fig, axes = figure(2, width=5.5)
    x = np.arange(len(fams))
    w = 0.8 / len(CRITERIA)
    by = {(r.family, r.criterion): r for r in rows}
    for ax, key, label in ((axes[0], "delta_obs_pct", "ΔObs (%)"),
                           (axes[1], "delta_error_pp", "ΔError (pp)")):
        for j, c in enumerate(CRITERIA):
            v = [getattr(by[f, c], key) for f in fams]
            e = [getattr(by[f, c], f"{key}_se") or 0.0 for f in fams]
            ax.bar(x + (j - 1) * w, v, w, yerr=e, capsize=0, ecolor="0.3",
                   label=f"short chains, {c}", **bar_style(j))
            paper = [getattr(by[f, c], f"paper_{key}") for f in fams]
            px = [x[i] + (j - 1) * w for i, p in enumerate(paper) if p is not None]
            py = [p for p in paper if p is not None]
            ax.scatter(px, py, marker="_", s=250, color="k", zorder=3,
                       label="paper" if j == 0 else None)
        ax.set_xticks(x, fams, fontsize=8)
        ax.set_ylabel(label)
        ax.grid(True, axis="y", alpha=0.3)
    legend_below(fig, axes[:1], ncol=4)
    fig.suptitle("Table I: ours (bars, ±1 SE) and the paper's (black marks)")
    fig.savefig(directory / "table1.png", dpi=110)
    return ["table1.png"]


TABLE1 = register_study(Study(
    name="table1",
    title="Table I: original vs short-chain sampler (stall, stale, both), beside the paper's",
    config_type=Table1Config,
    full=Table1Config,
    quick=lambda: Table1Config(n_mc=QUICK_MC),
    tasks=per_family_tasks,
    task=table1_task,
    run_from_dict=Table1Run.from_dict,
    summarise=summarise_table1,
    render=render_table1,
    plot=plot_table1,
    csv_rows=as_rows,
    order=10,
    warm=tiny_synthetic,
    paper="Table I",
))
