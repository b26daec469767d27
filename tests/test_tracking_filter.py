"""Tests of the LMB filter: prediction, Kalman update, cost matrix, grouping, housekeeping.

The association here is an exhaustive enumeration over the (tiny) problems of these tests, so
the filter is checked on its own against closed forms.
"""

import itertools
import math
import re

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from rankedassign import AssignmentProblem
from rankedassign.engine.rng import base_key
from rankedassign.metrics import ospa
from rankedassign.tracking import (
    PRESET_EXTRACTION,
    Association,
    AssociationResult,
    BirthComponent,
    Exact,
    LMBBirth,
    LMBFilter,
    Model,
    PoissonClutter,
    PositionSensor,
    ShortChainGibbs,
    gate_threshold,
    group_tracks,
    make_model,
    map_cardinality,
    marginals_from_hypotheses,
    paper_truth,
    run_scenario,
)
from rankedassign.tracking._kernels import MERGE_RULES, reduce_mixtures
from rankedassign.tracking.association import MultiSensorAssociation

BHATTA, VO_MA, HEAVIEST = (MERGE_RULES[k] for k in ("bhattacharyya", "vo-ma", "heaviest"))


class Enumerate(Association):
    """Exact marginals by enumerating every feasible hypothesis (small problems only)."""

    def __init__(self):
        self.problems = []

    def __call__(self, problem, rng):
        self.problems.append(problem)
        P, M = problem.n_rows, problem.n_meas
        cc = problem.compact_cost
        opts = [[c for c in range(M + 2) if np.isfinite(cc[i, c])] for i in range(P)]
        hyps = []
        for combo in itertools.product(*opts):
            meas = [c for c in combo if c < M]
            if len(meas) != len(set(meas)):
                continue
            hyps.append([c if c < M else (M + i if c == M else M + P + i)
                         for i, c in enumerate(combo)])
        a = np.array(hyps, dtype=np.int64)
        return AssociationResult(marginals_from_hypotheses(problem, a), 1, 7, 11, len(a))


def one_birth_model(r=0.4, clutter=5.0, cov=(30.0, 5.0, 30.0, 5.0), sensor=None):
    birth = LMBBirth((BirthComponent(r, [10.0, 1.0, -20.0, 2.0], np.diag(np.square(cov))),))
    return Model(sensor=sensor or PositionSensor(), clutter=PoissonClutter(clutter), birth=birth)


# --------------------------------------------------------------------------- helpers
def test_gate_threshold_matches_chi2():
    from scipy.stats import chi2

    for g in (0.5, 0.99, 0.9999999):
        assert_allclose(gate_threshold(g), chi2.ppf(g, 2), rtol=1e-9)
    assert_allclose(gate_threshold(0.9, 4), chi2.ppf(0.9, 4), rtol=1e-12)
    assert_allclose(gate_threshold(0.9999999), -2 * math.log(1e-7), rtol=1e-9)
    with pytest.raises(ValueError, match=r"gate_prob must be in \(0, 1\), got 1.0"):
        gate_threshold(1.0)
    with pytest.raises(TypeError, match="dim must be an int, got float 2.0"):
        gate_threshold(0.9, 2.0)
    with pytest.raises(ValueError, match="dim must be an int >= 1, got 0"):
        gate_threshold(0.9, 0)


def test_group_tracks_components():
    g = np.zeros((5, 4), dtype=bool)
    g[0, 1] = g[3, 1] = g[3, 2] = g[4, 2] = True  # 0-3-4 chained by z1, z2
    g[1, 3] = True
    groups = group_tracks(g)
    got = [(r.tolist(), c.tolist()) for r, c in groups]
    assert got == [([0, 3, 4], [1, 2]), ([1], [3]), ([2], [])]
    assert group_tracks(np.zeros((0, 3), dtype=bool)) == []
    with pytest.raises(ValueError, match=re.escape("gated must be a 2-D (T, M) array, got shape (3,)")):
        group_tracks(np.ones(3, dtype=bool))


def test_map_cardinality_brute_force():
    rng = np.random.default_rng(0)
    for _ in range(20):
        r = rng.random(rng.integers(0, 6))
        dist = np.zeros(len(r) + 1)
        for bits in itertools.product([0, 1], repeat=len(r)):
            dist[sum(bits)] += np.prod([q if b else 1 - q for q, b in zip(r, bits, strict=True)])
        assert map_cardinality(r) == int(np.argmax(dist))


