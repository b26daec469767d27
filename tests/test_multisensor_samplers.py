"""Multi-sensor samplers: reference row updates ≡ numba kernels bit for bit, preparation,
start states, packaging and every error message.

The pure-Python sweeps of :mod:`rankedassign.multisensor.reference` are the specification; the
numba sweep must produce the same states, consume the same uniforms and keep the Zobrist hash
of its state, on every method, scan and family (hypothesis; ``P = 0``, sensors without
measurements and ``V = 1..4`` included).
"""

import dataclasses

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from ms_standin import KINDS, StandIn, random_problem
from numpy.testing import assert_allclose, assert_array_equal

from rankedassign import kinds, sample_original, sample_short_chains
from rankedassign.engine._kernels import zobrist_keys
from rankedassign.engine.rng import SplitMix64
from rankedassign.multisensor import _kernels as K
from rankedassign.multisensor import reference as R
from rankedassign.multisensor.prepare import (
    METHODS,
    assignment_costs,
    prepare_data,
    start_state,
    states_to_assignments,
)


def _hash(zk, s):
    h = np.uint64(0)
    for pos, val in enumerate(s):
        h ^= zk[pos, val]
    return h


def run_both(problem, method, scan, survival_power, n_sweeps, seed, start="all_missed"):
    """Sweep the reference and the kernel side by side; assert equality after every sweep."""
    data = prepare_data(problem, method, scan, survival_power)
    rd = R.RefData(data)
    x0 = start_state(problem, start, method)
    x = x0.tolist()
    occ = R.new_work(rd, x)
    g = SplitMix64(seed)
    work = K.alloc_work(data, 3)
    K.reset_work(data, work, 2, x0)  # any slab: use the last one
    s = x0.copy()
    rs = np.array([seed], dtype=np.uint64)
    zk = zobrist_keys(len(s), max(problem.n_meas, default=0) + 2, np.uint64(7))
    h = _hash(zk, s)
    trajectory = []
    for _ in range(n_sweeps):
        R.sweep(rd, occ, x, g)
        h = np.uint64(K.sweep(data, work, 2, zk, s, h, rs))
        assert x == s.tolist()
        assert g.state == int(rs[0])
        assert h == _hash(zk, s)
        assert occ == [work.occ[2, v, : m + 1].tolist() for v, m in enumerate(problem.n_meas)]
        trajectory.append(list(x))
    return trajectory


@st.composite
def cases(draw):
    V = draw(st.integers(1, 4))
    P = draw(st.integers(0, 3))
    cap = {1: 4, 2: 3, 3: 2, 4: 2}[V]
    M = tuple(draw(st.integers(0, cap)) for _ in range(V))
    kind = draw(st.sampled_from(KINDS))
    seed = draw(st.integers(0, 2**32 - 1))
    return random_problem(P, M, seed, kind), seed


@given(case=cases(), method=st.sampled_from(METHODS),
       scan=st.sampled_from(["systematic", "random"]), power=st.sampled_from([1, "V"]),
       n_sweeps=st.integers(1, 12))
def test_reference_and_kernel_agree_bit_for_bit(case, method, scan, power, n_sweeps):
    problem, seed = case
    run_both(problem, method, scan, power, n_sweeps, seed)


def underflow_problem():
    """Row 0's best entry (measurement 1 of sensor 0) is ~800 above the rest of its row; while
    row 1 holds that measurement, every available shifted weight of row 0 underflows to 0 (for
    MM both the dead and the alive weight), so the exact fall-back draws run."""
    log_s = np.array([0.0, 0.0])
    th0 = np.array([[-800.0, 0.0], [-1.0, 0.0]])
    th1 = np.array([[0.0, -0.5], [0.0, -2.0]])
    la = log_s[:, None, None] + th0[:, :, None] + th1[:, None, :]
    return StandIn([-800.0, -1.0], la, log_s, (th0, th1))


@pytest.mark.parametrize("method", METHODS)
def test_agreement_on_the_underflow_path(method):
    traj = run_both(underflow_problem(), method, "systematic", 1, 60, 5,
                    start=[[0, 0], [1, 0]])
    rows0 = {tuple(t[:2]) for t in traj}
    assert len(rows0) > 1  # row 0 moves among its underflowed candidates


@pytest.mark.parametrize("method", METHODS)
def test_agreement_on_a_larger_problem(method):
    for kind in ("coupled", "extreme"):
        run_both(random_problem(4, (3, 0, 2), 11, kind), method, "random", "V", 40, 5)


