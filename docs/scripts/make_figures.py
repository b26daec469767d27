"""Regenerate every figure of the documentation site from the project's own code.

Run from the repository root::

    python docs/scripts/make_figures.py            # all figures into docs/figures/
    python docs/scripts/make_figures.py --only discovery --out /tmp/figs

Each figure is produced by one function below, registered in ``FIGURES`` under the file name
(without ``.png``) it writes. The configurations are small on purpose (the whole script runs in
well under a minute on a laptop); the full-size studies are ``rankedassign reproduce``'s job.
Every random draw comes from a fixed seed, so the figures are reproducible.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # run from a source checkout without installing

from rankedassign.single import synthetic  # noqa: E402

SEED = 20230627
DPI = 110


def cost_matrix_diagonal(out: Path) -> None:
    """Heatmap of the paper's diagonal cost matrix in the ``P x (M + 2P)`` layout."""
    prob = synthetic.diagonal()
    C = prob.cost
    P, M = prob.n_rows, prob.n_meas
    fig, ax = plt.subplots(figsize=(9.0, 2.9))
    masked = np.ma.masked_invalid(np.where(np.isfinite(C), C, np.nan))
    cmap = plt.get_cmap("viridis").copy()
    cmap.set_bad("white")
    im = ax.imshow(masked, cmap=cmap, aspect="equal")
    for x in (M - 0.5, M + P - 0.5):
        ax.axvline(x, color="black", lw=1.2)
    ax.set_xticks(range(prob.n_cols))
    ax.set_xticklabels([str(c) for c in range(prob.n_cols)], fontsize=7)
    ax.set_yticks(range(P))
    ax.set_ylabel("row i (label)")
    ax.set_xlabel("column c")
    for c0, c1, label in (
        (0, M, "measurements 0..M-1"),
        (M, M + P, "missed M+i"),
        (M + P, M + 2 * P, "dead M+P+i"),
    ):
        ax.text((c0 + c1 - 1) / 2, -0.65, label, ha="center", va="bottom", fontsize=8)
    for i in range(P):
        for c in range(prob.n_cols):
            if np.isfinite(C[i, c]) and (c < M and c == i or c >= M):
                ax.text(c, i, f"{C[i, c]:.2f}", ha="center", va="center", fontsize=5.5,
                        color="white" if C[i, c] < 2 else "black")
    cb = fig.colorbar(im, ax=ax, fraction=0.025, pad=0.01)
    cb.set_label("cost = -ln eta", fontsize=8)
    ax.set_title("Diagonal family (4 x 24): white = +inf (forbidden)", fontsize=9, pad=20)
    fig.tight_layout()
    fig.savefig(out, dpi=DPI)
    plt.close(fig)


def _error_curve(problem, budgets, run):
    """Truncation error of ``run(problem, n)`` for each observation budget ``n``."""
    import oracle

    errors, used = [], []
    for n in budgets:
        res = run(problem, n)
        errors.append(oracle.truncation_error(problem, res.assignments))
        used.append(res.n_observations)
    return np.asarray(used), np.asarray(errors)