def test_reduce_mixtures_prune_merge_cap():
    # track 0: two identical components merge; a negligible one is pruned.
    # track 1: dropped. track 2: 4 far-apart components capped to 2.
    m = np.zeros((8, 4))
    P = np.broadcast_to(np.eye(4), (8, 4, 4)).copy()
    w = np.array([0.5, 0.5 - 1e-7, 1e-7, 1.0, 0.4, 0.3, 0.2, 0.1])
    m[1, 0] = 1.0  # Mahalanobis 1 <= 4: merged with component 0
    m[4:, 0] = [0.0, 100.0, 200.0, 300.0]
    offsets = np.array([0, 3, 4, 8])
    keep = np.array([True, False, True])
    off, w2, m2, P2 = reduce_mixtures(offsets, w, m, P, keep, 1e-5, 4.0, 2, BHATTA)
    # equal covariances: every rule is the same Mahalanobis test
    for rule in (VO_MA, HEAVIEST):
        other = reduce_mixtures(offsets, w, m, P, keep, 1e-5, 4.0, 2, rule)
        for a, b in zip(other, (off, w2, m2, P2), strict=True):
            assert_array_equal(a, b)
    assert_array_equal(off, [0, 1, 3])
    assert_allclose(w2, [1.0, 0.4 / 0.7, 0.3 / 0.7], rtol=1e-12)
    wa, wb = 0.5, 0.5 - 1e-7
    mean = wb / (wa + wb)
    assert_allclose(m2[0, 0], mean, rtol=1e-12)
    # moment matching (Vo & Ma 2006, Table II): Σ w (P + (m - m̄)(m - m̄)ᵀ) / Σ w
    spread = (wa * mean**2 + wb * (1 - mean) ** 2) / (wa + wb)
    assert_allclose(P2[0, 0, 0], 1.0 + spread, rtol=1e-12)
    assert_allclose(m2[1:, 0], [0.0, 100.0], rtol=1e-12)


def test_reduce_mixtures_merge_distance_uses_candidate_covariance():
    # Vo & Ma (2006, Table II): merge i into the heaviest j when
    # (m_i - m_j)' P_i^-1 (m_i - m_j) <= U. Heaviest sharp (P = I), lighter broad (P = 100 I)
    # 5 m away: 25 / 100 = 0.25 <= 4 merges them (P_j^-1, as in Vo's MATLAB, would give 25)
    m = np.zeros((2, 4))
    m[1, 0] = 5.0
    P = np.stack([np.eye(4), 100.0 * np.eye(4)])
    w = np.array([0.6, 0.4])
    off, w2, m2, P2 = reduce_mixtures(np.array([0, 2]), w, m, P, np.array([True]), 1e-5, 4.0, 10,
                                       VO_MA)
    assert_array_equal(off, [0, 1])
    assert_allclose(m2[0, 0], 0.4 * 5.0, rtol=1e-12)
    spread = 0.6 * 2.0**2 + 0.4 * 3.0**2
    expect = 0.6 * np.eye(4) + 0.4 * 100.0 * np.eye(4)
    expect[0, 0] += spread
    assert_allclose(P2[0], expect, rtol=1e-12)
    # the other way round (broad component heaviest, sharp candidate): 25 > 4, kept apart
    off, w2, m2, P2 = reduce_mixtures(np.array([0, 2]), w, m, P[::-1].copy(),
                                       np.array([True]), 1e-5, 4.0, 10, VO_MA)
    assert_array_equal(off, [0, 2])
    assert_allclose(w2, [0.6, 0.4], rtol=1e-12)
    assert_allclose(P2, P[::-1], rtol=1e-12)
    # the heaviest component's covariance (Vo's MATLAB distance) gives the mirror image
    off, *_ = reduce_mixtures(np.array([0, 2]), w, m, P, np.array([True]), 1e-5, 4.0, 10,
                               HEAVIEST)
    assert_array_equal(off, [0, 2])
    off, *_ = reduce_mixtures(np.array([0, 2]), w, m, P[::-1].copy(), np.array([True]), 1e-5,
                               4.0, 10, HEAVIEST)
    assert_array_equal(off, [0, 1])
    # the Bhattacharyya criterion keeps a sharp and a broad component apart either way:
    # 25 / 50.5 + 4 ln(50.5⁴ / √(1 · 100⁴)) = 0.50 + 25.9 > 4
    for Pk in (P, P[::-1].copy()):
        off, *_ = reduce_mixtures(np.array([0, 2]), w, m, Pk, np.array([True]), 1e-5, 4.0, 10,
                                   BHATTA)
        assert_array_equal(off, [0, 2])


@pytest.mark.parametrize(("scale", "merged"), [(4.0, True), (5.0, False)])
def test_reduce_mixtures_bhattacharyya_threshold(scale, merged):
    # Coincident means, covariances I and s·I: 8 D_B = 4 (4 ln((1 + s) / 2) − 2 ln s),
    # 3.57 for s = 4 (merged at U = 4) and 4.70 for s = 5 (kept apart)
    val = 4 * (4 * np.log((1 + scale) / 2) - 2 * np.log(scale))
    assert (val <= 4.0) == merged
    m = np.zeros((2, 4))
    P = np.stack([np.eye(4), scale * np.eye(4)])
    w = np.array([0.7, 0.3])
    off, w2, m2, P2 = reduce_mixtures(np.array([0, 2]), w, m, P, np.array([True]), 1e-5, 4.0, 10,
                                       BHATTA)
    assert_array_equal(off, [0, 1] if merged else [0, 2])
    if merged:
        assert_allclose(P2[0], (0.7 + 0.3 * scale) * np.eye(4), rtol=1e-12)


