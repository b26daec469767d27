"""The Stone Soup plug-in (:mod:`rankedassign.stonesoup`) against Stone Soup's own classes.

No mocks: every hypothesiser, associator, metric generator, manager and simulator here is
Stone Soup's. The exact associator is held to ``JPDAwithEHM2`` (exact) on every marginal, to
``JPDA`` (enumeration of the joint hypotheses, no clusters) where that finishes quickly, and to
a brute-force enumeration of the whole scene as one problem.
"""

from __future__ import annotations

import datetime
import importlib
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("stonesoup")

from stonesoup.dataassociator.probability import JPDA, JPDAwithEHM2  # noqa: E402
from stonesoup.hypothesiser.distance import DistanceHypothesiser  # noqa: E402
from stonesoup.hypothesiser.probability import PDAHypothesiser  # noqa: E402
from stonesoup.measures import Mahalanobis  # noqa: E402
from stonesoup.metricgenerator.manager import MultiManager  # noqa: E402
from stonesoup.metricgenerator.ospametric import OSPAMetric  # noqa: E402
from stonesoup.models.measurement.linear import LinearGaussian  # noqa: E402
from stonesoup.models.measurement.nonlinear import (  # noqa: E402
    CartesianToBearingRange,
    CartesianToElevationBearing,
)
from stonesoup.models.transition.linear import (  # noqa: E402
    CombinedLinearGaussianTransitionModel,
    ConstantVelocity,
)
from stonesoup.models.transition.nonlinear import ConstantTurnSandwich  # noqa: E402
from stonesoup.predictor.kalman import (  # noqa: E402
    ExtendedKalmanPredictor,
    KalmanPredictor,
    UnscentedKalmanPredictor,
)
from stonesoup.types.detection import Detection  # noqa: E402
from stonesoup.types.groundtruth import GroundTruthPath, GroundTruthState  # noqa: E402
from stonesoup.types.numeric import Probability  # noqa: E402
from stonesoup.types.state import GaussianState, State, WeightedGaussianState  # noqa: E402
from stonesoup.types.track import Track  # noqa: E402
from stonesoup.updater.kalman import (  # noqa: E402
    ExtendedKalmanUpdater,
    KalmanUpdater,
    UnscentedKalmanUpdater,
)

import oracle  # noqa: E402
from rankedassign import AssignmentProblem  # noqa: E402
from rankedassign.metrics import ospa2  # noqa: E402
from rankedassign.stonesoup import (  # noqa: E402
    GLMBTracker,
    JPDAwithDP,
    JPDAwithGibbs,
    LMBTracker,
    OSPA2Metric,
    VectorisedPDAHypothesiser,
)
from rankedassign.stonesoup.hypothesisers import pda_pairs  # noqa: E402
from rankedassign.tracking import (  # noqa: E402
    Exact,
    LMBFilter,
    Murty,
    ShortChainGibbs,
)
from rankedassign.tracking.association import MultiSensorAssociation  # noqa: E402
from rankedassign.tracking.models import ConstantVelocity as OurCV  # noqa: E402
from rankedassign.tracking.models import LinearMotion, Model, make_model  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
T0 = datetime.datetime(2025, 1, 1)
T1 = T0 + datetime.timedelta(seconds=1)
CV = CombinedLinearGaussianTransitionModel([ConstantVelocity(0.05)] * 2)
MM = LinearGaussian(ndim_state=4, mapping=(0, 2), noise_covar=np.eye(2))
DENSITY = 1e-3


def _hypothesiser(prob_detect=0.9):
    return PDAHypothesiser(KalmanPredictor(CV), KalmanUpdater(MM),
                           clutter_spatial_density=DENSITY, prob_detect=prob_detect)


