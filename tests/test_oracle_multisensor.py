"""The multi-sensor oracle: enumeration, row DP (log Z and marginals), the surrogate's
normaliser, truncation error and best mass, against brute force, against each other, and
against the single-sensor oracle when V = 1."""

import numpy as np
import pytest
from cases import CASE_IDS, CASES, marginal_atol
from hypothesis import given
from multisensor_cases import MS_CASE_IDS, MS_CASES, brute_force, ms_problems
from numpy.testing import assert_allclose, assert_array_equal
from scipy.special import logsumexp

import oracle
from oracle.multisensor import dp as msdp
from oracle.multisensor import enumerate as msen
from rankedassign.multisensor import MultiSensorProblem, synthetic


def brute_marginals(problem):
    """``(dead (P,), tuples (P, T))`` by summing the normalised weights of brute force."""
    g = brute_force(problem)
    P, T = problem.n_rows, problem.n_tuples
    lw = problem.log_weight_of(g)
    w = np.exp(lw - lw.max())
    w /= w.sum()
    dims = np.array(problem.log_eta_alive.shape[1:])
    strides = np.array([int(np.prod(dims[v + 1:])) for v in range(len(dims))], dtype=np.int64)
    dead = np.zeros(P)
    tup = np.zeros((P, T))
    for n in range(P):
        is_dead = g[:, n, 0] == -1
        dead[n] = w[is_dead].sum()
        flat = (g[~is_dead, n, :] * strides).sum(axis=1)
        np.add.at(tup[n], flat, w[~is_dead])
    return dead, tup


def ms_atol(problem):
    """1e-12, widened for huge log-weights (a sum of terms of size |w| is known to ~eps |w|)."""
    big = np.abs(np.r_[problem.log_eta_dead, problem.log_eta_alive.ravel()])
    big = big[np.isfinite(big)].max(initial=0.0)
    return 1e-12 + 8 * np.finfo(float).eps * big * max(problem.n_rows, 1)


# ---------------------------------------------------------------- enumeration
def _check_enumeration(problem):
    r = oracle.enumerate_assignments(problem)
    g = brute_force(problem)
    costs = problem.cost_of(g) if len(g) else np.zeros(0)
    order = np.argsort(costs, kind="stable")
    # brute force is lexicographic, so ties end up in the same order: exact equality
    assert_array_equal(r.assignments, g[order])
    assert_array_equal(r.costs, costs[order])
    assert_array_equal(r.costs, problem.cost_of(r.assignments) if len(r.costs) else r.costs)
    assert len(r.costs) == problem.n_feasible()


@given(ms_problems())
def test_enumeration_equals_brute_force(problem):
    _check_enumeration(problem)


@pytest.mark.parametrize("name, problem", MS_CASES, ids=MS_CASE_IDS)
def test_cases_enumeration(name, problem):
    _check_enumeration(problem)


@given(ms_problems())
def test_enumeration_kernel_matches_reference(problem):
    codes, n = msen._enumerate(*msen._kernel_args(problem), problem.n_feasible(), False)
    ref = list(msen._enumerate_reference(problem))
    assert n == len(ref)
    if problem.n_rows:
        assert_array_equal(codes, np.array(ref, dtype=np.int64).reshape(len(ref), -1))
    _, m = msen._enumerate(*msen._kernel_args(problem), 2**40, True)
    assert m == len(ref)


@pytest.mark.parametrize("P, M, n", [
    (3, (4, 4), 6728), (4, (4, 4), 67744), (2, (16, 16), 75108), (3, (5, 5), 21488),
    (3, (4, 4, 4), 417176), (2, (6, 6, 6), 80194), (4, (5, 5), 330896), (5, (4, 4), 527232),
])
def test_size_table_by_enumeration(P, M, n):
    r = oracle.enumerate_assignments(synthetic.uniform(P, M))
    assert r.assignments.shape == (n, P, len(M))
    # every assignment distinct: each row as one integer (its entries the digits, base above
    # the largest entry), so that numpy sorts integers, not rows
    a = r.assignments.reshape(n, -1).astype(np.int64)
    a -= a.min()
    base = int(a.max()) + 1
    assert base ** a.shape[1] < 2**62  # the codes fit: distinct rows, distinct codes
    codes = a @ base ** np.arange(a.shape[1], dtype=np.int64)
    assert np.unique(codes).size == n


def test_counting_search_agrees_with_the_counting_dp():
    a = np.ones((4, 5, 4))
    a[0, 1, :] = 0.0
    a[2, :, 3] = 0.0
    p = MultiSensorProblem.from_eta(np.ones(4), a)
    _, n = msen._enumerate(*msen._kernel_args(p), 2**40, True)
    assert n == p.n_feasible() == len(brute_force(p))