def test_reduce_mixtures_orders_by_merged_weight():
    # the heaviest single component (0.3) is merged first but the later cluster of three
    # (0.25 + 0.25 + 0.2) outweighs it: the cluster must come first, and survive a cap of 1
    m = np.zeros((4, 4))
    m[1:, 0] = [100.0, 100.5, 101.0]
    P = np.broadcast_to(np.eye(4), (4, 4, 4)).copy()
    w = np.array([0.3, 0.25, 0.25, 0.2])
    off, w2, m2, _ = reduce_mixtures(np.array([0, 4]), w, m, P, np.array([True]), 1e-5, 4.0, 10,
                                  BHATTA)
    assert_allclose(w2, [0.7, 0.3], rtol=1e-12)
    assert_allclose(m2[0, 0], (0.25 * 100 + 0.25 * 100.5 + 0.2 * 101) / 0.7, rtol=1e-12)
    off, w2, m2, _ = reduce_mixtures(np.array([0, 4]), w, m, P, np.array([True]), 1e-5, 4.0, 1,
                                  BHATTA)
    assert_array_equal(off, [0, 1])
    assert_allclose(w2, [1.0], rtol=1e-12)
    assert m2[0, 0] > 99


# --------------------------------------------------------------------------- one scan, closed form
@pytest.mark.parametrize(
    "sensor",
    [PositionSensor(), PositionSensor(0.9, noise_cov=[[25.0, 30.0], [30.0, 400.0]])],
    ids=["paper-sensor", "correlated-noise"],
)
def test_prediction_and_kalman_update_closed_form(sensor):
    model = one_birth_model(sensor=sensor)
    f = LMBFilter(model, Enumerate(), merge_threshold=0.0)
    z = np.array([[25.0, -30.0]])
    rec = f.step(z)
    b = model.birth.components[0]
    H, R = model.sensor.H, model.sensor.R
    m0, P0, r0 = b.mean, b.cov, b.r
    S = H @ P0 @ H.T + R
    nu = z[0] - H @ m0
    lik = math.exp(-0.5 * nu @ np.linalg.solve(S, nu)) / (2 * math.pi * math.sqrt(np.linalg.det(S)))
    pd, kappa = model.sensor.p_d, model.clutter.intensity
    eta = np.array([r0 * pd * lik / kappa, r0 * (1 - pd), 1 - r0])  # (6.2)
    beta = eta / eta.sum()
    assert_allclose(rec.track_existence, [beta[0] + beta[1]], rtol=1e-12)
    K = P0 @ H.T @ np.linalg.inv(S)
    m_upd = m0 + K @ nu
    P_upd = (np.eye(4) - K @ H) @ P0
    w_det, w_miss = beta[0] / (1 - beta[2]), beta[1] / (1 - beta[2])
    order = np.argsort([-w_det, -w_miss])
    exp_w = np.array([w_det, w_miss])[order]
    exp_m = np.array([m_upd, m0])[order]
    exp_P = np.array([P_upd, P0])[order]
    assert_allclose(f.w, exp_w, rtol=1e-12)
    assert_allclose(f.m, exp_m, rtol=1e-12)
    assert_allclose(f.P, exp_P, rtol=1e-10, atol=1e-10)
    assert_array_equal(f.labels, [[1, 1]])
    # the problem the association saw: η in log space, in the paper's layout
    prob = f.association.problems[0]
    assert_allclose(prob.compact_cost, -np.log(eta)[None, :], rtol=1e-12)
    # next prediction (6.1): r <- P_S r, m <- F m, P <- F P F' + Q, births appended
    F, Q = model.motion.F, model.motion.Q
    r_post, m_post, P_post = f.r.copy(), f.m.copy(), f.P.copy()
    f.predict()
    assert_allclose(f.r[0], model.survival.p_s * r_post[0], rtol=1e-15)
    assert_allclose(f.m[:2], m_post @ F.T, rtol=1e-15)
    assert_allclose(f.P[:2], F @ P_post @ F.T + Q, rtol=1e-13)
    assert_array_equal(f.labels, [[1, 1], [2, 1]])
    assert_array_equal(f.offsets, [0, 2, 3])
    assert_allclose(f.m[2], m0)


