"""Our filters against Vo's own MATLAB filters (run in GNU Octave) on the same measurements.

Vo's public toolbox ships the joint δ-GLMB and LMB filters for his coordinated-turn,
bearing–range example (``jointglmb/ekf``, ``jointglmb/ukf``, ``jointlmb/ekf``,
``jointlmb/ukf``). This script draws the measurements of our presets ``"vo-ekf"`` /
``"vo-ukf"`` (his model, his truth), runs his ``run_filter`` on them unmodified in Octave, runs
ours (short chains, MAP extraction, his settings) on the same measurements, and prints per run
the mean OSPA (his ``c = 100``, ``p = 1``, against the same truth), the share of scans with the
same cardinality estimate, and the seconds each took.

His code is not part of this repository: pass the folder of a copy of his toolbox (e.g. a clone
of a public mirror) as ``--vo-dir``. Octave comes from the distribution's packages
(``apt-get install octave octave-statistics``: his code calls ``chi2inv``). Run from the repository's root::

    python benchmarks/vo_octave.py --vo-dir PATH --filters glmb lmb --seeds 0 1 2

The numbers measured with it are in ``benchmarks/README.md`` ("Vo's filters in Octave").
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from rankedassign import metrics
from rankedassign.tracking import GLMBFilter, LMBFilter, ShortChainGibbs, make_scenario

DRIVER = """\
pkg load statistics
addpath(genpath('{common}'));
addpath('{folder}');
model = gen_model;
meas.K = {K};
meas.Z = cell(meas.K, 1);
{Z}
rand('seed', {seed}); randn('seed', {seed});
t0 = tic;
est = run_filter(model, meas);
t = toc(t0);
fid = fopen('{out}', 'w');
fprintf(fid, '%.6f\\n', t);
for k = 1:meas.K
  X = est.X{{k}};
  for j = 1:size(X, 2)
    fprintf(fid, '%d,%.12g,%.12g\\n', k, X(1, j), X(3, j));
  end
  if size(X, 2) == 0
    fprintf(fid, '%d,nan,nan\\n', k);
  end
end
fclose(fid);
"""


def _matrix(z: np.ndarray) -> str:
    """Octave literal of the ``2 × n`` matrix ``[bearing; range]`` of a scan."""
    if z.shape[0] == 0:
        return "zeros(2, 0)"
    rows = [" ".join(f"{v:.17g}" for v in z[:, i]) for i in range(z.shape[1])]
    return "[" + "; ".join(rows) + "]"


def run_vo(vo_dir: Path, filter_name: str, variant: str, scans, seed: int, work: Path):
    """Vo's ``run_filter`` of ``joint<filter>/<variant>`` on ``scans``; (seconds, estimates)."""
    folder = vo_dir / f"joint{filter_name}" / variant
    out = work / f"vo_{filter_name}_{variant}_{seed}.csv"
    Z = "\n".join(f"meas.Z{{{k + 1}}} = {_matrix(s.z)};" for k, s in enumerate(scans))
    script = work / f"drive_{filter_name}_{variant}_{seed}.m"
    script.write_text(DRIVER.format(common=vo_dir / "_common", folder=folder, K=len(scans),
                                    Z=Z, seed=seed, out=out))
    subprocess.run(["octave", "--no-gui", "--quiet", str(script)], cwd=work, check=True,
                   stdout=subprocess.DEVNULL)
    lines = out.read_text().splitlines()
    est = [[] for _ in scans]
    for line in lines[1:]:
        k, x, y = line.split(",")
        if x != "nan":
            est[int(k) - 1].append((float(x), float(y)))
    return float(lines[0]), est


def run_ours(model, filter_name: str, scans, seed: int):
    """Our filter with short chains and Vo's settings; (seconds, estimates)."""
    opts = model.settings.filter_options(filter_name)
    if filter_name == "glmb":
        f = GLMBFilter(model, ShortChainGibbs(120, 25, tau_stall=5, tau_stale=10), **opts)
    else:
        f = LMBFilter(model, ShortChainGibbs(40, 25, tau_stall=5, tau_stale=10), **opts)
    dims = tuple(model.position_indices)
    est = []
    t = time.perf_counter()
    for k, s in enumerate(scans):
        rec = f.step(s.z, rng=[seed, k])
        est.append([tuple(x[list(dims)]) for x in rec.states])
    return time.perf_counter() - t, est


def _array(est, K):
    n = max((len(e) for e in est), default=0)
    out = np.full((K, max(n, 1), 2), np.nan)
    for k, e in enumerate(est):
        for j, p in enumerate(e):
            out[k, j] = p
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--vo-dir", type=Path, required=True, help="a copy of Vo's toolbox")
    ap.add_argument("--filters", nargs="+", default=["glmb", "lmb"], choices=["glmb", "lmb"])
    ap.add_argument("--variants", nargs="+", default=["ekf"], choices=["ekf", "ukf"])
    ap.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2])
    ap.add_argument("--scans", type=int, default=100)
    args = ap.parse_args(argv)
    if shutil.which("octave") is None:
        print("octave is not installed (apt-get install octave)", file=sys.stderr)
        return 2
    print("filter variant seed | OSPA ours  OSPA Vo  ratio | same N | s ours  s Vo  speed-up")
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for variant in args.variants:
            for seed in args.seeds:
                sc = make_scenario(f"vo-{variant}", rng=seed, n_scans=args.scans)
                K = len(sc.scans)
                truth = sc.truth.positions
                for name in args.filters:
                    t_ours, ours = run_ours(sc.model, name, sc.scans, seed)
                    t_vo, vo = run_vo(args.vo_dir, name, variant, sc.scans, seed, work)
                    o_ours = float(np.mean(metrics.ospa2(truth, _array(ours, K), 100.0, 1.0,
                                                         1).value))
                    o_vo = float(np.mean(metrics.ospa2(truth, _array(vo, K), 100.0, 1.0,
                                                       1).value))
                    same = float(np.mean([len(a) == len(b) for a, b in zip(ours, vo,
                                                                             strict=True)]))
                    print(f"{name:6} {variant:7} {seed:4} | {o_ours:9.2f} {o_vo:8.2f} "
                          f"{o_ours / o_vo:6.3f} | {100 * same:5.1f} % | {t_ours:6.1f} "
                          f"{t_vo:6.1f} {t_vo / t_ours:8.1f}x", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
