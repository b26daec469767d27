"""The non-linear measurement step against the compiled linear path, per scan.

Run the timings with::

    python -m pytest benchmarks/test_bench_nonlinear.py --benchmark-enable

(in the default suite each runs once as a smoke test). One group, the LMB and the δ-GLMB
filter on 100 scans each, all with ``ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)``:

* ``linear-compiled``: Vo's linear ``"vo"`` preset through the compiled Kalman kernels;
* ``linear-through-ekf``: the same model, the same measurements, given to the filter as a
  ``NonlinearModel`` with the EKF: the same problem size, so the ratio of the two is the cost
  of the numpy measurement step (issue target: at most 2x per scan);
* ``vo-ekf``: Vo's coordinated-turn, bearing–range preset with his EKF and settings, for
  reference (10 targets and 15 clutter points per scan instead of 12 and 30).

``extra_info`` holds the mean per-scan seconds of prediction, cost, association and update.
The numbers are in ``benchmarks/README.md``.
"""

import numpy as np
import pytest

from rankedassign.tracking import (
    GLMBFilter,
    LMBFilter,
    ShortChainGibbs,
    make_model,
    make_scenario,
    run_filter,
    run_scenario,
)
from rankedassign.tracking.nonlinear import (
    ExtendedKalmanFilter,
    GaussianBirth,
    LinearGaussianMeasurement,
    LinearGaussianMotion,
    NonlinearModel,
)

FILTERS = {"lmb": LMBFilter, "glmb": GLMBFilter}
CASES = ("linear-compiled", "linear-through-ekf", "vo-ekf")


def _assoc():
    return ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)


def _linear_through_ekf() -> NonlinearModel:
    lin = make_model("vo")
    birth = tuple(GaussianBirth(float(r), m, P) for r, m, P in
                  zip(lin.birth.r, lin.birth.means, lin.birth.covs, strict=True))
    return NonlinearModel(motion=LinearGaussianMotion.from_motion(lin.motion),
                          sensor=LinearGaussianMeasurement.from_sensor(lin.sensor),
                          clutter=lin.clutter, birth=birth, p_s=lin.survival.p_s,
                          filter=ExtendedKalmanFilter(), extraction=lin.extraction)


@pytest.fixture(scope="module")
def scans():
    return [s.z for s in make_scenario("vo", rng=0, n_scans=100).scans]


def _run(case, kind, scans):
    if case == "vo-ekf":
        return run_scenario("vo-ekf", _assoc(), rng=0, n_scans=100, filter=kind)
    model = make_model("vo") if case == "linear-compiled" else _linear_through_ekf()
    return run_filter(FILTERS[kind](model, _assoc()), scans, rng=0)


@pytest.mark.parametrize("case", CASES)
@pytest.mark.parametrize("kind", sorted(FILTERS))
def test_bench_nonlinear_step(benchmark, kind, case, scans):
    benchmark.group = "Non-linear measurement step vs compiled linear path, 100 scans"
    run = benchmark.pedantic(_run, args=(case, kind, scans), rounds=3, warmup_rounds=1)
    assert run.n_scans == 100
    benchmark.extra_info.update(
        {f"per_scan_{k}_s": float(np.mean(v)) for k, v in run.timings.items()})
    benchmark.extra_info.update(mean_tracks=float(run.n_tracks.mean()),
                                mean_meas=float(run.n_meas.mean()))
