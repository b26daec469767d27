"""Table I under every pair of stall x stale readings of the paper's pseudo-code (spec §3.2)."""

from __future__ import annotations

from dataclasses import dataclass

from .. import _format as fmt
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
    ALL_FAMILIES,
    CRITERIA,
    FAMILIES,
    OTHER_RANDOM,
    STALE_READINGS,
    STALL_READINGS,
    SyntheticConfig,
)
from ..paper import Z_LIMIT
from ..registry import Study, as_rows, per_family_tasks, register_study
from .table1 import disagreements, family_label


@dataclass(frozen=True)
class AblationConfig(SyntheticConfig):
    """Table I under every pair of stall x stale readings (spec §3.2).

    By default it adds the random family under the other reading of ``Pbar_D``
    (:data:`OTHER_RANDOM`, spec A2) to the paper's three, so that reading is ablated too.

    Attributes
    ----------
    n_mc, families, original_obs, n_chains, chain_length
        As in :class:`~rankedassign.experiments.config.SyntheticConfig`.
    tau_stall, tau_stale, pbar_d, granularity, diagonal_pbar_d
        As in :class:`~rankedassign.experiments.config.SyntheticConfig`.
    stall_readings : tuple of str
        Readings of the stall rule to run (a non-empty subset of :data:`STALL_READINGS`).
    stale_readings : tuple of str
        Readings of the stale rule to run (a non-empty subset of :data:`STALE_READINGS`);
        every stall reading is paired with every stale reading.

    Examples
    --------
    >>> from rankedassign.experiments import AblationConfig
    >>> len(AblationConfig().stall_readings) * len(AblationConfig().stale_readings)
    12
    """

    families: tuple[str, ...] = (*FAMILIES, OTHER_RANDOM)
    stall_readings: tuple[str, ...] = STALL_READINGS
    stale_readings: tuple[str, ...] = STALE_READINGS

    def __post_init__(self):
        super().__post_init__()
        for name, given, allowed in (
            ("stall_readings", self.stall_readings, STALL_READINGS),
            ("stale_readings", self.stale_readings, STALE_READINGS),
        ):
            if not given or any(r not in allowed for r in given):
                raise ValueError(f"{name} must be a non-empty subset of {allowed}, got {given!r}")

__all__ = ["ABLATION", "AblationRow", "AblationRun", "summarise_ablation", "consistency"]

#: Quick mode: Monte Carlo runs (the per-run settings are the paper's).
QUICK_MC = 10


@dataclass(frozen=True, kw_only=True)
class AblationRow(Table1Row):
    """A Table I row under one reading pair (``stall``, ``stale``; spec §3.2).

    The statistics are those of :class:`~rankedassign.experiments._synthetic.Table1Row`:
    ``eps_o``, ``eps_s`` are one run's truncation errors of the original and of the
    short-chain sampler, ``N_o``, ``N_s`` their observations; standard errors are ``None``
    for one run.

    Attributes
    ----------
    n_mc : int
        Paired Monte Carlo runs of the cell (the same matrix for both samplers in a run).
    obs_original_mean, obs_proposed_mean : float
        Mean observations (sweeps) per run of the original and of the short-chain sampler.
    error_original_mean, error_proposed_mean : float
        Mean exact truncation error (spec eq. 1.9) of each sampler, in percent.
    delta_obs_pct : float
        ΔObs, ``100 (mean N_o - mean N_s) / mean N_o``: the share of the original sampler's
        observations the short chains save, in percent.
    delta_error_pp : float
        ΔError, ``|mean(eps_s - eps_o)|`` (spec eq. 1.10), in percentage points.
    delta_error_signed_pp : float
        ``mean(eps_s - eps_o)`` in percentage points: positive when the short chains leave
        more of the target's mass uncovered.
    mean_abs_delta_error_pp : float
        Mean of the per-run ``|eps_s - eps_o|`` (spec A7), in percentage points.
    unique_original_mean, unique_proposed_mean : float
        Mean number of distinct assignments each sampler found.
    chains_proposed_mean : float
        Mean number of chains the short-chain sampler ran.
    stale_stop_fraction : float
        Fraction of runs in which the stale rule ended the short-chain sampler.
    delta_obs_pct_se : float or None
        Standard error of ``delta_obs_pct`` (delta method for the ratio of the paired means).
    delta_error_pp_se : float or None
        Standard error of the mean paired difference ``mean(eps_s - eps_o)``.
    mean_abs_delta_error_pp_se : float or None
        Standard error of ``mean_abs_delta_error_pp``.
    error_original_se, error_proposed_se : float or None
        Standard errors of ``error_original_mean`` and ``error_proposed_mean``.
    obs_original_se, obs_proposed_se, unique_original_se, unique_proposed_se : float or None
        Standard errors of the mean observations and of the mean distinct assignments of each
        sampler (``None`` for one run, and where a caller built the record without them).
    stale_stop_se : float or None
        Standard error of ``stale_stop_fraction`` (the mean of a 0/1 outcome per run).
    family : str
        Matrix family (:data:`~rankedassign.experiments.config.ALL_FAMILIES`).
    criterion : {"stall", "stale", "full"}
        Termination rules of the short-chain sampler: stall only, stale only, or both.
    paper_family : str or None
        The paper's family this row reads (``"random-pd"`` reads ``"random"``); ``None``
        where the paper has no such cell.
    paper_delta_obs_pct, paper_delta_error_pp : float or None
        The paper's ΔObs (%) and ΔError (pp) of the cell, ``None`` without a cell.
    delta_obs_z, delta_error_z : float or None
        Our distance to the paper's numbers in standard errors
        (:func:`~rankedassign.experiments.paper.distance_in_se`); ``None`` without a cell, with
        one run, or when the settings are not the paper's (not judged).
    agrees_with_paper : bool or None
        Whether ΔObs and ΔError both lie within three standard errors of the paper's
        (:func:`~rankedassign.experiments.paper.agrees`); ``None`` when not judged.
    stall : str
        Reading of the stall rule of the short chains (spec §3.2), one of
        :data:`~rankedassign.experiments.config.STALL_READINGS`.
    stale : str
        Reading of the stale rule, one of
        :data:`~rankedassign.experiments.config.STALE_READINGS`.
    """

    stall: str
    stale: str


