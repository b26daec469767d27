"""Adaptive-birth problem model, birth LMB and oracle (multisensor spec §4, §5, §6.1, §6.4)."""

import itertools

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal
from scipy.special import logsumexp
from scipy.stats import multivariate_normal

import oracle
from oracle.adaptive_birth import exact as ob
from rankedassign.adaptive_birth import AdaptiveBirthProblem, birth_from_samples
from rankedassign.adaptive_birth import reference as ref
from rankedassign.adaptive_birth.prepare import chain_inputs
from rankedassign.adaptive_birth.synthetic import make_family

H4 = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]])
P0 = np.diag([300.0**2, 20.0**2, 300.0**2, 20.0**2])


def gaussian_problem(seed=0, M=(3, 2, 3), n_min=2, tau_rU=0.0):
    """Three position sensors with different R, P_D and clutter on a 4-D state."""
    g = np.random.default_rng(seed)
    V = len(M)
    target = g.uniform(-100, 100, 2)
    z, ru = [], []
    for v in range(V):
        zz = g.uniform(-300, 300, (M[v], 2))
        if M[v]:
            zz[0] = target + g.normal(0, 5, 2)
        z.append(zz)
        ru.append(g.uniform(0.5, 1.0, M[v]))
    R = [np.diag([25.0, 36.0]), np.array([[16.0, 4.0], [4.0, 30.0]]), 49.0 * np.eye(2)][:V]
    R += [25.0 * np.eye(2)] * (V - len(R))
    return AdaptiveBirthProblem.from_measurements(
        z, ru, H=H4, R=R, P_D=list(np.linspace(0.6, 0.9, V)),
        clutter_intensity=[1e-4 * (v + 1) for v in range(V)], mu0=[10.0, 1.0, -5.0, 0.0],
        P0=P0, tau_rU=tau_rU, n_min=n_min), z, ru, R


# ----------------------------------------------------------------------------- problem model
def test_closed_form_equals_stacked_gaussian_on_every_tuple():
    # spec §4.2: rho(J) = prod r_U * Pi_miss * Pi_det * N(z_D; H_D mu0, H_D P0 H_D' + R_D)
    p, z, ru, R = gaussian_problem()
    pd = np.linspace(0.6, 0.9, 3)
    mu0 = np.array([10.0, 1.0, -5.0, 0.0])
    for J in itertools.product(*[range(m + 1) for m in p.n_meas]):
        want = 0.0
        zs, Hs, Rs = [], [], []
        for v, j in enumerate(J):
            if j == 0:
                want += np.log1p(-pd[v])
            else:
                want += np.log(ru[v][j - 1]) + np.log(pd[v]) - np.log(1e-4 * (v + 1))
                zs.append(z[v][j - 1])
                Hs.append(H4)
                Rs.append(R[v])
        if zs:
            HD = np.vstack(Hs)
            RD = np.zeros((2 * len(Rs),) * 2)
            for k, Rk in enumerate(Rs):
                RD[2 * k:2 * k + 2, 2 * k:2 * k + 2] = Rk
            want += multivariate_normal(HD @ mu0, HD @ P0 @ HD.T + RD).logpdf(np.concatenate(zs))
        assert_allclose(p.log_weight_of(list(J)), want, rtol=1e-9, atol=1e-9)


def test_posterior_equals_stacked_kalman_update():
    p, z, _, R = gaussian_problem()
    J = [1, 2, 0]
    mu0 = np.array([10.0, 1.0, -5.0, 0.0])
    HD = np.vstack([H4, H4])
    RD = np.zeros((4, 4))
    RD[:2, :2], RD[2:, 2:] = R[0], R[1]
    S = HD @ P0 @ HD.T + RD
    K = P0 @ HD.T @ np.linalg.inv(S)
    m = mu0 + K @ (np.concatenate([z[0][0], z[1][1]]) - HD @ mu0)
    P = P0 - K @ S @ K.T
    means, covs = p.posterior([J])
    assert_allclose(means[0], m, rtol=1e-8)
    assert_allclose(covs[0], P, rtol=1e-7, atol=1e-9)