def scene(n_tracks, n_dets, seed, spacing=2.0, groups=1):
    """Tracks on ``groups`` lines (far apart), detections near them: one cluster per group."""
    rng = np.random.default_rng(seed)
    tracks, dets = set(), set()
    for i in range(n_tracks):
        g = i % groups
        x = (i // groups) * spacing
        tracks.add(Track([GaussianState([[x], [0.0], [1000.0 * g], [0.0]], np.eye(4),
                                        timestamp=T0)]))
    for j in range(n_dets):
        g = j % groups
        x = rng.uniform(-1.0, (n_tracks // groups) * spacing)
        dets.add(Detection([[x], [1000.0 * g + rng.normal(0, 1.0)]], timestamp=T1,
                           measurement_model=MM))
    return tracks, dets


def table(result):
    """``{(track, detection or None): probability}`` of an associator's output."""
    return {(track, hyp.measurement if hyp else None): float(hyp.probability)
            for track, multi in result.items() for hyp in multi}


def assert_same(a, b, atol=1e-10):
    ta, tb = table(a), table(b)
    assert set(ta) == set(tb)
    worst = max((abs(ta[k] - tb[k]) for k in ta), default=0.0)
    assert worst <= atol, worst


# ------------------------------------------------------------------------------ packaging
def test_the_plugin_loader_finds_it():
    """Stone Soup's loader (``stonesoup.plugins``) imports us as ``stonesoup.plugins.rankedassign``."""
    import rankedassign.stonesoup as ours

    plugins = importlib.import_module("stonesoup.plugins.rankedassign")
    assert plugins is ours
    from stonesoup.plugins.rankedassign import JPDAwithDP as Loaded

    assert Loaded is JPDAwithDP


def test_pyproject_declares_the_extra_and_the_entry_point():
    text = (ROOT / "pyproject.toml").read_text()
    assert '[project.entry-points."stonesoup.plugins"]\nrankedassign = "rankedassign.stonesoup"' \
        in text
    assert 'stonesoup = ["stonesoup>=1.9,<1.10"]' in text
    # the README's test command installs ".[test]": the plug-in's tests must not skip there
    test_extra = text[text.index("test = ["):text.index("plot = [")]
    assert '"stonesoup>=1.9,<1.10"' in test_extra


def test_rankedassign_does_not_import_stone_soup():
    text = (ROOT / "rankedassign" / "__init__.py").read_text()
    assert "stonesoup" not in text


# ------------------------------------------------------------------------------ JPDAwithDP
@pytest.mark.parametrize("n_tracks, n_dets, seed, groups, spacing", [
    (1, 1, 0, 1, 2.0), (2, 3, 1, 1, 2.0), (5, 8, 2, 1, 2.0), (7, 11, 3, 1, 2.0),
    (12, 20, 4, 2, 2.0), (30, 58, 5, 1, 3.0),
])
def test_dp_equals_ehm2_on_every_marginal(n_tracks, n_dets, seed, groups, spacing):
    tracks, dets = scene(n_tracks, n_dets, seed, spacing=spacing, groups=groups)
    hyp = _hypothesiser()
    ours = JPDAwithDP(hyp)
    assert_same(ours.associate(tracks, dets, T1), JPDAwithEHM2(hyp).associate(tracks, dets, T1))
    assert ours.vectorised  # the hypotheses came from the vectorised pass
    assert_same(JPDAwithDP(hyp, vectorise=False).associate(tracks, dets, T1),
                JPDAwithEHM2(hyp).associate(tracks, dets, T1))


@pytest.mark.parametrize("n_tracks, n_dets, seed", [(2, 3, 0), (4, 5, 1), (4, 6, 2)])
def test_dp_equals_jpda_where_it_finishes(n_tracks, n_dets, seed):
    tracks, dets = scene(n_tracks, n_dets, seed, spacing=1.0)
    hyp = _hypothesiser()
    ours = JPDAwithDP(hyp)
    assert_same(ours.associate(tracks, dets, T1), JPDA(hyp).associate(tracks, dets, T1))
    assert ours.vectorised


def test_clusters_equal_one_big_problem():
    """Three clusters solved apart = the whole scene enumerated as one problem (and = JPDA)."""
    tracks, dets = scene(6, 8, 7, spacing=1.0, groups=3)
    hyp = _hypothesiser()
    hypotheses = {t: hyp.hypothesise(t, dets, T1) for t in tracks}
    order = list(tracks)
    dlist = sorted(dets, key=lambda d: tuple(d.state_vector.ravel()))
    col = {id(d): j for j, d in enumerate(dlist)}
    L = np.full((len(order), len(dlist)), -np.inf)
    miss = np.empty(len(order))
    for i, t in enumerate(order):
        for h in hypotheses[t]:
            if h:
                L[i, col[id(h.measurement)]] = h.probability.log_value
            else:
                miss[i] = h.probability.log_value
    problem = AssignmentProblem.from_log_eta(L, miss, np.full(len(order), -np.inf))
    ranked = oracle.enumerate_assignments(problem)  # every joint hypothesis of the scene
    w = np.exp(-(ranked.costs - ranked.costs.min()))
    w /= w.sum()
    ours = JPDAwithDP(hyp).associate(tracks, dets, T1)
    for i, t in enumerate(order):
        for h in ours[t]:
            j = col[id(h.measurement)] if h else len(dlist) + i
            expected = w[(ranked.assignments[:, i] == j)].sum()
            assert abs(float(h.probability) - expected) <= 1e-10
    assert_same(ours, JPDA(hyp).associate(tracks, dets, T1))


def test_empty_detections_and_no_tracks_as_jpda():
    tracks, _ = scene(3, 0, 0)
    hyp = _hypothesiser()
    ours = JPDAwithDP(hyp).associate(tracks, set(), T1)
    assert_same(ours, JPDA(hyp).associate(tracks, set(), T1))
    assert all(float(m[0].probability) == 1.0 and len(m) == 1 for m in ours.values())
    assert JPDAwithDP(hyp).associate(set(), set(), T1) == {}


def test_output_is_a_normalised_multiple_hypothesis_in_the_hypothesisers_order():
    tracks, dets = scene(4, 6, 3)
    hyp = _hypothesiser()
    ours = JPDAwithDP(hyp).associate(tracks, dets, T1)
    for t, multi in ours.items():
        given = hyp.hypothesise(t, dets, T1)
        assert [bool(h) for h in multi] == [bool(h) for h in given]
        assert abs(sum(float(h.probability) for h in multi) - 1.0) < 1e-12


def _crowd(n):
    """``n`` tracks at one place and ``n`` detections on them: one dense cluster."""
    tracks = {Track([GaussianState([[0.01 * i], [0.0], [0.0], [0.0]], np.eye(4), timestamp=T0)])
              for i in range(n)}
    dets = {Detection([[0.01 * j], [0.02]], timestamp=T1, measurement_model=MM) for j in range(n)}
    return tracks, dets


def test_a_cluster_beyond_the_dp_names_its_size_and_the_sampler():
    tracks, dets = _crowd(22)
    with pytest.raises(ValueError, match=r"a cluster of 22 tracks sharing 22 detections is "
                                         r"beyond the exact DP .*use JPDAwithGibbs"):
        JPDAwithDP(_hypothesiser()).associate(tracks, dets, T1)


def test_the_fallback_is_used_and_recorded():
    big_tracks, big_dets = _crowd(22)
    small_tracks, small_dets = scene(2, 2, 0)  # a second cluster, moved far away
    far = {Track([GaussianState(t.state_vector + [[0], [0], [5000.0], [0]], t.covar,
                                timestamp=T0)]) for t in small_tracks}
    far_dets = {Detection(d.state_vector + [[0], [5000.0]], timestamp=T1, measurement_model=MM)
                for d in small_dets}
    assoc = JPDAwithDP(_hypothesiser(), seed=0,
                       fallback=ShortChainGibbs(50, 10, tau_stall=5, tau_stale=10,
                                                marginals="rao-blackwell"))
    out = assoc.associate(big_tracks | far, big_dets | far_dets, T1)
    assert assoc.fallback_tracks == big_tracks
    assert assoc.fallback_log == [(T1, frozenset(big_tracks))]
    for multi in out.values():
        assert abs(sum(float(h.probability) for h in multi) - 1.0) < 1e-12
    # the far cluster is exact all the same
    exact = JPDAwithEHM2(_hypothesiser()).associate(far, far_dets, T1)
    assert_same({t: out[t] for t in far}, exact)
    assoc.associate(far, far_dets, T1)
    assert assoc.fallback_tracks == set()


class _MultiSensorOnly(MultiSensorAssociation):
    def __call__(self, problem, rng):  # pragma: no cover (refused before it is called)
        raise AssertionError


@pytest.mark.parametrize("bad, match", [
    (object(), r"fallback must be one of our associations .*got object"),
    (_MultiSensorOnly(), r"fallback cannot use _MultiSensorOnly: it solves multi-sensor problems "
                         r"only"),
    (Murty(5), None),  # the same truncation classes serve every sensor count: Murty is fine
])
def test_a_fallback_that_is_not_ours(bad, match):
    if match is None:
        JPDAwithDP(_hypothesiser(), fallback=bad)
        return
    with pytest.raises(TypeError, match=match):
        JPDAwithDP(_hypothesiser(), fallback=bad)


def test_a_hypothesiser_that_is_not_probabilistic():
    tracks, dets = scene(2, 2, 0)
    hyp = DistanceHypothesiser(KalmanPredictor(CV), KalmanUpdater(MM), Mahalanobis(), 10.0)
    for cls in (JPDAwithDP, JPDAwithGibbs):
        with pytest.raises(TypeError, match=r"needs probabilistic hypotheses "
                                            r"\(SingleProbabilityHypothesis.*got "
                                            r"SingleDistanceHypothesis"):
            cls(hyp).associate(tracks, dets, T1)


# ------------------------------------------------------------------------------ JPDAwithGibbs
def test_gibbs_is_close_to_exact_and_reproducible():
    tracks, dets = scene(7, 11, 3)
    hyp = _hypothesiser()
    exact = JPDAwithEHM2(hyp).associate(tracks, dets, T1)
    a = JPDAwithGibbs(hyp, seed=1).associate(tracks, dets, T1)
    b = JPDAwithGibbs(hyp, seed=1).associate(tracks, dets, T1)
    assert table(a) == table(b)
    # deterministic given the seed. The marginals are approximate: the unique hypotheses the
    # chains find hold part of the mass of this dense scene (seven tracks competing for eleven
    # detections), and the Rao-Blackwellised marginals measured 0.024 from the exact ones at
    # worst (the truncated ones 0.06)
    assert_same(a, exact, atol=0.05)
    # with the exact association as "sampler", the marginals are the exact ones
    assert_same(JPDAwithGibbs(hyp, association=Exact()).associate(tracks, dets, T1), exact)


def test_gibbs_handles_a_cluster_beyond_the_dp():
    tracks, dets = _crowd(22)
    out = JPDAwithGibbs(_hypothesiser(), seed=0,
                        association=ShortChainGibbs(20, 10, marginals="rao-blackwell")
                        ).associate(tracks, dets, T1)
    assert set(out) == tracks


def test_gibbs_refuses_an_association_that_is_not_ours():
    with pytest.raises(TypeError, match=r"association must be one of our associations"):
        JPDAwithGibbs(_hypothesiser(), association="gibbs")


# ------------------------------------------------------------------------------ vectorised hypotheses
MM2 = LinearGaussian(ndim_state=4, mapping=(0, 2), noise_covar=np.diag([0.5, 2.0]))


def _parts(predictor=KalmanPredictor, updater=KalmanUpdater, **options):
    kw = dict(clutter_spatial_density=DENSITY, prob_detect=0.9)
    kw.update(options)
    return dict(predictor=predictor(CV), updater=updater(MM), **kw)


def random_scene(seed, n_tracks=6, n_dets=10, models=(MM,), det_times=(T1,), far=0):
    """Tracks with random means, covariances and last-update times; detections of ``models``
    (None: the updater's) at ``det_times``; ``far`` of them 10 km away (their likelihood
    underflows)."""
    rng = np.random.default_rng(seed)
    tracks = set()
    for _ in range(n_tracks):
        a = rng.normal(size=(4, 4))
        x = rng.uniform(-5.0, 5.0, size=(4, 1)) * np.array([[1.0], [0.2], [1.0], [0.2]])
        tracks.add(Track([GaussianState(x, 0.3 * a @ a.T + 0.5 * np.eye(4),
                                        timestamp=T0 - datetime.timedelta(
                                            seconds=int(rng.integers(0, 3))))]))
    dets = set()
    for j in range(n_dets):
        z = rng.uniform(-6.0, 6.0, size=(2, 1)) + (1e4 if j < far else 0.0)
        dets.add(Detection(z, timestamp=det_times[j % len(det_times)],
                           measurement_model=models[j % len(models)]))
    return tracks, dets


def _same_state(a, b):
    assert type(a) is type(b)
    assert a.timestamp == b.timestamp
    for x, y in ((a.state_vector, b.state_vector), (a.covar, b.covar)):  # angles as floats
        np.testing.assert_allclose(np.asarray(x, dtype=np.float64),
                                   np.asarray(y, dtype=np.float64), rtol=1e-12, atol=0)
    if hasattr(b, "cross_covar"):
        np.testing.assert_allclose(a.cross_covar, b.cross_covar, rtol=1e-12, atol=0)


def assert_same_hypotheses(ours, theirs):
    """Field by field: the container, then each hypothesis' type, measurement, prediction,
    measurement prediction and probability (its log to 1e-12, i.e. 1e-12 relative)."""
    assert type(ours) is type(theirs)
    assert (ours.normalise, ours.total_weight) == (theirs.normalise, theirs.total_weight)
    assert len(ours) == len(theirs)
    for a, b in zip(ours, theirs, strict=True):
        assert type(a) is type(b) and bool(a) == bool(b)
        if b:
            assert a.measurement is b.measurement
        else:
            assert type(a.measurement) is type(b.measurement)
            assert a.measurement.timestamp == b.measurement.timestamp
        _same_state(a.prediction, b.prediction)
        if b.measurement_prediction is None:
            assert a.measurement_prediction is None
        else:
            _same_state(a.measurement_prediction, b.measurement_prediction)
        assert type(a.probability) is type(b.probability)
        if isinstance(b.probability, Probability):
            la, lb = a.probability.log_value, b.probability.log_value
            assert la == lb or abs(la - lb) <= 1e-12, (la, lb)
        else:  # Stone Soup's normalisation leaves a plain 0.0 where a probability underflows
            assert a.probability == b.probability == 0.0


#: hypothesiser options and scenes; every option of PDAHypothesiser's weights is exercised
HYPOTHESISER_CASES = {
    "default": ({}, {}),
    "no clutter density": (dict(clutter_spatial_density=None, prob_gate=Probability(0.99)), {}),
    "include_all, underflow": (dict(include_all=True), dict(far=3)),
    "not normalised": (dict(normalise=False), {}),
    "Probability types": (dict(prob_detect=Probability(0.75), prob_gate=0.9), {}),
    "extended Kalman": (dict(predictor=ExtendedKalmanPredictor,
                             updater=ExtendedKalmanUpdater), {}),
    "unscented Kalman": (dict(predictor=UnscentedKalmanPredictor,
                              updater=UnscentedKalmanUpdater), {}),
    "models and times": (dict(clutter_spatial_density=None),
                         dict(models=(MM, MM2, None),
                              det_times=(T1, T1 + datetime.timedelta(seconds=0.5)))),
    "no detections": ({}, dict(n_dets=0)),
}


@pytest.mark.parametrize("seed", [0, 1])
@pytest.mark.parametrize("case", sorted(HYPOTHESISER_CASES))
def test_vectorised_hypotheses_equal_the_hypothesisers(case, seed):
    """Random scenes: VectorisedPDAHypothesiser and the all-tracks pass (pda_pairs) give
    PDAHypothesiser's hypotheses, field by field."""
    options, scene_kw = HYPOTHESISER_CASES[case]
    tracks, dets = random_scene(seed, **scene_kw)
    parts = _parts(**options)
    theirs = PDAHypothesiser(**parts)
    ours = VectorisedPDAHypothesiser(**parts)
    stamp = T1 + datetime.timedelta(seconds=0.25) if "times" in case else T1
    pairs = pda_pairs(theirs, tracks, dets, stamp)
    assert pairs is not None and pairs.tracks == list(tracks)
    for i, track in enumerate(pairs.tracks):
        expected = theirs.hypothesise(track, dets, stamp)
        assert_same_hypotheses(ours.hypothesise(track, dets, stamp), expected)
        assert_same_hypotheses(pairs.multiple_hypothesis(i), expected)
    if case == "include_all, underflow":
        assert any(h.probability == 0.0 and not isinstance(h.probability, Probability)
                   for track in tracks for h in theirs.hypothesise(track, dets, stamp))


@pytest.mark.parametrize("case", sorted(HYPOTHESISER_CASES))
def test_dp_with_vectorised_hypotheses_equals_the_hypothesiser_path_and_ehm2(case):
    options, scene_kw = HYPOTHESISER_CASES[case]
    tracks, dets = random_scene(3, **scene_kw)
    hyp = PDAHypothesiser(**_parts(**options))
    fast = JPDAwithDP(hyp)
    slow = JPDAwithDP(hyp, vectorise=False)
    a, b = fast.associate(tracks, dets, T1), slow.associate(tracks, dets, T1)
    assert fast.vectorised and not slow.vectorised
    assert_same(a, b, atol=1e-12)
    for track in tracks:  # the same objects in the same order, as the hypothesiser's
        for x, y in zip(a[track], b[track], strict=True):
            assert x.measurement is y.measurement or not (x or y)
            _same_state(x.prediction, y.prediction)
    assert_same(a, JPDAwithEHM2(hyp).associate(tracks, dets, T1))
    assert_same(JPDAwithGibbs(hyp, association=Exact()).associate(tracks, dets, T1), b)


def test_ehm2_with_the_vectorised_hypothesiser_is_ehm2():
    tracks, dets = scene(12, 20, 4, groups=2)
    parts = _parts()
    assert_same(JPDAwithEHM2(VectorisedPDAHypothesiser(**parts)).associate(tracks, dets, T1),
                JPDAwithEHM2(PDAHypothesiser(**parts)).associate(tracks, dets, T1),
                atol=1e-12)


class CountingPDAHypothesiser(PDAHypothesiser):
    """A subclass, which may change ``hypothesise``: the associators must call it."""

    def hypothesise(self, track, detections, timestamp, **kwargs):
        self.calls = getattr(self, "calls", 0) + 1
        return super().hypothesise(track, detections, timestamp, **kwargs)


class ShiftedPredictor(KalmanPredictor):
    """A Kalman predictor whose ``predict`` is its own (not Stone Soup's cached one)."""

    def predict(self, prior, timestamp=None, **kwargs):
        return super().predict(prior, timestamp=timestamp, **kwargs)


def test_what_the_vectorised_pass_leaves_to_the_hypothesiser():
    tracks, dets = scene(5, 8, 2)
    counting = CountingPDAHypothesiser(**_parts())
    assoc = JPDAwithDP(counting)
    out = assoc.associate(tracks, dets, T1)
    assert not assoc.vectorised and counting.calls == len(tracks)
    assert_same(out, JPDAwithEHM2(_hypothesiser()).associate(tracks, dets, T1))
    # a predictor of its own, a non-linear measurement model, a detection with an angle
    own = PDAHypothesiser(**_parts(predictor=ShiftedPredictor))
    bearing = CartesianToBearingRange(ndim_state=4, mapping=(0, 2), noise_covar=np.eye(2))
    polar = {Detection(bearing.function(t.state, noise=False), timestamp=T1,
                       measurement_model=bearing) for t in tracks}
    nonlinear = PDAHypothesiser(**_parts(updater=ExtendedKalmanUpdater))
    for hyp, d in ((own, dets), (nonlinear, polar)):
        assert pda_pairs(hyp, tracks, d, T1) is None
        ours = VectorisedPDAHypothesiser(hyp.predictor, hyp.updater, DENSITY, 0.9)
        for track in tracks:
            assert_same_hypotheses(ours.hypothesise(track, d, T1),
                                   hyp.hypothesise(track, d, T1))
        assoc = JPDAwithDP(hyp)
        assert_same(assoc.associate(tracks, d, T1), JPDAwithEHM2(hyp).associate(tracks, d, T1))
        assert not assoc.vectorised
    assert pda_pairs(DistanceHypothesiser(KalmanPredictor(CV), KalmanUpdater(MM), Mahalanobis(),
                                          10.0), tracks, dets, T1) is None


def test_vectorise_false_and_the_missed_detection_error_on_both_paths():
    tracks, dets = scene(3, 4, 0)
    for vectorise in (True, False):
        hyp = PDAHypothesiser(**_parts(prob_detect=1.0, prob_gate=1.0))
        with pytest.raises(ValueError, match=r"JPDAwithDP: track .* has a missed-detection "
                                             r"probability of 0; JPDA needs it positive"):
            JPDAwithDP(hyp, vectorise=vectorise).associate(tracks, dets, T1)


# ------------------------------------------------------------------------------ OSPA2Metric
def _paths(rng, n, n_scans, cls_path, cls_state, jitter):
    out = set()
    for _ in range(n):
        start = int(rng.integers(0, n_scans - 1))
        stop = int(rng.integers(start + 1, n_scans + 1))
        x0 = rng.uniform(0, 50, size=4)
        out.add(cls_path([cls_state((x0 + k + rng.normal(0, jitter, 4)).reshape(-1, 1),
                                    timestamp=T0 + datetime.timedelta(seconds=k))
                          for k in range(start, stop)]))
    return out


def _as_array(paths, n_scans, mapping):
    paths = list(paths)
    a = np.full((n_scans, len(paths), len(mapping)), np.nan)
    for n, path in enumerate(paths):
        for s in path:
            k = int((s.timestamp - T0).total_seconds())
            a[k, n] = np.asarray(s.state_vector).ravel()[list(mapping)]
    return a


@pytest.mark.parametrize("c, p, window, base", [(10.0, 1, 5, "euclidean"), (5.0, 2, 3, "lp"),
                                                (20.0, 1, 1, "euclidean")])
def test_ospa2_metric_equals_ospa2(c, p, window, base):
    rng = np.random.default_rng(0)
    truths = _paths(rng, 4, 12, GroundTruthPath, GroundTruthState, 0.0)
    tracks = _paths(rng, 5, 12, Track, State, 1.0)
    gen = OSPA2Metric(c=c, p=p, window=window, base=base, mapping=(0, 2))
    manager = MultiManager([gen])
    manager.add_data({"groundtruth_paths": truths, "tracks": tracks})
    metric = gen.compute_metric(manager)
    stamps = sorted({s.timestamp for path in truths | tracks for s in path})
    assert [m.timestamp for m in metric.value] == stamps
    k = [int((t - T0).total_seconds()) for t in stamps]
    expected = ospa2(_as_array(truths, 12, (0, 2)), _as_array(tracks, 12, (0, 2)), c=c, p=p,
                     window=window, base=base).value[k]
    np.testing.assert_allclose([m.value for m in metric.value], expected, rtol=0, atol=0)
    assert metric.title == "OSPA(2) distances" and metric.generator is gen


def test_ospa2_beside_ospa_in_a_multimanager_and_metricplotter(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from stonesoup.measures import Euclidean
    from stonesoup.plotter import MetricPlotter

    rng = np.random.default_rng(1)
    truths = _paths(rng, 3, 8, GroundTruthPath, GroundTruthState, 0.0)
    tracks = _paths(rng, 3, 8, Track, State, 1.0)
    ospa = OSPAMetric(c=10, p=1, measure=Euclidean(mapping=(0, 2)))
    ospa2_gen = OSPA2Metric(c=10, p=1, window=1, mapping=(0, 2))
    manager = MultiManager([ospa, ospa2_gen])
    manager.add_data({"groundtruth_paths": truths, "tracks": tracks})
    metrics = manager.generate_metrics()
    a = metrics["ospa_generator"]["OSPA distances"].value
    b = metrics["ospa2_generator"]["OSPA(2) distances"].value
    # window 1: OSPA(2) is the OSPA of each scan's states
    np.testing.assert_allclose([float(m.value) for m in b], [float(m.value) for m in a],
                               rtol=1e-12)
    plotter = MetricPlotter()
    plotter.plot_metrics(metrics, combine_plots=True)
    plotter.fig.savefig(tmp_path / "metrics.png")
    assert (tmp_path / "metrics.png").stat().st_size > 0


def test_ospa2_metric_bad_input():
    gen = OSPA2Metric(c=10.0, p=1, window=2)
    manager = MultiManager([gen])
    manager.add_data({"groundtruth_paths": set(), "tracks": set()})
    with pytest.raises(ValueError, match=r"neither the tracks nor the truths have a state"):
        gen.compute_metric(manager)
    manager.add_data({"groundtruth_paths": {1}, "tracks": set()})
    with pytest.raises(TypeError, match=r"the truths must hold tracks or states, got int"):
        gen.compute_metric(manager)
    bad = OSPA2Metric(c=-1.0, p=1, window=2)
    manager.add_data({"groundtruth_paths": {GroundTruthPath([GroundTruthState(
        [[0.0]], timestamp=T0)])}, "tracks": set()})
    with pytest.raises(ValueError, match=r"c"):
        bad.compute_metric(manager)


# ------------------------------------------------------------------------------ trackers
def _line_scans(n=6, model=MM):
    """One target moving along x at 1 m/s, one detection per scan, no clutter."""
    return [(T0 + datetime.timedelta(seconds=k),
             {Detection([[1.0 * k], [0.0]], timestamp=T0 + datetime.timedelta(seconds=k),
                        measurement_model=model)}) for k in range(n)]


BIRTH = [WeightedGaussianState([[0], [0], [0], [0]], np.diag([4.0, 4, 4, 4]), weight=0.1)]
KW = dict(prob_detection=0.9, clutter_rate=1.0, clutter_spatial_density=1e-4,
          birth_components=BIRTH)


def test_lmb_tracker_is_our_filter_on_stone_soup_models():
    scans = _line_scans()
    tracker = LMBTracker(scans, CV, MM, association=Exact(), seed=0, **KW)
    reported = [(time, tracks) for time, tracks in tracker]
    assert [t for t, _ in reported] == [t for t, _ in scans]
    (track,) = reported[-1][1]
    assert track.id == "1:1" and len(track) == len(scans)
    assert track.metadata["label"] == (1, 1) and 0.99 < track.metadata["existence"] <= 1
    assert isinstance(track.state, GaussianState)
    # the same filter run by hand on the same measurements, with Stone Soup's F and Q
    model = tracker.filter.model
    f = LMBFilter(Model(LinearMotion(np.eye(4), np.zeros((4, 4))), model.sensor,
                        model.clutter, model.birth, model.survival),
                  Exact(), grouping=True, extraction="map")
    dt = datetime.timedelta(seconds=1)
    for k, (_, dets) in enumerate(scans):
        if k == 1:
            f.set_motion(LinearMotion(CV.matrix(time_interval=dt), CV.covar(time_interval=dt)))
        rec = f.step([d.state_vector.ravel() for d in dets], rng=k)
    np.testing.assert_allclose(track.state_vector.ravel(), rec.states[0], rtol=1e-12)
    assert tracker.tracks == reported[-1][1]


def test_lmb_tracker_with_clutter_and_a_stone_soup_simulator():
    from stonesoup.simulator.simple import (
        MultiTargetGroundTruthSimulator,
        SimpleDetectionSimulator,
    )

    truth = MultiTargetGroundTruthSimulator(
        CV, GaussianState([[0], [1], [0], [1]], np.diag([25.0, 1, 25, 1]), timestamp=T0),
        timestep=datetime.timedelta(seconds=1), number_steps=8, birth_rate=0.2,
        death_probability=0.02, initial_number_targets=2, seed=1)
    sim = SimpleDetectionSimulator(truth, MM, meas_range=np.array([[-100, 100], [-100, 100]]),
                                   detection_probability=0.9, clutter_rate=3.0, seed=2)
    scans = [(t, set(d)) for t, d in sim]
    birth = [WeightedGaussianState([[0], [1], [0], [1]], np.diag([25.0, 1, 25, 1]), weight=0.1)]
    tracker = LMBTracker(scans, CV, MM, prob_detection=0.9, clutter_rate=3.0,
                         clutter_spatial_density=sim.clutter_spatial_density,
                         birth_components=birth, seed=0,
                         association=ShortChainGibbs(50, 10, tau_stall=5, tau_stale=10,
                                                     marginals="rao-blackwell"))
    seen = set()
    for _, tracks in tracker:
        seen |= tracks
    assert seen and all(t.id.count(":") == 1 for t in seen)
    assert tracker.filter.model.clutter.intensity == pytest.approx(sim.clutter_spatial_density,
                                                                   rel=1e-12)


def test_glmb_tracker():
    tracker = GLMBTracker(_line_scans(), CV, MM, association=Murty(50), seed=0, **KW)
    for _, tracks in tracker:  # noqa: B007 (the last scan's tracks)
        pass
    (track,) = tracks
    assert track.id == "1:1" and len(track) == 6


def test_tracker_update_by_hand_and_time_steps():
    tracker = LMBTracker(None, CV, MM, association=Exact(), **KW)
    scans = _line_scans(4)
    for time, dets in scans[:2]:
        tracker.update_tracker(time, dets)
    with pytest.raises(ValueError, match=r"scan time .* is before the previous scan"):
        tracker.update_tracker(T0, set())
    with pytest.raises(AttributeError, match=r"has no detector"):
        iter(LMBTracker(None, CV, MM, association=Exact(), **KW))


@pytest.mark.parametrize("kwargs, error, match", [
    ({"transition_model": ConstantTurnSandwich([0.1, 0.1], 0.1, [ConstantVelocity(0.1)])},
     TypeError, r"LMBTracker supports linear-Gaussian transition models and ConstantTurn: the "
     r"transition model ConstantTurnSandwich is neither"),
    ({"measurement_model": CartesianToElevationBearing(4, (0, 2, 3), np.eye(2))}, TypeError,
     r"LMBTracker: the measurement model CartesianToElevationBearing has no counterpart in "
     r"rankedassign.tracking.nonlinear \(LinearGaussian, CartesianToBearingRange, "
     r"CartesianToElevationBearingRange and Cartesian2DToBearing have\): it needs array "
     r"forms of its function h, its Jacobian and its inverse"),
    ({"measurement_model": LinearGaussian(ndim_state=4, mapping=(0, 1), noise_covar=np.eye(2))},
     ValueError, r"mapping must name the two position components of a 4-D state, each moved "
     r"by its own velocity component in the transition model \(e.g. mapping \(0, 2\) of "
     r"\[x, vx, y, vy\]\); got mapping \(0, 1\), and the transition model moves position "
     r"component 0 by components \(1,\)"),
    ({"birth_components": [GaussianState([[0], [0], [0], [0]], np.eye(4))]}, ValueError,
     r"birth component 0 has no weight, and its weight is the existence probability r_B"),
    ({"birth_components": [WeightedGaussianState([[0], [0], [0], [0]], np.eye(4))]},
     ValueError, r"birth component 0 has weight 0.0, and its weight is the existence"),
    ({"birth_components": [State([[0], [0], [0], [0]])]}, TypeError,
     r"birth component 0 must be a WeightedGaussianState, got State"),
    ({"clutter_spatial_density": 0.0}, ValueError,
     r"clutter_spatial_density must be a positive finite number"),
])
def test_tracker_bad_models(kwargs, error, match):
    args = {"detector": None, "transition_model": CV, "measurement_model": MM,
            "association": Exact(), **KW, **kwargs}
    with pytest.raises(error, match=match):
        LMBTracker(**args)


def test_tracker_bad_detections():
    tracker = LMBTracker(None, CV, MM, association=Exact(), **KW)
    other = LinearGaussian(ndim_state=4, mapping=(0, 2), noise_covar=4 * np.eye(2))
    with pytest.raises(ValueError, match=r"has measurement model LinearGaussian \(mapping "
                                         r"\(0, 2\)\), not the tracker's measurement_model"):
        tracker.update_tracker(T0, {Detection([[0.0], [0.0]], timestamp=T0,
                                              measurement_model=other)})
    with pytest.raises(ValueError, match=r"has 3 dimensions, the measurement model gives 2"):
        tracker.update_tracker(T0, {Detection([[0.0], [0.0], [1.0]], timestamp=T0)})
    # an equal model (not the same object) and no model at all are the tracker's
    same = LinearGaussian(ndim_state=4, mapping=(0, 2), noise_covar=np.eye(2))
    tracker.update_tracker(T0, {Detection([[0.0], [0.0]], timestamp=T0, measurement_model=same),
                                Detection([[5.0], [0.0]], timestamp=T0)})


# ------------------------------------------------------------------------------ LinearMotion
def test_linear_motion_and_set_motion():
    cv = OurCV()
    assert make_model("paper").motion == cv
    m = Model(LinearMotion(cv.F, cv.Q))
    f = LMBFilter(m, Exact())
    g = LMBFilter(make_model("paper"), Exact())
    for k in range(3):
        a, b = f.step([[0.0, 0.0]], rng=k), g.step([[0.0, 0.0]], rng=k)
    np.testing.assert_array_equal(a.states, b.states)
    with pytest.raises(TypeError, match=r"motion must be a ConstantVelocity or LinearMotion"):
        f.set_motion("cv")
    with pytest.raises(ValueError, match=r"F must be a finite 4x4 matrix, got shape \(3, 3\)"):
        LinearMotion(np.eye(3), np.zeros((4, 4)))
    with pytest.raises(ValueError, match=r"Q must be a symmetric positive semi-definite 4x4"):
        LinearMotion(np.eye(4), -np.eye(4))
    with pytest.raises(TypeError, match=r"F must hold real numbers"):
        LinearMotion([["a"] * 4] * 4, np.zeros((4, 4)))


# ------------------------------------------------------------------------------ end to end
def _simulated_scans(n_steps=10):
    from stonesoup.simulator.simple import (
        MultiTargetGroundTruthSimulator,
        SimpleDetectionSimulator,
    )

    cv = CombinedLinearGaussianTransitionModel([ConstantVelocity(0.05)] * 2, seed=3)
    mm = LinearGaussian(ndim_state=4, mapping=(0, 2), noise_covar=np.eye(2), seed=4)
    truth = MultiTargetGroundTruthSimulator(
        cv, GaussianState([[0], [0], [0], [0]], np.diag([100.0, 1, 100, 1]), timestamp=T0),
        timestep=datetime.timedelta(seconds=1), number_steps=n_steps, birth_rate=0.2,
        death_probability=0.02, initial_number_targets=4, seed=1)
    sim = SimpleDetectionSimulator(truth, mm, meas_range=np.array([[-50, 50], [-50, 50]]),
                                   detection_probability=0.9, clutter_rate=3.0, seed=2)
    return [(t, set(d)) for t, d in sim], sim.clutter_spatial_density


def test_jpda_with_dp_in_stone_soups_tracker_tracks_as_ehm2():
    """A drop-in replacement: Stone Soup's JPDA tracker gives the same tracks with either."""
    from stonesoup.dataassociator.neighbour import GNNWith2DAssignment
    from stonesoup.deleter.error import CovarianceBasedDeleter
    from stonesoup.initiator.simple import MultiMeasurementInitiator
    from stonesoup.tracker.simple import MultiTargetMixtureTracker

    scans, density = _simulated_scans()
    predictor, updater = KalmanPredictor(CV), KalmanUpdater(MM)

    def run(associator_cls):
        deleter = CovarianceBasedDeleter(covar_trace_thresh=20.0)
        initiator = MultiMeasurementInitiator(
            prior_state=GaussianState([[0], [0], [0], [0]], np.diag([0.0, 1, 0, 1])),
            measurement_model=MM, deleter=deleter, updater=updater, min_points=2,
            data_associator=GNNWith2DAssignment(
                DistanceHypothesiser(predictor, updater, Mahalanobis(), missed_distance=3)))
        tracker = MultiTargetMixtureTracker(
            initiator=initiator, deleter=deleter, detector=scans, updater=updater,
            data_associator=associator_cls(PDAHypothesiser(
                predictor, updater, clutter_spatial_density=density, prob_detect=0.9)))
        out = []
        for _, tracks in tracker:
            out.append(sorted(tuple(np.round(t.state_vector.ravel(), 6)) for t in tracks))
        return out

    ours, theirs = run(JPDAwithDP), run(JPDAwithEHM2)
    assert sum(map(len, ours)) > 0
    assert ours == theirs


def test_lmb_tracker_seed_and_intervals():
    scans, density = _simulated_scans(8)
    kw = dict(prob_detection=0.9, clutter_rate=3.0, clutter_spatial_density=density,
              birth_components=[WeightedGaussianState([[0], [0], [0], [0]],
                                                      np.diag([100.0, 1, 100, 1]), weight=0.1)],
              association=ShortChainGibbs(50, 10, tau_stall=5, tau_stale=10))

    def states(seed):
        out = []
        for _, tracks in LMBTracker(scans, CV, MM, seed=seed, **kw):
            out.append(sorted((t.id, tuple(t.state_vector.ravel())) for t in tracks))
        return out

    assert states(7) == states(7)
    # a scan 2 s after the previous one is predicted with F and Q of 2 s
    tracker = LMBTracker(None, CV, MM, **kw)
    tracker.update_tracker(T0, set())
    tracker.update_tracker(T0 + datetime.timedelta(seconds=2), set())
    two = datetime.timedelta(seconds=2)
    np.testing.assert_array_equal(tracker.filter.model.motion.F, CV.matrix(time_interval=two))
    np.testing.assert_array_equal(tracker.filter.model.motion.Q, CV.covar(time_interval=two))


# ------------------------------------------------------------------------------ hostile input
@pytest.mark.parametrize("cls", [LMBTracker, GLMBTracker])
@pytest.mark.parametrize("time, detections, error, match", [
    (T0, None, TypeError, r"{who}: detections must be a set \(or list\) of Detection, got "
                          r"NoneType; an empty scan is set\(\)"),
    (T0, np.zeros((2, 2)), TypeError, r"{who}: detections must be a set \(or list\) of "
                                      r"Detection, got ndarray"),
    (T0, "ab", TypeError, r"detections must be a set \(or list\) of Detection, got str"),
    (T0, 3, TypeError, r"detections must be a set \(or list\) of Detection, got int"),
    (T0, [(1.0, 2.0)], TypeError, r"{who}: detections must hold Detection objects \(with a "
                                  r"state_vector and a measurement_model\), got tuple "
                                  r"\(1.0, 2.0\) in a scan at 2025-01-01 00:00:00"),
    (T0, [State([[0.0], [0.0]], timestamp=T0)], TypeError,
     r"detections must hold Detection objects .* got State"),
    (None, set(), TypeError, r"{who}: time must be a datetime.datetime, got NoneType None"),
    (3, set(), TypeError, r"{who}: time must be a datetime.datetime, got int 3"),
    (1.5, set(), TypeError, r"time must be a datetime.datetime, got float 1.5"),
    (T0, {Detection(np.array([[1 + 1j], [0.0]]), timestamp=T0, measurement_model=MM)},
     TypeError, r"{who}: the state_vector of a detection at 2025-01-01 00:00:00 must be real, "
                r"got dtype complex128"),
])
def test_tracker_refuses_scans_it_cannot_read(cls, time, detections, error, match):
    tracker = cls(None, CV, MM, association=Murty(5) if cls is GLMBTracker else Exact(), **KW)
    with pytest.raises(error, match=match.format(who=cls.__name__)):
        tracker.update_tracker(time, detections)
    assert tracker.filter.k == 0  # nothing ran
    # the accepted forms: a set, a list, a tuple, a frozenset of Detection; an empty set
    det = Detection([[0.0], [0.0]], timestamp=T0, measurement_model=MM)
    for k, dets in enumerate((set(), [det], (det,), frozenset({det}))):
        tracker.update_tracker(T0 + datetime.timedelta(seconds=k), dets)


@pytest.mark.parametrize("seed, error", [("x", TypeError), (1.5, TypeError), (-1, ValueError),
                                         ([1, -2], ValueError)])
def test_tracker_seed_is_named(seed, error):
    with pytest.raises(error, match=r"LMBTracker: seed must be None, a non-negative int or "
                                    r"anything numpy.random.default_rng accepts, got "):
        LMBTracker(None, CV, MM, association=Exact(), seed=seed, **KW)
    with pytest.raises(error, match=r"GLMBTracker: seed must be None"):
        GLMBTracker(None, CV, MM, association=Murty(5), seed=seed, **KW)


@pytest.mark.parametrize("mapping, error, match", [
    ((), ValueError, r"OSPA2Metric: mapping is empty, so every distance would be 0; give the "
                     r"dimensions to compare, e.g. \(0, 2\), or None for all"),
    ([], ValueError, r"mapping is empty"),
    ((-1,), ValueError, r"OSPA2Metric: mapping must hold non-negative state dimensions, got -1"),
    ((0, -2), ValueError, r"non-negative state dimensions, got -2"),
    ((0.0,), TypeError, r"OSPA2Metric: mapping must hold state dimensions \(ints\), got float "
                        r"0.0"),
    ((True,), TypeError, r"mapping must hold state dimensions \(ints\), got bool True"),
    (3, TypeError, r"OSPA2Metric: mapping must be None or a sequence of state dimensions "
                   r"\(ints\), got int 3"),
    ("02", TypeError, r"mapping must be None or a sequence of state dimensions"),
    ((0, 0), ValueError, r"OSPA2Metric: mapping repeats a dimension: \(0, 0\)"),
])
def test_ospa2_metric_checks_mapping_at_construction(mapping, error, match):
    with pytest.raises(error, match=match):
        OSPA2Metric(c=10.0, p=1, window=2, mapping=mapping)


def _one_truth_one_track(truth_stamps=(0, 1, 2), track_stamps=(1, 2)):
    """A truth and a track 3 m off; an int stamp is seconds after T0, anything else is used."""
    def stamp(s):
        return T0 + datetime.timedelta(seconds=s) if type(s) is int else s

    truth = GroundTruthPath([GroundTruthState([[float(k)], [0.0]], timestamp=stamp(s))
                             for k, s in enumerate(truth_stamps)])
    track = Track([State([[1.0], [3.0]], timestamp=stamp(s)) for s in track_stamps])
    return {"groundtruth_paths": {truth}, "tracks": {track}}


def test_ospa2_metric_checks_mapping_against_the_states_and_names_timestamps():
    def compute(gen, data):
        manager = MultiManager([gen])
        manager.add_data(data)
        return [round(float(m.value), 6) for m in gen.compute_metric(manager).value]

    data = _one_truth_one_track()
    assert compute(OSPA2Metric(c=10.0, p=1, window=2, mapping=[0, 1]), data) == \
        compute(OSPA2Metric(c=10.0, p=1, window=2), data)
    assert OSPA2Metric(c=10.0, p=1, window=2, mapping=np.array([1])).mapping == (1,)
    # mapping=() gave 0.0 at every time; (5,) an IndexError
    with pytest.raises(ValueError, match=r"OSPA2Metric: mapping \(5,\) names dimension 5, and "
                                         r"the truths have states of 2 dimensions"):
        compute(OSPA2Metric(c=10.0, p=1, window=2, mapping=(5,)), data)
    with pytest.raises(ValueError, match=r"mapping \(0, 2\) names dimension 2"):
        compute(OSPA2Metric(c=10.0, p=1, window=2, mapping=(0, 2)), data)
    # states without timestamps: a TypeError from sorting that did not name them
    with pytest.raises(TypeError, match=r"OSPA2Metric: a state of the tracks has no timestamp "
                                        r"\(None\); OSPA\(2\) orders the scans by the states' "
                                        r"timestamps"):
        compute(OSPA2Metric(c=10.0, p=1, window=2), _one_truth_one_track(track_stamps=(None,)))
    with pytest.raises(TypeError, match=r"a state of the truths has no timestamp"):
        compute(OSPA2Metric(c=10.0, p=1, window=2),
                _one_truth_one_track(truth_stamps=(0, None), track_stamps=(1,)))
    with pytest.raises(TypeError, match=r"OSPA2Metric: the states' timestamps cannot be "
                                        r"ordered, they mix datetime, float; give every state a "
                                        r"datetime timestamp"):
        compute(OSPA2Metric(c=10.0, p=1, window=2),
                _one_truth_one_track(truth_stamps=(0,), track_stamps=(2.5,)))
