"""Table I under every pair of stall x stale readings of the paper's pseudo-code (spec §3.2)."""

from __future__ import annotations

from dataclasses import dataclass

from .. import _format as fmt
from .._executor import run_seed
from .._synthetic import (
    Table1Row,
    make_problem,
    original_seed,
    paired_summary,
    paper_settings,
    proposed_seed,
    run_original,
    run_proposed,
    with_paper,
)
from ..config import ALL_FAMILIES, CRITERIA, FAMILIES, AblationConfig
from ..paper import Z_LIMIT
from ..registry import Study, as_rows, per_family_tasks, register_study
from .table1 import disagreements, family_label

__all__ = ["ABLATION", "AblationRow", "summarise_ablation", "consistency"]

#: Quick mode: Monte Carlo runs (the per-run settings are the paper's).
QUICK_MC = 10


@dataclass(frozen=True, kw_only=True)
class AblationRow(Table1Row):
    """A Table I row under one reading pair (``stall``, ``stale``; spec §3.2)."""

    stall: str
    stale: str


def ablation_task(cfg: AblationConfig, seed: int, run: int, family: str) -> dict:
    """One run of one family: the original sampler and every reading (pair).

    Stall-only runs depend on the stall reading alone and stale-only runs on the stale reading
    alone, so they are computed once per reading and shared by the pairs.
    """
    s = run_seed(seed, run)
    problem = make_problem(family, s, cfg)

    def proposed(stall, stale):
        rng = proposed_seed(s, family, stall, stale)
        return run_proposed(problem, cfg, rng, stall=stall, stale=stale)

    return {
        "run": run,
        "family": family,
        "original": run_original(problem, cfg.original_obs, original_seed(s, family)),
        "stall": {a: proposed(a, None) for a in cfg.stall_readings},
        "stale": {b: proposed(None, b) for b in cfg.stale_readings},
        "full": {
            f"{a}|{b}": proposed(a, b) for a in cfg.stall_readings for b in cfg.stale_readings
        },
    }


def summarise_ablation(runs: list[dict], cfg: AblationConfig) -> list[AblationRow]:
    """Rows ``(stall, stale, family, criterion)`` with the Table I statistics and the paper's.

    The ``"stall"`` criterion rows of one stall reading are the same runs for every stale
    reading (and likewise for ``"stale"``); they are repeated so each reading pair reads as a
    complete Table I.
    """
    rows = []
    judge = paper_settings(cfg)
    for a in cfg.stall_readings:
        for b in cfg.stale_readings:
            for fam in cfg.families:
                rs = sorted((r for r in runs if r["family"] == fam), key=lambda r: r["run"])
                orig = [r["original"] for r in rs]
                for crit, key in (("stall", a), ("stale", b), ("full", f"{a}|{b}")):
                    stats = paired_summary(orig, [r[crit][key] for r in rs])
                    rows.append(with_paper(fam, crit, stats, AblationRow, judge=judge,
                                           stall=a, stale=b))
    return rows


def consistency(rows, families=FAMILIES) -> str:
    """Verdict of one reading pair: do all its cells of ``families`` agree with the paper's?

    A cell agrees when ΔObs and ΔError both lie within three standard errors of the paper's
    (:func:`~rankedassign.experiments.paper.agrees`).

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
        cells = [f"{fmt.num(r.delta_obs_pct, 1)} / {fmt.num(r.delta_error_pp, 2)}"
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

Each cell is **ΔObs (%) / ΔError (pp)** against the original sampler on the same matrices,
{fmt.plural(n, "Monte Carlo run")}, paper settings otherwise ({cfg.n_chains:,} ×
{cfg.chain_length}, τ_stall = {cfg.tau_stall}, τ_stale = {cfg.tau_stale}; random family
`pbar_d = {cfg.pbar_d!r}`, `granularity = {cfg.granularity!r}`). The stall-only columns depend
only on the stall reading and the stale-only columns only on the stale reading (shared runs).
{alt} The paper's Table I is the bold row. Standard errors are in `ablation.json` /
`ablation.csv`.

{fmt.table(header, body + ([paper_row] if paper_row else []))}

"consistent with the paper?" applies Table I's rule to every cell of the paper's three
families: ΔObs and ΔError each within {Z_LIMIT:g} of our standard errors of the paper's number
± half a unit of its last printed digit; "no" lists the cells that are not. With
{fmt.plural(n, "run")} the standard errors are wide, so "yes" means "not contradicted at this
precision".

{first}
"""


ABLATION = register_study(Study(
    name="ablation",
    title="Table I under every reading of the stall and stale rules, beside the paper's",
    config_type=AblationConfig,
    full=AblationConfig,
    quick=lambda: AblationConfig(n_mc=QUICK_MC),
    tasks=per_family_tasks,
    task=ablation_task,
    summarise=summarise_ablation,
    render=render_ablation,
    plot=None,
    csv_rows=as_rows,
    order=50,
))
