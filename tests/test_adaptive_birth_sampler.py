"""Adaptive-birth Gibbs sampler: reference ≡ numba row update, stationarity (multisensor §4.3)."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from numpy.testing import assert_array_equal
from scipy.stats import chi2

from oracle.adaptive_birth import exact as ob
from rankedassign.adaptive_birth import AdaptiveBirthProblem
from rankedassign.adaptive_birth import _kernels as kern
from rankedassign.adaptive_birth import reference as ref
from rankedassign.adaptive_birth.prepare import chain_inputs
from rankedassign.engine.rng import SplitMix64, chain_state


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
def problems(draw):
    V = draw(st.integers(1, 4))
    M = tuple(draw(st.integers(0, 4)) for _ in range(V))
    seed = draw(st.integers(0, 2**32 - 1))
    if draw(st.booleans()):
        return _gaussian(seed, M, draw(st.integers(1, 4)))
    g = np.random.default_rng(seed)
    t = g.normal(0, 3, tuple(m + 1 for m in M))
    t[g.uniform(size=t.shape) < 0.3] = -np.inf
    t[(0,) * V] = 0.0
    return AdaptiveBirthProblem.from_log_weights(t)


def _zkeys(problem):
    K = max(problem.shape)
    g = np.random.default_rng(0)
    return g.integers(0, 2**63, (problem.n_sensors, K), dtype=np.uint64)


def _hash(zk, x):
    h = np.uint64(0)
    for v, j in enumerate(x):
        h ^= zk[v, j]
    return h


@given(problems(), st.sampled_from(["random", "fixed"]), st.integers(0, 2**63 - 1))
def test_reference_and_kernel_agree_bit_for_bit(problem, order, base):
    data = chain_inputs(problem, order)
    rd = ref.reference_data(data)
    zk = _zkeys(problem)
    work = kern.alloc_work(data, 2)
    for c in range(2):
        x = [0] * problem.n_sensors
        w = ref.new_work(rd, x)
        g = SplitMix64(chain_state(base, c))
        state = np.zeros(problem.n_sensors, dtype=np.int32)
        kern.reset_work(data, work, c, state)
        rs = np.array([chain_state(base, c)], dtype=np.uint64)
        h = np.uint64(0) ^ _hash(zk, state)
        for _ in range(15):
            ref.sweep(rd, w, x, g)
            # the kernel returns the hash as a Python int; passed back as it is, it would
            # compile the sweep a second time (int64 instead of the drivers' uint64)
            h = np.uint64(kern.sweep(data, work, c, zk, state, h, rs))
            assert x == state.tolist()
            assert h == _hash(zk, state)
            assert problem.log_weight_of(x) > -np.inf
        assert g.state == int(rs[0])               # same number of uniforms consumed


def _one_sweep_counts(problem, order, start, n, base):
    """Counts of the state after one sweep from ``start`` over ``n`` independent streams."""
    data = chain_inputs(problem, order)
    work = kern.alloc_work(data, 1)
    zk = _zkeys(problem)
    counts = np.zeros(problem.n_feasible(), dtype=np.int64)
    rs = np.zeros(1, dtype=np.uint64)
    for c in range(n):
        state = np.array(start, dtype=np.int32)
        rs[0] = chain_state(base, c)
        kern.sweep(data, work, 0, zk, state, np.uint64(0), rs)
        counts[np.ravel_multi_index(tuple(state), problem.shape)] += 1
    return counts


@pytest.mark.parametrize("order", ["random", "fixed"])
def test_one_sweep_law_is_the_exact_transition_matrix(order):
    # Spec §6.6 item 2 via §6.4: the exact one-sweep matrix K of the oracle has pi_B as its
    # only stationary law (tests/test_adaptive_birth.py), so a kernel whose one-sweep law
    # equals K from every state samples pi_B. From each of the 24 tuples of a 3-sensor problem,
    # 800 independent one-sweep chains; cells with expected count < 5 pooled per row; one
    # pooled chi-square test, alpha = 1e-4: fixed seed, false-failure probability 1e-4.
    g = np.random.default_rng(11)
    z = [np.array([[0.0], [3.0]]), np.array([[0.5]]), np.array([[0.2], [-4.0], [1.0]])]
    problem = AdaptiveBirthProblem.from_measurements(
        z, [g.uniform(0.5, 1, 2), [0.9], g.uniform(0.5, 1, 3)], H=[[1.0]], R=[[[1.0]], [[2.0]], [[1.5]]],
        P_D=[0.6, 0.7, 0.5], clutter_intensity=0.05, mu0=[0.0], P0=[[9.0]], tau_rU=0.0)
    K, pi = ob.transition_matrix(problem, order)
    n = 800
    stat, df = 0.0, 0
    for a in range(problem.n_feasible()):
        start = np.unravel_index(a, problem.shape)
        obs = _one_sweep_counts(problem, order, start, n, base=1000 + a)
        exp = n * K[a]
        big = exp >= 5
        o = np.append(obs[big], obs[~big].sum())
        e = np.append(exp[big], exp[~big].sum())
        if e[-1] == 0:
            assert o[-1] == 0
            o, e = o[:-1], e[:-1]
        stat += float(np.sum((o - e) ** 2 / e))
        df += len(e) - 1
    assert chi2.sf(stat, df) > 1e-4, (stat, df)


def test_fixed_order_never_draws_an_order_uniform():
    # V uniforms per sweep with sensor_order="fixed", 2V - 1 with "random"
    problem = AdaptiveBirthProblem.from_log_weights(np.zeros((2, 2, 2)))
    for order, per_sweep in (("fixed", 3), ("random", 5)):
        rd = ref.reference_data(chain_inputs(problem, order))
        x = [0, 0, 0]
        g = SplitMix64(5)
        ref.sweep(rd, ref.new_work(rd, x), x, g)
        h = SplitMix64(5)
        for _ in range(per_sweep):
            h.uniform()
        assert g.state == h.state


def test_chain_visits_only_positive_weight_tuples_and_moves():
    t = np.full((3, 3), -np.inf)
    t[0, 0] = 0.0
    t[0, 2] = 5.0
    t[1, 2] = 5.0
    problem = AdaptiveBirthProblem.from_log_weights(t, n_min=1)
    rd = ref.reference_data(chain_inputs(problem, "fixed"))
    x = [0, 0]
    g = SplitMix64(3)
    w = ref.new_work(rd, x)
    seen = set()
    for _ in range(200):
        ref.sweep(rd, w, x, g)
        seen.add(tuple(x))
    assert seen <= {(0, 0), (0, 2), (1, 2)} and (1, 2) in seen
    assert_array_equal(sorted(seen)[-1], [1, 2])