def test_accounting_and_timings_recorded():
    f = LMBFilter(one_birth_model(), Enumerate())
    rec = f.step([[25.0, -30.0], [900.0, 900.0]])
    assert (rec.n_meas, rec.n_meas_gated, rec.n_groups) == (2, 1, 1)
    assert (rec.invocations, rec.sweeps, rec.row_updates, rec.n_unique) == (1, 7, 11, 3)
    assert set(rec.timings) == {"prediction", "cost", "association", "update"}
    assert all(v >= 0 for v in rec.timings.values())
    # no gated measurement: closed form, no invocation
    rec = f.step([[900.0, 900.0]])
    assert (rec.n_meas_gated, rec.n_groups, rec.invocations) == (0, 0, 0)


def test_no_measurement_closed_form():
    model = one_birth_model(r=0.3)
    f = LMBFilter(model, Enumerate())
    f.step(np.empty((0, 2)))
    pd = model.sensor.p_d
    r_post = 0.3 * (1 - pd) / (0.3 * (1 - pd) + 0.7)
    assert_allclose(f.r, [r_post], rtol=1e-12)
    assert f.association.problems == []


@pytest.mark.parametrize("grouping", [False, True])
def test_sample_empty_groups_changes_only_the_accounting(grouping):
    # Problems without a gated measurement go to the association instead of the closed form:
    # with exact marginals the posterior is the same, and every group is one invocation.
    a = LMBFilter(make_model("paper-var"), Enumerate(), grouping=grouping)
    b = LMBFilter(make_model("paper-var"), Enumerate(), grouping=grouping,
                  sample_empty_groups=True)
    truth = paper_truth(8)
    rng = np.random.default_rng(3)
    extra = 0
    for k in range(8):
        _, X = truth.at(k)
        z = np.vstack([X[:, [0, 2]] + 10 * rng.standard_normal((len(X), 2)),
                       rng.uniform(-1000, 1000, (2, 2))])
        if k == 4:
            z = np.empty((0, 2))  # a scan without measurements: one empty problem
        ra, rb = a.step(z), b.step(z)
        assert_array_equal(ra.track_labels, rb.track_labels)
        assert_allclose(ra.track_existence, rb.track_existence, rtol=1e-12, atol=1e-15)
        assert_allclose(ra.states, rb.states, rtol=1e-12)
        assert rb.invocations == rb.n_groups >= ra.invocations == ra.n_groups
        extra += rb.invocations - ra.invocations
        if grouping:
            # every track is in exactly one group: the groups partition the rows
            sizes = [p.n_rows for p in b.association.problems[-rb.invocations:]]
            assert sum(sizes) == rb.n_tracks
        if k == 4:
            assert (ra.invocations, rb.invocations) == (0, 1)
    assert extra >= 8 if grouping else extra == 1


def test_gating_off_keeps_every_measurement():
    f = LMBFilter(one_birth_model(), Enumerate(), gate_prob=None)
    rec = f.step([[25.0, -30.0], [900.0, 900.0]])
    assert rec.n_meas_gated == 2
    assert f.association.problems[0].n_meas == 2


# --------------------------------------------------------------------------- tracking
def single_target_run(n_scans=40, seed=0, **options):
    model = Model(clutter=PoissonClutter(1e-3), birth=make_model("vo").birth)
    f = LMBFilter(model, Enumerate(), **options)
    truth = paper_truth(n_scans)
    rng = np.random.default_rng(seed)
    errors, reported = [], []
    for k in range(n_scans):
        x = truth.states[k, 1]  # target 2, born at scan 1 near birth location 2
        z = (x[[0, 2]] + 10.0 * rng.standard_normal(2))[None]
        rec = f.step(z)
        reported.append(rec.labels.tolist())
        if rec.states.shape[0]:
            errors.append(np.linalg.norm(rec.states[:, [0, 2]] - x[[0, 2]], axis=1).max())
    return np.array(errors), reported


@pytest.mark.parametrize("options", [{}, {"extraction": "map"}, {"estimate": "mean"},
                                     {"grouping": True}])
def test_single_target_tracked_within_a_few_metres(options):
    errors, reported = single_target_run(**options)
    # one confirmed track, the one born at scan 1 from birth component 2, from scan 1 on
    assert all(lab == [[1, 2]] for lab in reported)
    # measurement noise is 10 m per axis; the filtered error is smaller on average
    assert errors.mean() < 10.0
    assert errors.max() < 30.0


def test_grouping_gives_the_same_posterior_as_one_problem():
    # The joint association factorises over groups (spec §6.5a), so exact marginals per group
    # equal exact marginals of the whole problem.
    truth = paper_truth(12)
    model = make_model("vo")
    scans_rng = np.random.default_rng(5)
    zs = []
    for k in range(12):
        _, X = truth.at(k)
        zs.append(np.vstack([X[:, [0, 2]] + 10 * scans_rng.standard_normal((len(X), 2)),
                             scans_rng.uniform(-1000, 1000, (3, 2))]))
    a = LMBFilter(model, Enumerate())
    b = LMBFilter(model, Enumerate(), grouping=True)
    for z in zs:
        ra, rb = a.step(z), b.step(z)
        assert_array_equal(ra.track_labels, rb.track_labels)
        assert_allclose(ra.track_existence, rb.track_existence, rtol=1e-9, atol=1e-12)
        assert_allclose(ra.states, rb.states, rtol=1e-9, atol=1e-9)
        assert rb.n_groups >= ra.n_groups
    assert b.n_tracks >= 3


