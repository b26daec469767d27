"""Tests of the multi-sensor δ-GLMB filter against a naive multi-sensor δ-GLMB recursion and
against the single-sensor filter with one sensor.

The reference (:func:`naive_step`) keeps a δ-GLMB as ``{track set: weight}`` over
single-Gaussian tracks named by ``(label, history)``, updates a track *sensor after sensor*
with the textbook Kalman equations (the likelihood of a tuple is the product of the sequential
predictive likelihoods, an independent route to the stacked one of the filter), and enumerates
every multi-sensor assignment by brute force. With enumeration, no pruning and no cap the
filter must give the same posterior.
"""

import itertools
import math
import re

import numpy as np
import pytest
from numpy.testing import assert_allclose

import oracle
from rankedassign.tracking import (
    LBP,
    AdaptiveBirth,
    BirthComponent,
    Exact,
    GLMBFilter,
    LMBBirth,
    Model,
    MultiSensorGLMBFilter,
    MultiSensorModel,
    Murty,
    OriginalGibbs,
    PoissonClutter,
    PositionSensor,
    ShortChainGibbs,
    gate_threshold,
    make_model,
    make_multisensor_model,
    run_multisensor_scenario,
)
from rankedassign.tracking.association import BatchPlan
from rankedassign.tracking.multisensor import glmb as ms_glmb
from rankedassign.tracking.multisensor.glmb import truncate_multisensor
from rankedassign.tracking.multisensor.scenario import make_multisensor_scenario
from rankedassign.tracking.single.glmb import Hypotheses

GATE = gate_threshold(0.9999999)


def _model(n_births=1, p_d=(0.9, 0.8), sigma=(5.0, 8.0), clutter=2.0):
    births = tuple(BirthComponent(0.2, [10.0 * b, 0.0, 0.0, 0.0], np.diag([100.0, 4.0, 100.0,
                                                                           4.0]))
                   for b in range(n_births))
    base = Model(clutter=PoissonClutter(clutter, ((-100.0, 100.0), (-100.0, 100.0))),
                 birth=LMBBirth(births))
    return MultiSensorModel(base.motion, tuple(PositionSensor(p, s) for p, s in
                                               zip(p_d, sigma, strict=True)),
                            tuple(PoissonClutter(clutter, ((-100.0, 100.0), (-100.0, 100.0)))
                                  for _ in p_d), base.birth, base.survival)


def _kalman(m, P, H, R, z):
    S = H @ P @ H.T + R
    K = P @ H.T @ np.linalg.inv(S)
    nu = z - H @ m
    q = math.exp(-0.5 * nu @ np.linalg.solve(S, nu)) / (2 * math.pi *
                                                        math.sqrt(np.linalg.det(S)))
    return m + K @ nu, P - K @ S @ K.T, q


def naive_step(model, prior, tracks, zs, k, gate=GATE):
    """One exact multi-sensor δ-GLMB scan by brute force; names ``(label, history)`` with a
    history of per-scan tuples ``(j_1, ..., j_V)`` (−1 missed)."""
    F, Q = model.motion.F, model.motion.Q
    V = len(model.sensors)
    ps = model.survival.p_s
    pred = {n: (F @ m, F @ P @ F.T + Q) for n, (m, P) in tracks.items()}
    births = [(((k, b + 1), ()), (c.mean, c.cov, c.r))
              for b, c in enumerate(model.birth.components)]
    new_tracks, post = {}, {}
    for comp, w in prior.items():
        rows = [(n, m, P, r) for n, (m, P, r) in births]
        rows += [(n, pred[n][0], pred[n][1], ps) for n in sorted(comp)]
        options = []  # per row: [(tuple or None, weight, (mean, cov))]
        for _, m, P, p in rows:
            gl = []
            for v, s in enumerate(model.sensors):
                S = s.H @ P @ s.H.T + s.R
                ok = [j for j, z in enumerate(zs[v])
                      if (z - s.H @ m) @ np.linalg.solve(S, z - s.H @ m) <= gate]
                gl.append([-1] + ok)
            opts = [(None, 1.0 - p, None)]
            for t in itertools.product(*gl):
                mm, PP, wt = m, P, p
                for v, s in enumerate(model.sensors):  # sensor after sensor
                    if t[v] < 0:
                        wt *= 1.0 - s.p_d
                    else:
                        mm, PP, q = _kalman(mm, PP, s.H, s.R, zs[v][t[v]])
                        wt *= s.p_d * q / model.clutters[v].intensity
                opts.append((t, wt, (mm, PP)))
            options.append(opts)
        for choice in itertools.product(*options):
            used = [[o[0][v] for o in choice if o[0] is not None and o[0][v] >= 0]
                    for v in range(V)]
            if any(len(u) != len(set(u)) for u in used):
                continue
            child, wt = [], w
            for (n, _, _, _), (t, wo, state) in zip(rows, choice, strict=True):
                wt *= wo
                if t is None:
                    continue
                name = (n[0], n[1] + (t,))
                new_tracks[name] = state
                child.append(name)
            key = frozenset(child)
            post[key] = post.get(key, 0.0) + wt
    tot = sum(post.values())
    return {k_: v / tot for k_, v in post.items()}, new_tracks