def test_enumeration_refuses_above_the_limit_at_once():
    p = synthetic.uniform(8, (40, 40, 40))
    with pytest.raises(ValueError, match=r"problem too large to enumerate: \d+ feasible "
                                         r"assignments \(P = 8, M = \(40, 40, 40\)\) exceed "
                                         r"limit = 2000000"):
        oracle.enumerate_assignments(p)
    # forbidden options beyond the counting DP: the search stops past the limit
    a = np.ones((6, 21, 21))
    a[0, 1, 1] = 0.0
    q = MultiSensorProblem.from_eta(np.ones(6), a)
    with pytest.raises(ValueError, match=r"problem too large to enumerate: more than 1000 "
                                         r"feasible assignments \(P = 6, M = \(20, 20\)\) exceed "
                                         r"limit = 1000"):
        oracle.enumerate_assignments(q, limit=1000)
    assert msen.count_assignments(q, limit=1000) == 1001


@pytest.mark.heavy_python
def test_enumeration_refuses_a_huge_limit_with_the_count_and_the_bytes():
    # 76 511 176 assignments at 16 P V + 16 P + 24 = 216 bytes: within limit = 10**18, which
    # used to reach the allocation, but beyond the memory limit
    with pytest.raises(ValueError, match=(
            r"^problem too large to enumerate: 76511176 feasible assignments \(P = 4, "
            r"M = \(10, 10\)\) would take 15\.4 GiB \(16526414016 bytes\), more than the limit "
            r"of 4\.0 GiB \(4294967296 bytes\) \(rankedassign\.validation\.MAX_WORK_BYTES; "
            r"216 bytes each\)$")):
        oracle.enumerate_assignments(synthetic.uniform(4, (10, 10)), limit=10**18)
    # beyond the counting DP: the search stops past what the memory limit holds
    a = np.ones((6, 21, 21))
    a[0, 1, 1] = 0.0
    q = MultiSensorProblem.from_eta(np.ones(6), a)
    with pytest.raises(ValueError, match=(
            r"^problem too large to enumerate: more than 13765920 feasible assignments "
            r"\(P = 6, M = \(20, 20\)\) would take more than the limit of 4\.0 GiB "
            r"\(4294967296 bytes\) \(rankedassign\.validation\.MAX_WORK_BYTES; 312 bytes "
            r"each\)$")):
        oracle.enumerate_assignments(q, limit=10**18)
    # the limit message states the bytes too; a huge limit on a small problem changes nothing
    p = synthetic.diagonal()
    with pytest.raises(ValueError, match=r"67744 feasible assignments .* exceed limit = 67743 "
                                         r"\(they would take 14\.0 MiB \(14632704 bytes\)\)$"):
        oracle.enumerate_assignments(p, limit=67_743)
    got, want = oracle.enumerate_assignments(p, limit=10**18), oracle.enumerate_assignments(p)
    assert_array_equal(got.assignments, want.assignments)
    assert_array_equal(got.costs, want.costs)


@pytest.mark.parametrize("limit, err, match", [
    (0, ValueError, "limit must be an int >= 1, got 0"),
    (1.5, TypeError, "limit must be an int, got float 1.5"),
])
def test_enumeration_limit_messages(limit, err, match):
    with pytest.raises(err, match=match):
        oracle.enumerate_assignments(synthetic.uniform(1, (1,)), limit=limit)


def test_wrong_problem_type_messages():
    for f in (msen.enumerate_assignments, msdp.log_normalizer, msdp.marginals,
              msdp.surrogate_log_normalizer):
        with pytest.raises(TypeError, match="problem must be a MultiSensorProblem, got int; "
                                            "build one with MultiSensorProblem.from_eta"):
            f(3)


# ---------------------------------------------------------------- row DP vs enumeration
def _check_dp(problem):
    g = brute_force(problem)
    want = logsumexp(problem.log_weight_of(g)) if problem.n_rows else 0.0
    atol = ms_atol(problem)
    assert_allclose(oracle.log_normalizer(problem), want, rtol=0, atol=atol)
    m = oracle.marginals(problem)
    dead, tup = brute_marginals(problem)
    assert_allclose(m.dead, dead, rtol=0, atol=atol)
    assert_allclose(m.tuples.reshape(problem.n_rows, problem.n_tuples), tup, rtol=0, atol=atol)
    assert m.tuples.shape == problem.log_eta_alive.shape
    for v, sv in enumerate(m.sensors):
        M = problem.n_meas[v]
        assert sv.shape == (problem.n_rows, M + 2)
        assert_allclose(sv.sum(axis=1), 1.0, rtol=1e-13)
        assert (sv[:, :M].sum(axis=0) <= 1 + 1e-12).all()
        assert_array_equal(sv[:, M + 1], m.dead)
    # the enumeration fallback gives the same
    e = msdp._marginals(problem, "enumerate")
    assert_allclose(e.tuples, m.tuples, rtol=0, atol=atol)
    assert_allclose(msdp._log_normalizer(problem, "enumerate"), want, rtol=0, atol=atol)