def test_track_cap_and_pruning():
    model = one_birth_model()
    f = LMBFilter(model, Enumerate(), max_tracks=1, prune_track=1e-3)
    for _ in range(4):
        f.step([[25.0, -30.0]])
        assert f.n_tracks <= 1
        assert np.all(f.r > 1e-3)
    # the components of every track stay normalised and within the cap
    g = LMBFilter(model, Enumerate(), max_components=1)
    for _ in range(3):
        g.step([[25.0, -30.0], [40.0, -20.0]])
        assert np.all(np.diff(g.offsets) == 1)
        assert_allclose(np.add.reduceat(g.w, g.offsets[:-1]), 1.0, rtol=1e-12)


class BadShape(Association):
    def __call__(self, problem, rng):
        return AssociationResult(np.zeros((1, 1)), 1, 0, 0, 0)


class _MultiSensorOnly(MultiSensorAssociation):
    def __call__(self, problem, rng):  # pragma: no cover (refused before it is called)
        raise AssertionError


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        ({"model": "paper"}, TypeError, "model must be a Model"),
        ({"association": 3}, TypeError, "association must be callable"),
        ({"extraction": "best"}, ValueError,
         re.escape("unknown extraction 'best'; expected one of ('hysteresis', 'map', "
                   "'cluster-map')")),
        ({"estimate": "median"}, ValueError,
         re.escape("unknown estimate 'median'; expected one of ('max-weight', 'mean')")),
        ({"theta_upper": 1.5}, ValueError, "theta_upper must be <= 1.0, got 1.5"),
        ({"theta_upper": "high"}, TypeError, "theta_upper must be a real number, got str"),
        ({"theta_lower": 0.95}, ValueError, "theta_lower must be <= 0.9, got 0.95"),
        ({"prune_track": 1.0}, ValueError, "prune_track must be < 1, got 1.0"),
        ({"prune_component": -1.0}, ValueError, "prune_component must be >= 0.0, got -1.0"),
        ({"prune_component": 1.0}, ValueError, "prune_component must be < 1, got 1.0"),
        ({"merge_threshold": -1.0}, ValueError, "merge_threshold must be >= 0.0, got -1.0"),
        ({"merge_rule": "runnalls"}, ValueError, "unknown merge_rule 'runnalls'; expected one of"),
        ({"max_tracks": 0}, ValueError, "max_tracks must be an int >= 1, got 0"),
        ({"max_components": 2.5}, TypeError, "max_components must be an int, got float 2.5"),
        ({"gate_prob": 1.5}, ValueError, re.escape("gate_prob must be in (0, 1), got 1.5")),
        ({"gate_prob": "0.9"}, TypeError, "gate_prob must be a real number, got str"),
        ({"model": "paper"}, TypeError,
         "model must be a Model or NonlinearModel, got str; build one with"),
        ({"association": 3}, TypeError, "association must be callable"),
        # booleans were parsed by truthiness: "no" switched grouping on
        ({"grouping": "no"}, TypeError, "grouping must be True or False, got str 'no'"),
        ({"grouping": 1}, TypeError, "grouping must be True or False, got int 1"),
        ({"sample_empty_groups": "False"}, TypeError,
         "sample_empty_groups must be True or False, got str 'False'"),
        # a multi-sensor association failed at the first scan (AttributeError on 'dead')
        ({"association": _MultiSensorOnly()}, TypeError,
         re.escape("LMBFilter cannot use _MultiSensorOnly: it solves multi-sensor problems only "
                   "(its sensors attribute)")),
    ],
)
def test_filter_errors(kwargs, exc, match):
    args = {"model": make_model("paper"), "association": Enumerate()}
    args.update(kwargs)
    model = args.pop("model")
    assoc = args.pop("association")
    with pytest.raises(exc, match=match):
        LMBFilter(model, assoc, **args)


class Uniform(Association):
    """Equal weight on every column, forbidden pairs included (a broken association)."""

    def __call__(self, problem, rng):
        P, M = problem.n_rows, problem.n_meas
        return AssociationResult(np.full((P, M + 2), 1.0 / (M + 2)), 1, 0, 0, 0)


