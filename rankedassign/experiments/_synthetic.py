"""Building blocks shared by the synthetic-matrix studies (Table I, ablation, optimum, sweep).

Random streams of one Monte Carlo run ``r`` (``s = run_seed(seed, r)``), named so that every
study draws the same matrix and the same sampler trajectories for the same ``(seed, r)``:

* ``child_seed(s, 0)`` — the random-family matrix (``synthetic.random``);
* ``child_seed(s, 1, family)`` — the original sampler of the synthetic studies;
* ``child_seed(s, 2, family, variant)`` — the short-chain sampler under one termination
  variant (:func:`variant_key`), so e.g. Table I's "full" column and the ablation's
  (S3, T3) pair are the very same runs;
* ``child_seed(s, 3, family, L)`` — the sweep study's samplers (``L = 0``: original).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

import oracle

from .. import sample_original, sample_short_chains
from ..single import synthetic
from ._executor import child_seed, run_seed
from ._records import RunRecord
from .config import ALL_FAMILIES, STALE_READINGS, STALL_READINGS
from .paper import PAPER_TABLE1, agrees, distance_in_se

KEY_MATRIX, KEY_ORIGINAL, KEY_PROPOSED, KEY_SWEEP = 0, 1, 2, 3


def family_index(family: str) -> int:
    return ALL_FAMILIES.index(family)


def variant_key(stall: str | None, stale: str | None) -> int:
    """Integer naming a termination variant; ``None`` = rule off."""
    s = 0 if stall is None else 1 + STALL_READINGS.index(stall)
    t = 0 if stale is None else 1 + STALE_READINGS.index(stale)
    return 8 * s + t


@lru_cache(maxsize=8)
def _deterministic(family: str, pbar_d: str):
    return synthetic.diagonal(pbar_d=pbar_d) if family == "diagonal" else synthetic.uniform()


def make_problem(family: str, run_ss: np.random.SeedSequence, cfg):
    """The matrix of ``family`` for one Monte Carlo run (the random family is re-drawn)."""
    if family in ("random", "random-pd", "random-r_pd"):
        return synthetic.random(
            pbar_d=cfg.pbar_d if family == "random" else family.split("-", 1)[1],
            granularity=cfg.granularity,
            rng=child_seed(run_ss, KEY_MATRIX),
        )
    if family in ("diagonal", "uniform"):
        return _deterministic(family, getattr(cfg, "diagonal_pbar_d", cfg.pbar_d))
    raise ValueError(f"unknown family {family!r}; choose from {ALL_FAMILIES}")


@dataclass(frozen=True)
class SamplerRun(RunRecord):
    """What a synthetic study keeps of one sampler call: counts and the exact truncation error.

    Attributes
    ----------
    n_obs : int
        Observations (sweeps) spent.
    n_row_updates : int
        Row updates spent.
    n_unique : int
        Unique assignments found.
    n_chains : int
        Chains run.
    stop_reason : str
        Why the sampler stopped (``"budget"``, ``"stall"``, ``"stale"``, ...).
    error : float
        Exact truncation error (spec eq. 1.9) of the unique assignments, a fraction.
    """

    n_obs: int
    n_row_updates: int
    n_unique: int
    n_chains: int
    stop_reason: str
    error: float


def record(problem, res) -> SamplerRun:
    """What a study keeps of one sampler run: counts and the exact truncation error (1.9)."""
    return SamplerRun(
        n_obs=int(res.n_observations),
        n_row_updates=int(res.n_row_updates),
        n_unique=int(len(res.costs)),
        n_chains=int(res.n_chains_run),
        stop_reason=str(res.stop_reason),
        error=float(oracle.truncation_error(problem, res.assignments)),
    )


def run_original(problem, n_obs: int, rng) -> SamplerRun:
    return record(problem, sample_original(problem, n_obs, rng=rng))


def run_proposed(problem, cfg, rng, *, stall: str | None, stale: str | None) -> SamplerRun:
    """The short-chain sampler with the paper's settings; a ``None`` reading turns its rule off."""
    res = sample_short_chains(
        problem,
        cfg.n_chains,
        cfg.chain_length,
        tau_stall=None if stall is None else cfg.tau_stall,
        tau_stale=None if stale is None else cfg.tau_stale,
        stall=stall or STALL_READINGS[0],
        stale=stale or STALE_READINGS[0],
        rng=rng,
    )
    return record(problem, res)


def proposed_seed(run_ss, family: str, stall, stale):
    return child_seed(run_ss, KEY_PROPOSED, family_index(family), variant_key(stall, stale))


def original_seed(run_ss, family: str):
    return child_seed(run_ss, KEY_ORIGINAL, family_index(family))