def discovery(out: Path) -> None:
    """Truncation error against observations: one long chain vs short chains (no stopping).

    The short-chain sampler with both stopping rules at the paper's settings is marked where it
    stopped.
    """
    import oracle
    from rankedassign import sample_original, sample_short_chains

    budgets = np.unique(np.round(np.logspace(2, np.log10(250_000), 12)).astype(int))
    families = (
        ("uniform", synthetic.uniform()),
        (f"random (rng={SEED})", synthetic.random(rng=SEED)),
    )
    fig, axes = plt.subplots(1, 2, figsize=(10.0, 3.8), sharey=False)
    for ax, (name, prob) in zip(axes, families, strict=True):
        x, y = _error_curve(prob, budgets, lambda p, n: sample_original(p, n, rng=SEED))
        ax.loglog(x, y, "k-o", ms=3, lw=1.6, label="original (one chain)")
        for L, style in ((5, "C0--"), (25, "C1-"), (100, "C2-.")):
            x, y = _error_curve(
                prob,
                [b for b in budgets if b >= L],
                lambda p, n, L=L: sample_short_chains(p, n // L, L, rng=SEED),
            )
            ax.loglog(x, y, style, marker="s", ms=3, lw=1.2, label=f"short chains, length {L}")
        full = sample_short_chains(prob, 10_000, 25, tau_stall=5, tau_stale=25, rng=SEED)
        e_full = oracle.truncation_error(prob, full.assignments)
        ax.loglog([full.n_observations], [max(e_full, 1e-12)], "r*", ms=11,
                  label="stall 5 + stale 25, 10 000 x 25: where it stopped")
        ax.annotate(f"stopped: {full.stop_reason},\n{full.n_observations:,} obs.",
                    (full.n_observations, max(e_full, 1e-12)), textcoords="offset points",
                    xytext=(-8, -26), ha="right", fontsize=7.5, color="r")
        ax.set_title(f"{name}: |Gamma| = {prob.n_feasible():,}", fontsize=10)
        ax.set_xlabel("observations (sweeps)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("truncation error")
    axes[1].legend(fontsize=7.5, loc="upper right")
    fig.suptitle(f"Truncation error of the distinct hypotheses found (seed {SEED})", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=DPI)
    plt.close(fig)


def tracking(out: Path) -> None:
    """Tracks and OSPA(2) on the paper's scenario, short chains vs the original sampler."""
    from rankedassign.metrics import ospa2
    from rankedassign.tracking import OriginalGibbs, ShortChainGibbs, run_scenario

    short = run_scenario("paper", ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10), rng=SEED)
    long_ = run_scenario("paper", OriginalGibbs(10_000), rng=SEED)
    fig = plt.figure(figsize=(10.5, 4.6))
    gs = fig.add_gridspec(2, 2, width_ratios=(1.0, 1.25))
    ax = fig.add_subplot(gs[:, 0])
    T = short.truth
    for f in range(T.shape[1]):
        ax.plot(T[:, f, 0], T[:, f, 1], "-", color="0.55", lw=2.5, alpha=0.8,
                label="truth" if f == 0 else None)
    E = short.estimates
    colors = plt.get_cmap("tab20")
    for f in range(E.shape[1]):
        ax.plot(E[:, f, 0], E[:, f, 1], ".", ms=2.5, color=colors(f % 20))
    ax.plot([], [], ".", color="C0", label="estimates (short chains)")
    ax.set_xlim(-1000, 1000)
    ax.set_ylim(-1000, 1000)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.legend(fontsize=8, loc="upper right")
    ax.set_title("Paper scenario, one replication", fontsize=10)

    ax1 = fig.add_subplot(gs[0, 1])
    k = np.arange(1, T.shape[0] + 1)
    for run, label, style in ((long_, "original, 10 000 sweeps/call", "k-"),
                              (short, "short chains 400 x 25, stall 5, stale 10", "C1-")):
        d = ospa2(run.truth, run.estimates, c=200.0, p=1.0, window=5)
        ax1.plot(k, d.value, style, lw=1.2, label=f"{label} (mean {d.value.mean():.1f} m)")
    ax1.set_ylabel("OSPA(2) (m)")
    ax1.set_ylim(0, 200)
    ax1.legend(fontsize=7)
    ax1.grid(True, alpha=0.3)
    ax2 = fig.add_subplot(gs[1, 1], sharex=ax1)
    for run, label, style in ((long_, "original", "k-"), (short, "short chains", "C1-")):
        total = int(run.sweeps.sum())
        ax2.semilogy(k, np.cumsum(run.sweeps), style, lw=1.2, label=f"{label}: {total:,} sweeps")
    ax2.set_xlabel("scan")
    ax2.set_ylabel("cumulative sweeps")
    ax2.legend(fontsize=7)
    ax2.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=DPI)
    plt.close(fig)


def tracking_multisensor(out: Path) -> None:
    """OSPA(2) and cardinality error on the multi-sensor scenario: sensors 0, 1, 2 alone and
    fused, short chains with the MM kernel, one 30-scan replication."""
    from rankedassign.experiments.studies.multisensor_tracking import (
        MultiSensorStudyConfig,
        multisensor_tracking_task,
        plot_multisensor_tracking,
        summarise_multisensor_tracking,
    )

    cfg = MultiSensorStudyConfig(n_mc=1, n_scans=30, seed=SEED % 1000)
    recs = [multisensor_tracking_task(cfg, 0, s, ("short-chain", "mm"))
            for s in ((0,), (1,), (2,), (0, 1, 2))]
    # one association: one panel, the four sensor sets as its lines
    plot_multisensor_tracking(summarise_multisensor_tracking(recs), out, by="association")


def sweep_scaling(out: Path) -> None:
    """Time per sweep against M and P, direct sum against prefix sums: runs the scaling
    benchmark (about 10 s; the timings depend on the machine) and plots its JSON."""
    import subprocess
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        json_path = Path(tmp) / "scaling.json"
        subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                        str(ROOT / "benchmarks" / "test_bench_sweep_scaling.py"),
                        "--benchmark-enable", "--benchmark-only",
                        f"--benchmark-json={json_path}"], cwd=ROOT, check=True)
        subprocess.run([sys.executable, str(ROOT / "benchmarks" / "plot_sweep_scaling.py"),
                        str(json_path), str(out)], check=True)