def test_ratio_form_conditional_is_the_exact_conditional():
    # spec eq. 4.3: the row update's log-weights differ from ln rho(J^-s + j) by a constant in j
    p, *_ = gaussian_problem(seed=3)
    rd = ref.reference_data(chain_inputs(p))
    for J in itertools.product(*[range(m + 1) for m in p.n_meas]):
        x = list(J)
        for s in range(3):
            work = ref.new_work(rd, x)
            ref._sums(rd, work, x)
            lw, _ = ref.conditional_log_weights(rd, work, x, s)
            full = [p.log_weight_of(x[:s] + [j] + x[s + 1:]) for j in range(p.shape[s])]
            d = np.asarray(lw) - np.asarray(full)
            assert np.ptp(d) < 1e-9


def test_tau_rU_drop_rule_keeps_strictly_greater():
    z = [np.array([[0.0], [1.0], [2.0]])]
    p = AdaptiveBirthProblem.from_measurements(
        z, [[0.95, 0.9, 0.91]], H=[[1.0]], R=[[1.0]], P_D=0.5, clutter_intensity=1.0,
        mu0=[0.0], P0=[[1.0]], n_min=1)
    assert p.n_meas == (2,)
    assert_array_equal(p.kept[0], [0, 2])
    b = birth_from_samples(p, [[2]])
    assert_array_equal(b.measurements, [[2]])


def test_empty_sensor_and_log_weights_tensor():
    z = [np.zeros((0, 1)), np.array([[0.5]])]
    p = AdaptiveBirthProblem.from_measurements(
        z, [[], [0.99]], H=[[1.0]], R=[[1.0]], P_D=[0.5, 0.6], clutter_intensity=0.1,
        mu0=[0.0], P0=[[4.0]], n_min=1)
    assert p.shape == (1, 2)
    t = p.log_weights()
    assert t.shape == (1, 2) and not t.flags.writeable
    q = AdaptiveBirthProblem.from_log_weights(t, n_min=1)
    assert_allclose(q.log_weight_of([[0, 0], [0, 1]]), p.log_weight_of([[0, 0], [0, 1]]),
                    rtol=0, atol=0)
    assert repr(p) == "AdaptiveBirthProblem(V=2, n_meas=(0, 1), n_min=1, gaussian)"
    assert repr(q) == "AdaptiveBirthProblem(V=2, n_meas=(0, 1), n_min=1, tensor)"


@pytest.mark.parametrize("tensor, exc, match", [
    (np.float64(1.0), ValueError, "one axis per sensor"),
    (np.zeros((2, 0)), ValueError, "empty axis"),
    (np.array([0.0, np.nan]), ValueError, "contains NaN"),
    (np.array([0.0, np.inf]), ValueError, r"contains \+inf"),
    (np.array([-np.inf, 0.0]), ValueError, "all-missed tuple .* must be finite"),
    ([["a"]], TypeError, "log_weights must be a numeric array"),
])
def test_from_log_weights_errors(tensor, exc, match):
    with pytest.raises(exc, match=match):
        AdaptiveBirthProblem.from_log_weights(tensor)


def test_from_log_weights_n_min_errors():
    with pytest.raises(ValueError, match="n_min must be an int <= 2"):
        AdaptiveBirthProblem.from_log_weights(np.zeros((2, 2)), n_min=3)
    with pytest.raises(TypeError, match="n_min must be an int, got float"):
        AdaptiveBirthProblem.from_log_weights(np.zeros((2, 2)), n_min=1.0)


def _kw(**over):
    kw = dict(H=[[1.0]], R=[[1.0]], P_D=0.5, clutter_intensity=1.0, mu0=[0.0], P0=[[1.0]])
    kw.update(over)
    return kw