def paired_calls(cfg, seed: int, run: int, family: str):
    """One Monte Carlo run of one family of a Table I-like study: the matrix and both samplers.

    Parameters
    ----------
    cfg : SyntheticConfig
        The study's settings (the family's readings, the samplers' settings).
    seed : int
        The study's seed.
    run : int
        Monte Carlo run index; the run draws from ``run_seed(seed, run)``.
    family : str
        Matrix family (:data:`~rankedassign.experiments.config.ALL_FAMILIES`).

    Returns
    -------
    problem : SingleSensorProblem
        The run's matrix (:func:`make_problem`).
    original : SamplerRun
        The original sampler's call (``cfg.original_obs`` sweeps, its own stream).
    proposed : callable
        ``proposed(stall, stale) -> SamplerRun``: the short chains under one reading of each
        rule (``None``: the rule off), each variant on its own stream (:func:`proposed_seed`),
        so every study that runs a variant runs the very same chains.
    """
    s = run_seed(seed, run)
    problem = make_problem(family, s, cfg)

    def proposed(stall, stale):
        rng = proposed_seed(s, family, stall, stale)
        return run_proposed(problem, cfg, rng, stall=stall, stale=stale)

    return problem, run_original(problem, cfg.original_obs, original_seed(s, family)), proposed


def tiny_synthetic(cfg):
    """The warm-up settings of a Table I-like study: one run, 200 sweeps, 8 short chains."""
    return dataclasses.replace(cfg, n_mc=1, original_obs=200, n_chains=8)


@dataclass(frozen=True, kw_only=True)
class PairedStats:
    """Table I statistics of one (family, criterion) cell, from paired per-run records.

    Errors are in percent, their differences in percentage points; standard errors are
    ``None`` for one run. ``eps_o``, ``eps_s`` below are one run's truncation errors of the
    original and of the short-chain sampler, ``N_o``, ``N_s`` their observations.

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
    """

    n_mc: int
    obs_original_mean: float
    obs_proposed_mean: float
    error_original_mean: float
    error_proposed_mean: float
    delta_obs_pct: float
    delta_error_pp: float
    delta_error_signed_pp: float
    mean_abs_delta_error_pp: float
    unique_original_mean: float
    unique_proposed_mean: float
    chains_proposed_mean: float
    stale_stop_fraction: float
    delta_obs_pct_se: float | None
    delta_error_pp_se: float | None
    mean_abs_delta_error_pp_se: float | None
    error_original_se: float | None
    error_proposed_se: float | None
    # defaults: records built before these standard errors existed stay valid
    obs_original_se: float | None = None
    obs_proposed_se: float | None = None
    unique_original_se: float | None = None
    unique_proposed_se: float | None = None
    stale_stop_se: float | None = None


@dataclass(frozen=True, kw_only=True)
class Table1Row(PairedStats):
    """One row of Table I: a family, a criterion, our statistics and the paper's numbers.

    ``paper_*`` are the paper's values (``None`` where the paper has no such cell, e.g. the
    alternative reading of a family), ``*_z`` our distance to them in standard errors and
    ``agrees_with_paper`` whether both lie within three standard errors (spec §3.6).
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
    """

    family: str
    criterion: str
    paper_family: str | None = None
    paper_delta_obs_pct: float | None = None
    paper_delta_error_pp: float | None = None
    delta_obs_z: float | None = None
    delta_error_z: float | None = None
    agrees_with_paper: bool | None = None


def paper_family(family: str) -> str:
    """The paper's family that ``family`` reads (``"random-pd"`` -> ``"random"``)."""
    return family.split("-", 1)[0]


#: The paper's per-run settings of Table I (spec §3.4); other settings are not judged.
PAPER_SETTINGS = {"original_obs": 250_000, "n_chains": 10_000, "chain_length": 25,
                  "tau_stall": 5, "tau_stale": 25}


def paper_settings(cfg) -> bool:
    """Whether ``cfg`` runs the paper's per-run settings (only then are cells judged)."""
    return all(getattr(cfg, k) == v for k, v in PAPER_SETTINGS.items())


def with_paper(family: str, criterion: str, stats: PairedStats, cls=Table1Row, *,
               judge: bool = True, **extra):
    """A Table I row of ``cls`` carrying the paper's numbers of the same cell (if any).

    With ``judge=False`` (settings other than the paper's) the paper's numbers are carried but
    the distances and the verdict are left ``None``.
    """
    fields = dataclasses.asdict(stats)
    pf = paper_family(family)
    cell = PAPER_TABLE1.get((pf, criterion))
    if cell is None:
        return cls(family=family, criterion=criterion, **extra, **fields)
    if not judge:
        return cls(family=family, criterion=criterion, **extra, **fields, paper_family=pf,
                   paper_delta_obs_pct=cell.delta_obs_pct,
                   paper_delta_error_pp=cell.delta_error_pp)
    zo = distance_in_se(stats.delta_obs_pct, stats.delta_obs_pct_se, cell.delta_obs_pct)
    ze = distance_in_se(stats.delta_error_pp, stats.delta_error_pp_se, cell.delta_error_pp)
    ok = [agrees(stats.delta_obs_pct, stats.delta_obs_pct_se, cell.delta_obs_pct),
          agrees(stats.delta_error_pp, stats.delta_error_pp_se, cell.delta_error_pp)]
    return cls(
        family=family, criterion=criterion, **extra, **fields, paper_family=pf,
        paper_delta_obs_pct=cell.delta_obs_pct, paper_delta_error_pp=cell.delta_error_pp,
        delta_obs_z=zo, delta_error_z=ze,
        agrees_with_paper=None if None in ok else all(ok),
    )