def _as_dict(filt):
    return {frozenset(items): w for w, items in filt.components()}


def _prior():
    labels = [[0, 1], [0, 2]]
    means = np.array([[0.0, 1.0, 0.0, 0.0], [8.0, 0.0, 3.0, -1.0]])
    covs = np.tile(np.diag([25.0, 4.0, 25.0, 4.0]), (2, 1, 1))
    return labels, means, covs


ZS1 = [np.array([[1.0, -1.0], [9.0, 2.0]]), np.array([[0.5, 0.0], [30.0, 30.0]])]
ZS2 = [np.array([[2.0, -2.0]]), np.array([[9.5, 1.0], [1.5, -1.0]])]


def _exact_filter(model, **kw):
    return MultiSensorGLMBFilter(model, Exact(), prune_hypothesis=0.0, h_max=10**6,
                                 keep_histories=True, **kw)


# ----------------------------------------------------------------------------- exactness
def test_two_scans_of_two_sensors_are_the_exact_multisensor_recursion():
    model = _model()
    labels, means, covs = _prior()
    comps, weights = [[0, 1], [1], []], [0.5, 0.3, 0.2]
    f = _exact_filter(model, retained_mass=True)
    f.set_prior(labels, means, covs, comps, weights)
    names = [((a, b), ()) for a, b in map(tuple, labels)]
    post = {frozenset(names[i] for i in c): w for c, w in zip(comps, weights, strict=True)}
    tracks = {n: (m, P) for n, m, P in zip(names, means, covs, strict=True)}
    for k, zs in enumerate([ZS1, ZS2], start=1):
        rec = f.step(zs, rng=k)
        post, tracks = naive_step(model, post, tracks, zs, k)
        got = _as_dict(f)
        assert set(got) == set(post)
        keys = sorted(post, key=lambda s: sorted(s))
        assert_allclose([got[s] for s in keys], [post[s] for s in keys], rtol=1e-9,
                        atol=1e-15)
        assert rec.retained_mass == pytest.approx(1.0, abs=1e-12)
    # every entry of the table is one (label, history) in use, updated sensor after sensor
    in_use = {n for s in post for n in s}
    assert f.n_tracks == len(in_use)
    for e in range(f.n_tracks):
        name = (tuple(f.labels[e].tolist()), f._history(e))
        assert_allclose(f.m[f.offsets[e]], tracks[name][0], rtol=1e-9, atol=1e-9)
        assert_allclose(f.P[f.offsets[e]], tracks[name][1], rtol=1e-9, atol=1e-9)
    assert rec.n_meas == 3  # ZS2: 1 + 2 measurements


def test_one_sensor_gives_the_single_sensor_filter_to_1e_12():
    base = make_model("vo")
    gen = np.random.default_rng(3)
    kw = dict(h_max=10**6, keep_histories=True)  # no cap: equal weights may rank either way
    fs = GLMBFilter(base, Exact(), **kw)
    fm = MultiSensorGLMBFilter(base, Exact(), **kw)
    for k in range(3):
        z = np.r_[[[400.0 - 10 * k, -600.0 + 5 * k], [3.0 * k, 10.0]],
                  gen.uniform(-1000, 1000, (1, 2))]
        a = fs.step(z, rng=k)
        b = fm.step([z], rng=k)
        single = {frozenset(t): w for w, t in fs.components()}
        multi = {frozenset((lab, tuple(x[0] for x in h)) for lab, h in t): w
                 for w, t in fm.components()}
        assert set(single) == set(multi)
        keys = list(single)
        assert_allclose([multi[s] for s in keys], [single[s] for s in keys], rtol=0,
                        atol=1e-12)
        assert a.labels.tolist() == b.labels.tolist()
        assert_allclose(b.states, a.states, rtol=1e-12, atol=1e-9)
        assert_allclose(b.cardinality, a.cardinality, rtol=0, atol=1e-12)
        assert_allclose(b.track_existence, a.track_existence, rtol=0, atol=1e-12)
    assert fm.n_components > 100  # the test saw a real posterior