@pytest.mark.parametrize("args, kw, exc, match", [
    (([], []), _kw(), TypeError, "measurements must be a non-empty list"),
    (([[[0.0]]], [[1.0]]), _kw(mu0=[]), ValueError, "mu0 must have at least one"),
    (([[[0.0]]], [[1.0]]), _kw(P0=[[1.0, 0.0]]), ValueError, r"P0 must have shape \(n, n\)"),
    (([[[0.0]]], [[1.0]]), _kw(P0=[[-1.0]]), ValueError, "P0 must be positive definite"),
    (([[[0.0]]], [[1.0]]), _kw(H=[[1.0, 0.0]]), ValueError, r"H\[0\] must have n = 1 columns"),
    (([[[0.0]]], [[1.0]]), _kw(R=[[1.0, 0.0], [0.0, 1.0]]), ValueError,
     r"R\[0\] must have shape \(1, 1\)"),
    (([[[0.0]]], [[1.0]]), _kw(R=[[0.0]]), ValueError, r"R\[0\] must be positive definite"),
    (([[[0.0]]], [[1.0]]), _kw(P_D=1.0), ValueError, r"P_D\[0\] must be < 1"),
    (([[[0.0]]], [[1.0]]), _kw(P_D=0.0), ValueError, r"P_D\[0\] must be > 0.0"),
    (([[[0.0]]], [[1.0]]), _kw(P_D="x"), TypeError, r"P_D\[0\] must be a real number"),
    (([[[0.0]]], [[1.0]]), _kw(clutter_intensity=0.0), ValueError,
     r"clutter_intensity\[0\] must be finite and > 0"),
    (([[[0.0]]], [[1.0]]), _kw(clutter_intensity=[[1.0, 2.0]]), ValueError,
     r"clutter_intensity\[0\] must be a scalar or have shape \(1,\)"),
    (([[[0.0]]], [[1.5]]), _kw(), ValueError, r"r_U\[0\] must lie in \[0, 1\]"),
    (([[[0.0]]], [[1.0, 1.0]]), _kw(), ValueError, r"r_U\[0\] must have shape \(1,\)"),
    (([[[0.0]]], [1.0]), _kw(P_D=[0.5, 0.5]), ValueError,
     r"P_D must have one entry per sensor \(V = 1\), got 2"),
    (([[[0.0]]], 1.0), _kw(), ValueError, "r_U must be a list with one array per sensor"),
    (([[[0.0, 1.0]]], [[1.0]]), _kw(), ValueError, r"measurements\[0\] must have shape \(M, 1\)"),
    (([[[np.nan]]], [[1.0]]), _kw(), ValueError, r"measurements\[0\] contains NaN"),
])
def test_from_measurements_errors(args, kw, exc, match):
    with pytest.raises(exc, match=match):
        AdaptiveBirthProblem.from_measurements(*args, **kw)