@given(ms_problems())
def test_dp_against_enumeration(problem):
    _check_dp(problem)


@pytest.mark.parametrize("name, problem", MS_CASES, ids=MS_CASE_IDS)
def test_cases_dp_against_enumeration(name, problem):
    _check_dp(problem)


@pytest.mark.parametrize("family", ["diagonal", "random", "random_coupled", "geometric"])
def test_families_dp_against_enumeration(family):
    f = getattr(synthetic, family)
    p = f(4, (4, 4)) if family == "diagonal" else f(4, (4, 4), rng=2)
    r = oracle.enumerate_assignments(p)
    assert_allclose(oracle.log_normalizer(p), logsumexp(-r.costs), rtol=1e-12)
    m = oracle.marginals(p)
    e = msdp._marginals(p, "enumerate")
    assert_allclose(m.tuples, e.tuples, rtol=0, atol=1e-12)
    assert_allclose(m.dead, e.dead, rtol=0, atol=1e-12)


def _scaled_inputs(problem):
    masks, B = msdp.detection_masks(problem)
    w_dead, w_alive, _ = msdp._scaled_weights(problem)
    return w_dead, w_alive, masks, B


@given(ms_problems())
def test_dp_kernels_match_references(problem):
    if problem.n_rows == 0:
        return
    args = _scaled_inputs(problem)
    assert_allclose(msdp._row_dp(*args), msdp._row_dp_reference(*args), rtol=0,
                    atol=1e-12)
    dead, alive, log_z = msdp._row_marginal(*args, msdp.sensor_caps(problem, args[3]))
    tot = dead + alive.sum(axis=1)
    rd, ra = msdp._row_marginal_reference(*args)
    assert_allclose(dead / tot, rd, rtol=0, atol=1e-12)
    assert_allclose(alive / tot[:, None], ra, rtol=0, atol=1e-12)
    assert_allclose(log_z, msdp._row_dp_reference(*args), rtol=0, atol=1e-12)
    # the log-space kernels (used for huge weight ranges) agree with the linear ones
    _, _, masks, B = args
    la = np.ascontiguousarray(problem.log_eta_alive.reshape(problem.n_rows, problem.n_tuples))
    ld = problem.log_eta_dead
    shift = msdp._scaled_weights(problem)[2].sum()
    assert_allclose(msdp._row_dp_log(ld, la, masks, B), log_z + shift, rtol=0, atol=1e-12)
    lgd, lga, lz2 = msdp._row_marginal_log(ld, la, masks, B, msdp.sensor_caps(problem, B))
    tot = np.logaddexp(lgd, logsumexp(lga, axis=1))
    assert_allclose(np.exp(lgd - tot), rd, rtol=0, atol=1e-12)
    assert_allclose(np.exp(lga - tot[:, None]), ra, rtol=0, atol=1e-12)
    assert_allclose(lz2, log_z + shift, rtol=0, atol=1e-12)


def test_log_space_is_chosen_for_huge_ranges():
    assert not msdp._use_log_space(synthetic.random(4, (4, 4), rng=0))
    assert msdp._use_log_space(dict(MS_CASES)["huge_range"])


def test_unreachable_measurements_get_no_bit():
    a = np.ones((2, 4, 3))
    a[:, 3, :] = 0.0  # measurement 3 of sensor 1: no row may take it
    p = MultiSensorProblem.from_eta([1.0, 1.0], a)
    masks, B = msdp.detection_masks(p)
    assert B == 2 + 2
    assert (masks.reshape(4, 3)[3] == -1).all()
    _check_dp(p)


@pytest.mark.heavy_python
def test_dp_reaches_beyond_enumeration_separable_check():
    # |Gamma| ~ 1e13: the row DP (16 bits) against the surrogate normaliser, exact for the
    # separable random family (an independent algorithm, exponential in P only)
    p = synthetic.random(8, (8, 8), rng=3)
    assert p.n_feasible() > 10**12
    assert_allclose(oracle.log_normalizer(p), msdp.surrogate_log_normalizer(p), rtol=1e-12)
    m = oracle.marginals(p)
    assert_allclose(m.dead + m.tuples.sum(axis=(1, 2)), 1.0, rtol=1e-13)