def test_retained_mass_factorises_over_groups_as_the_whole_components_normaliser():
    model = _model(n_births=2)
    labels, means, covs = _prior()
    f = MultiSensorGLMBFilter(model, ShortChainGibbs(3, 2, method="exact"),
                              retained_mass=True, h_upd=40)
    f.set_prior(labels, means, covs, [[0, 1], [0]], [0.6, 0.4])
    prior_w = f.comp_w.copy()
    comps = [f.comp_tracks[f.comp_off[h]:f.comp_off[h + 1]].copy() for h in range(2)]
    rec = f.step(ZS1, rng=5)
    assert 0.0 < rec.retained_mass < 1.0
    # recompute with one oracle call per whole component, on a twin filter at the same scan
    g = MultiSensorGLMBFilter(model, ShortChainGibbs(3, 2, method="exact"),
                              h_upd=40)
    g.set_prior(labels, means, covs, [[0, 1], [0]], [0.6, 0.4])
    p_exist = g._predict()
    terms = g._terms([np.asarray(z) for z in ZS1], p_exist)
    counts = g._counts()
    from rankedassign.tracking.single import _glmb_kernels
    key = np.uint64(np.random.default_rng(5).integers(0, 2**63, dtype=np.uint64))
    children = g._truncate(terms, counts, _glmb_kernels.component_keys(key, 2))
    log_z = [oracle.log_normalizer(g._problem(g._rows(h), terms)[1]) for h in range(2)]
    log_k = [np.logaddexp.reduce(-children.cost[children.comp == h]) for h in range(2)]
    want = (np.exp(log_k) @ prior_w) / (np.exp(log_z) @ prior_w)
    assert rec.retained_mass == pytest.approx(want, rel=1e-10)
    assert [c.tolist() for c in comps] == [[0, 1], [0]]


@pytest.mark.parametrize("h_max", [10**6, 6])
def test_carried_mass_is_the_share_of_the_exact_posterior_the_cap_keeps(h_max):
    model = _model()
    labels, means, covs = _prior()
    comps, weights = [[0, 1], [1], []], [0.5, 0.3, 0.2]
    f = MultiSensorGLMBFilter(model, Exact(), prune_hypothesis=0.0, h_max=h_max,
                              retained_mass=True)
    f.set_prior(labels, means, covs, comps, weights)
    rec = f.step(ZS1, rng=1)
    names = [((a, b), ()) for a, b in map(tuple, labels)]
    prior = {frozenset(names[i] for i in c): w for c, w in zip(comps, weights, strict=True)}
    tracks = {n: (m, P) for n, m, P in zip(names, means, covs, strict=True)}
    post, _ = naive_step(model, prior, tracks, ZS1, 1)  # every child, merged, normalised
    heaviest = sorted(post.values(), reverse=True)[:h_max]
    assert rec.retained_mass == pytest.approx(1.0, abs=1e-12)
    assert rec.carried_mass == pytest.approx(sum(heaviest), abs=1e-12)
    if h_max < len(post):
        assert rec.n_components == h_max
        assert rec.carried_mass < rec.retained_mass - 1e-3
    else:
        assert rec.carried_mass == pytest.approx(rec.retained_mass, abs=1e-15)