def tracking_multisensor_adaptive(out: Path) -> None:
    """Static against adaptive birth on the multi-sensor scenario: the paper's static birth on
    sensors 0, 1 and adaptive birth on sensors 0, 1 and 0, 1, 2, short chains 400 x 25, one
    100-scan replication (seed 0, the runs of the table on the multi-sensor page)."""
    from rankedassign.experiments.studies.multisensor_tracking import (
        MultiSensorStudyConfig,
        multisensor_tracking_task,
        plot_multisensor_tracking,
        summarise_multisensor_tracking,
    )

    cfg = MultiSensorStudyConfig(n_mc=1, n_scans=100, seed=0)
    recs = [multisensor_tracking_task(cfg, 0, (0, 1), ("short-chain", "exact"))]
    recs += [multisensor_tracking_task(cfg, 0, s, ("short-chain", "exact"), "adaptive")
             for s in ((0, 1), (0, 1, 2))]
    # one panel per sensor set: static and adaptive birth side by side on sensors 0, 1
    plot_multisensor_tracking(summarise_multisensor_tracking(recs), out, by="sensors")


_GLMB = {}


def _glmb_summary():
    """The glmb_tracking study's quick run (two 100-scan runs per preset), run once for both
    of its figures."""
    from rankedassign.experiments import run_study
    from rankedassign.experiments.studies.glmb_tracking import GLMBStudyConfig

    if "summary" not in _GLMB:
        _GLMB["summary"] = run_study("glmb_tracking", GLMBStudyConfig.quick(), seed=0,
                                     progress=False)
    return _GLMB["summary"]


def glmb_tracking(out: Path) -> None:
    """The glmb_tracking study's per-scan panels (the study's quick settings)."""
    import shutil
    import tempfile

    from rankedassign.experiments.studies.glmb_tracking import plot_glmb_tracking

    assert out.name == "glmb_tracking.png"
    with tempfile.TemporaryDirectory() as tmp:  # it writes the trade-off figure too
        plot_glmb_tracking(_glmb_summary(), Path(tmp))
        shutil.copy(Path(tmp) / out.name, out)


def glmb_tradeoff(out: Path) -> None:
    """The glmb_tracking study's trade-off figure: OSPA(2) and carried mass against the
    hypotheses per scan over H_upd (the study's quick settings)."""
    from rankedassign.experiments.studies.glmb_tracking import plot_glmb_tradeoff

    assert out.name == "glmb_tradeoff.png"
    plot_glmb_tradeoff(_glmb_summary(), out.parent)


#: The summary of the full configuration's trade-off on four runs, committed with its command
#: (benchmarks/glmb_tracking_full/tradeoff): twelve minutes of CPU to recompute, so the figure
#: is redrawn from it rather than rerun here.
GLMB_TRADEOFF_SUMMARY = (ROOT / "benchmarks" / "glmb_tracking_full" / "tradeoff"
                         / "glmb_tracking.json")


def glmb_tradeoff_full(out: Path) -> None:
    """The glmb_tracking study's trade-off figure in the full configuration's settings (H_upd
    from 100 to 10 000, every GLMB truncation, on four runs), redrawn from the committed
    summary of that run."""
    import json
    import math
    import shutil
    import tempfile

    from rankedassign.experiments.studies.glmb_tracking import (
        GLMBPresetSummary,
        GLMBStudySummary,
        plot_glmb_tradeoff,
    )
    from rankedassign.experiments.vocabulary import DEPRECATED_FILTER_TRUNCATIONS

    data = json.loads(GLMB_TRADEOFF_SUMMARY.read_text())

    def point(q):
        # the JSON has null for NaN (the LMB points' carried mass); "h_upd" is None on purpose
        q = {k: math.nan if v is None and k != "h_upd" else v for k, v in q.items()}
        if "method" in q:  # written before the studies' vocabulary: "glmb-long", ...
            q["filter"], q["truncation"] = DEPRECATED_FILTER_TRUNCATIONS[q.pop("method")]
        return q

    presets = tuple(GLMBPresetSummary(
        preset=p["preset"], rows=(), comparisons=(), glmb_savings_pct=math.nan,
        lmb_savings_pct=math.nan, tradeoff=tuple(point(q) for q in p["tradeoff"]), curves={})
        for p in data["presets"])
    summary = GLMBStudySummary(n_mc=data["n_mc"], config=data["config"], presets=presets)
    with tempfile.TemporaryDirectory() as tmp:
        plot_glmb_tradeoff(summary, Path(tmp))
        shutil.copy(Path(tmp) / "glmb_tradeoff.png", out)


