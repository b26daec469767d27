"""Herded Gibbs on the multi-sensor and adaptive-birth kinds (``sample_herded`` and
``sample_short_chains(herding=...)``), and the multi-sensor LMB association that herds.

The numba drivers are held to the pure-Python references bit for bit (every result field)
over random problems, every method, both keys and every initial weight, with key tables small
enough to force fall-backs; one thread to two, one slice to many. The keys are checked on
problems whose rows share nothing (a shared key never changes there, so each row's choice
frequencies are the exact marginals within ``K / n``), the long-run frequencies against the
exact posterior of the oracle, and bad input against pinned messages.
"""

import dataclasses

import numpy as np
import pytest
from cases import TWO_WORKERS_HERDED
from hypothesis import given, settings
from hypothesis import strategies as st
from ms_standin import KINDS as FAMILIES
from ms_standin import StandIn, random_problem
from numpy.testing import assert_array_equal

import oracle
from rankedassign import (
    Herding,
    kinds,
    reference,
    sample_herded,
    sample_original,
    sample_short_chains,
    samplers,
)
from rankedassign.adaptive_birth import AdaptiveBirthProblem
from rankedassign.engine.herding import DEFAULT_MAX_KEYS
from rankedassign.multisensor import MultiSensorProblem
from rankedassign.multisensor import synthetic as ms_synthetic

KEYS = ("shared", "full")
INITS = ("conditional", "zero", "uniform")
METHODS = ("exact", "mm", "mm-fixed", "componentwise")


def _same(a, b, discarded=True):
    """Every field of two results, bit for bit (``n_speculative_discarded`` if asked)."""
    assert_array_equal(a.assignments, b.assignments)
    assert_array_equal(a.costs.view(np.uint64), b.costs.view(np.uint64))
    assert_array_equal(a.counts, b.counts)
    assert (a.n_observations, a.n_row_updates, a.n_chains_run, a.stop_reason, a.n_keys,
            a.n_fallbacks) == (b.n_observations, b.n_row_updates, b.n_chains_run,
                               b.stop_reason, b.n_keys, b.n_fallbacks)
    if discarded:
        assert a.n_speculative_discarded == b.n_speculative_discarded


@pytest.fixture(scope="module")
def registered():
    """The stand-in multi-sensor problem dispatches like the real MultiSensorProblem."""
    standin = dataclasses.replace(kinds.kind_named("multisensor"), problem_type=StandIn)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(kinds, "KINDS", kinds.KINDS + (standin,))
        yield


@st.composite
def ms_cases(draw):
    V = draw(st.integers(1, 3))
    P = draw(st.integers(1, 3))
    cap = {1: 4, 2: 3, 3: 2}[V]
    M = tuple(draw(st.integers(0, cap)) for _ in range(V))
    problem = random_problem(P, M, draw(st.integers(0, 2**32 - 1)), draw(st.sampled_from(FAMILIES)))
    method = draw(st.sampled_from(METHODS))
    beta = 1.0 if method == "componentwise" else draw(st.sampled_from([1.0, 0.6]))
    return problem, dict(method=method, beta=beta, scan=draw(st.sampled_from(["systematic",
                                                                               "random"])))


def _gaussian(seed, M, n_state):
    g = np.random.default_rng(seed)
    V = len(M)
    H = np.eye(n_state)[: min(2, n_state)]
    d = H.shape[0]
    z = [g.uniform(-20, 20, (m, d)) for m in M]
    ru = [g.uniform(0.0, 1.0, m) for m in M]
    R = [np.diag(g.uniform(1.0, 9.0, d)) for _ in range(V)]
    return AdaptiveBirthProblem.from_measurements(
        z, ru, H=H, R=R, P_D=list(g.uniform(0.2, 0.95, V)), clutter_intensity=1e-3,
        mu0=np.zeros(n_state), P0=np.diag(g.uniform(50.0, 400.0, n_state)), tau_rU=0.2)


