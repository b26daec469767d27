"""Our non-linear LMB and δ-GLMB filters against Vo's MATLAB filters on identical measurements.

The steps, each its own sub-command (``VO`` a checkout of Vo's toolbox with its
``jointglmb/ekf``, ``jointlmb/ekf`` and ``_common`` folders)::

    python benchmarks/vo_octave_comparison.py write  MEAS.txt  [--seed 7]
    python benchmarks/vo_octave_comparison.py driver VO/run_vo.m
    cd VO && octave --eval "run_vo('VO', 'jointglmb/ekf', 'MEAS.txt', 'OUT_GLMB.txt', 100)"
    cd VO && octave --eval "run_vo('VO', 'jointlmb/ekf', 'MEAS.txt', 'OUT_LMB.txt', 100)"
    python benchmarks/vo_octave_comparison.py compare MEAS.txt --glmb OUT_GLMB.txt --lmb OUT_LMB.txt

``write`` draws the ``"vo-ekf"`` scenario (``make_scenario("vo-ekf", rng=seed)``) and writes
its measurements, one ``scan bearing range`` row per measurement (``"vo-ukf"`` draws the same
ones: the presets differ only in the single-object filter; ``compare --preset vo-ukf`` runs our
UKF filters against Vo's ``*/ukf`` folders). Vo's filters are run on them
unmodified (his ``jointglmb/ekf`` and ``jointlmb/ekf`` folders and ``_common`` of a mirror of
his toolbox, e.g. ``Benzlxs/Tracking_filter``): a driver of a few lines calls his
``gen_model`` and ``run_filter`` with ``meas.Z{k}`` read from the file and writes the
estimated positions (``est.X{k}`` rows 1 and 3) and the CPU time (``cputime``) as ``cpu C wall
W`` then ``scan x y`` rows (``scan nan nan`` for an empty estimate). ``compare`` runs our
filters (the paper's short chains, 400 x 25; Vo's ``H_upd``, gate and pruning; MAP extraction) on the
same measurements and prints a Markdown table: mean OSPA (``c = 100`` m, ``p = 1``, Vo's
``plot_results`` settings), the fraction of scans whose estimated cardinality equals Vo's,
and the CPU time of a whole run.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from rankedassign.metrics import ospa2
from rankedassign.tracking import ShortChainGibbs, make_scenario, run_filter
from rankedassign.tracking.filters import make_filter

#: The Octave driver: Vo's gen_model and run_filter, unmodified, on the written measurements.
DRIVER = """\
function run_vo(root, folder, measfile, outfile, K)
  pkg load statistics;  % chi2inv, used by his run_filter
  addpath(fullfile(root, folder)); addpath(fullfile(root, '_common'));
  rand('seed', 1); randn('seed', 1);
  model = gen_model;
  D = load(measfile);
  meas.K = K; meas.Z = cell(K, 1);
  for k = 1:K
    meas.Z{k} = D(D(:,1) == k, 2:3)';
    if isempty(meas.Z{k}), meas.Z{k} = zeros(2, 0); end
  end
  t0 = cputime; tw = tic;
  est = run_filter(model, meas);
  cpu = cputime - t0; wall = toc(tw);
  f = fopen(outfile, 'w');
  fprintf(f, 'cpu %.6f wall %.6f\\n', cpu, wall);
  for k = 1:K
    X = est.X{k};
    for i = 1:size(X, 2)
      fprintf(f, '%d %.10g %.10g\\n', k, X(1, i), X(3, i));
    end
    if size(X, 2) == 0, fprintf(f, '%d nan nan\\n', k); end
  end
  fclose(f);
