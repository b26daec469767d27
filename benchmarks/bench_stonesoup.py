"""The Stone Soup plug-in: ``JPDAwithDP`` against Stone Soup's ``JPDAwithEHM2``, end to end.

Run with::

    python -m pytest benchmarks/bench_stonesoup.py --benchmark-enable --benchmark-columns=min,median,mean,rounds

One group per scene (tracks / detections: 7 / 11, 30 / 58, 60 / 120, and 30 / 58 with the
tracks closer together) and mode, every associator warm (numba compiled, the scene built once,
one warm-up round), in two modes:

* ``end-to-end``: the whole ``associate`` with Stone Soup's ``PDAHypothesiser`` (a Kalman
  predictor and updater), then the clustering, the marginals and the output hypotheses. Four
  associators: ``JPDAwithDP`` as a user gets it (the hypotheses from the vectorised pass),
  ``JPDAwithDP-hypothesiser`` (``vectorise=False``: the hypothesiser called track by track,
  as ``JPDAwithEHM2`` calls it), ``JPDAwithEHM2``, and ``JPDAwithEHM2-vectorised`` (Stone
  Soup's EHM2 with our ``VectorisedPDAHypothesiser``, the same hypotheses faster: the
  comparison of the two associations with fast hypotheses on both sides). The last is left
  out of the dense scene, where EHM2's own minute dominates either way.
* ``association``: the hypotheses computed once beforehand (a hypothesiser that hands them
  back, which is not a ``PDAHypothesiser``, so no vectorised pass), so that only what the two
  associations do differently is timed.

Tracks sit on a line 3 m apart (2 m in the ``dense`` scene) with the detections scattered
along it, so that neighbouring tracks share detections: at 30 / 58 every track is in one
cluster (the target of issue #28: ``JPDAwithDP`` at least 5x faster than ``JPDAwithEHM2``
there, end to end). ``extra_info`` records the clusters, the largest one and whether the
vectorised pass ran. The file is not collected by the default suite (its name does not start
with ``test_``): ``JPDAwithEHM2`` takes seconds on the larger scenes. The numbers are in
``benchmarks/README.md``.
"""

from __future__ import annotations

import datetime

import numpy as np
import pytest

pytest.importorskip("stonesoup")

from stonesoup.base import Property  # noqa: E402
from stonesoup.dataassociator.probability import JPDAwithEHM2  # noqa: E402
from stonesoup.hypothesiser.base import Hypothesiser  # noqa: E402
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

from rankedassign.stonesoup import JPDAwithDP, VectorisedPDAHypothesiser  # noqa: E402
from rankedassign.tracking import group_tracks  # noqa: E402

T0 = datetime.datetime(2025, 1, 1)
T1 = T0 + datetime.timedelta(seconds=1)
CV = CombinedLinearGaussianTransitionModel([ConstantVelocity(0.05)] * 2)
MM = LinearGaussian(ndim_state=4, mapping=(0, 2), noise_covar=np.eye(2))
#: name -> (tracks, detections, spacing of the tracks in m)
SCENES = {"7x11": (7, 11, 3.0), "30x58": (30, 58, 3.0), "60x120": (60, 120, 3.0),
          "30x58-dense": (30, 58, 2.0)}
#: name -> associator made from a PDAHypothesiser
ASSOCIATORS = {
    "JPDAwithDP": JPDAwithDP,
    "JPDAwithDP-hypothesiser": lambda hyp: JPDAwithDP(hyp, vectorise=False),
    "JPDAwithEHM2": JPDAwithEHM2,
    "JPDAwithEHM2-vectorised": lambda hyp: JPDAwithEHM2(VectorisedPDAHypothesiser(
        hyp.predictor, hyp.updater, clutter_spatial_density=hyp.clutter_spatial_density,
        prob_detect=hyp.prob_detect)),
}
CASES = [(name, scene, "end-to-end") for scene in sorted(SCENES) for name in ASSOCIATORS
         if not (name == "JPDAwithEHM2-vectorised" and SCENES[scene][2] < 3)]
CASES += [(name, scene, "association") for scene in sorted(SCENES)
          for name in ("JPDAwithDP", "JPDAwithEHM2")]


def _hypothesiser():
    return PDAHypothesiser(KalmanPredictor(CV), KalmanUpdater(MM), clutter_spatial_density=1e-3,
                           prob_detect=0.9)


class _Given(Hypothesiser):
    """Hands back hypotheses computed beforehand (the ``association`` mode)."""

    table: dict = Property(doc="Track -> its MultipleHypothesis.")

    def hypothesise(self, track, detections, timestamp, **kwargs):
        return self.table[track]


def _scene(n_tracks, n_dets, spacing, seed=5):
    rng = np.random.default_rng(seed)
    tracks = {Track([GaussianState([[i * spacing], [0.0], [0.0], [0.0]], np.eye(4),
                                   timestamp=T0)]) for i in range(n_tracks)}
    dets = {Detection([[rng.uniform(-1.0, n_tracks * spacing)], [rng.normal(0.0, 1.0)]],
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
    out = {name: _scene(*spec) for name, spec in SCENES.items()}
    small = _scene(3, 4, 3.0)
    JPDAwithDP(_hypothesiser()).associate(*small, T1)  # compile the oracle's kernels
    return out


@pytest.mark.parametrize("name, scene, mode", CASES)
def test_bench_jpda(benchmark, scenes, name, scene, mode):
    tracks, dets = scenes[scene]
    hyp = _hypothesiser()
    n_tracks, n_dets, spacing = SCENES[scene]
    benchmark.group = (f"JPDA, {n_tracks} tracks / {n_dets} detections, {spacing:g} m apart, "
                       f"{mode}")
    clusters = _clusters(hyp, tracks, dets)
    if mode == "association":
        hyp = _Given({t: hyp.hypothesise(t, dets, T1) for t in tracks})
    assoc = ASSOCIATORS[name](hyp)
    benchmark.extra_info.update(n_clusters=len(clusters),
                                largest_cluster=max(clusters, key=lambda c: c[0]))
    slow = name.startswith("JPDAwithEHM2") and (n_tracks >= 60 or spacing < 3)
    out = benchmark.pedantic(assoc.associate, args=(tracks, dets, T1), rounds=3 if slow else 5,
                             warmup_rounds=1)
    benchmark.extra_info["vectorised"] = getattr(assoc, "vectorised", False)
    assert set(out) == tracks
    assert benchmark.extra_info["vectorised"] == (name == "JPDAwithDP" and mode == "end-to-end")
