"""Targets of the multi-sensor δ-GLMB filter on the ``"multi"`` scenario with the narrow
birth (where the exact sampler's update fits): fusion gain, short against long chains. The
estimate is Vo's (``extraction="map"``), as in the study's GLMB rows.

Fifteen 100-scan runs (seeds 0-2; each single sensor and the three fused with short chains,
the three fused with the long chain), about four minutes on two cores: behind the ``study``
marker with the LMB filter's targets (``python -m pytest -m study``).
"""

import numpy as np
import pytest

from rankedassign.metrics import ospa2
from rankedassign.tracking import (
    OriginalGibbs,
    ShortChainGibbs,
    run_multisensor_scenario,
)

pytestmark = pytest.mark.study

SEEDS = (0, 1, 2)
SETS = ((0,), (1,), (2,), (0, 1, 2))


def mean_ospa(run):
    return float(ospa2(run.truth, run.estimates, c=200, p=1, window=5).value.mean())


@pytest.fixture(scope="module")
def runs():
    """GLMB runs with the exact multi-sensor sampler: short chains on every sensor set, the long
    chain on the three sensors."""
    short = ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, method="exact")
    long = OriginalGibbs(10_000, method="exact")
    out = {}
    for seed in SEEDS:
        for sensors in SETS:
            out[seed, sensors, "short"] = run_multisensor_scenario(
                short, rng=seed, sensors=sensors, birth="narrow", filter="glmb",
                extraction="map")
        out[seed, (0, 1, 2), "long"] = run_multisensor_scenario(
            long, rng=seed, sensors=(0, 1, 2), birth="narrow", filter="glmb", extraction="map")
    return out


def _mean(runs, sensors, assoc):
    return np.mean([mean_ospa(runs[seed, sensors, assoc]) for seed in SEEDS])


def test_fusing_three_sensors_beats_the_best_single_sensor_by_20_percent(runs):
    # measured: 18.8 m fused against 39.7 m for the best single sensor (sensor 2), 53 % lower
    best_single = min(_mean(runs, s, "short") for s in SETS[:3])
    assert _mean(runs, (0, 1, 2), "short") <= 0.8 * best_single


@pytest.mark.xfail(strict=True, reason=(
    "measured shortfall on these three seeds, not shown to be ruled out by the model: with "
    "the MAP estimate the short chains trail the long chain by 5.2 % on seeds 0-2 (18.81 m "
    "against 17.88 m; per seed 16.25/16.27, 22.27/20.61, 17.90/16.77). Over seeds 0-9 "
    "(the runs of this fixture, rng = 0..9) the gap is 3.9 % (19.18 m against 18.46 m), "
    "within the target, "
    "and single seeds range from -10 % to +25 %; with the preset's hysteresis estimate the "
    "short chains are 4.7 % better on seeds 0-2 (23.5 m against 24.7 m)"))
def test_short_chains_are_within_5_percent_of_the_long_chain(runs):
    assert _mean(runs, (0, 1, 2), "short") <= 1.05 * _mean(runs, (0, 1, 2), "long")


@pytest.mark.xfail(strict=True, reason=(
    "the long chain of the GLMB filter spends only T_h - 1 sweeps per component (about H_upd "
    "per scan, not 10 000 per call as in the LMB filter), so stall/stale have little to cut: "
    "measured on seeds 0-2, three sensors, narrow birth, 100 scans: 62 452 against 72 048 "
    "sweeps per run, 13.3 % fewer (the LMB filter: 99.1 %)"))
def test_short_chains_use_90_percent_fewer_sweeps_than_the_long_chain(runs):
    short = sum(int(runs[s, (0, 1, 2), "short"].sweeps.sum()) for s in SEEDS)
    long = sum(int(runs[s, (0, 1, 2), "long"].sweeps.sum()) for s in SEEDS)
    assert short <= 0.1 * long
