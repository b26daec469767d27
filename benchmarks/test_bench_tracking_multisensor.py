"""Multi-sensor LMB (and δ-GLMB) filter speed: one 100-scan run of the ``"multi"`` scenario per sensor set
(``V = 1, 2, 3``) and association, with the static birth and with adaptive birth; the
multi-sensor δ-GLMB filter alone with short chains (``test_bench_multi_glmb``).

Run the timings with::

    python -m pytest benchmarks/test_bench_tracking_multisensor.py --benchmark-enable

In the default suite (benchmarks disabled) each case runs once on 2 scans as a smoke test, the
long chain with 1 000 sweeps per call instead of 10 000.
Speed is measured, not asserted; the numbers are in ``benchmarks/README.md``. ``extra_info``
holds the per-scan seconds of each phase and the run's sweeps, row updates and sampler calls.
"""

import numpy as np
import pytest

from rankedassign.tracking import (
    Exact,
    OriginalGibbs,
    ShortChainGibbs,
    run_multisensor_scenario,
)

SENSORS = {"V1": (0,), "V2": (0, 1), "V3": (0, 1, 2)}
METHODS = {
    "short-400x25": lambda smoke=False: ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, method="exact"),
    "short-400x25-mm": lambda smoke=False: ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, method="mm"),
    "short-400x25-mm-fixed": lambda smoke=False: ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, method="mm-fixed"),
    "long-10000": lambda smoke=False: OriginalGibbs(1_000 if smoke else 10_000, method="exact"),
}


def _run(benchmark, make, sensors, birth="paper", filter="lmb"):
    smoke = benchmark.disabled
    n_scans = 2 if smoke else 100
    run = benchmark.pedantic(
        lambda: run_multisensor_scenario(make(smoke), rng=0, n_scans=n_scans, sensors=sensors,
                                         birth=birth, filter=filter),
        rounds=1, iterations=1, warmup_rounds=0,
    )
    benchmark.extra_info.update(
        {f"per_scan_{k}_s": float(np.mean(v)) for k, v in run.timings.items()}
    )
    benchmark.extra_info.update(
        sweeps=int(run.sweeps.sum()), row_updates=int(run.row_updates.sum()),
        invocations=int(run.invocations.sum()), mean_meas_gated=float(run.n_meas_gated.mean()),
        mean_births=float(run.n_births.mean()), max_births=int(run.n_births.max()),
        mean_tracks=float(run.n_tracks.mean()),
    )


@pytest.mark.parametrize("sensors", sorted(SENSORS))
@pytest.mark.parametrize("method", sorted(METHODS))
def test_bench_multi_scenario(benchmark, method, sensors):
    _run(benchmark, METHODS[method], SENSORS[sensors])


@pytest.mark.parametrize("sensors", sorted(SENSORS))
def test_bench_multi_narrow_birth_exact(benchmark, sensors):
    # the exact DP needs the narrow birth (the paper's birth tracks gate every measurement)
    _run(benchmark, lambda smoke: Exact(), SENSORS[sensors], birth="narrow")


@pytest.mark.parametrize("sensors", sorted(SENSORS))
@pytest.mark.parametrize("method", sorted(METHODS))
def test_bench_multi_adaptive_birth(benchmark, method, sensors):
    # adaptive birth (AdaptiveBirth() defaults, spec §7.2): no static birth; extra_info holds
    # the per-scan seconds of the birth sampler ("per_scan_birth_s") and the births per scan
    _run(benchmark, METHODS[method], SENSORS[sensors], birth="adaptive")


@pytest.mark.parametrize("filter", ["lmb", "glmb"])
@pytest.mark.benchmark(group="multisensor-glmb-vs-lmb")
def test_bench_multi_glmb_against_lmb(benchmark, filter):
    # the δ-GLMB filter against the LMB filter on the same measurements: three sensors, MM
    # short chains, the narrow birth (target: GLMB at most 20x the LMB filter's time)
    _run(benchmark, METHODS["short-400x25-mm"], SENSORS["V3"], birth="narrow", filter=filter)


@pytest.mark.parametrize("method", ["short-400x25", "short-400x25-mm"])
@pytest.mark.benchmark(group="multisensor-glmb")
def test_bench_multi_glmb(benchmark, method):
    # the multi-sensor δ-GLMB filter alone, short chains with Alg. 1's row conditional
    # ("exact") and with MM, three sensors, the narrow birth: the rows compared before and
    # after its components' chains moved into one compiled call per scan (the MM row is the
    # "glmb" row of the group above, kept here so that the two methods are compared together)
    _run(benchmark, METHODS[method], SENSORS["V3"], birth="narrow", filter="glmb")