def test_step_errors():
    f = LMBFilter(one_birth_model(), BadShape())
    with pytest.raises(ValueError, match="association returned beta of shape"):
        f.step([[25.0, -30.0]])
    # "vo" births are 10 m wide: each of these measurements is in one birth's gate only, so the
    # one problem of the scan has forbidden pairs
    u = LMBFilter(make_model("vo"), Uniform())
    with pytest.raises(ValueError, match="nonzero marginal for a pair outside the gate"):
        u.step([[0.0, 0.0], [0.0, 5.0], [400.0, -600.0]])
    g = LMBFilter(one_birth_model(), Enumerate())
    with pytest.raises(ValueError, match="measurements must be finite"):
        g.step([[np.nan, 0.0]])
    # a (3, 4) array is not six measurements, and a bare pair is not a list of them
    with pytest.raises(ValueError, match=re.escape("must have shape (M, 2), got shape (3, 4)")):
        g.step(np.zeros((3, 4)))
    with pytest.raises(ValueError, match=re.escape("must have shape (M, 2), got shape (2,)")):
        g.step([25.0, -30.0])
    assert g.step([]).n_meas == 0  # an empty list is a scan without measurements


def test_a_plain_function_is_an_association():
    enum = Enumerate()

    def enumerate_marginals(problem, rng):
        return enum(problem, rng)

    z = [[25.0, -30.0], [40.0, -20.0]]
    a = LMBFilter(one_birth_model(), enumerate_marginals, grouping=np.True_)
    b = LMBFilter(one_birth_model(), Enumerate(), grouping=True)
    assert a.grouping is True
    for _ in range(2):
        ra, rb = a.step(z, rng=0), b.step(z, rng=0)
        assert_array_equal(ra.track_existence, rb.track_existence)


@pytest.mark.parametrize(
    ("z", "exc", "match"),
    [
        # strings were parsed as numbers
        ([["1.5", "2"]], TypeError,
         re.escape("measurements must be real numbers, got strings (dtype <U3) in a scan of "
                   "shape (1, 2)")),
        # (5, 0) and (0, 3) were taken as an empty scan
        (np.zeros((5, 0)), ValueError,
         re.escape("measurements must have shape (M, 2), got shape (5, 0) (a scan without "
                   "measurements is [] or shape (0, 2))")),
        (np.zeros((0, 3)), ValueError, re.escape("must have shape (M, 2), got shape (0, 3)")),
        ([[]], ValueError, re.escape("must have shape (M, 2), got shape (1, 0)")),
        # numpy's "inhomogeneous shape" and "float() argument" errors before
        ([[1.0, 2.0], [3.0]], ValueError,
         re.escape("measurements must be an (M, 2) array of real numbers, got a ragged "
                   "sequence (rows of different lengths)")),
        ([[1 + 2j, 0.0]], TypeError,
         re.escape("measurements must be real numbers, got complex numbers (dtype complex128) "
                   "in a scan of shape (1, 2)")),
        ([[True, False]], TypeError, "measurements must be real numbers, got booleans"),
        (None, TypeError, re.escape("measurements must be real numbers, got objects (dtype "
                                    "object) in a scan of shape ()")),
        ([[0.0, 0.0], [np.inf, 1.0]], ValueError,
         re.escape("measurements must be finite, got inf at [1, 0] in a scan of shape (2, 2)")),
        (5.0, ValueError, re.escape("measurements must have shape (M, 2), got shape ()")),
    ],
)
def test_measurement_errors(z, exc, match):
    f = LMBFilter(one_birth_model(), Enumerate())
    with pytest.raises(exc, match=match):
        f.step(z)
    assert f.k == 0  # refused before the prediction


def test_empty_scans_and_integer_measurements():
    for empty in ([], np.zeros(0), np.zeros((0, 2)), ()):
        assert LMBFilter(one_birth_model(), Enumerate()).step(empty).n_meas == 0
    # ints (and Python ints beyond int64) are real numbers: the same as the floats
    a = LMBFilter(one_birth_model(), Enumerate()).step([[25, -30], [10**20, 0]])
    b = LMBFilter(one_birth_model(), Enumerate()).step([[25.0, -30.0], [1e20, 0.0]])
    assert_array_equal(a.track_existence, b.track_existence)


def _beta(values):
    """An association returning the fixed marginals ``values`` (of a 1-row, 1-measurement
    problem)."""

    def fixed(problem, rng):
        return AssociationResult(np.array([values], dtype=float), 1, 0, 0, 0)

    return fixed


class NaNBeta(Association):
    def __call__(self, problem, rng):
        return AssociationResult(np.full((problem.n_rows, problem.n_meas + 2), np.nan), 1, 0, 0,
                                 0)