SCALING_SUMMARY = ROOT / "benchmarks" / "scaling_full" / "scaling.json"


def scaling_full(out: Path) -> None:
    """The scaling study's figure in its full configuration (N = 10 to 10 000, three runs of
    ten scans), redrawn from the committed summary of that run."""
    import json
    import math
    import shutil
    import tempfile

    from rankedassign.experiments.studies.scaling import ScalingRow, ScalingSummary, plot_scaling

    data = json.loads(SCALING_SUMMARY.read_text())
    # the JSON has null for NaN (a standard error of one run, the LMB filter's cluster fields)
    rows = [ScalingRow(**{k: math.nan if v is None else v for k, v in r.items()})
            for r in data["rows"]]
    with tempfile.TemporaryDirectory() as tmp:
        plot_scaling(ScalingSummary(rows=rows), Path(tmp))
        shutil.copy(Path(tmp) / "scaling.png", out)


_TH = {}


def _tempering_herding(out: Path, which: str) -> None:
    """The tempering_herding study's plots from its quick settings without the tracking part
    (one run serves both figures)."""
    import dataclasses
    import shutil
    import tempfile

    from rankedassign.experiments import get_study, run_study
    from rankedassign.experiments.studies.tempering_herding import plot_tempering_herding

    if "summary" not in _TH:
        cfg = dataclasses.replace(get_study("tempering_herding").quick(), tracking_mc=0)
        _TH["summary"] = run_study("tempering_herding", cfg, seed=0, progress=False)
    with tempfile.TemporaryDirectory() as tmp:
        plot_tempering_herding(_TH["summary"], Path(tmp))
        shutil.copy(Path(tmp) / f"tempering_herding_{which}.png", out)


def tempering_herding_obs(out: Path) -> None:
    """Truncation error against observations, every method, every family (quick study)."""
    _tempering_herding(out, "obs")


def tempering_herding_time(out: Path) -> None:
    """Truncation error against seconds per call, every method, every family (quick study)."""
    _tempering_herding(out, "time")


def _page_figure(page_name: str, figure: str, out: Path) -> None:
    """Run a page's code blocks as written, in a temporary folder; copy the figure it saves."""
    import os
    import re
    import shutil
    import tempfile

    page = (ROOT / "docs" / page_name).read_text()
    code = "\n".join(re.findall(r"^```python\n(.*?)^```$", page, flags=re.S | re.M))
    here = os.getcwd()
    with tempfile.TemporaryDirectory() as tmp:
        os.chdir(tmp)
        try:
            exec(compile(code, f"docs/{page_name}", "exec"), {"__name__": "docs_page"})
        finally:
            os.chdir(here)
        shutil.copy(Path(tmp) / figure, out)


def stonesoup_ospa(out: Path) -> None:
    """The example of docs/stonesoup.md: its code blocks, run as written, save this figure."""
    _page_figure("stonesoup.md", "stonesoup_ospa.png", out)


def stonesoup_bearing_range(out: Path) -> None:
    """The gallery page docs/stonesoup-bearing-range.md, run as written."""
    _page_figure("stonesoup-bearing-range.md", "stonesoup_bearing_range.png", out)


FIGURES = {
    "cost_matrix_diagonal": cost_matrix_diagonal,
    "sweep_scaling": sweep_scaling,
    "discovery": discovery,
    "tracking": tracking,
    "tracking_multisensor": tracking_multisensor,
    "tracking_multisensor_adaptive": tracking_multisensor_adaptive,
    "glmb_tracking": glmb_tracking,
    "glmb_tradeoff": glmb_tradeoff,
    "glmb_tradeoff_full": glmb_tradeoff_full,
    "scaling_full": scaling_full,
    "stonesoup_ospa": stonesoup_ospa,
    "stonesoup_bearing_range": stonesoup_bearing_range,
    "tempering_herding_obs": tempering_herding_obs,
    "tempering_herding_time": tempering_herding_time,
}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "figures")
    parser.add_argument("--only", nargs="*", choices=sorted(FIGURES), default=None)
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    for name in args.only or FIGURES:
        t0 = time.perf_counter()
        FIGURES[name](args.out / f"{name}.png")
        print(f"{name}.png  {time.perf_counter() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