def test_states_stay_feasible():
    problem = random_problem(4, (2, 3), 3, "coupled")
    for method in METHODS:
        for x in run_both(problem, method, "systematic", 1, 50, 1):
            g = states_to_assignments(problem, np.array([x]))[0]
            dead = g[:, 0] < 0
            assert ((g < 0) == dead[:, None]).all()  # all-or-none dead rows (spec eq. 1.1)
            for v in range(2):
                used = g[:, v][g[:, v] > 0]
                assert len(set(used.tolist())) == len(used)  # positive 1-1 per sensor
            if method == "componentwise":
                assert not dead.any()  # the collapsed space has no dead row


def test_exact_start_all_dead_and_explicit():
    problem = random_problem(3, (2, 2), 4, "coupled")
    run_both(problem, "exact", "systematic", 1, 5, 2, start="all_dead")
    run_both(problem, "mm", "systematic", 1, 5, 2, start=[[1, 2], [-1, -1], [0, 1]])


# ------------------------------------------------------------------------------ preparation
def test_shifted_weights_and_targets():
    problem = random_problem(2, (1, 2), 0, "coupled")
    data = prepare_data(problem, "exact", "random")
    Wd, ld, Wa, la = data.Wd, data.ld, data.Wa, data.la
    assert (data.method, data.random_scan, data.P, data.V) == (0, True, 2, 2)
    assert data.n_meas.tolist() == [1, 2] and data.strides.tolist() == [3, 1]
    full = np.concatenate([ld[:, None], la], axis=1)
    assert_allclose(np.concatenate([Wd[:, None], Wa], axis=1),
                    np.exp(full - full.max(axis=1, keepdims=True)), rtol=1e-15)
    # componentwise: dead merged into (0, ..., 0) (spec §1.6)
    la_c = prepare_data(problem, "componentwise", "systematic").la
    assert_allclose(la_c[:, 0], np.logaddexp(problem.log_eta_dead,
                                             problem.log_eta_alive[:, 0, 0]), rtol=1e-15)
    assert_array_equal(la_c[:, 1:], problem.log_eta_alive.reshape(2, -1)[:, 1:])


def test_mm_dead_probabilities():
    problem = random_problem(3, (2, 1), 1, "separable")
    for power, alpha in ((1, 1), ("V", 2)):
        data = prepare_data(problem, "mm-fixed", "systematic", power)
        qdead = data.qdead
        full = alpha * problem.log_s + sum(np.logaddexp.reduce(t, axis=1)
                                           for t in problem.log_theta)
        expect = np.exp(problem.log_eta_dead) / (np.exp(problem.log_eta_dead) + np.exp(full))
        assert_allclose(qdead, expect, rtol=1e-12)
        # exclusion variant at the all-missed state of the other rows: Ed / (Ed + Ea prod sums)
        data = prepare_data(problem, "mm", "systematic", power)
        Th, Ea, Ed = data.Th, data.Ea, data.Ed
        q_excl = Ed / (Ed + Ea * Th.sum(axis=2).prod(axis=1))
        assert_allclose(q_excl, expect, rtol=1e-12)


def test_costs_are_exact_log_weights():
    problem = random_problem(2, (2, 1), 2, "coupled")
    g = np.array([[[1, 0], [-1, -1]], [[0, 1], [2, 0]]])
    la, ld = problem.log_eta_alive, problem.log_eta_dead
    expect = [-(la[0, 1, 0] + ld[1]), -(la[0, 0, 1] + la[1, 2, 0])]
    assert_allclose(assignment_costs(problem, g, "mm"), expect, rtol=1e-15)
    gc = np.array([[[0, 0], [2, 1]]])
    expect_c = -(np.logaddexp(ld[0], la[0, 0, 0]) + la[1, 2, 1])
    assert_allclose(assignment_costs(problem, gc, "componentwise"), [expect_c], rtol=1e-15)


def test_state_encoding():
    problem = random_problem(2, (2, 1), 2)
    x = start_state(problem, [[2, 0], [-1, -1]], "exact")
    assert x.dtype == np.int32 and x.tolist() == [3, 1, 0, 0]
    assert_array_equal(states_to_assignments(problem, x[None]), [[[2, 0], [-1, -1]]])
    assert start_state(problem, "all_missed", "mm").tolist() == [1, 1, 1, 1]
    assert start_state(problem, "all_dead", "exact").tolist() == [0, 0, 0, 0]
    # the collapsed space has no dead row: all_dead is all_missed there
    assert start_state(problem, "all_dead", "componentwise").tolist() == [1, 1, 1, 1]


def test_zero_rows_and_sensor_without_measurements():
    run_both(random_problem(0, (2, 0), 1), "exact", "random", 1, 3, 1)
    p = random_problem(2, (0,), 1, "coupled")
    for method in METHODS:
        run_both(p, method, "systematic", 1, 5, 3)