def paired_summary(original: list[SamplerRun], proposed: list[SamplerRun]) -> PairedStats:
    """Table I statistics of one (family, criterion) cell from paired per-run records.

    ``delta_obs_pct = 100 (mean N_o - mean N_s) / mean N_o`` with a delta-method standard error
    of the ratio of the paired means; ``delta_error_pp = |mean(eps_s - eps_o)|`` (= spec 1.10,
    ``|mean eps_o - mean eps_s|``) with the standard error of the mean per-run paired difference;
    ``mean_abs_delta_error_pp`` is the mean of per-run ``|eps_s - eps_o|`` (spec A7) with its
    standard error. Errors are in percentage points. Standard errors are ``None`` for one run.
    A record is a :class:`SamplerRun` or any with its ``n_obs``, ``n_unique``, ``n_chains``,
    ``stop_reason`` and ``error`` (the multi-sensor study's calls).
    """
    n = len(original)
    if n != len(proposed) or n == 0:
        raise ValueError("need the same positive number of original and proposed runs")
    No = np.array([r.n_obs for r in original], dtype=float)
    Ns = np.array([r.n_obs for r in proposed], dtype=float)
    eo = 100.0 * np.array([r.error for r in original])
    es = 100.0 * np.array([r.error for r in proposed])
    Uo = np.array([r.n_unique for r in original], dtype=float)
    Us = np.array([r.n_unique for r in proposed], dtype=float)
    stale = np.array([r.stop_reason == "stale" for r in proposed], dtype=float)
    mo, ms = No.mean(), Ns.mean()
    d = es - eo
    out = {
        "n_mc": n,
        "obs_original_mean": float(mo),
        "obs_proposed_mean": float(ms),
        "error_original_mean": float(eo.mean()),
        "error_proposed_mean": float(es.mean()),
        "delta_obs_pct": float(100.0 * (mo - ms) / mo),
        "delta_error_pp": float(abs(d.mean())),
        "delta_error_signed_pp": float(d.mean()),
        "mean_abs_delta_error_pp": float(np.abs(d).mean()),
        "unique_original_mean": float(np.mean([r.n_unique for r in original])),
        "unique_proposed_mean": float(np.mean([r.n_unique for r in proposed])),
        "chains_proposed_mean": float(np.mean([r.n_chains for r in proposed])),
        "stale_stop_fraction": float(np.mean([r.stop_reason == "stale" for r in proposed])),
    }
    if n > 1:
        cov = np.cov(np.vstack([No, Ns]), ddof=1)
        # Delta method for R = mean N_s / mean N_o (paired): Var R ~ grad' Cov grad / n.
        var_r = (cov[1, 1] / mo**2 + ms**2 * cov[0, 0] / mo**4 - 2 * ms * cov[0, 1] / mo**3) / n
        se = {
            "delta_obs_pct_se": float(100.0 * math.sqrt(max(var_r, 0.0))),
            "delta_error_pp_se": float(d.std(ddof=1) / math.sqrt(n)),
            "mean_abs_delta_error_pp_se": float(np.abs(d).std(ddof=1) / math.sqrt(n)),
            "error_original_se": float(eo.std(ddof=1) / math.sqrt(n)),
            "error_proposed_se": float(es.std(ddof=1) / math.sqrt(n)),
            "obs_original_se": float(No.std(ddof=1) / math.sqrt(n)),
            "obs_proposed_se": float(Ns.std(ddof=1) / math.sqrt(n)),
            "unique_original_se": float(Uo.std(ddof=1) / math.sqrt(n)),
            "unique_proposed_se": float(Us.std(ddof=1) / math.sqrt(n)),
            "stale_stop_se": float(stale.std(ddof=1) / math.sqrt(n)),
        }
    else:
        se = dict.fromkeys(
            (
                "delta_obs_pct_se",
                "delta_error_pp_se",
                "mean_abs_delta_error_pp_se",
                "error_original_se",
                "error_proposed_se",
                "obs_original_se",
                "obs_proposed_se",
                "unique_original_se",
                "unique_proposed_se",
                "stale_stop_se",
            )
        )
    out.update(se)
    return PairedStats(**out)