def test_carried_mass_of_a_sampled_truncation_is_at_most_its_retained_mass():
    model = _model(n_births=2)
    labels, means, covs = _prior()
    for h_max in (10**6, 3):
        f = MultiSensorGLMBFilter(model, ShortChainGibbs(3, 2, method="exact"), h_upd=40,
                                  h_max=h_max, prune_hypothesis=0.0, retained_mass=True)
        f.set_prior(labels, means, covs, [[0, 1], [0]], [0.6, 0.4])
        for k, zs in enumerate([ZS1, ZS2], start=1):
            rec = f.step(zs, rng=k)
            assert 0.0 < rec.carried_mass <= rec.retained_mass * (1 + 1e-12)
            if h_max == 10**6:
                assert rec.carried_mass == pytest.approx(rec.retained_mass, abs=1e-15)
    assert rec.carried_mass < rec.retained_mass  # the cap of 3 bit


def test_a_count_of_one_keeps_the_all_missed_child_without_a_problem(monkeypatch):
    model = _model()
    f = MultiSensorGLMBFilter(model, ShortChainGibbs(5, 5, method="mm"), h_upd=1)
    labels, means, covs = _prior()
    f.set_prior(labels, means, covs)
    monkeypatch.setattr(MultiSensorGLMBFilter, "_problem",
                        lambda *a: pytest.fail("a count of 1 needs no problem"))
    rec = f.step(ZS1, rng=0)
    assert rec.sweeps == 0 and rec.n_unique == 1
    assert [len(t) for _, t in f.components()] == [3]  # both tracks and the birth, missed
    assert all(h == ((-1, -1),) for _, t in f.components() for _, h in t)


# ----------------------------------------------------------------------------- the samplers
@pytest.mark.parametrize("method", ["exact", "mm", "mm-fixed"])
def test_the_chains_truncate_with_every_method_and_repeat_with_the_rng(method):
    model = make_multisensor_model((0, 1), birth="narrow")
    scen_z = [[[400.0, -600.0], [0.0, 0.0]], [[402.0, -598.0]]]
    runs = []
    for _ in range(2):
        f = MultiSensorGLMBFilter(model, ShortChainGibbs(50, 5, tau_stall=5,
                                                                    tau_stale=10,
                                                                    method=method))
        recs = [f.step(scen_z, rng=k) for k in range(3)]
        runs.append((f.components(), [r.sweeps for r in recs]))
    assert runs[0] == runs[1]
    assert sum(runs[0][1]) > 0


def _same_record(a, b) -> list:
    """The fields of two scan records that differ in any bit (the timings aside)."""
    diff = []
    for name in a._fields:
        x, y = getattr(a, name), getattr(b, name)
        if name == "timings":
            continue
        if isinstance(x, np.ndarray):
            if x.dtype != y.dtype or x.shape != y.shape or x.tobytes() != y.tobytes():
                diff.append(name)
        elif isinstance(x, float):
            if np.float64(x).tobytes() != np.float64(y).tobytes():
                diff.append(name)
        elif x != y:
            diff.append(name)
    return diff


@pytest.mark.parametrize("sensors, seed", [((0, 1, 2), 1), ((0, 2), 2)])
@pytest.mark.parametrize("assoc", [
    ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10),           # the default method, mm
    ShortChainGibbs(30, 6, method="mm", scan="random"),
    ShortChainGibbs(40, 10, tau_stall=3, tau_stale=4, method="exact", scan="random"),
    OriginalGibbs(120),
    OriginalGibbs(80, method="exact"),
], ids=repr)
def test_the_compiled_path_gives_the_per_component_records_bit_for_bit(assoc, sensors, seed,
                                                                       monkeypatch):
    # the filter runs every component's chains in one compiled call where the truncation's
    # plan allows it; with the plan withheld it builds each component's MultiSensorProblem and
    # calls the public sampler. Same hypotheses, same order, same costs: the same records.
    scen = make_multisensor_scenario(rng=seed, n_scans=6, sensors=sensors, birth="narrow")
    with monkeypatch.context() as m:
        m.setattr(type(assoc), "batch_plan",
                  lambda self, sensors: BatchPlan(start_alone=True))
        loop = MultiSensorGLMBFilter(scen.model, assoc)
    compiled = MultiSensorGLMBFilter(scen.model, assoc)
    assert compiled._plan.chains and not loop._plan.chains
    for k, scan in enumerate(scen.scans):
        zs = [s.z for s in scan]
        want = loop.step(zs, rng=[seed, k])
        with monkeypatch.context() as m:  # the compiled path never asks per component
            m.setattr(ms_glmb, "truncate_multisensor",
                      lambda *a, **kw: pytest.fail("a component truncated in Python"))
            got = compiled.step(zs, rng=[seed, k])
        assert _same_record(want, got) == [], f"scan {k}"
        assert compiled.components() == loop.components()
    assert want.sweeps > 0 and want.n_unique > 1