end
"""


def write(path: str, seed: int) -> None:
    sc = make_scenario("vo-ekf", rng=seed)
    with open(path, "w") as f:
        for k, s in enumerate(sc.scans):
            for z in s.z:
                f.write(f"{k + 1} {float(z[0])!r} {float(z[1])!r}\n")


def read_measurements(path: str, n_scans: int) -> list:
    rows = np.loadtxt(path, ndmin=2)
    return [rows[rows[:, 0] == k + 1, 1:3] for k in range(n_scans)]


def read_estimates(path: str, n_scans: int):
    with open(path) as f:
        head = f.readline().split()
        rows = np.loadtxt(f, ndmin=2)
    cpu = float(head[1])
    est = np.full((n_scans, int(max(np.bincount(rows[:, 0].astype(int))) + 1), 2), np.nan)
    card = np.zeros(n_scans, dtype=int)
    for k in range(n_scans):
        r = rows[(rows[:, 0] == k + 1) & np.isfinite(rows[:, 1])]
        est[k, : len(r)] = r[:, 1:3]
        card[k] = len(r)
    return est, card, cpu


def ours(kind: str, scans: list, seed: int, preset: str = "vo-ekf"):
    sc = make_scenario(preset, rng=0, n_scans=1)  # the model only
    settings = sc.model.settings
    # the paper's short chains (400 chains of 25 observations, stall 5, stale 10)
    filt = make_filter(kind, sc.model, ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10),
                       multi=False, **settings.filter_options(kind))
    t0 = time.process_time()
    run = run_filter(filt, scans, rng=seed)
    cpu = time.process_time() - t0
    return run.estimates, run.n_estimated, cpu


def compare(meas: str, outs: dict, seed: int, n_scans: int = 100,
            preset: str = "vo-ekf") -> None:
    from rankedassign.tracking.nonlinear import make_nonlinear_model, vo_truth

    truth = vo_truth(make_nonlinear_model("vo-ekf"), n_scans).positions
    scans = read_measurements(meas, n_scans)
    ours(list(outs)[0], scans[:3], seed, preset)  # compile the kernels outside the timing
    # (Vo's run_filter on a prefix of the run reads only those scans)
    print("| filter | mean OSPA, Vo | mean OSPA, ours | same cardinality as Vo | "
          "CPU s, Vo | CPU s, ours | speed-up |")
    print("|---|---|---|---|---|---|---|")
    for kind, path in outs.items():
        vo_est, vo_card, vo_cpu = read_estimates(path, n_scans)
        est, card, cpu = ours(kind, scans, seed, preset)
        o_vo = ospa2(truth, vo_est, c=100.0, p=1, window=1).value.mean()
        o_us = ospa2(truth, est, c=100.0, p=1, window=1).value.mean()
        same = float((card == vo_card).mean())
        print(f"| {kind} | {o_vo:.2f} m | {o_us:.2f} m ({100 * (o_us / o_vo - 1):+.1f} %) | "
              f"{100 * same:.0f} % | {vo_cpu:.1f} | {cpu:.2f} | {vo_cpu / cpu:.0f}x |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    w = sub.add_parser("write")
    w.add_argument("meas")
    w.add_argument("--seed", type=int, default=7)
    d = sub.add_parser("driver")
    d.add_argument("path")
    c = sub.add_parser("compare")
    c.add_argument("meas")
    c.add_argument("--glmb")
    c.add_argument("--lmb")
    c.add_argument("--seed", type=int, default=0)
    c.add_argument("--n-scans", type=int, default=100)
    c.add_argument("--preset", choices=("vo-ekf", "vo-ukf"), default="vo-ekf",
                   help="our filters' preset; run Vo's ekf or ukf folders to match")
    a = ap.parse_args()
    if a.cmd == "write":
        write(a.meas, a.seed)
    elif a.cmd == "driver":
        with open(a.path, "w") as f:
            f.write(DRIVER)
    else:
        outs = {k: v for k, v in (("glmb", a.glmb), ("lmb", a.lmb)) if v}
        compare(a.meas, outs, a.seed, a.n_scans, a.preset)


if __name__ == "__main__":
    main()