@pytest.mark.parametrize(
    ("association", "match"),
    [
        # NaN or negative marginals dropped every track silently before
        (NaNBeta(), re.escape("association NaNBeta returned a non-finite marginal: "
                              "beta[0, 0] = nan")),
        (_beta([0.5, -0.5, 1.0]),
         re.escape("association _beta.<locals>.fixed returned a negative marginal: "
                   "beta[0, 1] = -0.5")),
        (_beta([0.5, 0.25, 0.0]),
         re.escape("association _beta.<locals>.fixed returned marginals that are not a "
                   "distribution: beta[0, :].sum() = 0.75, not 1 (tolerance 1e-09)")),
        (_beta([np.inf, 0.0, 0.0]), r"returned a non-finite marginal: beta\[0, 0\] = inf"),
    ],
)
def test_association_output_is_checked(association, match):
    f = LMBFilter(one_birth_model(), association)
    with pytest.raises(ValueError, match=match):
        f.step([[25.0, -30.0]])


def test_association_output_within_the_tolerance_is_accepted():
    rec = LMBFilter(one_birth_model(), _beta([0.5, 0.25, 0.25 + 1e-12])).step([[25.0, -30.0]])
    assert_allclose(rec.track_existence, [0.75], rtol=1e-12)


@pytest.mark.parametrize(
    ("rng", "exc", "match"),
    [
        (1.5, TypeError, r"rng must be None, a non-negative int or sequence of them, a "
                         r"SeedSequence, a BitGenerator or a Generator; got 1.5 \(SeedSequence"),
        ("seed", TypeError, r"rng must be None, .*; got 'seed'"),
        (-1, ValueError, r"rng must be None, .*; got -1 \(expected non-negative integer\)"),
    ],
)
def test_step_rng_errors(rng, exc, match):
    f = LMBFilter(one_birth_model(), Enumerate())
    with pytest.raises(exc, match=match):
        f.step([[25.0, -30.0]], rng=rng)


def test_step_with_a_random_state_is_reproducible():
    # "does not implement spawning" before; the samplers take one draw from a RandomState, and
    # the filter seeds its Generator with that same draw
    z = [[0.0, 0.0], [5.0, 3.0], [400.0, -600.0], [410.0, -590.0]]

    def run(rng):
        f = LMBFilter(make_model("vo"), ShortChainGibbs(20, 5, tau_stall=5, tau_stale=10))
        return [f.step(z, rng=rng) for _ in range(3)]

    rs = np.random.RandomState(7)
    a, b = run(rs), run(np.random.RandomState(7))
    ref = np.random.RandomState(7)
    keys = [base_key(ref) for _ in range(3)]
    g = LMBFilter(make_model("vo"), ShortChainGibbs(20, 5, tau_stall=5, tau_stale=10))
    c = [g.step(z, rng=k) for k in keys]
    for ra, rb, rc in zip(a, b, c, strict=True):
        assert_array_equal(ra.track_existence, rb.track_existence)
        assert_array_equal(ra.track_existence, rc.track_existence)
        assert ra.sweeps == rc.sweeps
    assert rs.randint(2**31) == ref.randint(2**31)  # advanced by one draw a scan


def test_run_scenario_requires_association():
    with pytest.raises(TypeError, match="run_scenario needs an association"):
        run_scenario("paper")
    with pytest.raises(ValueError, match="unknown preset 'nope'; expected one of"):
        run_scenario("nope", Enumerate())
    with pytest.raises(ValueError, match="n_scans must be an int >= 1, got 0"):
        run_scenario("vo", Enumerate(), n_scans=0)
    with pytest.raises(TypeError, match="n_scans must be an int, got float 2.0"):
        run_scenario("vo", Enumerate(), n_scans=2.0)
    with pytest.raises(ValueError, match="unknown extraction 'top'"):
        run_scenario("vo", Enumerate(), n_scans=2, extraction="top")


def test_run_scenario_argument_errors():
    # numpy's MemoryError (349 TiB) before
    with pytest.raises(ValueError, match=re.escape(
            "n_scans must be an int <= 1000000 (MAX_SCANS), got 1000000000000: the truth of that "
            "many scans alone would need 349.2 TiB")):
        run_scenario("vo", Enumerate(), n_scans=10**12)
    with pytest.raises(TypeError, match="grouping must be True or False, got str 'no'"):
        run_scenario("vo", Enumerate(), n_scans=2, grouping="no")
    with pytest.raises(TypeError, match=r"rng must be None, .*; got 'seed'"):
        run_scenario("vo", Enumerate(), n_scans=2, rng="seed")
    with pytest.raises(ValueError, match=r"rng must be None, .*; got -1"):
        run_scenario("vo", Enumerate(), n_scans=2, rng=-1)
    with pytest.raises(TypeError, match="LMBFilter cannot use _MultiSensorOnly: it solves "
                                        "multi-sensor problems only"):
        run_scenario("vo", _MultiSensorOnly(), n_scans=2)


