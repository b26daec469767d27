"""Truncation error against the number of observations, without early stopping."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ... import sample_original, sample_short_chains
from ...validation import check_fields
from .. import _format as fmt
from .._executor import child_seed, run_seed
from .._plots import legend_below, series_style
from .._records import RunRecord
from .._synthetic import KEY_SWEEP, SamplerRun, family_index, make_problem, record
from ..config import (
    DEFAULT_GRANULARITY,
    DEFAULT_PBAR_D,
    PBAR_D_READINGS,
    check_families,
    check_positive,
)
from ..paper import PAPER_SWEEP_TOLERANCE_PCT
from ..registry import Study, as_rows, per_family_tasks, register_study


@dataclass(frozen=True)
class SweepConfig:
    """Truncation error against the number of observations, no early stopping.

    Attributes
    ----------
    n_mc : int
        Monte Carlo runs per family.
    families : tuple of str
        Matrix families to run (:data:`ALL_FAMILIES`).
    obs_grid : tuple of int
        Observation budgets (sweeps), strictly increasing; at budget ``n`` the original
        sampler runs ``n`` sweeps and the short-chain sampler ``n // L`` chains of ``L``.
    chain_lengths : tuple of int
        Chain lengths ``L`` of the short-chain sampler (a length above the budget is skipped).
    pbar_d : {"r_pd", "pd"}
        ``Pbar_D`` of the random family, and of the diagonal family if it is run (spec A2).
    granularity : {"row", "matrix"}
        Whether the random family draws ``P_s, P_d`` per row or once per matrix (spec A5).

    Examples
    --------
    >>> from rankedassign.experiments import SweepConfig
    >>> SweepConfig().chain_lengths
    (5, 10, 25, 50, 100)
    """

    n_mc: int = 100
    families: tuple[str, ...] = ("uniform", "random")
    #: Observation budgets (sweeps); the short-chain sampler runs ``n // L`` chains of ``L``.
    obs_grid: tuple[int, ...] = (
        100, 200, 500, 1_000, 2_000, 5_000, 10_000, 20_000, 50_000, 100_000, 250_000,
    )
    chain_lengths: tuple[int, ...] = (5, 10, 25, 50, 100)
    pbar_d: str = DEFAULT_PBAR_D
    granularity: str = DEFAULT_GRANULARITY

    def __post_init__(self):
        check_fields(self)
        check_positive("n_mc", self.n_mc)
        check_families("families", self.families)
        if not self.obs_grid or not self.chain_lengths:
            raise ValueError("obs_grid and chain_lengths must not be empty")
        for n in self.obs_grid:
            check_positive("obs_grid entry", n)
        for n in self.chain_lengths:
            check_positive("chain_lengths entry", n)
        if tuple(sorted(set(self.obs_grid))) != tuple(self.obs_grid):
            raise ValueError(f"obs_grid must be strictly increasing, got {self.obs_grid}")
        # the same readings, and messages, as SyntheticConfig's (spec A2, A5)
        if self.pbar_d not in PBAR_D_READINGS:
            raise ValueError(f"pbar_d must be 'r_pd' or 'pd', got {self.pbar_d!r}")
        if self.granularity not in ("row", "matrix"):
            raise ValueError(f"granularity must be 'row' or 'matrix', got {self.granularity!r}")

__all__ = ["SWEEP", "SweepRow", "SweepRun", "SweepPoint", "ChainLengthCheck", "summarise_sweep",
           "chain_length_checks"]

#: Quick mode: Monte Carlo runs and observation budgets (the per-run settings are the paper's).
QUICK_MC, QUICK_GRID = 10, (100, 1_000, 10_000, 100_000, 250_000)


@dataclass(frozen=True)
class SweepRow:
    """Error statistics (percent) of one family, sampler and observation budget over runs.

    Standard errors are ``None`` for one run.

    Attributes
    ----------
    family : str
        Matrix family (:data:`~rankedassign.experiments.config.ALL_FAMILIES`).
    sampler : str
        ``"original"`` or ``"short-<L>"``, the short-chain sampler with chains of ``L`` sweeps
        and no early stopping.
    chain_length : int or None
        ``L`` of a short-chain sampler, ``None`` for the original one.
    budget : int
        Observation budget ``n`` of the grid point: the original sampler runs ``n`` sweeps,
        the short-chain sampler ``n // L`` chains of ``L``.
    n_obs_mean : float
        Mean observations actually made (``L (n // L)`` for the short chains).
    n_unique_mean : float
        Mean number of distinct assignments found.
    error_pct_mean : float
        Mean truncation error (spec eq. 1.9), in percent.
    error_pct_se : float or None
        Its standard error.
    error_pct_q10, error_pct_q90 : float
        10 % and 90 % quantiles of the per-run errors, in percent.
    diff_vs_original_pp_mean : float
        Mean per-run difference to the original sampler's error at the same budget on the
        same matrix, in percentage points (0 for the original sampler).
    diff_vs_original_pp_se : float or None
        Its standard error.
    n_mc : int
        Monte Carlo runs.
    n_obs_se, n_unique_se : float or None
        Standard errors of ``n_obs_mean`` and ``n_unique_mean``; ``None`` for one run.
    """

    family: str
    sampler: str
    chain_length: int | None
    budget: int
    n_obs_mean: float
    n_unique_mean: float
    error_pct_mean: float
    error_pct_se: float | None
    error_pct_q10: float
    error_pct_q90: float
    diff_vs_original_pp_mean: float
    diff_vs_original_pp_se: float | None
    n_mc: int
    # last and with defaults, so a record built with the fields above stays valid
    n_obs_se: float | None = None
    n_unique_se: float | None = None


@dataclass(frozen=True)
class ChainLengthCheck:
    """The paper's statement at one budget: the error does not depend on the chain length.

    ``spread_pp`` is the largest minus the smallest mean error over the chain lengths run at
    this budget; the statement holds when every chain length lies within
    ``PAPER_SWEEP_TOLERANCE_PCT`` (0.1 pp) of their midpoint, i.e. ``spread_pp <= 0.2``.
    ``max_se_pp`` is the largest standard error among them: above the tolerance, the runs
    cannot tell.

    Attributes
    ----------
    family : str
        Matrix family.
    budget : int
        Observation budget of the check.
    chain_lengths : tuple of int
        The chain lengths run at this budget, in the order of the rows.
    spread_pp : float
        Largest minus smallest mean error over those chain lengths, in percentage points.
    max_se_pp : float or None
        Largest standard error of those mean errors (pp); ``None`` with one run.
    holds : bool
        Whether ``spread_pp <= 2 * PAPER_SWEEP_TOLERANCE_PCT`` (0.2 pp).
    """

    family: str
    budget: int
    chain_lengths: tuple[int, ...]
    spread_pp: float
    max_se_pp: float | None
    holds: bool


@dataclass(frozen=True)
class _GridPoint(RunRecord):
    """Where a :class:`SweepPoint` lies on the grid: its first three fields."""

    sampler: str
    chain_length: int | None
    budget: int


# The grid point's fields first, then the call's (a dataclass takes its bases' fields in
# reverse order of the MRO): the order sweep_runs.json has always had.
@dataclass(frozen=True)
class SweepPoint(SamplerRun, _GridPoint):
    """One sampler at one budget of a sweep run: the grid point and the sampler's call.

    Attributes
    ----------
    sampler : str
        ``"original"`` or ``"short-<L>"``.
    chain_length : int or None
        ``L`` of the short chains (None for the original sampler).
    budget : int
        Sweeps of the grid point.
    n_obs, n_row_updates, n_unique, n_chains, stop_reason, error
        The sampler's call, a ``SamplerRun`` (``rankedassign.experiments._synthetic``).
    """


@dataclass(frozen=True)
class SweepRun(RunRecord):
    """Every grid point of one run and family (:func:`sweep_task`).

    Attributes
    ----------
    run : int
        Monte Carlo run.
    family : str
        Matrix family.
    points : list of SweepPoint
        In grid order, the original sampler first at each budget.
    """

    run: int
    family: str
    points: list

    @classmethod
    def from_dict(cls, data: dict) -> SweepRun:
        """The record of one object of ``sweep_runs.json``.

        Parameters
        ----------
        data : dict
            Its fields, the points as objects.

        Returns
        -------
        SweepRun
        """
        return super().from_dict({**data, "points": [
            SweepPoint.from_dict(p) for p in data.get("points", [])]})


def sweep_task(cfg: SweepConfig, seed: int, run: int, family: str) -> SweepRun:
    """Every grid point of one run and family.

    Each sampler keeps one stream across the grid, so a run's curve follows one sampler
    trajectory observed after more and more sweeps (sampler outputs are prefix-consistent).
    """
    s = run_seed(seed, run)
    problem = make_problem(family, s, cfg)
    fi = family_index(family)
    points = []
    for n in cfg.obs_grid:
        res = sample_original(problem, n, rng=child_seed(s, KEY_SWEEP, fi, 0))
        points.append(SweepPoint(sampler="original", chain_length=None, budget=n,
                                 **record(problem, res).to_dict()))
        for L in cfg.chain_lengths:
            if n < L:
                continue
            res = sample_short_chains(problem, n // L, L, rng=child_seed(s, KEY_SWEEP, fi, L))
            points.append(SweepPoint(sampler=f"short-{L}", chain_length=L, budget=n,
                                     **record(problem, res).to_dict()))
    return SweepRun(run=run, family=family, points=points)


def _se(x) -> float | None:
    """Standard error of the mean of ``x``; ``None`` for one value."""
    x = np.asarray(x, dtype=float)
    return float(x.std(ddof=1) / math.sqrt(x.size)) if x.size > 1 else None


def summarise_sweep(runs: list[SweepRun], cfg=None) -> list[SweepRow]:
    """Rows ``(family, sampler, budget)``: error statistics over runs (percent).

    Parameters
    ----------
    runs : list of SweepRun
        Per-run records of the study's task, each point a :class:`SweepPoint` (``sampler``,
        ``chain_length``, ``budget``, ``n_obs``, ``n_unique``, ``error`` as a fraction).
    cfg : SweepConfig, optional
        Not used: the rows follow from the records alone. Accepted so the function has the
        ``summarise(runs, cfg)`` signature of every study.

    Returns
    -------
    list of SweepRow
        One row per (family, sampler, budget), in the order the records first name them.
    """
    groups: dict[tuple, list[SweepPoint]] = {}
    diffs: dict[tuple, list[float]] = {}
    for r in runs:
        ref = {p.budget: p.error for p in r.points if p.sampler == "original"}
        for p in r.points:
            key = (r.family, p.sampler, p.budget)
            groups.setdefault(key, []).append(p)
            # Paired with the original sampler of the same run (same matrix) and budget.
            diffs.setdefault(key, []).append(100.0 * (p.error - ref[p.budget]))
    rows = []
    for (fam, sampler, budget), ps in groups.items():
        e = 100.0 * np.array([p.error for p in ps])
        d = np.array(diffs[fam, sampler, budget])
        n = len(ps)
        rows.append(SweepRow(
            family=fam,
            sampler=sampler,
            chain_length=ps[0].chain_length,
            budget=budget,
            n_obs_mean=float(np.mean([p.n_obs for p in ps])),
            n_unique_mean=float(np.mean([p.n_unique for p in ps])),
            error_pct_mean=float(e.mean()),
            error_pct_se=float(e.std(ddof=1) / math.sqrt(n)) if n > 1 else None,
            error_pct_q10=float(np.quantile(e, 0.1)),
            error_pct_q90=float(np.quantile(e, 0.9)),
            diff_vs_original_pp_mean=float(d.mean()),
            diff_vs_original_pp_se=float(d.std(ddof=1) / math.sqrt(n)) if n > 1 else None,
            n_mc=n,
            n_obs_se=_se([p.n_obs for p in ps]),
            n_unique_se=_se([p.n_unique for p in ps]),
        ))
    return rows


def chain_length_checks(rows: list[SweepRow]) -> list[ChainLengthCheck]:
    """The paper's ±0.1 % statement checked at every family and budget with two chain lengths.

    Parameters
    ----------
    rows : list of SweepRow
        Rows of :func:`summarise_sweep`; only the short-chain rows are compared.

    Returns
    -------
    list of ChainLengthCheck
        One check per (family, budget) at which at least two chain lengths were run, in the
        order the rows first name them.

    Examples
    --------
    >>> from rankedassign.experiments.studies.sweep import SweepRow, chain_length_checks
    >>> def row(L, e):
    ...     return SweepRow("uniform", f"short-{L}", L, 1000, 1000, 900, e, 0.01, e, e, 0, 0, 5)
    >>> chain_length_checks([row(5, 40.0), row(25, 40.15)])[0].holds
    True
    """
    out = []
    keys = dict.fromkeys((r.family, r.budget) for r in rows)
    for fam, budget in keys:
        short = [r for r in rows if (r.family, r.budget) == (fam, budget)
                 and r.chain_length is not None]
        if len(short) < 2:
            continue
        means = [r.error_pct_mean for r in short]
        ses = [r.error_pct_se for r in short if r.error_pct_se is not None]
        spread = max(means) - min(means)
        out.append(ChainLengthCheck(
            family=fam, budget=budget, chain_lengths=tuple(r.chain_length for r in short),
            spread_pp=float(spread), max_se_pp=max(ses) if ses else None,
            holds=bool(spread <= 2 * PAPER_SWEEP_TOLERANCE_PCT + 1e-12),
        ))
    return out


_HEADER = ["family", "sampler", "observations", "unique", "ε (%) ± SE", "ε 10–90 % (%)",
           "ε − ε original (pp, < 0: more accurate than the original)"]


def _verdict(checks: list[ChainLengthCheck]) -> str:
    if not checks:
        return "No budget was run with two chain lengths, so the statement is not checked."
    lines = []
    for fam in dict.fromkeys(c.family for c in checks):
        cs = [c for c in checks if c.family == fam]
        bad = [c for c in cs if not c.holds]
        worst = max(cs, key=lambda c: c.spread_pp)
        noisy = [c for c in bad if c.max_se_pp is not None
                 and c.max_se_pp > PAPER_SWEEP_TOLERANCE_PCT]
        if not bad:
            lines.append(f"- {fam}: **holds** at every budget (largest spread "
                         f"{fmt.num(worst.spread_pp)} pp at {worst.budget:,}).")
        else:
            at = ", ".join(f"{c.budget:,} ({fmt.num(c.spread_pp)} pp)" for c in bad)
            tail = (f"; at {len(noisy)} of them the standard errors exceed 0.1 pp, so these "
                    "runs cannot settle it there" if noisy else "")
            lines.append(f"- {fam}: **does not hold** at {len(bad)} of {len(cs)} budgets: "
                         f"{at}{tail}.")
    return "\n".join(lines)


def _summary(checks: list[ChainLengthCheck]) -> str:
    """One sentence: on how many families the chain-length statement holds."""
    fams = list(dict.fromkeys(c.family for c in checks))
    if not fams:
        return "The chain-length statement is not checked (no budget has two chain lengths)."
    held = [f for f in fams if all(c.holds for c in checks if c.family == f)]
    unsettled = [f for f in fams if f not in held and all(
        c.holds or (c.max_se_pp is not None and c.max_se_pp > PAPER_SWEEP_TOLERANCE_PCT)
        for c in checks if c.family == f)]
    text = (f"The paper's chain-length statement holds at every budget on {len(held)} of "
            f"{len(fams)} families" + (f" ({', '.join(held)})" if held else "") + ".")
    if unsettled:
        text += (" Where it fails on " + ", ".join(unsettled) + " the standard errors exceed "
                 "the tolerance, so these runs cannot settle it.")
    return text


def render_sweep(rows: list[SweepRow], cfg: SweepConfig) -> str:
    """The sweep section: the error at the largest budget and the chain-length check."""
    top = max(cfg.obs_grid)
    body = [
        [r.family, r.sampler, fmt.pm_count(r.n_obs_mean, r.n_obs_se, n_runs=r.n_mc),
         fmt.pm_count(r.n_unique_mean, r.n_unique_se, n_runs=r.n_mc),
         fmt.pm(r.error_pct_mean, r.error_pct_se, n_runs=r.n_mc),
         f"{fmt.num(r.error_pct_q10, 3)} – {fmt.num(r.error_pct_q90, 3)}",
         fmt.pm(r.diff_vs_original_pp_mean, r.diff_vs_original_pp_se, n_runs=r.n_mc)]
        for r in rows
        if r.budget == top
    ]
    n = rows[0].n_mc if rows else 0
    checks = chain_length_checks(rows)
    return f"""## Sweep — truncation error against observations (no early stopping)

![sweep](sweep.png)

Top: mean over {fmt.plural(n, "run")} with a band of ±1 standard error (shaded); bottom: the
paired difference to the original sampler (same matrix, same budget, same run); budgets
{", ".join(f"{b:,}" for b in cfg.obs_grid)} observations; the short-chain sampler runs
⌊budget / L⌋ chains of length L.

{fmt.runs_note(r.n_mc for r in rows)}

**Verdict.** The paper states that at a fixed observation budget the truncation error is
unaffected (±{PAPER_SWEEP_TOLERANCE_PCT:g} %) by the chain length. {_summary(checks)} Checked
at every budget run with at least two chain lengths (all of the short-chain means within
±{PAPER_SWEEP_TOLERANCE_PCT:g} pp of their midpoint):

{_verdict(checks)}

At the largest budget ({top:,}):

{fmt.table(_HEADER, body)}
"""


def plot_sweep(rows: list[SweepRow], directory: Path) -> list[str]:
    """Error against observations (top) and its paired difference to the original (bottom).

    One column per family; bands are ±1 standard error over runs; the title says whether the
    paper's ±0.1 % chain-length statement holds.
    """
    from matplotlib.figure import Figure


    fams = list(dict.fromkeys(r.family for r in rows))
    checks = chain_length_checks(rows)
    fig = Figure(figsize=(6.0 * len(fams), 7.0), layout="constrained")
    axes = fig.subplots(2, len(fams), squeeze=False, sharex="col")
    for col, fam in enumerate(fams):
        top, bottom = axes[0, col], axes[1, col]
        samplers = list(dict.fromkeys(r.sampler for r in rows if r.family == fam))
        for i, s in enumerate(samplers):
            rs = sorted((r for r in rows if r.family == fam and r.sampler == s),
                        key=lambda r: r.n_obs_mean)
            x = np.array([r.n_obs_mean for r in rs])
            style = series_style(i)
            for ax, key in ((top, "error_pct"), (bottom, "diff_vs_original_pp")):
                y = np.array([getattr(r, f"{key}_mean") for r in rs])
                se = np.array([getattr(r, f"{key}_se") or 0.0 for r in rs])
                ax.plot(x, y, label=s, **style)
                ax.fill_between(x, y - se, y + se, color=style["color"], alpha=0.15, lw=0)
        cs = [c for c in checks if c.family == fam]
        verdict = ("" if not cs else "paper's ±0.1 % chain-length claim "
                   + ("holds" if all(c.holds for c in cs) else
                      f"fails at {sum(not c.holds for c in cs)} of {len(cs)} budgets"))
        top.set_title(f"{fam} family\n{verdict}", fontsize=10)
        top.set_ylabel("truncation error (%)")
        bottom.set_ylabel("error − original error (pp)")
        bottom.set_xlabel("observations (sweeps)")
        for ax in (top, bottom):
            ax.set_xscale("log")
            ax.grid(True, which="both", alpha=0.3)
    legend_below(fig, axes[0, :1], ncol=6)
    fig.savefig(directory / "sweep.png", dpi=110)
    return ["sweep.png"]


SWEEP = register_study(Study(
    name="sweep",
    title="truncation error against observations for several chain lengths",
    config_type=SweepConfig,
    full=SweepConfig,
    quick=lambda: SweepConfig(n_mc=QUICK_MC, obs_grid=QUICK_GRID),
    tasks=per_family_tasks,
    task=sweep_task,
    run_from_dict=SweepRun.from_dict,
    summarise=summarise_sweep,
    render=render_sweep,
    plot=plot_sweep,
    csv_rows=as_rows,
    order=20,
    warm=lambda c: replace(c, n_mc=1, obs_grid=c.obs_grid[:1], chain_lengths=c.chain_lengths[:1]),
    warm_after="table1",  # Table I's samplers, compiled by its first tiny task
))