def test_what_the_compiled_path_cannot_reproduce_runs_per_component(monkeypatch):
    # mm-fixed's dead probability is the sampler's own sum over the component's columns
    calls = []
    real = ms_glmb.truncate_multisensor
    monkeypatch.setattr(ms_glmb, "truncate_multisensor",
                        lambda *a, **kw: calls.append(1) or real(*a, **kw))
    scen = make_multisensor_scenario(rng=3, n_scans=2, sensors=(0, 1), birth="narrow")
    f = MultiSensorGLMBFilter(scen.model, ShortChainGibbs(20, 5, method="mm-fixed"))
    for k, scan in enumerate(scen.scans):
        f.step([s.z for s in scan], rng=k)
    assert calls


def test_a_scan_whose_rows_cannot_all_be_missed_is_refused_as_before():
    # p_d = 1: no row can be missed by sensor 0, so the chains' all-missed start has weight 0;
    # the compiled path leaves such a scan to the per-component path, whose sampler refuses it
    f = MultiSensorGLMBFilter(_model(p_d=(1.0, 0.8)), ShortChainGibbs(20, 5))
    f.set_prior(*_prior())
    assert f._plan.chains
    with pytest.raises(ValueError, match=r"start 'all_missed' is infeasible: rows \[0, 1, 2\]"):
        f.step(ZS1, rng=0)


def test_truncate_multisensor_gives_unique_feasible_hypotheses_with_exact_costs():
    model = _model()
    labels, means, covs = _prior()
    f = MultiSensorGLMBFilter(model, Exact())
    f.set_prior(labels, means, covs)
    p_exist = f._predict()
    terms = f._terms([np.asarray(z) for z in ZS1], p_exist)
    _, problem = f._problem(f._rows(0), terms)
    for assoc in [OriginalGibbs(50, method="exact"),
                  ShortChainGibbs(20, 5, method="mm"), Exact()]:
        hyp = truncate_multisensor(assoc, problem, 30, rng=1)
        a = hyp.assignments
        assert a.shape[1:] == (problem.n_rows, 2)
        assert problem.is_feasible(a).all()
        assert np.unique(a.reshape(a.shape[0], -1), axis=0).shape[0] == a.shape[0]
        assert_allclose(hyp.costs, -problem.log_weight_of(a), rtol=1e-12)
    assert truncate_multisensor(Exact(), problem, 0).assignments.shape[0] == \
        oracle.enumerate_assignments(problem).costs.size


def test_a_custom_association_supplies_hypotheses_and_is_checked():
    model = _model()

    class AllMissed:
        sensors = "multi-sensor"

        def __call__(self, problem, rng):  # pragma: no cover (not called by the GLMB filter)
            raise AssertionError

        def hypotheses(self, problem, budget, rng):
            a = problem.all_missed()[None]
            return Hypotheses(a, -problem.log_weight_of(a))

    f = MultiSensorGLMBFilter(model, AllMissed())
    f.step(ZS1, rng=0)
    assert f.n_components == 1

    class Twice(AllMissed):
        def hypotheses(self, problem, budget, rng):
            a = problem.all_missed()[None]
            return Hypotheses(np.r_[a, a], np.zeros(2))

    with pytest.raises(ValueError, match="returned duplicate assignments"):
        MultiSensorGLMBFilter(model, Twice()).step(ZS1, rng=0)

    class Flat(AllMissed):
        def hypotheses(self, problem, budget, rng):
            return Hypotheses(np.zeros((1, problem.n_rows), dtype=np.int64), np.zeros(1))

    with pytest.raises(ValueError, match=r"MultiSensorGLMBFilter: association Flat returned assignments of shape "
                                         r"\(1, 1\), expected \(n >= 1, 1, 2\)"):
        MultiSensorGLMBFilter(model, Flat()).step(ZS1, rng=0)


