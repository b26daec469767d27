"""Table I under every reading of the random family that the paper's text admits.

The paper defines ``Pbar_D = r P_D`` but Vo's code uses ``P_D`` (spec A2), and it does not say
whether ``P_s, P_d`` are drawn per row or once per matrix (A5). ``Pbar_D`` also enters the
diagonal family, so every random reading is combined with each diagonal reading into a whole
Table I (nine cells), judged against the paper's nine cells at once with the
three-standard-error rule; the combinations with the same ``Pbar_D`` in both families are the
readings of one consistent text, the others read the two families differently. The uniform
family depends on neither choice and is run once; each family's runs are those of the
``table1`` study for the same seed and reading (same streams).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

from ...validation import check_fields
from .. import _format as fmt
from .._synthetic import Table1Row, paired_summary, paper_settings, tiny_synthetic, with_paper
from ..config import (
    CRITERIA,
    DEFAULT_DIAGONAL_PBAR_D,
    DEFAULT_GRANULARITY,
    DEFAULT_PBAR_D,
    FAMILIES,
    PBAR_D_READINGS,
    check_positive,
)
from ..paper import Z_LIMIT
from ..registry import Study, as_rows, register_study
from .table1 import Table1Config, Table1Run, table1_task

#: Readings of the random family the paper's text admits (spec A2, A5): ``(pbar_d,
#: granularity)`` with ``Pbar_D`` = ``r P_d`` or ``P_d`` and ``P_s, P_d`` drawn per row or once
#: per matrix (``q`` is per entry in every reading).
RANDOM_READINGS = (("r_pd", "row"), ("pd", "row"), ("r_pd", "matrix"), ("pd", "matrix"))


@dataclass(frozen=True)
class ReadingsConfig:
    """Table I (all nine cells) under each reading of the random family (spec A2, A5).

    ``Pbar_D`` also enters the diagonal family: every random reading is combined with each
    reading of the diagonal family's ``Pbar_D`` in ``diagonal_readings``, so each combination
    is a complete Table I; the uniform family depends on neither choice and is run once.

    Attributes
    ----------
    n_mc : int
        Monte Carlo runs per family and reading.
    readings : tuple of (str, str)
        ``(pbar_d, granularity)`` readings of the random family, a non-empty subset of
        :data:`RANDOM_READINGS` (lists are turned into tuples).
    diagonal_readings : tuple of str
        ``Pbar_D`` readings of the diagonal family, a non-empty subset of
        ``("r_pd", "pd")``.
    original_obs : int
        Sweeps of the original sampler's single chain.
    n_chains, chain_length : int
        ``N_S`` chains of ``N_C`` sweeps of the short-chain sampler.
    tau_stall, tau_stale : int
        Thresholds of the stall and stale rules (readings S3, T3).

    Examples
    --------
    >>> from rankedassign.experiments.studies.readings import ReadingsConfig
    >>> ReadingsConfig().readings[:2]
    (('r_pd', 'row'), ('pd', 'row'))
    """

    n_mc: int = 100
    readings: tuple[tuple[str, str], ...] = RANDOM_READINGS
    diagonal_readings: tuple[str, ...] = PBAR_D_READINGS
    original_obs: int = 250_000
    n_chains: int = 10_000
    chain_length: int = 25
    tau_stall: int = 5
    tau_stale: int = 25

    def __post_init__(self):
        check_fields(self)
        for name in ("n_mc", "original_obs", "n_chains", "chain_length", "tau_stall", "tau_stale"):
            check_positive(name, getattr(self, name))
        readings = tuple(tuple(r) for r in self.readings)
        if not readings or any(r not in RANDOM_READINGS for r in readings):
            raise ValueError(
                f"readings must be a non-empty subset of {RANDOM_READINGS}, got {self.readings!r}"
            )
        object.__setattr__(self, "readings", readings)
        diag = self.diagonal_readings
        if not diag or any(r not in PBAR_D_READINGS for r in diag):
            raise ValueError(f"diagonal_readings must be a non-empty subset of "
                             f"{PBAR_D_READINGS}, got {diag!r}")

__all__ = ["READINGS", "ReadingRow", "ReadingsRun", "summarise_readings", "reading_verdicts"]

#: Quick mode: Monte Carlo runs (the per-run settings are the paper's).
QUICK_MC = 20


@dataclass(frozen=True, kw_only=True)
class ReadingRow(Table1Row):
    """A Table I row under one reading: ``diagonal_pbar_d`` for the diagonal family and
    (``pbar_d``, ``granularity``) for the random family.

    The statistics are those of :class:`~rankedassign.experiments._synthetic.Table1Row`:
    ``eps_o``, ``eps_s`` are one run's truncation errors of the original and of the
    short-chain sampler, ``N_o``, ``N_s`` their observations; standard errors are ``None``
    for one run. The three readings label the whole combination; a family's numbers depend
    only on the readings it uses (the uniform family's on none).

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
    diagonal_pbar_d : {"r_pd", "pd"}
        ``Pbar_D`` of the diagonal family in this combination (spec A2): ``r P_d`` or ``P_d``.
    pbar_d : {"r_pd", "pd"}
        ``Pbar_D`` of the random family in this combination (spec A2).
    granularity : {"row", "matrix"}
        Whether the random family draws ``P_s, P_d`` per row or once per matrix (spec A5).
    """

    diagonal_pbar_d: str
    pbar_d: str
    granularity: str


def _key(family: str, diagonal_pbar_d: str, pbar_d: str, granularity: str) -> tuple:
    """What the family's matrices depend on: nothing, one ``Pbar_D``, or it and the granularity."""
    if family == "uniform":
        return (family, None, None)
    if family == "diagonal":
        return (family, diagonal_pbar_d, None)
    return (family, pbar_d, granularity)


def _combinations(cfg: ReadingsConfig) -> list[tuple[str, str, str]]:
    """``(diagonal_pbar_d, pbar_d, granularity)``: the same ``Pbar_D`` in both families first."""
    combos = [(d, a, b) for a, b in cfg.readings for d in cfg.diagonal_readings]
    return sorted(combos, key=lambda c: c[0] != c[1])


def _table1_config(cfg: ReadingsConfig, family: str, pbar, granularity) -> Table1Config:
    return Table1Config(
        n_mc=cfg.n_mc, families=(family,), original_obs=cfg.original_obs,
        n_chains=cfg.n_chains, chain_length=cfg.chain_length, tau_stall=cfg.tau_stall,
        tau_stale=cfg.tau_stale, pbar_d=pbar or "r_pd", diagonal_pbar_d=pbar or "r_pd",
        granularity=granularity or "row",
    )


def readings_tasks(cfg: ReadingsConfig, seed: int) -> list[tuple]:
    """One Table I task per distinct (family, reading it depends on) and run."""
    keys = dict.fromkeys(_key(f, *c) for c in _combinations(cfg) for f in FAMILIES)
    return [(_table1_config(cfg, *k), seed, r, k[0]) for k in keys for r in range(cfg.n_mc)]


@dataclass(frozen=True)
class ReadingsRun(Table1Run):
    """A Table I run of one family under one reading, labelled with it.

    Attributes
    ----------
    run, family, original, stall, stale, full
        As in :class:`~rankedassign.experiments.studies.table1.Table1Run`.
    key : list
        ``[family, Pbar_D reading, granularity]``: the reading the family's matrix depends on
        (None where it does not: the uniform family reads neither, the diagonal family its
        ``diagonal_pbar_d`` alone).
    """

    key: list


def readings_task(t1cfg: Table1Config, seed: int, run: int, family: str) -> ReadingsRun:
    """A Table I run of one family under the reading in ``t1cfg``, labelled with it."""
    out = table1_task(t1cfg, seed, run, family)
    return ReadingsRun(
        **{f.name: getattr(out, f.name) for f in fields(out)},
        key=list(_key(family, t1cfg.diagonal_pbar_d, t1cfg.pbar_d, t1cfg.granularity)))


def summarise_readings(runs: list[ReadingsRun], cfg: ReadingsConfig) -> list[ReadingRow]:
    """Nine Table I rows (with the paper's cells) per combination of readings.

    Parameters
    ----------
    runs : list of ReadingsRun
        Per-run Table I records of the study's tasks, each labelled with the ``key`` of the
        reading its family depends on.
    cfg : ReadingsConfig
        The settings of the runs (readings; the cells are judged against the paper's only
        under its per-run settings).

    Returns
    -------
    list of ReadingRow
        Per combination ``(diagonal_pbar_d, pbar_d, granularity)`` (those with the same
        ``Pbar_D`` in both families first), the three families' ``"stall"``, ``"stale"`` and
        ``"full"`` rows.
    """
    rows = []
    judge = paper_settings(cfg)
    for d, a, b in _combinations(cfg):
        for fam in FAMILIES:
            key = list(_key(fam, d, a, b))
            rs = sorted((r for r in runs if r.key == key), key=lambda r: r.run)
            for crit in CRITERIA:
                stats = paired_summary([r.original for r in rs],
                                       [r.criterion(crit) for r in rs])
                rows.append(with_paper(fam, crit, stats, ReadingRow, judge=judge,
                                           diagonal_pbar_d=d, pbar_d=a, granularity=b))
    return rows


def reading_verdicts(rows: list[ReadingRow]) -> dict[tuple[str, str, str], list[str]]:
    """``{(diagonal_pbar_d, pbar_d, granularity): cells that differ from the paper's}``.

    An empty list means consistent (or not judged: other settings than the paper's).

    A cell differs when its ΔObs or its ΔError lies more than three standard errors from the
    paper's (:func:`~rankedassign.experiments.paper.agrees`).

    Parameters
    ----------
    rows : list of ReadingRow
        Rows of :func:`summarise_readings`.

    Returns
    -------
    dict of tuple to list of str
        For every combination ``(diagonal_pbar_d, pbar_d, granularity)`` among the rows, in
        their order, the cells ``"<family> <criterion>"`` that disagree with the paper's.
    """
    out: dict[tuple[str, str, str], list[str]] = {}
    for r in rows:
        off = out.setdefault((r.diagonal_pbar_d, r.pbar_d, r.granularity), [])
        if r.agrees_with_paper is False:
            off.append(f"{r.family} {r.criterion}")
    return out


def _pbar(a: str) -> str:
    return "r·P_d" if a == "r_pd" else "P_d"


def _cell(r) -> str:
    return (f"{fmt.pm(r.delta_obs_pct, r.delta_obs_pct_se, 1, n_runs=r.n_mc)} / "
            f"{fmt.pm(r.delta_error_pp, r.delta_error_pp_se, 2, n_runs=r.n_mc)}")


def _overall(combos, verdicts, by, cols, default) -> str:
    """The section's verdict: which complete readings agree with all nine cells."""
    ok = [c for c in combos if not verdicts[c]
          and any(by[c + (f, k)].agrees_with_paper is not None for f, k in cols)]
    judged = [c for c in combos
              if any(by[c + (f, k)].agrees_with_paper is not None for f, k in cols)]
    if not judged:
        return ("No reading is judged against the paper: the settings are not the paper's, or "
                "one run has no standard error.")

    def name(c):
        return f"diagonal {_pbar(c[0])}, random {_pbar(c[1])} with {c[2]} P_s, P_d"

    if not ok:
        return (f"None of the {len(judged)} readings agrees with all nine of the paper's cells "
                f"within {Z_LIMIT:g} standard errors.")
    return (f"{len(ok)} of the {len(judged)} readings agree with all nine of the paper's cells "
            f"within {Z_LIMIT:g} standard errors: " + "; ".join(
                f"({i}) {name(c)}" + (" (the default)" if c == default else "")
                for i, c in enumerate(ok, 1)) + ".")


def render_readings(rows: list[ReadingRow], cfg: ReadingsConfig) -> str:
    """The section: one line per combination of readings with its nine cells and the verdict."""
    default = (DEFAULT_DIAGONAL_PBAR_D, DEFAULT_PBAR_D, DEFAULT_GRANULARITY)
    cols = [(f, c) for f in FAMILIES for c in CRITERIA]
    by = {(r.diagonal_pbar_d, r.pbar_d, r.granularity, r.family, r.criterion): r for r in rows}
    verdicts = reading_verdicts(rows)
    combos = _combinations(cfg)
    n = rows[0].n_mc if rows else 0
    body = []
    for combo in combos:
        d, a, b = combo
        cells = [_cell(by[combo + (f, c)]) for f, c in cols]
        off = verdicts[combo]
        compared = any(by[combo + (f, c)].agrees_with_paper is not None for f, c in cols)
        verdict = "–" if not compared else ("yes" if not off else "no: " + ", ".join(off))
        notes = [n for n, on in (("default", combo == default), ("mixed", d != a)) if on]
        name = (f"diagonal {_pbar(d)}; random {_pbar(a)}, {b} P_s, P_d"
                + (f" ({', '.join(notes)})" if notes else ""))
        body.append([name, *cells, verdict])
    if combos:
        first = combos[0]
        body.append(["**paper**"] + [
            f"**{by[first + (f, c)].paper_delta_obs_pct:.2f} / "
            f"{by[first + (f, c)].paper_delta_error_pp:.2f}**" for f, c in cols] + [""])
    detail = []
    for a, b in cfg.readings:
        combo = (cfg.diagonal_readings[0], a, b)
        r1, r2 = by[combo + ("random", "stale")], by[combo + ("random", "full")]
        detail.append(
            f"- random, P̄_D = {_pbar(a)}, {b} P_s, P_d: stale ΔObs "
            f"{fmt.pm(r1.delta_obs_pct, r1.delta_obs_pct_se)} % "
            f"({fmt.versus(r1.delta_obs_pct, r1.delta_obs_pct_se, 0.0)}; stale stops in "
            f"{100 * r1.stale_stop_fraction:.0f} % of runs); full ΔObs "
            f"{fmt.pm(r2.delta_obs_pct, r2.delta_obs_pct_se)} % "
            f"({fmt.versus(r2.delta_obs_pct, r2.delta_obs_pct_se, r2.paper_delta_obs_pct)}), "
            f"ΔError {fmt.pm(r2.delta_error_pp, r2.delta_error_pp_se)} pp "
            f"({fmt.versus(r2.delta_error_pp, r2.delta_error_pp_se, r2.paper_delta_error_pp)})")
    if not paper_settings(cfg):
        detail.insert(0, "- These settings are not the paper's (spec §3.4), so no reading is "
                         "judged against the paper's numbers.")
    return f"""## Readings of the random family — which agree with all nine cells of Table I?

The paper's text admits P̄_D = r·P_d (its definition) or P̄_D = P_d (Vo's code), and P_s, P_d
drawn per row or once per matrix (spec A2, A5); q is drawn per entry in every reading. P̄_D
also enters the diagonal family: each line combines a reading of the diagonal family's P̄_D
with a reading of the random family into a complete Table I (the uniform family depends on
neither choice and is shared). Lines marked "mixed" read P̄_D differently in the two families.
{fmt.plural(n, "Monte Carlo run")} per family and reading, the settings of Table I; each cell is
**ΔObs (%) / ΔError (pp)**, the paper's are in bold. A line is consistent when all nine cells
lie within {Z_LIMIT:g} standard errors of the paper's (ΔObs and ΔError each). The line marked
"default" is what the Table I study runs; the reasons are in the documentation's ambiguity
list (A2, A5).

{fmt.runs_note(r.n_mc for r in rows)}

**Verdict.** {_overall(combos, verdicts, by, cols, default)}

{fmt.table(["reading", *[f"{f} {c}" for f, c in cols], "consistent with all nine?"], body)}

The random family under each reading:

{chr(10).join(detail)}
"""


READINGS = register_study(Study(
    name="random_readings",
    title="Table I under every reading of the random family (P̄_D, granularity of P_s, P_d)",
    config_type=ReadingsConfig,
    full=ReadingsConfig,
    quick=lambda: ReadingsConfig(n_mc=QUICK_MC),
    tasks=readings_tasks,
    task=readings_task,
    run_from_dict=ReadingsRun.from_dict,
    summarise=summarise_readings,
    render=render_readings,
    plot=None,
    csv_rows=as_rows,
    order=70,
    warm=tiny_synthetic,
    warm_after="table1",  # Table I's samplers, compiled by its first tiny task
    paper="Table I",
))