@pytest.mark.parametrize("z, kw, match", [
    # 1e160 used to be accepted, and ln rho, log_normalizer and marginals came out NaN
    ([[[0.0], [1e160]], [[0.0]]], {}, r"^measurements\[0\]\[1\] = \[1e\+160\] is too large "
     r"for the closed form of ln rho: z' R\[0\]\^-1 z = inf exceeds 2\*\*1000 / \(V \+ 1\) = "
     r"3\.57e\+300 \(V = 2\); beyond it the information sums overflow and ln rho would be "
     r"NaN$"),
    ([[[0.0], [-1e155]], [[0.0]]], {}, r"^measurements\[0\]\[1\] = \[-1e\+155\] is too large"),
    ([[[0.0]], [[np.inf]]], {}, r"^measurements\[1\]\[0\] = \[inf\] is not finite$"),
    ([[[0.0]]], _kw(mu0=[1e160]), r"^mu0 = \[1e\+160\] is too large for the closed form of ln "
     r"rho: mu0' P0\^-1 mu0 = inf exceeds 2\*\*1000 / \(V \+ 1\) = 5\.36e\+300 \(V = 1\)"),
    ([[[0.0]]], _kw(mu0=[np.inf]), r"^mu0 must be finite, got \[inf\]$"),
    ([[[0.0]]], _kw(P0=[[np.inf]]), r"^P0 must be finite, got \[\[inf\]\]$"),
    ([[[0.0]]], _kw(P0=[[1e-320]]), r"^P0 is too close to singular for the closed form of ln "
     r"rho: P0\^-1 has an entry of inf, above 2\*\*1000"),
    ([[[0.0]]], _kw(H=[[np.inf]]), r"^H\[0\] must be finite, got \[\[inf\]\]$"),
    ([[[0.0]]], _kw(R=[[np.inf]]), r"^R\[0\] must be finite, got \[\[inf\]\]$"),
    ([[[0.0]]], _kw(H=[[1e160]]), r"^H\[0\]' R\[0\]\^-1 H\[0\] has an entry of inf, above "
     r"2\*\*1000 / \(V \+ 1\) = 5\.36e\+300 \(V = 1\): R\[0\] is too close to singular or "
     r"H\[0\] too large"),
])
def test_from_measurements_refuses_what_would_make_ln_rho_nan(z, kw, match):
    kw = kw or _kw()
    with pytest.raises(ValueError, match=match):
        AdaptiveBirthProblem.from_measurements(z, [[1.0] * len(zv) for zv in z], **kw)


def test_far_measurements_within_the_bound_give_finite_answers():
    # z = 1e150: z' R^-1 z = 1e300 <= 2**1000 / 3, accepted; its tuples have ln rho ~ -1e299
    # (weight 0), and the oracle's answers are finite: the measurement's marginal is 0
    p = AdaptiveBirthProblem.from_measurements([[[0.0], [1e150]], [[0.0]]],
                                               [[1.0, 1.0], [1.0]], **_kw())
    lw = p.log_weights()
    assert np.isfinite(lw).all() and (lw[2] < -1e298).all()
    assert np.isfinite(oracle.log_normalizer(p))
    m = oracle.marginals(p)
    assert all(np.isfinite(mv).all() for mv in m) and m[0][2] == 0.0
    near = AdaptiveBirthProblem.from_measurements([[[0.0]], [[0.0]]], [[1.0], [1.0]], **_kw())
    assert_allclose(oracle.log_normalizer(p), oracle.log_normalizer(near), rtol=1e-12)
    # a huge measurement that the tau_rU rule drops plays no part
    q = AdaptiveBirthProblem.from_measurements([[[0.0], [1e300]], [[0.0]]],
                                               [[1.0, 0.5], [1.0]], **_kw())
    assert q.n_meas == (1, 1) and np.isfinite(oracle.log_normalizer(q))


def test_from_measurements_tau_and_n_min_errors():
    with pytest.raises(ValueError, match="tau_rU must be <= 1.0"):
        AdaptiveBirthProblem.from_measurements([[[0.0]]], [[1.0]], tau_rU=2.0, **_kw())
    with pytest.raises(ValueError, match="n_min must be an int <= 1"):
        AdaptiveBirthProblem.from_measurements([[[0.0]]], [[1.0]], n_min=2, **_kw())


def test_tuple_checks_are_pinned():
    p = AdaptiveBirthProblem.from_log_weights(np.zeros((2, 3)))
    with pytest.raises(ValueError, match=r"tuples must have shape \(n, V\) or \(V,\) with V = 2"):
        p.log_weight_of([0, 0, 0])
    with pytest.raises(ValueError, match=r"tuples has an entry outside 0..M_v, M = \(1, 2\)"):
        p.log_weight_of([2, 0])
    with pytest.raises(TypeError, match="tuples must be integers, got dtype float64"):
        p.log_weight_of([0.0, 1.0])
    assert p.log_weight_of(np.zeros((0, 2), dtype=int)).shape == (0,)
    with pytest.raises(ValueError, match="posterior needs the linear-Gaussian model"):
        p.posterior([[0, 0]])