def test_size_b_uses_enumeration_and_agrees_with_the_surrogate():
    p = synthetic.random(2, (16, 16), rng=1)  # 32 bits: beyond the row DP
    assert msdp.detection_masks(p)[1] == 32
    assert_allclose(oracle.log_normalizer(p), msdp.surrogate_log_normalizer(p), rtol=1e-12)
    m = oracle.marginals(p)
    assert m.tuples.shape == (2, 17, 17)
    with pytest.raises(ValueError, match=r"problem too large for the row DP: 32 reachable "
                                         r"measurements > 22 bits"):
        msdp._log_normalizer(p, "dp")


def test_too_large_for_dp_and_enumeration():
    p = synthetic.uniform(8, (12, 12))
    with pytest.raises(ValueError, match=r"problem too large for the exact row DP: 24 reachable "
                                         r"measurements > 22 bits, and for enumeration: more "
                                         r"than 2000000 feasible assignments \(P = 8, M = "
                                         r"\(12, 12\)\)"):
        oracle.log_normalizer(p)
    with pytest.raises(ValueError, match="unknown method 'fast'"):
        msdp._log_normalizer(p, "fast")


def test_diagonal_marginals_are_dominated_by_the_diagonal():
    m = oracle.marginals(synthetic.diagonal())
    for n in range(4):
        assert m.tuples[n, n + 1, n + 1] > 0.999
        assert m.sensors[0][n, n] > 0.999 and m.sensors[1][n, n] > 0.999


# ---------------------------------------------------------------- surrogate normaliser
@given(ms_problems(max_rows=3, max_sensors=3))
def test_surrogate_normaliser_equals_row_dp_of_surrogate(problem):
    # attach random factors to the problem and compare with the DP of the surrogate problem
    rng = np.random.default_rng(problem.n_rows * 7 + problem.n_sensors)
    P = problem.n_rows
    th = [rng.uniform(0, 3, (P, m + 1)) * (rng.random((P, m + 1)) > 0.2) for m in problem.n_meas]
    s = rng.uniform(0, 1, P)
    d = np.exp(problem.log_eta_dead)
    try:
        p = MultiSensorProblem.from_factors(d, s, th)
    except ValueError:
        return  # a row with no positive weight
    want = oracle.log_normalizer(p.surrogate())
    assert_allclose(msdp.surrogate_log_normalizer(p), want, rtol=0, atol=1e-12)


@pytest.mark.parametrize("P, M", [(4, (4, 4)), (3, (4, 4, 4)), (2, (16, 16))])
def test_surrogate_normaliser_on_families(P, M):
    p = synthetic.random_coupled(P, M, rng=5)
    want = logsumexp(-oracle.enumerate_assignments(p.surrogate()).costs)
    assert_allclose(msdp.surrogate_log_normalizer(p), want, rtol=1e-12)
    g = synthetic.geometric(P, M, rng=5)
    want = logsumexp(-oracle.enumerate_assignments(g.surrogate()).costs)
    assert_allclose(msdp.surrogate_log_normalizer(g), want, rtol=1e-12)


@given(ms_problems(max_rows=3, max_sensors=1, max_tuples=4))
def test_permanent_kernel_matches_reference(problem):
    P = problem.n_rows
    rng = np.random.default_rng(P)
    theta = rng.uniform(0, 1, (P, problem.n_meas[0] + 1))
    want = msdp._permanent_reference(theta)
    assert_allclose(msdp._permanent(theta), want, rtol=1e-13)
    # read-only, as the surrogate passes a problem's log factors: one signature of the kernel
    log_theta = np.log(theta)
    log_theta.setflags(write=False)
    assert_allclose(np.exp(msdp._permanent(log_theta, log_space=True)), want, rtol=1e-12)


def test_surrogate_messages():
    with pytest.raises(ValueError, match=r"surrogate_log_normalizer needs the separable factors"):
        msdp.surrogate_log_normalizer(MultiSensorProblem.from_eta([1.0], np.ones((1, 2, 2))))
    p = synthetic.uniform(23, (1,))
    with pytest.raises(ValueError, match=r"problem too large for the surrogate normaliser: P = "
                                         r"23 rows > 22 \(2\^P alive sets\)"):
        msdp.surrogate_log_normalizer(p)
    assert msdp.surrogate_log_normalizer(synthetic.uniform(0, (3,))) == 0.0