# ----------------------------------------------------------------------------- births, runs
def test_adaptive_birth_starts_tracks_from_unexplained_measurements():
    model = make_multisensor_model((0, 1), birth="adaptive")
    f = MultiSensorGLMBFilter(model, ShortChainGibbs(50, 5, tau_stall=5,
                                                                tau_stale=10, method="mm"),
                              birth=AdaptiveBirth())
    recs, births = [], []
    for k in range(6):
        z = [[100.0 + 10 * k, 200.0 - 5 * k]]
        recs.append(f.step([z, z], rng=k))
        births.append(f.n_births)
    assert recs[0].n_tracks == 0 and f.r_U is not None
    assert births[0] == 0 and births[1] > 0  # the first scan's measurements make births
    assert "birth" in recs[0].timings
    assert recs[-1].labels.shape[0] == 1
    assert_allclose(recs[-1].states[0, [0, 2]], [150.0, 175.0], atol=15.0)
    # the measurement of the confirmed track is explained: r_U is small for it
    assert f.r_U[0][0] < 0.1 and f.r_U[1][0] < 0.1


def test_run_multisensor_scenario_runs_both_filters_on_the_same_measurements():
    kw = dict(rng=2, n_scans=3, sensors=(0, 2), birth="narrow")
    assoc = ShortChainGibbs(20, 5, tau_stall=5, tau_stale=10, method="mm")
    glmb = run_multisensor_scenario(assoc, filter="glmb", **kw)
    lmb = run_multisensor_scenario(assoc, **kw)
    assert glmb.n_meas.tolist() == lmb.n_meas.tolist()
    assert glmb.truth.shape == lmb.truth.shape == (3, 12, 2)
    assert glmb.association == repr(assoc) == lmb.association


# ----------------------------------------------------------------------------- bad input
def test_wrong_scans_and_bad_measurements_are_refused_with_the_sensor_named():
    f = MultiSensorGLMBFilter(_model(), Exact())
    with pytest.raises(ValueError, match=r"one measurement array per sensor \(V = 2\), got "
                                         r"1 arrays"):
        f.step([ZS1[0]])
    with pytest.raises(ValueError, match=r"one measurement array per sensor \(V = 2\), got "
                                         r"an array"):
        f.step(np.zeros((2, 1, 2)))
    with pytest.raises(TypeError, match="one measurement array per sensor"):
        f.step("zz")
    with pytest.raises(ValueError, match="measurements of sensor 1"):
        f.step([ZS1[0], [[np.nan, 0.0]]])


@pytest.mark.parametrize("assoc, exc, match", [
    (Murty(5), TypeError, "MultiSensorGLMBFilter cannot use Murty: Murty's ranked search solves "
                          "one sensor's problem"),
    (LBP(), TypeError, "MultiSensorGLMBFilter cannot use LBP: it returns association marginals "
                       "only"),
    (ShortChainGibbs(10, 5, method="componentwise"), ValueError,
     r"method in \('exact', 'mm', 'mm-fixed'\), got 'componentwise'"),
    (Exact(fallback=OriginalGibbs(10, method="componentwise")),
     ValueError, "collapsed target"),
    (lambda problem, rng: None, TypeError, "returns association marginals only"),
    (5, TypeError, "association must be callable"),
])
def test_associations_that_cannot_truncate_are_refused(assoc, exc, match):
    with pytest.raises(exc, match=match):
        MultiSensorGLMBFilter(_model(), assoc)


@pytest.mark.parametrize("kwargs, exc, match", [
    (dict(h_upd=0), ValueError, "h_upd must be a positive integer"),
    (dict(h_max=1.5), ValueError, "h_max must be a positive integer"),
    (dict(prune_hypothesis=1.0), ValueError, r"prune_hypothesis must be in \[0, 1\)"),
    (dict(extraction="mean"), ValueError, "extraction"),
    (dict(birth="adaptive"), TypeError, "birth"),
    (dict(birth_threshold=-1.0), ValueError, "birth_threshold"),
])
def test_bad_options_are_refused_as_for_the_single_sensor_filter(kwargs, exc, match):
    with pytest.raises(exc, match=match):
        MultiSensorGLMBFilter(_model(), Exact(), **kwargs)


def test_a_model_of_the_wrong_type_is_refused():
    with pytest.raises(TypeError, match="model"):
        MultiSensorGLMBFilter("vo", Exact())