def test_chain_inputs_sensor_order_error():
    p = AdaptiveBirthProblem.from_log_weights(np.zeros((2, 3)))
    with pytest.raises(ValueError, match="unknown sensor_order 'rand'"):
        chain_inputs(p, "rand")
    with pytest.raises(TypeError, match="problem must be an AdaptiveBirthProblem, got list"):
        chain_inputs([1], "random")


# ----------------------------------------------------------------------------- birth LMB
def test_birth_from_samples_components():
    p, *_ = gaussian_problem(seed=5)
    F = np.eye(4)
    F[0, 1] = F[2, 3] = 1.0
    Q = 0.5 * np.eye(4)
    tuples = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 1], [1, 1, 0], [2, 0, 3]]
    b = birth_from_samples(p, tuples, F=F, Q=Q, r_b_max=1.0, lambda_b=1.0)
    # all-missed and single-detection tuples dropped; duplicates once, discovery order
    assert_array_equal(b.tuples, [[1, 1, 0], [1, 1, 1], [2, 0, 3]])
    assert_array_equal(b.measurements, [[0, 0, -1], [0, 0, 0], [1, -1, 2]])
    lr = p.log_weight_of(b.tuples)
    assert_allclose(b.log_rho, lr)
    assert_allclose(b.r, np.exp(lr - logsumexp(lr)), rtol=1e-12)
    assert_allclose(b.r.sum(), 1.0, rtol=1e-12)
    m, P = p.posterior(b.tuples)
    assert_allclose(b.means, m @ F.T)
    assert_allclose(b.covs, F @ P @ F.T + Q)
    capped = birth_from_samples(p, tuples, r_b_max=0.01, lambda_b=3.0)
    assert_allclose(capped.r, np.minimum(0.01, 3 * b.r))
    assert_allclose(capped.covs, P)            # F = I, Q = 0 by default


def test_birth_from_samples_accepts_results_and_n_min():
    p, *_ = gaussian_problem(seed=5, n_min=0)
    b = birth_from_samples(p, [[0, 0, 0], [0, 1, 0]])
    assert_array_equal(b.tuples, [[0, 1, 0]])  # n_min = 0 still drops the all-missed tuple
    none = birth_from_samples(p, [[0, 0, 0]])
    assert none.tuples.shape == (0, 3) and none.means.shape == (0, 4) and none.r.shape == (0,)


@pytest.mark.parametrize("kw, exc, match", [
    (dict(r_b_max=0.0), ValueError, "r_b_max must be > 0.0"),
    (dict(r_b_max=1.5), ValueError, "r_b_max must be <= 1.0"),
    (dict(lambda_b=0.0), ValueError, "lambda_b must be > 0.0"),
    (dict(F=np.eye(3)), ValueError, r"F must have shape \(4, 4\)"),
    (dict(Q=np.eye(2)), ValueError, r"Q must have shape \(4, 4\)"),
])
def test_birth_from_samples_errors(kw, exc, match):
    p, *_ = gaussian_problem()
    with pytest.raises(exc, match=match):
        birth_from_samples(p, [[1, 1, 0]], **kw)


def test_birth_from_samples_needs_gaussian_and_problem():
    with pytest.raises(ValueError, match="birth_from_samples needs the linear-Gaussian model"):
        birth_from_samples(AdaptiveBirthProblem.from_log_weights(np.zeros((2, 2))), [[1, 1]])
    with pytest.raises(TypeError, match="problem must be an AdaptiveBirthProblem, got str"):
        birth_from_samples("p", [[1, 1]])