@st.composite
def ab_cases(draw):
    V = draw(st.integers(1, 4))
    M = tuple(draw(st.integers(0, 3)) for _ in range(V))
    seed = draw(st.integers(0, 2**32 - 1))
    if draw(st.booleans()):
        problem = _gaussian(seed, M, draw(st.integers(1, 3)))
    else:
        g = np.random.default_rng(seed)
        t = g.normal(0, 3, tuple(m + 1 for m in M))
        t[g.uniform(size=t.shape) < 0.3] = -np.inf
        t[(0,) * V] = 0.0
        problem = AdaptiveBirthProblem.from_log_weights(t)
    return problem, dict(sensor_order=draw(st.sampled_from(["random", "fixed"])),
                         beta=draw(st.sampled_from([1.0, 0.6])))


def _herding_kw(data):
    return dict(keys=data.draw(st.sampled_from(KEYS)), init=data.draw(st.sampled_from(INITS)),
                max_keys=data.draw(st.sampled_from([1, 3, 40, DEFAULT_MAX_KEYS])))


# ------------------------------------------------------------------ reference = numba, bits
@settings(max_examples=80, deadline=None)
@given(data=st.data())
def test_multisensor_one_chain_reference_equals_numba(registered, data):
    problem, kw = data.draw(ms_cases())
    kw.update(_herding_kw(data), rng=data.draw(st.integers(0, 2**32)))
    n_obs = data.draw(st.integers(0, 40))
    res = sample_herded(problem, n_obs, **kw)
    _same(reference.sample_herded(problem, n_obs, **kw), res)
    assert res.n_keys <= kw["max_keys"] and int(res.counts.sum()) == n_obs
    if kw["method"] in ("exact", "componentwise"):  # MM's surrogate may leave the support
        assert np.isfinite(res.costs).all()


@TWO_WORKERS_HERDED
@settings(max_examples=40, deadline=None)
@given(data=st.data())
def test_multisensor_short_chains_reference_serial_parallel_and_slices_agree(registered, data):
    problem, kw = data.draw(ms_cases())
    kw.update(herding=Herding(**_herding_kw(data)), rng=data.draw(st.integers(0, 2**32)),
              tau_stall=data.draw(st.sampled_from([None, 2, 4])),
              tau_stale=data.draw(st.sampled_from([None, 1, 4])))
    n_chains, chain_length = data.draw(st.integers(1, 60)), data.draw(st.integers(1, 8))
    one = sample_short_chains(problem, n_chains, chain_length, **kw)
    _same(reference.sample_short_chains(problem, n_chains, chain_length, **kw), one)
    _same(one, sample_short_chains(problem, n_chains, chain_length, workers=2, **kw),
          discarded=False)
    with pytest.MonkeyPatch.context() as m:
        m.setattr(samplers, "_SLICE_WORK", 1)
        _same(one, sample_short_chains(problem, n_chains, chain_length, workers=2, **kw),
              discarded=False)


@settings(max_examples=60, deadline=None)
@given(data=st.data())
def test_adaptive_birth_one_chain_reference_equals_numba(data):
    problem, kw = data.draw(ab_cases())
    kw.update(_herding_kw(data), rng=data.draw(st.integers(0, 2**32)))
    n_obs = data.draw(st.integers(0, 40))
    res = sample_herded(problem, n_obs, **kw)
    _same(reference.sample_herded(problem, n_obs, **kw), res)
    assert res.n_keys <= kw["max_keys"] and int(res.counts.sum()) == n_obs
    assert np.isfinite(res.costs).all()