# ---------------------------------------------------------------- V = 1 is the single sensor
@pytest.mark.parametrize("name, sp", CASES, ids=CASE_IDS)
def test_single_sensor_results_agree(name, sp):
    mp = MultiSensorProblem.from_assignment_problem(sp)
    atol = marginal_atol(sp)
    assert_allclose(oracle.log_normalizer(mp), oracle.log_normalizer(sp), rtol=1e-12, atol=atol)
    assert_allclose(oracle.marginals(mp).sensors[0], oracle.marginals(sp), rtol=0, atol=atol)
    rs, rm = oracle.enumerate_assignments(sp), oracle.enumerate_assignments(mp)
    assert len(rs.costs) == len(rm.costs) == mp.n_feasible()
    assert_array_equal(np.sort(rm.costs), np.sort(rs.costs))
    if sp.n_rows:
        gs = sp.cols_to_gamma(rs.assignments)
        key = lambda a: {tuple(r) for r in a}  # noqa: E731
        assert key(rm.assignments[:, :, 0]) == key(gs)
        half = gs[: max(1, len(gs) // 2)]
        assert_allclose(oracle.truncation_error(mp, half[:, :, None]),
                        oracle.truncation_error(sp, sp.gamma_to_cols(half)), rtol=1e-9,
                        atol=1e-12)
        assert_allclose(oracle.best_mass(mp, 3), oracle.best_mass(sp, 3), rtol=1e-9, atol=1e-12)
        assert_allclose(msdp.surrogate_log_normalizer(mp), oracle.log_normalizer(sp), rtol=1e-12,
                        atol=atol)


# ---------------------------------------------------------------- truncation error, best mass
def test_truncation_error_basics():
    p = synthetic.random_coupled(3, (2, 2), rng=1)
    r = oracle.enumerate_assignments(p)
    assert oracle.truncation_error(p, r.assignments) == 0.0
    assert oracle.truncation_error(p, np.zeros((0, 3, 2), dtype=int)) == 1.0
    top = r.assignments[:10]
    err = oracle.truncation_error(p, np.concatenate([top, top[::-1]]))  # duplicates count once
    assert_allclose(err, 1 - oracle.best_mass(p, 10), rtol=1e-12)
    assert_allclose(oracle.truncation_error(p, top[0]), 1 - oracle.best_mass(p, 1), rtol=1e-12)
    assert oracle.best_mass(p, 0) == 0.0
    assert oracle.best_mass(p, 10**6) == 1.0


def test_truncation_error_of_the_empty_problem():
    p = MultiSensorProblem.from_eta(np.zeros(0), np.zeros((0, 2, 2)))
    assert oracle.truncation_error(p, np.zeros((1, 0, 2), dtype=int)) == 0.0


def test_truncation_error_messages():
    p = MultiSensorProblem.from_eta([1.0, 1.0], np.ones((2, 2, 2)))
    with pytest.raises(ValueError, match=r"assignment 1 of the input, \[\[1, 0\], \[1, 1\]\], is "
                                         r"infeasible: it has an entry out of range, a row "
                                         r"mixing -1 with other values, a forbidden option, or a "
                                         r"measurement of some sensor used twice"):
        oracle.truncation_error(p, [[[0, 0], [0, 0]], [[1, 0], [1, 1]]])
    with pytest.raises(ValueError, match=r"assignments must have shape \(P, V\) = \(2, 2\)"):
        oracle.truncation_error(p, [[0, 0]])
    with pytest.raises(TypeError, match="assignments must be an integer array"):
        oracle.truncation_error(p, [[[0.5, 0], [0, 0]]])


def test_best_mass_messages():
    with pytest.raises(ValueError, match=r"best_mass of a multi-sensor problem needs the "
                                         r"enumeration: more than 2000000 feasible assignments "
                                         r"\(P = 8, M = \(12, 12\)\)"):
        oracle.best_mass(synthetic.uniform(8, (12, 12)), 1)
    with pytest.raises(ValueError, match="k must be an int >= 0, got -1"):
        oracle.best_mass(synthetic.uniform(1, (1,)), -1)
    with pytest.raises(TypeError, match="k must be an int, got float 1.0"):
        oracle.best_mass(synthetic.uniform(1, (1,)), 1.0)


def test_uniform_best_mass_is_a_fraction_of_the_count():
    assert_allclose(oracle.best_mass(synthetic.uniform(3, (2, 2)), 100),
                    100 / synthetic.uniform(3, (2, 2)).n_feasible(), rtol=1e-12)