# ----------------------------------------------------------------------------- oracle
@st.composite
def tensors(draw):
    V = draw(st.integers(1, 3))
    shape = tuple(draw(st.integers(1, 4)) for _ in range(V))
    g = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    t = g.normal(0, 2, shape)
    t[g.uniform(size=shape) < 0.2] = -np.inf
    t[(0,) * V] = g.normal()
    return AdaptiveBirthProblem.from_log_weights(t, n_min=draw(st.integers(0, V)))


@given(tensors(), st.data())
def test_oracle_against_brute_force(p, data):
    t = p.log_weights()
    flat = [(J, t[J]) for J in itertools.product(*[range(s) for s in p.shape])]
    assert oracle.enumerate_assignments(p).assignments.shape == (len(flat), p.n_sensors)
    assert_allclose(oracle.log_normalizer(p), logsumexp([w for _, w in flat]), rtol=1e-12)
    marg = oracle.marginals(p)
    Z = np.exp(logsumexp([w for _, w in flat]))
    for v in range(p.n_sensors):
        want = [sum(np.exp(w) for J, w in flat if J[v] == j) / Z for j in range(p.shape[v])]
        assert_allclose(marg[v], want, rtol=1e-10, atol=1e-14)
    kept = [(J, w) for J, w in flat if sum(j > 0 for j in J) >= max(p.n_min, 1)]
    idx = data.draw(st.lists(st.integers(0, len(flat) - 1), max_size=6))
    chosen = np.array([flat[i][0] for i in idx], dtype=np.int64).reshape(-1, p.n_sensors)
    ref_mass = sum(np.exp(w) for _, w in kept)
    if not kept or ref_mass == 0:
        with pytest.raises(ValueError, match="T\\* .* have zero weight"):
            oracle.truncation_error(p, chosen)
        return
    got = {tuple(J) for J in chosen.tolist()}
    want = 1.0 - sum(np.exp(w) for J, w in kept if J in got) / ref_mass
    assert_allclose(oracle.truncation_error(p, chosen), max(want, 0.0), rtol=1e-9, atol=1e-12)


def test_enumeration_order_and_limit():
    p = AdaptiveBirthProblem.from_log_weights(np.log([[1.0, 2.0], [3.0, 4.0]]))
    r = oracle.enumerate_assignments(p)
    assert_array_equal(r.assignments, [[1, 1], [1, 0], [0, 1], [0, 0]])
    assert_allclose(r.costs, -np.log([4.0, 3.0, 2.0, 1.0]))
    with pytest.raises(ValueError, match="problem too large to enumerate: 4 tuples"):
        oracle.enumerate_assignments(p, limit=3)
    with pytest.raises(TypeError, match="limit must be an int"):
        oracle.enumerate_assignments(p, limit=3.0)


def test_enumeration_refuses_a_huge_limit_with_the_count_and_the_bytes():
    # 2**40 tuples (40 sensors, one measurement each) with limit = 10**18 used to reach
    # numpy's "array is too big" in the index grid; 8 (3 V + 3) = 984 bytes per tuple
    p = AdaptiveBirthProblem.from_measurements([[[0.0]]] * 40, [[1.0]] * 40, **_kw())
    with pytest.raises(ValueError, match=(
            r"^problem too large to enumerate: 1099511627776 tuples \(M = \(1, 1, .*, 1\)\) "
            r"would take 984\.0 TiB \(1081919441731584 bytes\), more than the limit of 4\.0 "
            r"GiB \(4294967296 bytes\) \(rankedassign\.validation\.MAX_WORK_BYTES; 984 bytes "
            r"each\)$")):
        oracle.enumerate_assignments(p, limit=10**18)
    small = AdaptiveBirthProblem.from_log_weights(np.log([[1.0, 2.0], [3.0, 4.0]]))
    r = oracle.enumerate_assignments(small, limit=10**18)
    assert_array_equal(r.assignments, [[1, 1], [1, 0], [0, 1], [0, 0]])
    with pytest.raises(ValueError, match=r"4 tuples \(M = \(1, 1\)\) exceed limit = 3 \(they "
                                         r"would take 288 bytes\)$"):
        oracle.enumerate_assignments(small, limit=3)