@TWO_WORKERS_HERDED
@settings(max_examples=30, deadline=None)
@given(data=st.data())
def test_adaptive_birth_short_chains_reference_serial_parallel_and_slices_agree(data):
    problem, kw = data.draw(ab_cases())
    kw.update(herding=Herding(**_herding_kw(data)), rng=data.draw(st.integers(0, 2**32)),
              tau_stall=data.draw(st.sampled_from([None, 2, 4])),
              tau_stale=data.draw(st.sampled_from([None, 1, 4])))
    n_chains, chain_length = data.draw(st.integers(1, 60)), data.draw(st.integers(1, 8))
    one = sample_short_chains(problem, n_chains, chain_length, **kw)
    _same(reference.sample_short_chains(problem, n_chains, chain_length, **kw), one)
    _same(one, sample_short_chains(problem, n_chains, chain_length, workers=2, **kw),
          discarded=False)
    with pytest.MonkeyPatch.context() as m:
        m.setattr(samplers, "_SLICE_WORK", 1)
        _same(one, sample_short_chains(problem, n_chains, chain_length, workers=2, **kw),
              discarded=False)


# ------------------------------------------------------------------ fixed cases
def _ms(seed=0, P=3, M=(2, 2)):
    return ms_synthetic.random(P, M, rng=seed)


def _ab(seed=0):
    return _gaussian(seed, (3, 2, 2), 2)


@pytest.mark.parametrize("method", METHODS)
def test_a_tiny_table_falls_back_and_is_counted(method):
    p = _ms(1)
    for keys in KEYS:
        kw = dict(keys=keys, max_keys=2, rng=3, method=method)
        res = sample_herded(p, 200, **kw)
        assert res.n_keys == 2 and res.n_fallbacks > 0
        _same(res, reference.sample_herded(p, 200, **kw))
        free = sample_herded(p, 200, keys=keys, rng=3, method=method)
        assert free.n_fallbacks == 0 and free.n_keys > 2
    ab = sample_herded(_ab(), 200, max_keys=2, rng=3)
    assert ab.n_keys == 2 and ab.n_fallbacks > 0


@TWO_WORKERS_HERDED
def test_parallel_tallies_count_only_the_observed_sweeps():
    p = _ms(2, P=4, M=(3, 3))
    kw = dict(tau_stall=3, tau_stale=10, rng=2, herding=Herding(max_keys=30), method="mm")
    one = sample_short_chains(p, 400, 20, **kw)
    two = sample_short_chains(p, 400, 20, workers=2, **kw)
    _same(one, two, discarded=False)
    assert two.n_speculative_discarded > 0 and one.n_fallbacks > 0


@pytest.mark.parametrize("method", METHODS)
def test_deterministic_whatever_the_rng(method):
    """Systematic scan, room for every key, non-random initial weights: nothing is drawn."""
    p = _ms(3)
    for init in ("conditional", "zero"):
        a = sample_herded(p, 300, init=init, rng=1, method=method)
        _same(a, sample_herded(p, 300, init=init, rng=99, method=method))
        assert a.n_fallbacks == 0
    uniform = [sample_herded(p, 300, init="uniform", rng=r, method=method) for r in (1, 99)]
    assert uniform[0].n_keys > 0
    ab = _ab(1)
    _same(sample_herded(ab, 300, rng=1, sensor_order="fixed"),
          sample_herded(ab, 300, rng=99, sensor_order="fixed"))


def test_same_rng_same_result_and_uniform_weights_make_short_chains_differ():
    p = _ms(4)
    kw = dict(rng=5, method="exact")
    h = Herding(init="uniform")
    _same(sample_short_chains(p, 30, 10, herding=h, **kw),
          sample_short_chains(p, 30, 10, herding=h, **kw))
    same = sample_short_chains(p, 30, 10, herding=Herding(init="conditional"), **kw)
    seeded = sample_short_chains(p, 30, 10, herding=h, **kw)
    assert len(seeded) > 2 * len(same)          # identical deterministic chains add nothing


def test_adaptive_birth_shared_and_full_keys_are_one_key():
    """The conditional of sensor ``s`` depends on every other entry of the tuple."""
    for p in (_ab(2), AdaptiveBirthProblem.from_log_weights(
            np.random.default_rng(0).normal(size=(3, 4, 2)))):
        _same(sample_herded(p, 200, keys="shared", rng=1),
              sample_herded(p, 200, keys="full", rng=1))