def test_the_workspace_holds_the_mm_dead_alive_draw_without_measurements():
    """MM's dead/alive draw writes two candidate slots; with no measurement on any sensor the
    workspace once had one (numba checks no bounds: the write went past the array)."""
    p = random_problem(2, (0,), 1, "coupled")
    for method in METHODS:
        data = prepare_data(p, method, "systematic")
        wbuf, lbuf = K.alloc_work(data, 3)[4:6]
        assert wbuf.shape[1] >= 2 and lbuf.shape[1] >= 2, method


# ------------------------------------------------------------------------------ errors
def test_error_messages():
    problem = random_problem(2, (1, 1), 0)
    with pytest.raises(ValueError, match=r"unknown method 'gibbs'; expected one of"):
        prepare_data(problem, "gibbs", "systematic")
    with pytest.raises(ValueError, match=r"unknown scan 'rand'"):
        prepare_data(problem, "exact", "rand")
    with pytest.raises(ValueError, match=r"unknown survival_power 2; expected one of \(1, 'V'\)"):
        prepare_data(problem, "mm", "systematic", 2)
    with pytest.raises(ValueError, match=r"unknown survival_power True"):
        prepare_data(problem, "mm", "systematic", True)
    bare = StandIn(problem.log_eta_dead, problem.log_eta_alive)
    with pytest.raises(ValueError, match=r"method='mm' needs the separable factors log_s and "
                                         r"log_theta of the problem \(spec §3.1\)"):
        prepare_data(bare, "mm", "systematic")
    with pytest.raises(ValueError, match=r"method='mm-fixed' needs the separable factors"):
        prepare_data(bare, "mm-fixed", "systematic")
    prepare_data(bare, "exact", "systematic")  # exact and componentwise need no factors


def test_start_error_messages():
    problem = random_problem(2, (1, 2), 0)
    with pytest.raises(ValueError, match=r"unknown start 'lsap'; expected one of"):
        start_state(problem, "lsap", "exact")
    with pytest.raises(TypeError, match=r"start must be 'all_missed', 'all_dead' or an integer "
                                        r"array gamma of shape \(P, V\), got dtype float64"):
        start_state(problem, np.zeros((2, 2)), "exact")
    with pytest.raises(ValueError, match=r"start array must have shape \(P, V\) = \(2, 2\), "
                                         r"got \(2,\)"):
        start_state(problem, [0, 0], "exact")
    with pytest.raises(ValueError, match=r"has an index outside -1..M_v"):
        start_state(problem, [[2, 0], [0, 0]], "exact")
    with pytest.raises(ValueError, match=r"start rows \[1\] are partly dead"):
        start_state(problem, [[0, 0], [-1, 0]], "exact")
    with pytest.raises(ValueError, match=r"uses a measurement of sensor 1 twice"):
        start_state(problem, [[0, 2], [1, 2]], "exact")
    la = problem.log_eta_alive.copy()
    la[1, 0, 0] = -np.inf
    ld = problem.log_eta_dead.copy()
    ld[0] = -np.inf
    p2 = StandIn(ld, la)
    with pytest.raises(ValueError, match=r"start 'all_missed' is infeasible: rows \[1\] have "
                                         r"zero weight there"):
        start_state(p2, "all_missed", "exact")
    with pytest.raises(ValueError, match=r"start 'all_dead' is infeasible: rows \[0\]"):
        start_state(p2, "all_dead", "exact")
    with pytest.raises(ValueError, match=r"start 'the start array' is infeasible: rows \[0\]"):
        start_state(p2, [[-1, -1], [1, 1]], "exact")
    # collapsed: row 1 at (0, 0) keeps the weight of dead
    assert start_state(p2, "all_missed", "componentwise").tolist() == [1, 1, 1, 1]


