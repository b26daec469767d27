"""Per scan: our Stone Soup trackers against Stone Soup's JPDA tracker on the same detections.

Run with::

    python -m pytest benchmarks/bench_stonesoup_trackers.py --benchmark-enable --benchmark-columns=min,median,mean,rounds

One group per sensor (``position``: Kalman; ``bearing-range``: EKF on both sides), the
scenario of ``benchmarks/stonesoup_trackers.py`` (seed 0, 100 scans, the detections recorded
once): a round runs a freshly built tracker over all 100 scans, so that the time per scan is
the round's time / 100 (``extra_info["ms_per_scan"]``). Three trackers: ``LMBTracker`` and
``GLMBTracker`` with births from the measurements (default associations), and the JPDA tracker
(``MultiTargetMixtureTracker``, ``JPDAwithEHM2``, ``MultiMeasurementInitiator``,
``CovarianceBasedDeleter``) in its best cell of that script's grid (``min_points=2``,
``covar_trace_thresh=100`` for both sensors). Every tracker warm: one untimed run first (our
kernels loaded or compiled, Stone Soup's caches filled). The file is not collected by the
default suite (its name does not start with ``test_``): the JPDA tracker takes seconds a
round. The numbers are in ``benchmarks/README.md``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

pytest.importorskip("stonesoup")

sys.path.insert(0, str(Path(__file__).resolve().parent))
import stonesoup_trackers as script  # noqa: E402

N_SCANS = 100
BEST = {"min_points": 2, "covar_trace_thresh": 100.0}


@pytest.fixture(scope="module", params=["position", "bearing-range"])
def data(request):
    return request.param, script.simulate(0, N_SCANS, request.param)


def _run(tracker) -> int:
    n = 0
    for _ in tracker:
        n += 1
    return n


@pytest.mark.parametrize("kind", ["LMB", "GLMB", "JPDA"])
def test_bench_tracker_per_scan(benchmark, data, kind):
    sensor, (scans, _, density, cv, mm) = data

    def make():
        if kind == "JPDA":
            return script.jpda_tracker(scans, density, cv, mm, **BEST)
        return script.our_tracker(kind, scans, density, cv, mm, 0)

    assert _run(make()) == N_SCANS     # warm-up, untimed
    benchmark.group = f"trackers, {sensor} sensor, {N_SCANS} scans (seed 0)"
    n = benchmark.pedantic(lambda: _run(make()), rounds=3, iterations=1)
    assert n == N_SCANS
    benchmark.extra_info["ms_per_scan"] = 1e3 * benchmark.stats.stats.min / N_SCANS
