"""The Stone Soup plug-in: ``JPDAwithDP`` against Stone Soup's ``JPDAwithEHM2``, end to end.

Run with::

    python -m pytest benchmarks/bench_stonesoup.py --benchmark-enable --benchmark-columns=min,median,mean,rounds

One group per size (tracks / detections: 7 / 11, 30 / 58, 60 / 120), both associators warm
(numba compiled, the scene built once), each call the whole ``associate``: the hypothesiser
(Stone Soup's ``PDAHypothesiser`` with a Kalman predictor and updater), the clustering, the
marginals and the output hypotheses. Tracks sit on a line 3 m apart with the detections
scattered along it, so that neighbouring tracks share detections: at 30 / 58 every track is
in one cluster (the target of issue #28: ``JPDAwithDP`` at least 5x faster than
``JPDAwithEHM2`` there). ``extra_info`` records the clusters and the largest one. The file is
not collected by the default suite (its name does not start with ``test_``): ``JPDAwithEHM2``
takes seconds at 60 / 120. The numbers are in ``benchmarks/README.md``.
"""

from __future__ import annotations

import datetime

import numpy as np
import pytest

pytest.importorskip("stonesoup")

from stonesoup.dataassociator.probability import JPDAwithEHM2  # noqa: E402
from stonesoup.hypothesiser.probability import PDAHypothesiser  # noqa: E402
from stonesoup.models.measurement.linear import LinearGaussian  # noqa: E402
from stonesoup.models.transition.linear import (  # noqa: E402
    CombinedLinearGaussianTransitionModel,
    ConstantVelocity,
)
from stonesoup.predictor.kalman import KalmanPredictor  # noqa: E402
from stonesoup.types.detection import Detection  # noqa: E402
from stonesoup.types.state import GaussianState  # noqa: E402
from stonesoup.types.track import Track  # noqa: E402
from stonesoup.updater.kalman import KalmanUpdater  # noqa: E402

from rankedassign.stonesoup import JPDAwithDP  # noqa: E402
from rankedassign.tracking import group_tracks  # noqa: E402

T0 = datetime.datetime(2025, 1, 1)
T1 = T0 + datetime.timedelta(seconds=1)
CV = CombinedLinearGaussianTransitionModel([ConstantVelocity(0.05)] * 2)
MM = LinearGaussian(ndim_state=4, mapping=(0, 2), noise_covar=np.eye(2))
SPACING = 3.0
SIZES = [(7, 11), (30, 58), (60, 120)]
ASSOCIATORS = {"JPDAwithDP": JPDAwithDP, "JPDAwithEHM2": JPDAwithEHM2}


def _hypothesiser():
    return PDAHypothesiser(KalmanPredictor(CV), KalmanUpdater(MM), clutter_spatial_density=1e-3,
                           prob_detect=0.9)


def _scene(n_tracks, n_dets, seed=5):
    rng = np.random.default_rng(seed)
    tracks = {Track([GaussianState([[i * SPACING], [0.0], [0.0], [0.0]], np.eye(4),
                                   timestamp=T0)]) for i in range(n_tracks)}
    dets = {Detection([[rng.uniform(-1.0, n_tracks * SPACING)], [rng.normal(0.0, 1.0)]],
                      timestamp=T1, measurement_model=MM) for _ in range(n_dets)}
    return tracks, dets


def _clusters(hyp, tracks, dets):
    col = {id(d): j for j, d in enumerate(dets)}
    gated = np.zeros((len(tracks), len(dets)), dtype=bool)
    for i, t in enumerate(tracks):
        for h in hyp.hypothesise(t, dets, T1):
            if h:
                gated[i, col[id(h.measurement)]] = True
    sizes = [(r.size, c.size) for r, c in group_tracks(gated) if c.size]
    return sizes


@pytest.fixture(scope="module")
def scenes():
    out = {size: _scene(*size) for size in SIZES}
    hyp = _hypothesiser()
    small = _scene(3, 4)
    JPDAwithDP(hyp).associate(*small, T1)  # compile the oracle's kernels
    return out


@pytest.mark.parametrize("size", SIZES, ids=lambda s: f"{s[0]}x{s[1]}")
@pytest.mark.parametrize("name", sorted(ASSOCIATORS))
def test_bench_jpda(benchmark, scenes, size, name):
    tracks, dets = scenes[size]
    hyp = _hypothesiser()
    assoc = ASSOCIATORS[name](hyp)
    benchmark.group = f"JPDA end to end, {size[0]} tracks / {size[1]} detections"
    clusters = _clusters(hyp, tracks, dets)
    benchmark.extra_info.update(n_clusters=len(clusters),
                                largest_cluster=max(clusters, key=lambda c: c[0]))
    rounds = 3 if name == "JPDAwithEHM2" and size[0] >= 60 else 5
    out = benchmark.pedantic(assoc.associate, args=(tracks, dets, T1), rounds=rounds,
                             warmup_rounds=1)
    assert set(out) == tracks