def test_truncation_error_ignores_non_births_and_pins_messages():
    p = AdaptiveBirthProblem.from_log_weights(np.log([[1.0, 2.0], [3.0, 4.0]]), n_min=2)
    assert oracle.truncation_error(p, [[0, 0], [0, 1], [1, 0]]) == 1.0   # none is a birth
    assert oracle.truncation_error(p, [[1, 1]]) == 0.0
    assert oracle.truncation_error(p, np.zeros((0, 2), dtype=int)) == 1.0
    with pytest.raises(ValueError, match=r"assignments must have shape \(n, V\)"):
        oracle.truncation_error(p, [[0, 0, 0]])
    q = AdaptiveBirthProblem.from_log_weights(np.array([[0.0, -np.inf], [-np.inf, -np.inf]]),
                                              n_min=1)
    with pytest.raises(ValueError, match="have zero weight"):
        oracle.truncation_error(q, [[0, 1]])


def test_dense_tensor_limit(monkeypatch):
    from rankedassign.adaptive_birth import problem as ab

    monkeypatch.setattr(ab, "_MAX_TENSOR", 10)
    p, *_ = gaussian_problem()
    with pytest.raises(ValueError, match="tuple space too large for a dense tensor: 48 > 10"):
        p.log_weights()


@pytest.mark.parametrize("order", ["random", "fixed"])
def test_transition_matrix_is_stochastic_and_leaves_pi_B_invariant(order):
    p, *_ = gaussian_problem(seed=1)
    K, pi = ob.transition_matrix(p, order)
    assert_allclose(K.sum(axis=1), 1.0, rtol=1e-12)
    assert_allclose(pi @ K, pi, rtol=1e-10, atol=1e-15)
    # eigenvalue 1 is simple (the chain is irreducible and aperiodic), so pi_B is the only
    # stationary law and the top left eigenvector
    w, vecs = np.linalg.eig(K.T)
    assert np.sort(np.abs(w))[-2] < 1 - 1e-6
    top = np.real(vecs[:, np.argmax(np.real(w))])
    assert_allclose(top / top.sum(), pi, rtol=1e-8, atol=1e-14)


def test_transition_matrix_errors_and_zero_fibers():
    p, *_ = gaussian_problem()
    with pytest.raises(ValueError, match="tuple space too large for a transition matrix: 48"):
        ob.transition_matrix(p, limit=10)
    with pytest.raises(ValueError, match="unknown sensor_order 'x'"):
        ob.transition_matrix(p, "x")
    t = np.array([[0.0, -np.inf], [-np.inf, -np.inf]])
    K, pi = ob.transition_matrix(AdaptiveBirthProblem.from_log_weights(t), "fixed")
    assert_allclose(pi, [1, 0, 0, 0])
    assert_allclose(K[:3, 0], 1.0)            # (1, 1) has weight 0 on both of its fibers:
    assert K[3, 3] == 1.0                      # it stays put


def test_make_family_sizes_and_uniform():
    p = make_family("uniform", 3, 2)
    assert p.n_feasible() == 27 and oracle.log_normalizer(p) == pytest.approx(np.log(27))
    d = make_family("diagonal", 4, 4, rng=0)
    assert d.n_meas == (4, 4, 4, 4)
    # the three targets' full tuples hold most of pi_B restricted to births
    best = oracle.enumerate_assignments(d).assignments[:3]
    assert (best[:, :] > 0).all()
    with pytest.raises(ValueError, match="the random family needs M >= 3"):
        make_family("random", 2, 2)
    with pytest.raises(ValueError, match="unknown family 'x'"):
        make_family("x", 2)