@dataclass(frozen=True)
class AblationRun(RunRecord):
    """One run of one family: the original sampler and the short chains under every reading.

    Attributes
    ----------
    run : int
        Monte Carlo run.
    family : str
        Matrix family.
    original : SamplerRun
        The original sampler.
    stall : dict of str to SamplerRun
        The stall rule alone, by stall reading.
    stale : dict of str to SamplerRun
        The stale rule alone, by stale reading.
    full : dict of str to SamplerRun
        Both rules, by ``"<stall reading>|<stale reading>"``.
    """

    run: int
    family: str
    original: SamplerRun
    stall: dict
    stale: dict
    full: dict

    @classmethod
    def from_dict(cls, data: dict) -> AblationRun:
        """The record of one object of ``ablation_runs.json``.

        Parameters
        ----------
        data : dict
            Its fields, each sampler's call as an object.

        Returns
        -------
        AblationRun
        """
        calls = {k: {a: SamplerRun.from_dict(c) for a, c in data[k].items()}
                 for k in ("stall", "stale", "full") if k in data}
        if "original" in data:
            calls["original"] = SamplerRun.from_dict(data["original"])
        return super().from_dict({**data, **calls})


def ablation_task(cfg: AblationConfig, seed: int, run: int, family: str) -> AblationRun:
    """One run of one family: the original sampler and every reading (pair).

    Stall-only runs depend on the stall reading alone and stale-only runs on the stale reading
    alone, so they are computed once per reading and shared by the pairs.
    """
    _, original, proposed = paired_calls(cfg, seed, run, family)
    return AblationRun(
        run=run,
        family=family,
        original=original,
        stall={a: proposed(a, None) for a in cfg.stall_readings},
        stale={b: proposed(None, b) for b in cfg.stale_readings},
        full={
            f"{a}|{b}": proposed(a, b) for a in cfg.stall_readings for b in cfg.stale_readings
        },
    )


def summarise_ablation(runs: list[AblationRun], cfg: AblationConfig) -> list[AblationRow]:
    """Rows ``(stall, stale, family, criterion)`` with the Table I statistics and the paper's.

    The ``"stall"`` criterion rows of one stall reading are the same runs for every stale
    reading (and likewise for ``"stale"``); they are repeated so each reading pair reads as a
    complete Table I.

    Parameters
    ----------
    runs : list of AblationRun
        Per-run records of the study's task: per run and family the original sampler's
        record and the short chains' under every reading (``"stall"``, ``"stale"`` by
        reading, ``"full"`` by ``"<stall>|<stale>"``).
    cfg : AblationConfig
        The settings of the runs (reading and family order; the cells are judged against
        the paper's only under its per-run settings).

    Returns
    -------
    list of AblationRow
        For each stall reading, each stale reading and each family, the ``"stall"``,
        ``"stale"`` and ``"full"`` rows.
    """
    rows = []
    judge = paper_settings(cfg)
    for a in cfg.stall_readings:
        for b in cfg.stale_readings:
            for fam in cfg.families:
                rs = sorted((r for r in runs if r.family == fam), key=lambda r: r.run)
                orig = [r.original for r in rs]
                for crit, key in (("stall", a), ("stale", b), ("full", f"{a}|{b}")):
                    stats = paired_summary(orig, [getattr(r, crit)[key] for r in rs])
                    rows.append(with_paper(fam, crit, stats, AblationRow, judge=judge,
                                           stall=a, stale=b))
    return rows