def _independent_rows():
    """Three rows, two sensors with three measurements each; row ``n`` can only be given
    measurement ``n + 1`` of each sensor, so no row's conditional depends on another's."""
    rng = np.random.default_rng(0)
    P, M = 3, 3
    la = rng.normal(size=(P, M + 1, M + 1))
    for n in range(P):
        bad = [j for j in range(1, M + 1) if j != n + 1]
        la[n, bad, :] = -np.inf
        la[n, :, bad] = -np.inf
    return MultiSensorProblem(rng.normal(size=P), la)


def _row_frequencies(problem, res):
    """Each row's dead and tuple frequencies, in the layout of oracle.marginals."""
    P = problem.n_rows
    dead = np.zeros(P)
    tup = np.zeros((P,) + tuple(m + 1 for m in problem.n_meas))
    for g, k in zip(res.assignments, res.counts, strict=True):
        for n in range(P):
            if g[n, 0] < 0:
                dead[n] += k
            else:
                tup[(n,) + tuple(g[n])] += k
    total = res.counts.sum()
    return dead / total, tup / total


def test_exact_shared_keys_of_independent_rows_never_change():
    p = _independent_rows()
    n = 2_000
    exact = oracle.marginals(p)
    shared = sample_herded(p, n, method="exact")
    assert shared.n_keys == 3                # one key per row: no other row holds its gate
    dead, tup = _row_frequencies(p, shared)
    K = 1 + 16                               # dead and the 16 tuples
    assert np.abs(dead - exact.dead).max() <= K / n
    assert np.abs(tup - exact.tuples).max() <= K / n
    full = sample_herded(p, n, method="exact", keys="full")
    assert full.n_keys > 3                   # the other rows' states vary


def test_mm_shared_keys_of_independent_rows():
    """MM: the dead/alive draw and one draw per sensor, each of a key that never changes."""
    rng = np.random.default_rng(5)
    P, M = 3, 3
    log_s = np.log(rng.uniform(0.2, 0.9, P))
    th = [np.log(rng.uniform(0.1, 1.0, (P, M + 1))) for _ in range(2)]
    for n in range(P):
        for t in th:
            t[n, [j for j in range(1, M + 1) if j != n + 1]] = -np.inf
    la = log_s[:, None, None] + th[0][:, :, None] + th[1][:, None, :]
    q = MultiSensorProblem(np.log1p(-np.exp(log_s)), la, log_s, tuple(th))
    for method in ("mm", "mm-fixed"):
        for keys, n_keys in (("shared", P * 3), ("full", None)):
            res = sample_herded(q, 500, method=method, keys=keys)
            assert res.n_fallbacks == 0
            if n_keys is not None:
                assert res.n_keys == n_keys, (method, res.n_keys)
            else:
                assert res.n_keys > P * 3


def _tv(problem, res):
    """Total variation between the visit frequencies and the exact posterior."""
    ranked = oracle.enumerate_assignments(problem)
    pi = np.exp(-(ranked.costs - ranked.costs.min()))
    pi /= pi.sum()
    index = {a.tobytes(): i for i, a in enumerate(np.asarray(ranked.assignments, np.int64))}
    freq = np.zeros(len(pi))
    for a, k in zip(np.asarray(res.assignments, np.int64), res.counts, strict=True):
        freq[index[a.tobytes()]] += k
    return 0.5 * np.abs(freq / freq.sum() - pi).sum()


