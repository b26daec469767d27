"""Targets of the multi-sensor tracking study on the paper's wide birth: the fusion gain of
three sensors over the best single sensor, and what the wide birth rules out (the 95 % sweep
saving, the exact update).

Twelve runs of the multi-sensor filter over 100 scans (seeds 0-2, each sensor alone and all
three), about five minutes of one core on the 2-core machine, most of it in the three runs
with all three sensors (the exact row conditional over three sensors' gated measurements:
68 s each, measured 2026-12-07).
Behind the ``study`` marker, outside the default run: ``python -m pytest -m study``; CI runs
them as a tier of their own. The narrow-birth targets are in
``tests/test_tracking_multisensor_targets.py``, a module of their own so that the tier's two
workers (whole modules per worker) run the two side by side."""

import numpy as np
import pytest
from multisensor_targets import SHORT, mean_ospa

from rankedassign.tracking import Exact, ShortChainGibbs, run_multisensor_scenario

pytestmark = pytest.mark.study


@pytest.fixture(scope="module")
def paper_runs():
    """Short-chain runs on the 'multi' scenario, seeds 0-2: each single sensor and all three."""
    out = {}
    for seed in range(3):
        for sensors in [(0,), (1,), (2,), (0, 1, 2)]:
            out[seed, sensors] = run_multisensor_scenario(
                ShortChainGibbs(**SHORT), rng=seed, sensors=sensors)
    return out


def test_fusing_three_sensors_beats_the_best_single_sensor_by_20_percent(paper_runs):
    mean = {s: np.mean([mean_ospa(paper_runs[seed, s]) for seed in range(3)])
            for s in [(0,), (1,), (2,), (0, 1, 2)]}
    best_single = min(mean[(0,)], mean[(1,)], mean[(2,)])
    assert mean[(0, 1, 2)] <= 0.8 * best_single


@pytest.mark.xfail(strict=True,
                   reason="paper birth, V = 3, seed 0: 153 791 sweeps over about 100 calls "
                          "(one group per scan), a reduction of about 85 %, not 95 %")
def test_short_chains_use_95_percent_fewer_sweeps_on_the_paper_birth(paper_runs):
    # the long chain spends 10 000 sweeps on every sampler call; the short chains get the
    # same calls (one per group with measurements)
    for seed in range(3):
        run = paper_runs[seed, (0, 1, 2)]
        assert run.sweeps.sum() <= 0.05 * 10_000 * run.invocations.sum()


@pytest.mark.xfail(strict=True, raises=ValueError,
                   reason="the paper's birth tracks (sigma 300 m) gate every measurement of "
                          "every sensor: one group per scan with about 69 measurements over "
                          "V = 3 sensors, beyond the 22-bit exact DP")
def test_exact_update_on_the_paper_birth():
    run_multisensor_scenario(Exact(), rng=0, n_scans=3, sensors=(0, 1, 2))
