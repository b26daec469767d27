"""The adaptive-birth study: Table I layout on the AB families, and error vs observations.

Spec ``multisensor.md`` §5, §6.5: the short-chain architecture (stall S3 / stale T3, one
observation = one sweep over the sensors, every chain from the all-missed tuple) against the
original long chain, on three families of adaptive-birth problems with ``V`` in ``{4, 6, 8}``
sensors (``M`` = 10, 6, 4 measurements per sensor: 14 641, 117 649 and 390 625 tuples):

* **diagonal** — 3 well-separated targets seen by every sensor (``P_D = 0.95``), the rest of
  each sensor's measurements clutter, ``r_U = 0.99`` for every measurement;
* **uniform** — ``rho = 1`` on every tuple (``psibar_B = 1``, ``r_U = 1``);
* **random** — 3 targets and the clutter uniform in the region, ``P_D^(v) ~ U[0.5, 0.99]``,
  ``r_U ~ U[tau_rU, 1]``.

The truncation error of a run is the exact one of :func:`oracle.truncation_error` (spec §5:
mass of the birth tuples ``T*`` with ``>= n_min`` detections that the run missed). The
functions here are the study's computation — one Monte Carlo task, the Table I summary, the
report table and the plot — for the experiment registry to wrap.

References
----------
.. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
   Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023, Table I.
.. [2] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "Multi-sensor joint adaptive birth sampler
   for labeled random finite set tracking", IEEE Trans. Signal Process. 70, 2022.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

import oracle

from ...adaptive_birth.synthetic import FAMILIES, SIZES, make_family
from ...samplers import sample_original, sample_short_chains
from ...validation import check_choice, check_fields, check_int
from .. import _format as fmt
from .._plots import MARKERS, PALETTE, figure, legend_below
from .._records import RunRecord
from ..registry import Study, register_study

__all__ = ["ADAPTIVE_BIRTH", "AdaptiveBirthRow", "AdaptiveBirthSummary",
           "summarise_adaptive_birth", "CRITERIA", "AdaptiveBirthStudyConfig", "QUICK", "FULL",
           "run_task", "summarise", "curve", "format_table", "plot", "ABCall",
           "AdaptiveBirthRun", "CurvePoint", "AdaptiveBirthCurve", "task_from_dict"]

CRITERIA = ("stall", "stale", "full")


@dataclass(frozen=True)
class AdaptiveBirthStudyConfig:
    """Settings of the adaptive-birth study.

    Attributes
    ----------
    n_mc : int
        Monte Carlo runs per (family, V).
    sensors : tuple of int
        Values of ``V`` (each with ``M = SIZES[V]``).
    families : tuple of str
        Problem families (:data:`rankedassign.adaptive_birth.synthetic.FAMILIES`).
    original_obs : int
        Sweeps of the original chain (the port's ``H = 1000``).
    n_chains, chain_length, tau_stall, tau_stale : int
        Short-chain settings (spec §5 synthetic defaults: ``N_C = 25``, ``tau_stall = 5``,
        ``tau_stale = 25``; ``N_S N_C`` = the original's budget by default).
    curve_obs : tuple of int
        Observation budgets of the error-vs-observations curve (original chain, short chains
        without termination rules and ``N_C = chain_length``).
    """

    n_mc: int = 20
    sensors: tuple = (4, 6, 8)
    families: tuple = FAMILIES
    original_obs: int = 1000
    n_chains: int = 40
    chain_length: int = 25
    tau_stall: int = 5
    tau_stale: int = 25
    curve_obs: tuple = (25, 50, 100, 200, 400, 1000, 2000)

    def __post_init__(self):
        check_fields(self)
        for name in ("n_mc", "original_obs", "n_chains", "chain_length", "tau_stall",
                     "tau_stale"):
            check_int(getattr(self, name), name, minimum=1)
        for name, values in (("sensors", self.sensors), ("families", self.families),
                             ("curve_obs", self.curve_obs)):
            if not values:
                raise ValueError(f"{name} must not be empty")
        for V in self.sensors:
            # the study's exact posterior enumerates (M + 1)**V tuples: 5**10 ~ 1e7 at most
            check_int(V, "sensors: V", minimum=1, maximum=10)
        for f in self.families:
            check_choice(f, "families: family", FAMILIES)
        for n in self.curve_obs:
            check_int(n, "curve_obs entry", minimum=1)


#: The quick reproduction (a few seconds).
QUICK = AdaptiveBirthStudyConfig(n_mc=2, curve_obs=(100, 1000))
#: The full study.
FULL = AdaptiveBirthStudyConfig()


def _seeds(seed: int, run: int, family: str, V: int) -> list:
    ss = np.random.SeedSequence([seed, run, FAMILIES.index(family), V])
    return ss.spawn(2 + len(CRITERIA) + 1)


@dataclass(frozen=True)
class ABCall(RunRecord):
    """One sampler call of :func:`run_task`.

    Attributes
    ----------
    n_obs : int
        Observations (sweeps) spent.
    n_unique : int
        Unique assignments found.
    n_chains : int
        Chains run.
    stop_reason : str
        Why the sampler stopped.
    error : float
        Exact truncation error of the unique assignments, a fraction.
    """

    n_obs: int
    n_unique: int
    n_chains: int
    stop_reason: str
    error: float


@dataclass(frozen=True)
class AdaptiveBirthRun(RunRecord):
    """One Monte Carlo run of one family and ``V`` (:func:`run_task`).

    Attributes
    ----------
    kind : str
        ``"run"`` (a task of the study is a run or a curve, :class:`AdaptiveBirthCurve`).
    run : int
        Monte Carlo run.
    family : str
        Problem family.
    V : int
        Sensors.
    original : ABCall
        The original chain (``original_obs`` sweeps).
    stall, stale, full : ABCall
        The short chains under each criterion.
    """

    kind: str
    run: int
    family: str
    V: int
    original: ABCall
    stall: ABCall
    stale: ABCall
    full: ABCall

    @classmethod
    def from_dict(cls, data: dict) -> AdaptiveBirthRun:
        """The record of a ``"run"`` object of ``adaptive_birth_runs.json``.

        Parameters
        ----------
        data : dict
            Its fields, each call as an object.

        Returns
        -------
        AdaptiveBirthRun
        """
        calls = {k: ABCall.from_dict(data[k]) for k in ("original", *CRITERIA) if k in data}
        return super().from_dict({**data, **calls})


@dataclass(frozen=True)
class CurvePoint(RunRecord):
    """One budget of :func:`curve`.

    Attributes
    ----------
    n_obs : int
        The budget (sweeps).
    error_original, error_short : float
        Mean truncation errors (fractions) over the problems.
    error_original_se, error_short_se : float
        Their standard errors (NaN for one problem).
    """

    n_obs: int
    error_original: float
    error_short: float
    error_original_se: float
    error_short_se: float


@dataclass(frozen=True)
class AdaptiveBirthCurve(RunRecord):
    """The error-against-observations curve of one family and ``V`` (a task of the study).

    Attributes
    ----------
    kind : str
        ``"curve"``.
    family : str
        Problem family.
    V : int
        Sensors.
    points : list of CurvePoint
        One per budget of ``curve_obs``.
    """

    kind: str
    family: str
    V: int
    points: list

    @classmethod
    def from_dict(cls, data: dict) -> AdaptiveBirthCurve:
        """The record of a ``"curve"`` object of ``adaptive_birth_runs.json``.

        Parameters
        ----------
        data : dict
            Its fields, the points as objects.

        Returns
        -------
        AdaptiveBirthCurve
        """
        return super().from_dict({**data, "points": [
            CurvePoint.from_dict(q) for q in data.get("points", [])]})


def task_from_dict(data: dict) -> AdaptiveBirthRun | AdaptiveBirthCurve:
    """One object of ``adaptive_birth_runs.json`` read back, by its ``kind``.

    Parameters
    ----------
    data : dict
        A run's or a curve's fields.

    Returns
    -------
    AdaptiveBirthRun or AdaptiveBirthCurve

    Raises
    ------
    ValueError
        If ``kind`` is neither ``"run"`` nor ``"curve"``.
    """
    kind = data.get("kind") if isinstance(data, dict) else None
    if kind not in ("run", "curve"):
        raise ValueError(f"an adaptive_birth task has kind 'run' or 'curve', got {kind!r}")
    return (AdaptiveBirthRun if kind == "run" else AdaptiveBirthCurve).from_dict(data)


def _record(problem, res) -> ABCall:
    return ABCall(n_obs=int(res.n_observations), n_unique=len(res),
                  n_chains=int(res.n_chains_run), stop_reason=res.stop_reason,
                  error=float(oracle.truncation_error(problem, res.assignments)))


_RULES = {"stall": (True, False), "stale": (False, True), "full": (True, True)}


def run_task(cfg: AdaptiveBirthStudyConfig, seed: int, run: int, family: str,
             V: int) -> AdaptiveBirthRun:
    """One Monte Carlo run: original chain and the three short-chain criteria on one problem.

    Parameters
    ----------
    cfg : AdaptiveBirthStudyConfig
        Settings: ``original_obs`` sweeps of the original chain, ``n_chains`` chains of
        ``chain_length`` sweeps and the thresholds ``tau_stall``, ``tau_stale`` of the short
        chains.
    seed : int
        Base seed of the study; with ``run``, ``family`` and ``V`` it seeds one
        :class:`numpy.random.SeedSequence` whose children draw the problem and each sampler.
    run : int
        Index of the Monte Carlo run (0-based); a different ``run`` draws a different problem.
    family : {"diagonal", "uniform", "random"}
        Problem family (:data:`~rankedassign.adaptive_birth.synthetic.FAMILIES`).
    V : int
        Number of sensors; the problem has ``SIZES[V]`` measurements per sensor (4 for a ``V``
        not in :data:`~rankedassign.adaptive_birth.synthetic.SIZES`).

    Returns
    -------
    AdaptiveBirthRun
        The original chain's call and the three criteria's (:class:`ABCall`).

    Examples
    --------
    >>> cfg = AdaptiveBirthStudyConfig(n_mc=1, original_obs=100, n_chains=4)
    >>> out = run_task(cfg, 0, 0, "diagonal", 4)
    >>> out.original.n_obs, out.full.n_obs <= 100
    (100, True)
    """
    s = _seeds(seed, run, family, V)
    problem = make_family(family, V, rng=s[0])
    original = _record(problem, sample_original(problem, cfg.original_obs, rng=s[1]))
    out = {}
    for i, crit in enumerate(CRITERIA):
        stall, stale = _RULES[crit]
        res = sample_short_chains(problem, cfg.n_chains, cfg.chain_length,
                                  tau_stall=cfg.tau_stall if stall else None,
                                  tau_stale=cfg.tau_stale if stale else None, rng=s[2 + i])
        out[crit] = _record(problem, res)
    return AdaptiveBirthRun(kind="run", run=run, family=family, V=V, original=original, **out)


def _se(x) -> float:
    x = np.asarray(x, dtype=float)
    return float(x.std(ddof=1) / math.sqrt(x.size)) if x.size > 1 else float("nan")


def _ratio_se(no, ns) -> float:
    """Standard error (%) of ``100 (1 - mean ns / mean no)`` over paired runs (delta method,
    as Table I's ``delta_obs_pct_se``); NaN for one run."""
    n = no.size
    mo, ms = no.mean(), ns.mean()
    if n < 2 or mo == 0:
        return float("nan")
    cov = np.cov(np.vstack([no, ns]), ddof=1)
    var = (cov[1, 1] / mo**2 + ms**2 * cov[0, 0] / mo**4 - 2 * ms * cov[0, 1] / mo**3) / n
    return float(100.0 * math.sqrt(max(var, 0.0)))


def summarise(runs: list) -> list:
    """Table I rows (family x V x criterion) from the records of :func:`run_task`.

    ``delta_obs_pct = 100 (mean N_o - mean N_s) / mean N_o``, ``delta_error_pp = 100 |mean
    eps_o - mean eps_s|`` (as the paper's Table I), with the standard error of the mean paired
    difference, plus the raw means.

    Parameters
    ----------
    runs : list of AdaptiveBirthRun
        Records of :func:`run_task`, in any order (each call's ``n_obs`` and ``error`` are
        read). Runs are grouped by ``(family, V)`` in order of first appearance.

    Returns
    -------
    list of dict
        One row per ``(family, V)`` and criterion (``"stall"``, ``"stale"``, ``"full"``, in
        that order), with keys ``family``, ``V``, ``criterion``, ``n_mc``,
        ``delta_obs_pct``, ``delta_error_pp``, ``delta_error_se_pp`` (NaN for one run),
        ``error_original``, ``error_short`` (mean errors as fractions), ``obs_original`` and
        ``obs_short`` (mean sweeps), ``delta_obs_se_pct``, ``error_original_se_pp`` and
        ``error_short_se_pp`` (standard errors, NaN for one run): the fields of
        :class:`AdaptiveBirthRow`.

    Examples
    --------
    >>> rec = ABCall(n_obs=100, n_unique=3, n_chains=1, stop_reason="budget", error=0.1)
    >>> stall = ABCall(n_obs=50, n_unique=2, n_chains=2, stop_reason="stall", error=0.2)
    >>> runs = [AdaptiveBirthRun(kind="run", run=0, family="uniform", V=4, original=rec,
    ...                          stall=stall, stale=rec, full=rec)]
    >>> summarise(runs)[0]["delta_obs_pct"], round(summarise(runs)[0]["delta_error_pp"], 9)
    (50.0, 10.0)
    """
    rows = []
    keys = list(dict.fromkeys((r.family, r.V) for r in runs))
    for fam, V in keys:
        rs = sorted((r for r in runs if r.family == fam and r.V == V), key=lambda r: r.run)
        no = np.array([r.original.n_obs for r in rs], dtype=float)
        eo = np.array([r.original.error for r in rs])
        for crit in CRITERIA:
            ns = np.array([getattr(r, crit).n_obs for r in rs], dtype=float)
            es = np.array([getattr(r, crit).error for r in rs])
            rows.append({
                "family": fam, "V": V, "criterion": crit, "n_mc": len(rs),
                "delta_obs_pct": float(100 * (no.mean() - ns.mean()) / no.mean()),
                "delta_error_pp": float(100 * abs(eo.mean() - es.mean())),
                "delta_error_se_pp": 100 * _se(es - eo),
                "error_original": float(eo.mean()), "error_short": float(es.mean()),
                "obs_original": float(no.mean()), "obs_short": float(ns.mean()),
                "delta_obs_se_pct": _ratio_se(no, ns),
                "error_original_se_pp": 100 * _se(eo), "error_short_se_pp": 100 * _se(es),
            })
    return rows


def curve(cfg: AdaptiveBirthStudyConfig, seed: int, family: str, V: int) -> list[CurvePoint]:
    """Mean truncation error against the observation budget (original vs short chains).

    Short chains run without termination rules, ``N_C = cfg.chain_length`` and
    ``N_S = budget / N_C`` chains, so both samplers spend the same budget.

    Parameters
    ----------
    cfg : AdaptiveBirthStudyConfig
        Settings: ``n_mc`` problems, the budgets ``curve_obs`` (sweeps) and ``chain_length``.
    seed : int
        Base seed of the study; the problems are those of :func:`run_task` with runs
        ``0 .. n_mc - 1`` (the same seeds), the samplers draw from a further child seed.
    family : {"diagonal", "uniform", "random"}
        Problem family (:data:`~rankedassign.adaptive_birth.synthetic.FAMILIES`).
    V : int
        Number of sensors (``SIZES[V]`` measurements per sensor).

    Returns
    -------
    list of CurvePoint
        One point per budget of ``cfg.curve_obs``, in that order: ``n_obs`` (the budget),
        ``error_original``, ``error_short`` (mean truncation errors as fractions over
        ``cfg.n_mc`` problems) and their standard errors ``error_original_se``,
        ``error_short_se`` (NaN for one problem).

    Examples
    --------
    >>> cfg = AdaptiveBirthStudyConfig(n_mc=1, curve_obs=(25, 50))
    >>> [p.n_obs for p in curve(cfg, 0, "uniform", 4)]
    [25, 50]
    """
    seeds = [_seeds(seed, run, family, V) for run in range(cfg.n_mc)]
    problems = [make_family(family, V, rng=s[0]) for s in seeds]    # the table's problems
    out = []
    for budget in cfg.curve_obs:
        eo, es = [], []
        for s, problem in zip(seeds, problems, strict=True):
            eo.append(_record(problem, sample_original(problem, budget, rng=s[-1])).error)
            res = sample_short_chains(problem, max(1, budget // cfg.chain_length),
                                      cfg.chain_length, rng=s[-1])
            es.append(_record(problem, res).error)
        out.append(CurvePoint(n_obs=budget, error_original=float(np.mean(eo)),
                              error_short=float(np.mean(es)),
                              error_original_se=_se(eo), error_short_se=_se(es)))
    return out


def _nan(x) -> float:
    return math.nan if x is None else float(x)


def format_table(rows: list) -> str:
    """The Table I layout as Markdown, each mean with its standard error.

    Parameters
    ----------
    rows : list of dict
        Rows of :func:`summarise`. A missing or NaN standard error (one run) is written as
        ``(1 run)`` beside a row of ``n_mc == 1`` and left out otherwise.

    Returns
    -------
    str
        A Markdown table: the header, the rule, then one line per row in order: family,
        ``V``, criterion, runs, ΔObs (%; positive: the short chains save), the signed paired
        difference ``ε̄_s − ε̄_o`` (pp; negative: the short chains are more accurate) and the
        two mean errors in percent.

    Examples
    --------
    >>> print(format_table([]).splitlines()[0])  # doctest: +NORMALIZE_WHITESPACE
    | family | V | criterion | runs | ΔObs (%, > 0: short chains save) | ε̄ short − ε̄ original
    (pp, < 0: short chains more accurate) | ε̄ original (%) | ε̄ short (%) |
    """
    lines = ["| family | V | criterion | runs | ΔObs (%, > 0: short chains save) | "
             "ε̄ short − ε̄ original (pp, < 0: short chains more accurate) | ε̄ original (%) | "
             "ε̄ short (%) |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        n = r.get("n_mc")

        def cell(x, se, digits=2, n=n):
            return fmt.pm(x, _nan(se), digits, n_runs=n)

        lines.append(
            f"| {r['family']} | {r['V']} | {r['criterion']} | {n if n is not None else '–'} | "
            f"{cell(r['delta_obs_pct'], r.get('delta_obs_se_pct'))} | "
            f"{cell(100 * (r['error_short'] - r['error_original']), r.get('delta_error_se_pp'))}"
            f" | {cell(100 * r['error_original'], r.get('error_original_se_pp'))} | "
            f"{cell(100 * r['error_short'], r.get('error_short_se_pp'))} |")
    return "\n".join(lines)


def verdict(rows: list) -> str:
    """One sentence per family: do the paper's savings carry over to this sampler?

    Judged on the "full" criterion (stall and stale, the proposed sampler): the savings carry
    over when it saves observations (``ΔObs > 0``) at every ``V`` while its mean error is at
    most 1 percentage point above the original's (the sign matters here: restarts can make the
    short chains *more* accurate). Each ``V`` is given with the paired difference of the errors
    and its standard error when the rows have one.

    Examples
    --------
    >>> verdict([{"family": "diagonal", "V": 4, "criterion": "full", "delta_obs_pct": 90.0,
    ...           "error_original": 0.5, "error_short": 0.001}])  # doctest: +NORMALIZE_WHITESPACE
    'diagonal: savings carry over (90.0 % fewer observations; error 50.00 % -> 0.10 % at V = 4,
    the short chains 49.90 pp more accurate).'
    """
    out = []
    for fam in dict.fromkeys(r["family"] for r in rows):
        full = [r for r in rows if r["family"] == fam and r["criterion"] == "full"]

        def diff(r):
            d = 100 * (r["error_short"] - r["error_original"])
            se = _nan(r.get("delta_error_se_pp"))
            if abs(d) < 0.005:
                return "no difference"
            word = "more" if d < 0 else "less"
            return (f"the short chains {fmt.pm(abs(d), se, 2)} pp {word} accurate")

        detail = ", ".join(f"{r['error_original'] * 100:.2f} % -> {r['error_short'] * 100:.2f} % "
                           f"at V = {r['V']}, {diff(r)}" for r in full)
        saved = [r["delta_obs_pct"] for r in full]
        worse = max((r["error_short"] - r["error_original"]) * 100 for r in full)
        span = (f"{min(saved):.1f} %" if min(saved) == max(saved)
                else f"{min(saved):.1f}-{max(saved):.1f} %")
        if min(saved) > 0 and worse < 1.0:
            out.append(f"{fam}: savings carry over ({span} fewer observations; error {detail}).")
        elif max(saved) <= 0 and abs(worse) < 1.0:
            out.append(f"{fam}: no saving and no loss (no rule fires; error {detail}).")
        else:
            out.append(f"{fam}: savings cost accuracy ({span} fewer observations; error "
                       f"{detail}).")
    return " ".join(out)


def plot(curves: dict, path) -> None:
    """Error-vs-observations figure: one panel per family, original vs short chains per V.

    Parameters
    ----------
    curves : dict
        ``{(family, V): curve(...)}`` (lists of :class:`CurvePoint`).
    path : str or Path
        Output file (PNG/SVG).

    Notes
    -----
    Colour and marker name ``V``, the line style the sampler (solid: the original chain,
    dashed: the short chains), so at most six series share a panel and they stay apart in
    greyscale; one legend below the panels. A panel whose errors span less than a decade is
    drawn on a linear axis (a logarithmic one would have a single labelled tick).
    """

    fams = list(dict.fromkeys(f for f, _ in curves))
    vs = list(dict.fromkeys(v for _, v in curves))
    fig, axes = figure(len(fams), width=4.2, height=3.4)
    for ax, fam in zip(axes, fams, strict=True):
        ys = []
        same = True  # every short-chain curve of the panel lies on its original's
        for (f, V), pts in curves.items():
            if f != fam:
                continue
            i = vs.index(V)
            n = [p.n_obs for p in pts]
            same &= all(abs(p.error_short - p.error_original)
                        <= 0.005 * max(abs(p.error_original), 1e-12) for p in pts)
            # the short chains' markers are larger hollow rings drawn below the originals'
            # filled ones: where a dashed line lies on its solid twin, both still show
            for key, ls, who, face in (("error_original", "-", "original", None),
                                       ("error_short", "--", "short chains", "white")):
                y = [max(100 * getattr(p, key), 1e-14) for p in pts]
                ys += y
                colour = PALETTE[(i + 1) % len(PALETTE)]
                ax.plot(n, y, ls=ls, color=colour, marker=MARKERS[i % len(MARKERS)],
                        ms=4 if face is None else 7, lw=1.4, mfc=face or colour,
                        zorder=2.5 if face is None else 2, label=f"{who}, V = {V}")
        ax.set_xscale("log")
        if ys and max(ys) / min(ys) >= 10:
            ax.set_yscale("log")
        ax.set_title(f"{fam} family" + ("\n(short chains on the original's lines)"
                                         if same and ys else ""), fontsize=10)
        ax.set_xlabel("observations (sweeps)")
        ax.set_ylabel("truncation error (%)")
        ax.grid(True, which="both", alpha=0.3)
    legend_below(fig, axes[:1], ncol=len(vs))
    fig.suptitle("Adaptive birth: truncation error against the budget "
                 "(no termination rules, mean over runs)", fontsize=10)
    fig.savefig(path, dpi=110)




@dataclass(frozen=True)
class AdaptiveBirthRow:
    """One Table I row of the adaptive-birth study (errors are fractions, Δ in % and pp).

    Attributes
    ----------
    family : str
        Problem family of multi-sensor spec §6.5 (one of ``FAMILIES``).
    V : int
        Number of sensors (each with ``M = SIZES[V]`` measurements).
    criterion : {"stall", "stale", "full"}
        Termination rules of the short chains: stall only, stale only, or both (S3, T3).
    n_mc : int
        Monte Carlo runs (problems drawn) of the cell.
    delta_obs_pct : float
        ΔObs, ``100 (mean N_o - mean N_s) / mean N_o``, in percent.
    delta_error_pp : float
        ΔError, ``100 |mean eps_o - mean eps_s|``, in percentage points.
    delta_error_se_pp : float or None
        Standard error of the mean paired difference ``eps_s - eps_o``, in percentage points;
        ``None`` for one run.
    error_original, error_short : float
        Mean truncation error (over the birth tuples) of the original chain and of the
        short chains, as fractions.
    obs_original, obs_short : float
        Mean observations (sweeps) of each sampler per run.
    delta_obs_se_pct : float or None
        Standard error of ``delta_obs_pct`` (delta method for the ratio of the paired means).
    error_original_se_pp, error_short_se_pp : float or None
        Standard errors of the two mean errors, in percentage points.
    """

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
    delta_obs_se_pct: float | None = None
    error_original_se_pp: float | None = None
    error_short_se_pp: float | None = None


@dataclass(frozen=True)
class AdaptiveBirthSummary:
    """The study's summary: the Table I rows, the error-vs-observation curves, the verdict.

    Attributes
    ----------
    rows : tuple of AdaptiveBirthRow
        Per family and ``V`` (in the settings' order), the ``"stall"``, ``"stale"`` and
        ``"full"`` rows.
    curves : dict of str to list of CurvePoint
        Keyed ``"<family>, V=<V>"``: the points of :func:`curve`.
    verdict : str
        One sentence per family (:func:`verdict`), judged on the ``"full"`` rows; empty when
        no run was summarised.
    """

    rows: tuple
    curves: dict
    verdict: str


def adaptive_birth_tasks(cfg: AdaptiveBirthStudyConfig, seed: int) -> list[tuple]:
    """Monte Carlo runs of the table, then one curve task per (family, V)."""
    cells = [(f, V) for f in cfg.families for V in cfg.sensors]
    return ([("run", cfg, seed, r, f, V) for f, V in cells for r in range(cfg.n_mc)]
            + [("curve", cfg, seed, 0, f, V) for f, V in cells])


def adaptive_birth_task(kind: str, cfg: AdaptiveBirthStudyConfig, seed: int, run: int, family: str,
                        V: int) -> AdaptiveBirthRun | AdaptiveBirthCurve:
    """One task: a Monte Carlo run (:func:`~.run_task`) or a curve."""
    if kind == "run":
        return run_task(cfg, seed, run, family, V)
    return AdaptiveBirthCurve(kind="curve", family=family, V=V,
                              points=curve(cfg, seed, family, V))


def summarise_adaptive_birth(runs: list,
                             cfg: AdaptiveBirthStudyConfig) -> AdaptiveBirthSummary:
    """Typed rows of :func:`~.summarise`, the curves and the verdict.

    Parameters
    ----------
    runs : list of AdaptiveBirthRun and AdaptiveBirthCurve
        Records of :func:`adaptive_birth_task` (Monte Carlo runs and curves).
    cfg : AdaptiveBirthStudyConfig
        The settings of the runs (not read: the records carry what the summary needs).

    Returns
    -------
    AdaptiveBirthSummary
        The typed rows, the curves by ``"<family>, V=<V>"`` and the verdict.
    """
    raw = summarise([r for r in runs if r.kind == "run"])
    ses = ("delta_error_se_pp", "delta_obs_se_pct", "error_original_se_pp", "error_short_se_pp")
    rows = tuple(AdaptiveBirthRow(**{**r, **{k: None if math.isnan(r[k]) else r[k]
                                              for k in ses}}) for r in raw)
    curves = {f"{r.family}, V={r.V}": r.points for r in runs if r.kind == "curve"}
    return AdaptiveBirthSummary(rows=rows, curves=curves,
                                verdict=verdict(raw) if raw else "")


def _raw(rows) -> list[dict]:
    return [{**r.__dict__, **{k: math.nan if getattr(r, k) is None else getattr(r, k)
                              for k in ("delta_error_se_pp", "delta_obs_se_pct",
                                        "error_original_se_pp", "error_short_se_pp")}}
            for r in rows]


#: The full run's result (``FULL``, 20 runs), as the Multi-sensor page of the documentation
#: records it; the quick verdict names it, since 2 runs cannot resolve the size of the gain.
FULL_RESULT = ("the full run (20 Monte Carlo runs per family and V, documented on the "
               "Multi-sensor page) found 72–76 % fewer observations on the diagonal and random "
               "families with errors lower by 37–75 pp (standard errors 7–9 pp), and no "
               "difference on the uniform family")


def _curve_cell(p: CurvePoint, n: int) -> str:
    return " / ".join(fmt.pm(100 * getattr(p, k), 100 * getattr(p, f"{k}_se"), n_runs=n)
                      for k in ("error_original", "error_short"))


def render_adaptive_birth(summary: AdaptiveBirthSummary, cfg: AdaptiveBirthStudyConfig) -> str:
    """The report section: settings, the verdict, the Table I layout and the curves."""
    n = summary.rows[0].n_mc if summary.rows else 0
    budgets = list(cfg.curve_obs)
    curve_rows = [[key, *(_curve_cell(p, n) for p in pts)]
                  for key, pts in summary.curves.items()]
    sizes = ", ".join(f"V = {V}: M = {SIZES.get(V, 4)}" for V in cfg.sensors)
    if n >= 10:
        resolve = ""
    else:
        resolve = (f" With {fmt.plural(n, 'run')} per cell the standard errors are rough (or "
                   f"missing), so the quick run shows the direction, not the size: "
                   f"{FULL_RESULT}.")
    return f"""## Adaptive birth — original vs short chains on the adaptive-birth sampler

The paper has no adaptive-birth numbers (it only expects "similar results", multi-sensor spec
§5), so there is no paper column. Families of multi-sensor spec §6.5 ({", ".join(cfg.families)};
{sizes}); the original sampler is one chain of {cfg.original_obs:,} sweeps, the short chains
{cfg.n_chains:,} × {cfg.chain_length} sweeps (the same budget), τ_stall = {cfg.tau_stall},
τ_stale = {cfg.tau_stale}, readings S3/T3; {fmt.plural(n, "Monte Carlo run")} per family and V.
The error is the exact truncation error over the birth tuples with at least n_min detections.
ΔObs = 100 (N̄_o − N̄_s)/N̄_o; the error column is the signed paired difference ε̄_s − ε̄_o,
so a negative number is a gain of the short chains. {fmt.runs_note([r.n_mc for r in
summary.rows])}

**Verdict.** Judged on the "full" criterion (both rules): {verdict(_raw(summary.rows))}{resolve}

{format_table(_raw(summary.rows))}

Mean truncation error (%) ± standard error against the observation budget, "original / short
chains" (short chains of {cfg.chain_length} sweeps without termination rules, the same budget;
{fmt.plural(n, "problem")} per cell):

{fmt.table(["family, V", *(f"{b:,}" for b in budgets)], curve_rows)}

![Adaptive birth: truncation error against observations](adaptive_birth.png)
"""


def plot_adaptive_birth(summary: AdaptiveBirthSummary, directory: Path) -> list[str]:
    """The error-vs-observations figure of :func:`~.plot`."""
    curves = {}
    for key, pts in summary.curves.items():
        fam, v = key.split(", V=")
        curves[fam, int(v)] = pts
    plot(curves, Path(directory) / "adaptive_birth.png")
    return ["adaptive_birth.png"]


def _csv(summary: AdaptiveBirthSummary) -> list[dict]:
    return [dict(r.__dict__) for r in summary.rows]


ADAPTIVE_BIRTH = register_study(Study(
    name="adaptive_birth",
    title="adaptive-birth sampler: original vs short chains (Table I layout, error curves)",
    config_type=AdaptiveBirthStudyConfig,
    full=lambda: FULL,
    quick=lambda: QUICK,
    tasks=adaptive_birth_tasks,
    task=adaptive_birth_task,
    run_from_dict=task_from_dict,
    summarise=summarise_adaptive_birth,
    render=render_adaptive_birth,
    plot=plot_adaptive_birth,
    csv_rows=_csv,
    order=90,
    default_run=False,
    warm=lambda c: replace(c, n_mc=1, sensors=c.sensors[:1], original_obs=60, n_chains=6,
                               chain_length=10, curve_obs=(20, 60)),
))