def test_long_herded_chains_approach_the_posterior():
    """On a tiny problem (68 assignments; 24 tuples for adaptive birth) the frequencies of a
    long herded chain are at most half as far from the exact posterior (total variation) as
    those of Gibbs chains of the same length (mean of three seeds; deterministic, so no false
    failures). docs/herding.md has the numbers."""
    p = ms_synthetic.random(2, (2, 2), rng=7)     # separable: the MM surrogate is exact
    n = 20_000
    for method in ("exact", "mm"):
        gibbs = np.mean([_tv(p, sample_original(p, n, rng=r, method=method)) for r in range(3)])
        for keys in KEYS:
            herded = _tv(p, sample_herded(p, n, keys=keys, method=method))
            assert herded <= gibbs / 2, (method, keys, herded, gibbs)
    ab = _ab(3)
    gibbs = np.mean([_tv(ab, sample_original(ab, n, rng=r)) for r in range(3)])
    assert _tv(ab, sample_herded(ab, n, sensor_order="fixed")) <= gibbs / 2


# ------------------------------------------------------------------ bad input
@pytest.mark.parametrize("problem, kw, exc, msg", [
    ("ms", {"keys": "leaf"}, ValueError, r"unknown keys 'leaf'"),
    ("ms", {"init": "random"}, ValueError, r"unknown init 'random'"),
    ("ms", {"max_keys": 0}, ValueError, "max_keys"),
    ("ms", {"method": "gibbs"}, ValueError, "method"),
    ("ms", {"method": "componentwise", "beta": 0.5}, ValueError,
     r"beta != 1 does not apply to method='componentwise'"),
    ("ab", {"scan": "random"}, ValueError, r"scan='random' does not apply"),
    ("ab", {"sensor_order": "zigzag"}, ValueError, "sensor_order"),
    ("ab", {"method": "exact"}, TypeError, r"unexpected option\(s\) \['method'\]"),
])
def test_bad_input(problem, kw, exc, msg):
    p = _ms() if problem == "ms" else _ab()
    for backend in ("numba", "python"):
        with pytest.raises(exc, match=msg):
            sample_herded(p, 10, backend=backend, **kw)


# ------------------------------------------------------------------ LMB association
def test_multisensor_herded_association_in_the_lmb_filter():
    from rankedassign.tracking import (
        HerdedGibbs,
        MultiSensorLMBFilter,
        make_multisensor_model,
        make_multisensor_scenario,
        run_filter,
    )

    sensors = (0, 2)
    sc = make_multisensor_scenario(rng=0, n_scans=8, sensors=sensors)
    scans = [tuple(s.z for s in scan) for scan in sc.scans]
    for assoc in (HerdedGibbs(100, method="exact"),
                  HerdedGibbs(10, n_chains=40, tau_stall=3, tau_stale=5,
                                         method="mm")):
        a, b = (run_filter(MultiSensorLMBFilter(make_multisensor_model(sensors), assoc), scans,
                           rng=1, truth=sc.truth) for _ in range(2))
        assert np.isfinite(a.ospa2.value).all() and a.estimates.shape[0] == 8
        r = [v for scan in a.existence for v in scan.values()]
        assert r and all(0.0 <= v <= 1.0 for v in r)           # finite existence
        est = a.estimates[~np.isnan(a.estimates)]
        assert np.isfinite(est).all() and int(a.sweeps.sum()) > 0
        assert_array_equal(a.estimates, b.estimates)            # reproducible
        assert a.existence == b.existence
    p = _ms(5)
    out = HerdedGibbs(200, method="exact")(p, 7)
    res = sample_herded(p, 200, rng=7, method="exact")
    assert out.sweeps == 200 and out.n_unique == len(res)
    assert np.isfinite(out.dead).all() and np.isfinite(out.tuples).all()
    short = HerdedGibbs(25, n_chains=100, tau_stall=5, tau_stale=10, method="exact")
    assert short.herding.init == "uniform"
    got = short(p, 7)
    ref = sample_short_chains(p, 100, 25, tau_stall=5, tau_stale=10, rng=7, method="exact",
                              herding=Herding(init="uniform"))
    assert got.sweeps == ref.n_observations and got.n_unique == len(ref)
    assert repr(HerdedGibbs(25, n_chains=400, tau_stall=5, tau_stale=10,
                            keys="full", method="exact")) == \
        "HerdedGibbs(25, keys='full', n_chains=400, tau_stall=5, tau_stale=10, method='exact')"
