"""The δ-GLMB tracking study: GLMB against LMB, every truncation, on the same measurements.

``rankedassign reproduce glmb_tracking`` runs, on Vo's example (preset ``"vo"``), the LMB
filter with the long chain and the short chains, and the δ-GLMB filter
(:class:`~rankedassign.tracking.GLMBFilter`) with the long chain (Vo's truncation), the short
chains and Murty's k best, every method of a run on the same measurements. Per scan it records
OSPA(2), the cardinality error, the sweeps, the components kept and — for the GLMB filter —
the posterior mass the truncation retains (``../shared/spec/glmb.md`` §4), and reports the
tables, the per-scan plots and a verdict: do the short chains' savings carry over to the GLMB
filter, at what cost in OSPA(2) and in retained mass?
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ... import metrics, tracking
from ...engine.rng import spawning_generator
from ...validation import check_choice, check_fields
from .. import _format as fmt
from .._executor import run_seed
from .._plots import figure
from ..paper import PAPER_TOTALS
from ..registry import Study, register_study

__all__ = ["GLMB_METHODS", "GLMBStudyConfig", "GLMBMethodSummary", "GLMBStudySummary",
           "glmb_tracking_task", "summarise_glmb_tracking", "GLMB_TRACKING"]

#: Methods of the study: filter and truncation.
GLMB_METHODS = ("lmb-long", "lmb-short", "glmb-long", "glmb-short", "glmb-murty")
_LABELS = {"lmb-long": "LMB, long chain", "lmb-short": "LMB, short chains",
           "glmb-long": "GLMB, long chain", "glmb-short": "GLMB, short chains",
           "glmb-murty": "GLMB, Murty"}
_COLORS = {"lmb-long": "0.45", "lmb-short": "C1", "glmb-long": "C0", "glmb-short": "C3",
           "glmb-murty": "C4"}
#: Targets of issue #26: GLMB short chains within 5 % of the long chain, GLMB within 10 % of
#: LMB, in mean OSPA(2).
SHORT_VS_LONG_TARGET, GLMB_VS_LMB_TARGET = 5.0, 10.0


@dataclass(frozen=True)
class GLMBStudyConfig:
    """Settings of the ``glmb_tracking`` study.

    Attributes
    ----------
    n_mc, n_scans : int
        Monte Carlo runs and scans per run.
    preset : str
        Single-sensor model preset (``"vo"``, Vo's example).
    methods : tuple of str
        Of :data:`GLMB_METHODS`.
    murty_runs : int
        Runs (the first ones) of ``"glmb-murty"``: a Python loop of one Murty search per
        component, some 60 s a run.
    h_upd, h_max : int
        The GLMB filter's ``H_upd`` and ``H_max`` (Vo: 1000 and 1000).
    original_obs : int
        Sweeps per call of the LMB filter's long chain (10 000), cap of the GLMB's.
    n_chains, chain_length, tau_stall, tau_stale : int
        Short chains (400, 25, 5, 10).
    murty_k : int
        Cap of Murty's ``k`` (each component takes ``k = min(murty_k, T_h)``).
    retained_mass : bool
        Compute the retained posterior mass of the GLMB runs.
    ospa_c, ospa_p, ospa_window : float, float, int
        OSPA(2) (spec §7: 200 m, 1, 5 scans).

    Examples
    --------
    >>> from rankedassign.experiments.studies.glmb_tracking import GLMBStudyConfig
    >>> GLMBStudyConfig().n_mc, GLMBStudyConfig.quick().n_mc
    (10, 2)
    """

    n_mc: int = 10
    n_scans: int = 100
    preset: str = "vo"
    methods: tuple = GLMB_METHODS
    murty_runs: int = 2
    h_upd: int = 1000
    h_max: int = 1000
    original_obs: int = 10_000
    n_chains: int = 400
    chain_length: int = 25
    tau_stall: int = 5
    tau_stale: int = 10
    murty_k: int = 1000
    retained_mass: bool = True
    ospa_c: float = 200.0
    ospa_p: float = 1.0
    ospa_window: int = 5

    @classmethod
    def quick(cls) -> GLMBStudyConfig:
        """Two runs of 100 scans, every method but Murty (which takes a minute a run)."""
        return cls(n_mc=2, methods=GLMB_METHODS[:4], murty_runs=0)

    def __post_init__(self):
        check_fields(self, where="glmb_tracking: ")
        object.__setattr__(self, "methods", tuple(self.methods))
        for m in self.methods:
            check_choice(m, "method", GLMB_METHODS)
        check_choice(self.preset, "preset", ("vo", "paper", "paper-var"))
        for name in ("n_mc", "n_scans", "h_upd", "h_max", "original_obs", "n_chains",
                     "chain_length", "tau_stall", "tau_stale", "murty_k", "ospa_window"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be >= 1, got {getattr(self, name)}")
        if self.murty_runs < 0:
            raise ValueError(f"murty_runs must be >= 0, got {self.murty_runs}")


def _association(cfg: GLMBStudyConfig, method: str):
    kind = method.split("-")[1]
    if kind == "long":
        return tracking.OriginalGibbs(cfg.original_obs)
    if kind == "short":
        return tracking.ShortChainGibbs(cfg.n_chains, cfg.chain_length, tau_stall=cfg.tau_stall,
                                        tau_stale=cfg.tau_stale)
    return tracking.Murty(cfg.murty_k)


def glmb_tracking_task(cfg: GLMBStudyConfig, seed: int, run: int, method: str) -> dict:
    """One run of one method; every method of a run sees the same measurements.

    Parameters
    ----------
    cfg : GLMBStudyConfig
        The study's settings (preset, scans, budgets, OSPA(2) parameters).
    seed : int
        The study's seed; run ``run`` draws from ``run_seed(seed, run)``, split into the
        measurements' stream and the filter's, as :func:`~rankedassign.tracking.run_scenario`
        does with that ``rng``.
    run : int
        Monte Carlo run index (0-based).
    method : str
        One of ``cfg.methods``: ``"lmb-long"``, ``"lmb-short"``, ``"glmb-long"``,
        ``"glmb-short"`` or ``"glmb-murty"``.

    Returns
    -------
    dict
        Plain data for JSON: ``run``, ``method``, the per-scan ``ospa2`` curve,
        ``cardinality_error`` (absolute, per scan), ``sweeps`` and ``components`` per scan,
        ``retained_mass`` per scan (``None`` where not computed) and ``seconds`` of filter time.
    """
    meas_rng, filter_rng = spawning_generator(run_seed(seed, run)).spawn(2)
    sc = tracking.make_scenario(cfg.preset, rng=meas_rng, n_scans=cfg.n_scans)
    extraction = tracking.PRESET_EXTRACTION[cfg.preset]
    assoc = _association(cfg, method)
    if method.startswith("glmb"):
        filt = tracking.GLMBFilter(sc.model, assoc, h_upd=cfg.h_upd, h_max=cfg.h_max,
                                   extraction=extraction, retained_mass=cfg.retained_mass)
    else:
        filt = tracking.LMBFilter(sc.model, assoc, extraction=extraction)
    K = sc.truth.n_scans
    est, sweeps, comps, kept, n_est, secs = [], [], [], [], [], 0.0
    for scan, g in zip(sc.scans, filter_rng.spawn(K), strict=True):
        rec = filt.step(scan.z, rng=g)
        est.append(dict(zip(map(tuple, rec.labels.tolist()), rec.states, strict=True)))
        sweeps.append(int(rec.sweeps))
        comps.append(int(getattr(rec, "n_components", 0)))
        kept.append(float(getattr(rec, "retained_mass", math.nan)))
        n_est.append(int(rec.labels.shape[0]))
        secs += sum(rec.timings.values())
    e = metrics.tracks_to_array(est, dims=(0, 2))
    if e.shape[2] == 0:
        e = np.full((K, 0, 2), np.nan)
    o2 = metrics.ospa2(sc.truth.positions, e, cfg.ospa_c, cfg.ospa_p, cfg.ospa_window)
    card_err = np.abs(np.array(n_est) - sc.truth.n_targets)
    return {
        "run": run, "method": method,
        "ospa2": np.asarray(o2.value, dtype=float).tolist(),
        "cardinality_error": card_err.astype(int).tolist(),
        "sweeps": sweeps, "components": comps,
        # JSON has no NaN: None where the mass is not available
        "retained_mass": [None if math.isnan(v) else v for v in kept],
        "seconds": secs,
    }


def glmb_tasks(cfg: GLMBStudyConfig, seed: int) -> list[tuple]:
    """``(cfg, seed, run, method)``: every run of every method (Murty: ``murty_runs``)."""
    return [(cfg, seed, r, m) for r in range(cfg.n_mc) for m in cfg.methods
            if m != "glmb-murty" or r < cfg.murty_runs]


@dataclass(frozen=True)
class GLMBMethodSummary:
    """One method over its runs: means (and standard errors over runs) of the per-run values.

    Attributes
    ----------
    method : str
        The method (``"glmb-short"``, ...).
    n_runs : int
        Runs it ran.
    ospa2_mean, ospa2_se : float
        Mean OSPA(2) over scans and runs (m), and the standard error over the runs' means.
    cardinality_error_mean : float
        Mean absolute cardinality error over scans and runs.
    sweeps : float
        Sweeps per run (total over the scans), mean over runs.
    components_mean : float
        GLMB components kept per scan, mean (0 for the LMB filter).
    retained_mass_mean, retained_mass_min : float
        Posterior mass retained per scan, mean and worst over every scan of every run (NaN for
        the LMB filter, or where it was not computed).
    seconds : float
        Filter time per run (s), mean over runs.
    """

    method: str
    n_runs: int
    ospa2_mean: float
    ospa2_se: float
    cardinality_error_mean: float
    sweeps: float
    components_mean: float
    retained_mass_mean: float
    retained_mass_min: float
    seconds: float


@dataclass(frozen=True)
class GLMBStudySummary:
    """The study's rows, the paired comparisons of the targets, and the per-scan curves.

    Attributes
    ----------
    n_mc : int
        Monte Carlo runs.
    config : dict
        The settings the study ran with.
    rows : tuple of GLMBMethodSummary
        One per method, in the order of ``config["methods"]``.
    short_vs_long_pct : float
        GLMB short chains' mean OSPA(2) over the GLMB long chain's, minus 1, in % (paired over
        the runs both ran).
    glmb_savings_pct, lmb_savings_pct : float
        Sweeps the short chains save against the long chain (%), on the GLMB and on the LMB
        filter.
    glmb_vs_lmb_short_pct, glmb_vs_lmb_long_pct : float
        GLMB over LMB mean OSPA(2), minus 1, in %: short chains against short chains, long
        chain against long chain.
    curves : dict
        Per-scan means for the plot: ``"scan"`` and, per method ``m``, ``ospa2_m``,
        ``cardinality_error_m``, ``components_m``, ``sweeps_m`` and ``retained_mass_m``.
    """

    n_mc: int
    config: dict
    rows: tuple
    short_vs_long_pct: float
    glmb_savings_pct: float
    lmb_savings_pct: float
    glmb_vs_lmb_short_pct: float
    glmb_vs_lmb_long_pct: float
    curves: dict


def _se(x) -> float:
    x = np.asarray(x, dtype=float)
    return float(x.std(ddof=1) / math.sqrt(x.size)) if x.size > 1 else math.nan


def _masses(r) -> np.ndarray:
    return np.array([math.nan if v is None else v for v in r["retained_mass"]], dtype=float)


def summarise_glmb_tracking(runs: list[dict], cfg: GLMBStudyConfig) -> GLMBStudySummary:
    """Per-method rows, the paired target comparisons and the per-scan means.

    Parameters
    ----------
    runs : list of dict
        Records of :func:`glmb_tracking_task`.
    cfg : GLMBStudyConfig
        The settings of the runs (methods, scans).

    Returns
    -------
    GLMBStudySummary
    """
    by = {m: sorted((r for r in runs if r["method"] == m), key=lambda r: r["run"])
          for m in cfg.methods}
    rows, curves = [], {"scan": list(range(1, cfg.n_scans + 1))}
    for m, rs in by.items():
        if not rs:
            continue
        o = np.array([r["ospa2"] for r in rs])
        mass = np.array([_masses(r) for r in rs])
        finite = mass[np.isfinite(mass)]
        rows.append(GLMBMethodSummary(
            method=m, n_runs=len(rs), ospa2_mean=float(o.mean()), ospa2_se=_se(o.mean(axis=1)),
            cardinality_error_mean=float(np.mean([r["cardinality_error"] for r in rs])),
            sweeps=float(np.mean([sum(r["sweeps"]) for r in rs])),
            components_mean=float(np.mean([r["components"] for r in rs])),
            retained_mass_mean=float(finite.mean()) if finite.size else math.nan,
            retained_mass_min=float(finite.min()) if finite.size else math.nan,
            seconds=float(np.mean([r["seconds"] for r in rs])),
        ))
        curves[f"ospa2_{m}"] = o.mean(axis=0).tolist()
        curves[f"cardinality_error_{m}"] = np.mean([r["cardinality_error"] for r in rs],
                                                   axis=0).tolist()
        curves[f"components_{m}"] = np.mean([r["components"] for r in rs], axis=0).tolist()
        curves[f"sweeps_{m}"] = np.mean([r["sweeps"] for r in rs], axis=0).tolist()
        if finite.size:
            with np.errstate(invalid="ignore"):
                curves[f"retained_mass_{m}"] = np.nanmean(mass, axis=0).tolist()

    def paired(a, b, key="ospa2"):
        """Mean of a's per-run means over b's, minus 1 (%), over the runs both have."""
        ra = {r["run"]: np.mean(r[key]) if key == "ospa2" else sum(r[key]) for r in by.get(a, [])}
        rb = {r["run"]: np.mean(r[key]) if key == "ospa2" else sum(r[key]) for r in by.get(b, [])}
        common = sorted(set(ra) & set(rb))
        if not common:
            return math.nan
        return 100.0 * (np.mean([ra[i] for i in common]) / np.mean([rb[i] for i in common]) - 1)

    return GLMBStudySummary(
        n_mc=cfg.n_mc,
        config={"preset": cfg.preset, "n_scans": cfg.n_scans, "h_upd": cfg.h_upd,
                "h_max": cfg.h_max, "original_obs": cfg.original_obs,
                "n_chains": cfg.n_chains, "chain_length": cfg.chain_length,
                "tau_stall": cfg.tau_stall, "tau_stale": cfg.tau_stale, "murty_k": cfg.murty_k,
                "ospa_c": cfg.ospa_c, "ospa_p": cfg.ospa_p, "ospa_window": cfg.ospa_window},
        rows=tuple(rows),
        short_vs_long_pct=paired("glmb-short", "glmb-long"),
        glmb_savings_pct=-paired("glmb-short", "glmb-long", "sweeps"),
        lmb_savings_pct=-paired("lmb-short", "lmb-long", "sweeps"),
        glmb_vs_lmb_short_pct=paired("glmb-short", "lmb-short"),
        glmb_vs_lmb_long_pct=paired("glmb-long", "lmb-long"),
        curves=curves,
    )


def _off(v: float, what: str) -> str:
    return f"{fmt.num(abs(v), 1)} % {'above' if v >= 0 else 'below'} {what}"


def _verdict(s: GLMBStudySummary) -> str:
    parts = []
    paper = 100.0 * (1 - PAPER_TOTALS["proposed"] / PAPER_TOTALS["original"])
    if math.isfinite(s.short_vs_long_pct):
        ok = abs(s.short_vs_long_pct) <= SHORT_VS_LONG_TARGET
        parts.append(
            f"On the GLMB filter the short chains' mean OSPA(2) is "
            f"{_off(s.short_vs_long_pct, 'the long chain’s')} (target: within "
            f"{SHORT_VS_LONG_TARGET:g} %, {'met' if ok else 'not met'}), with "
            f"{fmt.num(s.glmb_savings_pct, 1)} % fewer sweeps"
            + (f"; on the LMB filter they save {fmt.num(s.lmb_savings_pct, 1)} %"
               if math.isfinite(s.lmb_savings_pct) else "")
            + f" (the paper: {fmt.num(paper, 1)} %). The savings do not carry over in "
            "proportion: the GLMB's long chain already spends only `T_h − 1` sweeps per "
            "component, some `H_upd` per scan in all, so most components have a budget of a "
            "few sweeps that no stopping rule can cut.")
    for name, v in (("short chains", s.glmb_vs_lmb_short_pct),
                    ("long chain", s.glmb_vs_lmb_long_pct)):
        if math.isfinite(v):
            ok = v <= GLMB_VS_LMB_TARGET
            parts.append(f"With the {name}, the GLMB filter's mean OSPA(2) is "
                         f"{_off(v, 'the LMB filter’s')} (target: at most "
                         f"{GLMB_VS_LMB_TARGET:g} % above, {'met' if ok else 'not met'}).")
    mass = {r.method: r for r in s.rows if math.isfinite(r.retained_mass_mean)}
    if mass:
        parts.append("Posterior mass retained per scan (mean, worst scan): " + "; ".join(
            f"{_LABELS[m]} {fmt.num(r.retained_mass_mean, 4)}, {fmt.num(r.retained_mass_min, 4)}"
            for m, r in mass.items()) + ". The mass a truncation drops is the price of its "
            "savings in the GLMB filter; the LMB filter cannot show it.")
    return " ".join(parts)


def render_glmb_tracking(s: GLMBStudySummary, cfg: GLMBStudyConfig) -> str:
    """The study's report section."""
    c = s.config
    header = ["method", "runs", "OSPA(2) (m)", "cardinality error (abs.)", "sweeps per run",
              "components", "retained mass (mean / min)", "seconds per run"]
    rows = [[_LABELS[r.method], str(r.n_runs), fmt.pm(r.ospa2_mean, r.ospa2_se),
             fmt.num(r.cardinality_error_mean, 3), fmt.integer(r.sweeps),
             fmt.num(r.components_mean, 1) if r.method.startswith("glmb") else "–",
             (f"{fmt.num(r.retained_mass_mean, 4)} / {fmt.num(r.retained_mass_min, 4)}"
              if math.isfinite(r.retained_mass_mean) else "–"),
             fmt.num(r.seconds, 2)] for r in s.rows]
    return f"""## δ-GLMB against LMB — every truncation on the same measurements (issue #26)

Preset `{c["preset"]}`, {fmt.plural(s.n_mc, "Monte Carlo run")} of {c["n_scans"]} scans; every
method of a run sees the same measurements. GLMB: `H_upd = {c["h_upd"]}`, `H_max = {c["h_max"]}`,
component count `T_h = round(H_upd √w_h / Σ √w)`; long chain `T_h − 1` sweeps per component
(at most {c["original_obs"]:,}; LMB: {c["original_obs"]:,} per scan); short chains
{c["n_chains"]} × {c["chain_length"]}, τ_stall = {c["tau_stall"]}, τ_stale = {c["tau_stale"]},
within the same `T_h − 1`; Murty `k = min({c["murty_k"]}, T_h)`. OSPA(2): c = {c["ospa_c"]:g} m,
p = {c["ospa_p"]:g}, window {c["ospa_window"]}. The retained mass is
`Σ_h w_h K_h / Σ_h w_h Z_h` with the exact normalisers (spec §4).

{fmt.table(header, rows)}

**Verdict.** {_verdict(s)}

![OSPA(2), cardinality error, components and retained mass per scan](glmb_tracking.png)
"""


def plot_glmb_tracking(s: GLMBStudySummary, directory: Path) -> list[str]:
    """Four panels per scan: OSPA(2), cardinality error, components, retained mass."""
    cur = s.curves
    k = np.array(cur["scan"])
    fig, axes = figure(4, width=4.5, height=3.6)
    methods = [r.method for r in s.rows]
    for ax, what, ylabel in zip(axes, ("ospa2", "cardinality_error", "components",
                                       "retained_mass"),
                                ("OSPA(2) (m)", "abs. cardinality error", "components",
                                 "retained mass"), strict=True):
        for m in methods:
            key = f"{what}_{m}"
            if key in cur and (what not in ("components", "retained_mass")
                               or m.startswith("glmb")):
                ax.plot(k, cur[key], label=_LABELS[m], lw=1, color=_COLORS[m])
        ax.set_xlabel("scan")
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.suptitle(f"δ-GLMB and LMB on preset {s.config['preset']!r}, mean of "
                 f"{fmt.plural(s.n_mc, 'run')}", fontsize=10)
    name = "glmb_tracking.png"
    fig.savefig(Path(directory) / name, dpi=110)
    return [name]


def _csv_rows(s: GLMBStudySummary) -> list[dict]:
    return [dict(r.__dict__) for r in s.rows]


GLMB_TRACKING = register_study(Study(
    name="glmb_tracking",
    title="δ-GLMB against LMB with the long chain, the short chains and Murty (issue #26)",
    config_type=GLMBStudyConfig,
    full=GLMBStudyConfig,
    quick=GLMBStudyConfig.quick,
    tasks=glmb_tasks,
    task=glmb_tracking_task,
    summarise=summarise_glmb_tracking,
    render=render_glmb_tracking,
    plot=plot_glmb_tracking,
    csv_rows=_csv_rows,
    paper="",
    order=75,
))