def consistency(rows, families=FAMILIES) -> str:
    """Verdict of one reading pair: do all its cells of ``families`` agree with the paper's?

    A cell agrees when ΔObs and ΔError both lie within three standard errors of the paper's
    (:func:`~rankedassign.experiments.paper.agrees`).

    Parameters
    ----------
    rows : iterable of Table1Row
        The rows of one reading pair (e.g. :class:`AblationRow` with the same ``stall`` and
        ``stale``).
    families : sequence of str, optional
        Families whose cells count (default the paper's three).

    Returns
    -------
    str
        ``"yes"``, ``"no: <cells>"``, or ``"–"`` when no cell can be compared.
    """
    rows = [r for r in rows if r.family in families]
    compared = [r for r in rows if r.agrees_with_paper is not None]
    if not compared:
        return "–"
    off = [f"{r.family} {r.criterion}" for r in compared if not r.agrees_with_paper]
    return "yes" if not off else "no: " + ", ".join(off)


def render_ablation(rows: list[AblationRow], cfg: AblationConfig) -> str:
    """The ablation section: every reading pair as a Table I with the 3-SE verdict."""
    fams = [f for f in ALL_FAMILIES if any(r.family == f for r in rows)]
    paper_fams = [f for f in fams if f in FAMILIES]
    extra = [f for f in fams if f not in FAMILIES]
    cols = [(f, c) for f in fams for c in CRITERIA]
    pairs = list(dict.fromkeys((r.stall, r.stale) for r in rows))
    by = {(r.stall, r.stale, r.family, r.criterion): r for r in rows}
    header = (["stall", "stale"] + [f"{f} {c}" for f, c in cols]
              + ["consistent with the paper?"]
              + [f"{f} consistent?" for f in extra])
    body = []
    for a, b in pairs:
        pair_rows = [by[a, b, f, c] for f, c in cols]
        cells = [f"{fmt.pm(r.delta_obs_pct, r.delta_obs_pct_se, 1, n_runs=r.n_mc)} / "
                 f"{fmt.pm(r.delta_error_pp, r.delta_error_pp_se, 2, n_runs=r.n_mc)}"
                 for r in pair_rows]
        body.append([a, b, *cells, consistency(pair_rows, paper_fams)]
                    + [consistency([r for r in pair_rows if r.family == f], (f,))
                       for f in extra])
    paper_row = ["**paper**", ""] + [
        f"**{fmt.num(by[pairs[0] + (f, c)].paper_delta_obs_pct, 2)} / "
        f"{fmt.num(by[pairs[0] + (f, c)].paper_delta_error_pp, 2)}**" for f, c in cols
    ] + [""] * (1 + len(extra)) if pairs else []
    n = rows[0].n_mc if rows else 0
    rec = [r for r in rows if (r.stall, r.stale) == pairs[0]] if pairs else []
    off = disagreements(rec, lambda f: family_label(f, cfg))
    first = (f"Under the recommended pair ({pairs[0][0]}, {pairs[0][1]}) every cell agrees."
             if pairs and not off else
             f"Under the recommended pair, cells more than {Z_LIMIT:g} SE from the paper's:\n\n"
             + "\n".join(f"- {line}" for line in off) if pairs else "")
    if not paper_settings(cfg):
        first = ("These settings are not the paper's (spec §3.4), so no cell is judged against "
                 "the paper's.")
    alt = " ".join(
        f"`{f}` is the random family read as {family_label(f, cfg).split(': ', 1)[1]} "
        "(spec A2), drawn from the same uniforms as `random` in each run; its cells are "
        "compared with the paper's random row in a column of their own."
        for f in extra
    )
    return f"""## Ablation — every reading of stall × stale (spec §3.2), beside the paper's

**Verdict.** {first}

Each cell is **ΔObs (%) / ΔError (pp)**, each ± one standard error, against the original
sampler on the same matrices (ΔObs > 0: the short chains save; ΔError = |ε̄_s − ε̄_o|, 0: no
accuracy lost),
{fmt.plural(n, "Monte Carlo run")}, paper settings otherwise ({cfg.n_chains:,} ×
{cfg.chain_length}, τ_stall = {cfg.tau_stall}, τ_stale = {cfg.tau_stale}; random family
`pbar_d = {cfg.pbar_d!r}`, `granularity = {cfg.granularity!r}`). The stall-only columns depend
only on the stall reading and the stale-only columns only on the stale reading (shared runs).
{alt} The paper's Table I is the bold row. {fmt.runs_note(r.n_mc for r in rows)}

{fmt.table(header, body + ([paper_row] if paper_row else []))}

"consistent with the paper?" applies Table I's rule to every cell of the paper's three
families: ΔObs and ΔError each within {Z_LIMIT:g} of our standard errors of the paper's number
± half a unit of its last printed digit; "no" lists the cells that are not. With
{fmt.plural(n, "run")} the standard errors are wide, so "yes" means "not contradicted at this
precision".
"""


ABLATION = register_study(Study(
    name="ablation",
    title="Table I under every reading of the stall and stale rules, beside the paper's",
    config_type=AblationConfig,
    full=AblationConfig,
    quick=lambda: AblationConfig(n_mc=QUICK_MC),
    tasks=per_family_tasks,
    task=ablation_task,
    run_from_dict=AblationRun.from_dict,
    summarise=summarise_ablation,
    render=render_ablation,
    plot=None,
    csv_rows=as_rows,
    order=50,
    warm=tiny_synthetic,
    warm_after="table1",  # Table I's samplers, compiled by its first tiny task
))