# ------------------------------------------------------------------------------ public API
@pytest.fixture(scope="module")
def registered():
    """The stand-in problem dispatches like the real MultiSensorProblem."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(kinds, "KINDS", kinds.KINDS + (dataclasses.replace(kinds.kind_named("multisensor"), problem_type=StandIn),))
        yield


STALLS = ["global-consecutive", "global-cumulative", "chain-local"]
STALES = ["consecutive", "cumulative", "literal-set", "literal-multiset"]


def assert_same(a, b, discarded=True):
    assert_array_equal(a.assignments, b.assignments)
    assert_array_equal(a.costs, b.costs)
    assert_array_equal(a.counts, b.counts)
    assert (a.n_observations, a.n_row_updates, a.n_chains_run, a.stop_reason) == (
        b.n_observations, b.n_row_updates, b.n_chains_run, b.stop_reason)
    if discarded:
        assert a.n_speculative_discarded == b.n_speculative_discarded


@given(case=cases(), method=st.sampled_from(METHODS),
       scan=st.sampled_from(["systematic", "random"]), stall=st.sampled_from(STALLS),
       stale=st.sampled_from(STALES), tau_stall=st.sampled_from([None, 1, 3]),
       tau_stale=st.sampled_from([None, 1, 4]), n_chains=st.integers(0, 12),
       chain_length=st.integers(0, 6))
def test_short_chains_numba_equals_reference(registered, case, method, scan, stall, stale,
                                             tau_stall, tau_stale, n_chains, chain_length):
    problem, seed = case
    kw = dict(tau_stall=tau_stall, tau_stale=tau_stale, stall=stall, stale=stale, scan=scan,
              rng=seed, method=method)
    nb = sample_short_chains(problem, n_chains, chain_length, **kw)
    py = sample_short_chains(problem, n_chains, chain_length, backend="python", **kw)
    assert_same(nb, py)
    assert nb.assignments.shape == (len(nb), problem.n_rows, problem.n_sensors)
    par = sample_short_chains(problem, n_chains, chain_length, workers=2, **kw)
    assert_same(par, nb, discarded=False)


def test_original_sampler_result(registered):
    problem = random_problem(3, (2, 2), 1, "coupled")
    for method in METHODS:
        res = sample_original(problem, 300, rng=4, method=method)
        ref = sample_original(problem, 300, rng=4, method=method, backend="python")
        assert_same(res, ref)
        assert res.n_observations == 300 and res.n_chains_run == 1
        assert res.n_row_updates == 900 and int(res.counts.sum()) == 300
        assert res.assignments.shape == (len(res), 3, 2)
        assert_array_equal(res.assignments[0], np.zeros((3, 2)))  # all-missed start first
        assert len(res) > 5
        # exact -log w(gamma) for every method (collapsed weights for componentwise)
        assert_allclose(res.costs, assignment_costs(problem, res.assignments, method),
                        rtol=0, atol=0)
        # the original sampler is one short chain without rules
        assert_same(res, sample_short_chains(problem, 1, 300, rng=4, method=method))


def test_default_method_is_mm_and_options(registered):
    problem = random_problem(3, (2, 1), 2, "coupled")
    assert_same(sample_original(problem, 50, rng=1),
                sample_original(problem, 50, rng=1, method="mm", survival_power=1))
    a = sample_original(problem, 50, rng=1, survival_power="V")
    assert a.n_observations == 50
    res = sample_original(problem, 20, rng=1, method="exact", start="all_dead")
    assert_array_equal(res.assignments[0], -np.ones((3, 2)))
    start = [[1, 0], [-1, -1], [2, 1]]
    res = sample_original(problem, 20, rng=1, method="exact", start=start)
    assert_array_equal(res.assignments[0], start)


def test_public_error_messages(registered):
    problem = random_problem(2, (1, 1), 0)
    bare = StandIn(problem.log_eta_dead, problem.log_eta_alive)
    with pytest.raises(ValueError, match=r"method='mm' needs the separable factors"):
        sample_original(bare, 5)  # the default method needs log_s and log_theta
    with pytest.raises(TypeError, match=r"unexpected option\(s\) \['mode'\] for a multi-sensor "
                                        r"problem; expected 'method' and 'survival_power'"):
        sample_short_chains(problem, 2, 2, mode="x")
    with pytest.raises(ValueError, match=r"unknown method 'gibbs'"):
        sample_original(problem, 5, method="gibbs", backend="python")


# ------------------------------------------------------------------------------ real class
@pytest.mark.parametrize("family", ["random", "random_coupled", "diagonal", "uniform"])
def test_real_problem_class(family):
    from rankedassign.multisensor import MultiSensorProblem, synthetic

    make = getattr(synthetic, family)
    problem = make(P=3, M=(2, 2), rng=1) if family.startswith("random") else make(P=3, M=(2, 2))
    assert isinstance(problem, MultiSensorProblem)
    for method in METHODS:
        res = sample_short_chains(problem, 30, 10, tau_stall=5, tau_stale=10, rng=2,
                                  method=method)
        assert_same(res, sample_short_chains(problem, 30, 10, tau_stall=5, tau_stale=10, rng=2,
                                             method=method, backend="python"))
        if method != "componentwise":
            assert_allclose(res.costs, -problem.log_weight_of(res.assignments), rtol=1e-13)
    bare = MultiSensorProblem.from_log_eta(problem.log_eta_dead, problem.log_eta_alive)
    with pytest.raises(ValueError, match=r"method='mm' needs the separable factors"):
        sample_original(bare, 5)
    assert len(sample_original(bare, 5, method="exact", rng=0)) >= 1