def test_the_scenario_runner_refuses_what_the_glmb_filter_cannot_do():
    assoc = ShortChainGibbs(5, 5, method="exact")
    with pytest.raises(ValueError, match="filter"):
        run_multisensor_scenario(assoc, n_scans=1, filter="phd")
    with pytest.raises(ValueError, match="grouping=False applies to the LMB filter only"):
        run_multisensor_scenario(assoc, n_scans=1, filter="glmb", grouping=False)
    with pytest.raises(ValueError, match="distinct indices"):
        run_multisensor_scenario(assoc, n_scans=1, filter="glmb", sensors=(0, 7))


def test_exact_without_fallback_names_the_component_too_large():
    model = _model(clutter=2.0)
    f = MultiSensorGLMBFilter(model, Exact())
    import rankedassign.tracking.association as mod

    labels, means, covs = _prior()
    f.set_prior(labels, means, covs)
    old = mod.EXACT_LIMIT
    try:
        mod.EXACT_LIMIT = 3
        with pytest.raises(ValueError, match=r"Exact\(\) cannot enumerate a "
                                             r"component's problem of 3 rows"):
            f.step(ZS1, rng=0)
        g = MultiSensorGLMBFilter(model, Exact(
            fallback=ShortChainGibbs(5, 5, method="exact")))
        g.set_prior(labels, means, covs)
        g.step(ZS1, rng=0)
        assert g.association.n_fallback == 1
    finally:
        mod.EXACT_LIMIT = old


def test_run_scenario_on_multi_runs_the_multisensor_glmb_filter():
    from rankedassign.tracking import run_scenario

    assoc = ShortChainGibbs(20, 5, tau_stall=5, tau_stale=10, method="mm")
    run = run_scenario("multi", assoc, filter="glmb", rng=2, n_scans=2, sensors=(0, 2),
                       birth="narrow")
    same = run_multisensor_scenario(assoc, filter="glmb", rng=2, n_scans=2, sensors=(0, 2),
                                    birth="narrow")
    assert run.n_unique.tolist() == same.n_unique.tolist()
    with pytest.raises(ValueError, match="filter='glmb' runs without grouping"):
        run_scenario("multi", assoc, filter="glmb", grouping=True, n_scans=1)


# ----------------------------------------------------------------------------- hostile input
def test_a_scan_beyond_the_tuple_limit_is_refused_before_the_tuples_are_built(monkeypatch):
    import rankedassign.tracking.multisensor.glmb as mod

    # four sensors of 30 measurements without gates: 4 entries x 31**4 tuples (it took 25 s
    # and 5.4 GB, and 36 measurements a MemoryError, before the guard)
    model = make_multisensor_model((0, 1, 2, 3))
    f = MultiSensorGLMBFilter(model, ShortChainGibbs(50, 5, method="mm"),
                              gate_prob=None)
    z = np.random.default_rng(0).uniform(-900, 900, size=(30, 2))
    monkeypatch.setattr(mod, "_stacked", lambda *a, **k: pytest.fail("built the tuples"))
    with pytest.raises(ValueError, match=re.escape(
            "MultiSensorGLMBFilter: the 4 entries of this scan allow 3694084 measurement "
            "tuples (one gated measurement or missed per sensor; at most [30, 30, 30, 30] gated "
            "measurements per sensor for one entry), above TUPLE_LIMIT = 1000000")):
        f.step([z] * 4, rng=0)
    assert 4 * 31**4 == 3694084
    # uneven sensors: the count is per entry, over what each sensor gates for it
    g = MultiSensorGLMBFilter(model, ShortChainGibbs(50, 5, method="mm"),
                              gate_prob=None)
    monkeypatch.setattr(mod, "TUPLE_LIMIT", 4 * 3 * 1 * 2 * 5 - 1)
    zs = [z[:2], np.empty((0, 2)), z[:1], z[:4]]
    with pytest.raises(ValueError, match=re.escape(
            "the 4 entries of this scan allow 120 measurement tuples (one gated measurement or "
            "missed per sensor; at most [2, 0, 1, 4] gated measurements per sensor for one "
            "entry), above TUPLE_LIMIT = 119")):
        g.step(zs, rng=0)