def test_run_scenario_with_a_random_state():
    # the Generator seeded with one draw from the RandomState, as the samplers take
    a = run_scenario("vo", Exact(), rng=np.random.RandomState(3), n_scans=3, grouping=True)
    b = run_scenario("vo", Exact(), rng=base_key(np.random.RandomState(3)), n_scans=3,
                     grouping=True)
    for sa, sb in zip(a.scenario.scans, b.scenario.scans, strict=True):
        assert_array_equal(sa.z, sb.z)
    assert_array_equal(np.nan_to_num(a.estimates, nan=-1.0), np.nan_to_num(b.estimates, nan=-1.0))


def test_run_scenario_with_exact_enumeration_on_vo_preset():
    run = run_scenario("vo", Enumerate(), rng=2, n_scans=15, grouping=True,
                       extraction="hysteresis")
    assert run.extraction == "hysteresis"
    assert run.truth.shape == (15, 12, 2)
    assert run.estimates.shape[0] == 15 and run.estimates.shape[2] == 2
    assert len(run.estimate_labels) == run.estimates.shape[1]
    for name in ("invocations", "sweeps", "row_updates", "n_unique", "n_tracks", "n_meas",
                 "n_meas_gated", "n_groups", "n_estimated"):
        arr = getattr(run, name)
        assert arr.dtype == np.int64 and arr.shape == (15,)
    assert_array_equal(run.sweeps, 7 * run.invocations)
    assert np.all(run.n_tracks >= 4)
    # after a few scans the three targets are tracked
    for k in range(5, 15):
        x = run.truth[k][~np.isnan(run.truth[k]).any(axis=1)]
        y = run.estimates[k][~np.isnan(run.estimates[k]).any(axis=1)]
        assert ospa(x, y, 100.0, 1).value < 20.0
    # same rng, same measurements and estimates
    again = run_scenario("vo", Enumerate(), rng=2, n_scans=15, grouping=True,
                         extraction="hysteresis")
    assert_array_equal(run.estimates, again.estimates)
    for s1, s2 in zip(run.scenario.scans, again.scenario.scans, strict=True):
        assert_array_equal(s1.z, s2.z)


def test_run_scenario_extraction_defaults_to_the_preset_setting():
    # "paper": hysteresis (spec 6.5); "vo": MAP cardinality, as in Vo's public example
    assert PRESET_EXTRACTION == {"paper": "hysteresis", "paper-var": "hysteresis", "vo": "map"}
    for preset in ("paper", "paper-var", "vo"):
        run = run_scenario(preset, Exact(), rng=0, n_scans=1)
        assert run.extraction == PRESET_EXTRACTION[preset]
        assert run_scenario(preset, Exact(), rng=0, n_scans=1,
                            extraction="map").extraction == "map"

def test_extraction_rules_on_the_vo_preset():
    # MAP: the n̂ tracks of largest r, n̂ the MAP cardinality of the LMB (Vo's code).
    # Hysteresis (6.5, A19): reported iff r reached ϑ_u = 0.9 at some scan and r >= ϑ_l = 1e-3
    # now; tracks are pruned at r <= 1e-3, so a confirmed track is reported until pruned.
    vo_map = run_scenario("vo", Enumerate(), rng=2, n_scans=8, grouping=True)
    hyst = run_scenario("vo", Enumerate(), rng=2, n_scans=8, grouping=True,
                        extraction="hysteresis")
    peak = {}
    for k in range(8):
        ex = vo_map.existence[k]
        n_hat = map_cardinality(list(ex.values()))
        top = sorted(ex, key=lambda lab: -ex[lab])[:n_hat]
        assert sorted(vo_map.labelled_estimates[k]) == sorted(top)
        ex = hyst.existence[k]
        for lab, r in ex.items():
            peak[lab] = max(peak.get(lab, 0.0), r)
        confirmed = [lab for lab, r in ex.items() if peak[lab] >= 0.9 and r >= 1e-3]
        assert sorted(hyst.labelled_estimates[k]) == sorted(confirmed)
    assert hyst.n_estimated.sum() > 0


def test_marginals_from_hypotheses_errors_and_values():
    p = AssignmentProblem.from_eta([[3.0, 1.0], [1.0, 2.0]], [1.0, 1.0], [1.0, 0.5])
    full = Enumerate()(p, None).beta
    assert_allclose(full.sum(axis=1), 1.0, rtol=1e-12)
    with pytest.raises(ValueError, match="at least one hypothesis"):
        marginals_from_hypotheses(p, np.empty((0, 2), dtype=np.int64))
    with pytest.raises(ValueError, match=r"shape \(H, P\)"):
        marginals_from_hypotheses(p, [[0, 1, 2]])
    with pytest.raises(ValueError, match="feasible"):
        marginals_from_hypotheses(p, [[0, 0]])
    # a single hypothesis gets all the weight
    assert_allclose(marginals_from_hypotheses(p, [[0, 1]]),
                    [[1, 0, 0, 0], [0, 1, 0, 0]], rtol=0, atol=0)