def test_the_tuples_are_itertools_product_of_each_entrys_gated_lists():
    model = _model(n_births=2)
    labels, means, covs = _prior()
    f = MultiSensorGLMBFilter(model, Exact())
    f.set_prior(labels, means, covs)
    p_exist = f._predict()
    zs = [np.array([[1.0, -1.0], [9.0, 2.0], [500.0, 500.0]]),
          np.array([[0.5, 0.0], [30.0, 30.0], [8.0, 3.0]])]
    terms = f._terms(zs, p_exist)
    want = []
    for t in range(f.n_tracks):
        lists = [np.r_[0, np.flatnonzero(terms.gated[v][t]) + 1] for v in range(2)]
        want += list(itertools.product(*lists))
    assert terms.tup_g.tolist() == [list(x) for x in want]
    assert terms.tup_g.dtype == np.int64
    assert len(want) > f.n_tracks  # some entries gate measurements


class _MSReturns:
    """A custom multi-sensor truncation whose output is ``make(problem)``."""

    sensors = "multi-sensor"

    def __init__(self, make):
        self.make = make

    def __call__(self, problem, rng):  # pragma: no cover (not called by the GLMB filter)
        raise AssertionError

    def hypotheses(self, problem, budget, rng):
        return self.make(problem)


@pytest.mark.parametrize("make, exc, match", [
    (lambda p: (p.all_missed()[None], np.zeros(1)), TypeError, re.escape(
        "MultiSensorGLMBFilter: association _MSReturns returned a tuple from hypotheses(problem, "
        "budget, rng), not hypotheses: return Hypotheses(assignments, costs)")),
    (lambda p: 7, TypeError, "association _MSReturns returned an int from hypotheses"),
    (lambda p: Hypotheses(p.all_missed()[None] + 0.25, np.zeros(1)), TypeError, re.escape(
        "MultiSensorGLMBFilter: association _MSReturns returned assignments of dtype float64, "
        "expected integer column indices")),
    (lambda p: Hypotheses(p.all_missed()[None] + 9, np.zeros(1)), ValueError, re.escape(
        "MultiSensorGLMBFilter: association _MSReturns returned an entry out of range: "
        "assignments[0, 0, 0] = 9 (row 0, sensor 0), expected -1..2")),
    (lambda p: Hypotheses(p.all_missed()[None] - 2, np.zeros(1)), ValueError,
     re.escape("assignments[0, 0, 0] = -2 (row 0, sensor 0), expected -1..2")),
    (lambda p: Hypotheses(p.all_missed()[None], [np.nan]), ValueError, re.escape(
        "association _MSReturns returned a NaN cost (costs[0])")),
    (lambda p: Hypotheses(p.all_missed()[None], np.zeros(2)), ValueError, re.escape(
        "returned costs of shape (2,), expected (1,), one per assignment")),
    (lambda p: Hypotheses(np.r_[p.all_missed()[None], p.all_missed()[None]], np.zeros(2)),
     ValueError, "association _MSReturns returned duplicate assignments"),
])
def test_a_custom_multisensor_truncation_is_checked_by_the_same_function(make, exc, match):
    f = MultiSensorGLMBFilter(_model(), _MSReturns(make))
    with pytest.raises(exc, match=match):
        f.step(ZS1, rng=0)


def test_set_prior_refuses_labels_of_the_births_of_either_birth():
    labels, means, covs = _prior()
    f = _exact_filter(_model(n_births=2))
    with pytest.raises(ValueError, match=re.escape(
            "labels[1] = (2, 2) is a label the filter gives a birth: the births of scan k are "
            "labelled (k, 1..2) from scan 1 on")):
        f.set_prior([[0, 1], [2, 2]], means, covs)
    f.set_prior([[0, 1], [2, 3]], means, covs)  # above the two births of every scan
    # adaptive births are (k, 1..n), n changing from scan to scan: only birth scan 0 is safe
    g = MultiSensorGLMBFilter(make_multisensor_model((0, 1), birth="adaptive"),
                              ShortChainGibbs(50, 5, method="mm"),
                              birth=AdaptiveBirth())
    with pytest.raises(ValueError, match=re.escape(
            "labels[1] = (2, 9) is a label the filter gives a birth: the adaptive births of "
            "scan k are labelled (k, 1..n) from scan 1 on; label a prior's tracks with birth "
            "scan 0 (as (0, 2))")):
        g.set_prior([[0, 1], [2, 9]], means, covs)
    g.set_prior(labels, means, covs)
    with pytest.raises(TypeError, match=re.escape("labels must be pairs of ints, got float 1.5")):
        g.set_prior([[0, 1], [0, 1.5]], means, covs)
