"""Tests of rankedassign.multisensor.problem: construction, weights, counting, V = 1, bad input."""

import math

import numpy as np
import pytest
from cases import CASE_IDS, CASES, problems
from hypothesis import given
from multisensor_cases import MS_CASE_IDS, MS_CASES, brute_force, ms_problems
from numpy.testing import assert_allclose, assert_array_equal

from rankedassign import AssignmentProblem
from rankedassign.multisensor import MultiSensorProblem, count_feasible_all_positive, synthetic
from rankedassign.multisensor import problem as msp

inf = np.inf


# ---------------------------------------------------------------- construction
def test_from_eta_attributes_are_read_only_float64_c_contiguous():
    a = np.arange(1.0, 13.0).reshape(2, 2, 3)
    p = MultiSensorProblem.from_eta([0.5, 0.0], a)
    assert p.n_rows == 2 and p.n_sensors == 2 and p.n_meas == (1, 2) and p.shape == (2, 1, 2)
    assert p.n_tuples == 6
    for arr in (p.log_eta_dead, p.log_eta_alive, p.tuples):
        assert arr.flags.c_contiguous and not arr.flags.writeable
    assert p.log_eta_dead.dtype == np.float64 and p.log_eta_alive.dtype == np.float64
    assert_allclose(p.log_eta_alive, np.log(a), rtol=1e-15)
    assert p.log_eta_dead[1] == -inf
    assert p.log_s is None and p.log_theta is None
    with pytest.raises(ValueError, match="read-only"):
        p.log_eta_alive[0, 0, 0] = 1.0


def test_input_arrays_are_copied():
    a = np.ones((1, 2, 2))
    p = MultiSensorProblem.from_eta([1.0], a)
    a[0, 0, 0] = 5.0
    assert p.log_eta_alive[0, 0, 0] == 0.0


def test_from_log_eta_equals_from_eta():
    rng = np.random.default_rng(0)
    a = rng.uniform(0.01, 3, size=(3, 2, 3, 2))
    d = rng.uniform(0.01, 1, 3)
    x = MultiSensorProblem.from_eta(d, a)
    y = MultiSensorProblem.from_log_eta(np.log(d), np.log(a))
    assert x == y and hash(x) == hash(y)
    assert x != MultiSensorProblem.from_eta(d * 2, a)
    assert (x == 3) is False
    assert repr(x) == "MultiSensorProblem(P=3, M=(1, 2, 1))"


def test_equality_includes_the_factors_and_pickling_keeps_everything_read_only():
    import pickle

    th = [np.array([[0.5, 2.0]]), np.array([[0.25, 4.0, 1.0]])]
    f = MultiSensorProblem.from_factors([0.5], [0.9], th)
    e = MultiSensorProblem.from_log_eta(f.log_eta_dead, f.log_eta_alive)
    assert f != e and e == MultiSensorProblem.from_log_eta(f.log_eta_dead, f.log_eta_alive)
    assert hash(f) == hash(e)  # equal weights, equal hash
    assert f != MultiSensorProblem.from_factors([0.5], [0.9], [th[0], th[1] * 1.5])
    for p in (f, e):
        q = pickle.loads(pickle.dumps(p))
        assert q == p
        assert not q.log_eta_alive.flags.writeable and not q.log_eta_dead.flags.writeable
    q = pickle.loads(pickle.dumps(f))
    assert not q.log_s.flags.writeable and not q.log_theta[1].flags.writeable


def test_from_factors_products_and_surrogate():
    rng = np.random.default_rng(1)
    th = [rng.uniform(0.1, 2, (2, 3)), rng.uniform(0.1, 2, (2, 2))]
    s = np.array([0.3, 0.8])
    c = rng.uniform(0.5, 2, (2, 3, 2))
    p = MultiSensorProblem.from_factors([0.7, 0.2], s, th, coupling=c)
    want = s[:, None, None] * th[0][:, :, None] * th[1][:, None, :]
    assert_allclose(np.exp(p.log_eta_alive), want * c, rtol=1e-14)
    assert_allclose(np.exp(p.surrogate().log_eta_alive), want, rtol=1e-14)
    assert_allclose(p.log_s, np.log(s), rtol=0)
    assert_allclose(p.log_theta[1], np.log(th[1]), rtol=0)
    assert p.surrogate().log_eta_dead is not None
    assert_array_equal(p.surrogate().log_eta_dead, p.log_eta_dead)
    sep = MultiSensorProblem.from_factors([0.7, 0.2], s, th)
    assert_allclose(sep.surrogate().log_eta_alive, sep.log_eta_alive, rtol=1e-15)


def test_surrogate_needs_factors():
    p = MultiSensorProblem.from_eta([1.0], np.ones((1, 2, 2)))
    with pytest.raises(ValueError, match=r"the surrogate problem needs the separable factors s "
                                         r"and theta \(spec §3.1\); build the problem with "
                                         r"MultiSensorProblem.from_factors"):
        p.surrogate()


def test_eta_and_assignment_helpers():
    p = MultiSensorProblem.from_eta([0.5, 0.25], np.full((2, 2, 3), 2.0))
    d, a = p.eta()
    assert_allclose(d, [0.5, 0.25], rtol=1e-15)
    assert_allclose(a, 2.0, rtol=1e-15)
    assert_array_equal(p.all_missed(), np.zeros((2, 2)))
    assert_array_equal(p.all_dead(), -np.ones((2, 2)))
    assert p.tuples.tolist() == [[0, 0], [0, 1], [0, 2], [1, 0], [1, 1], [1, 2]]


# ---------------------------------------------------------------- weights
def test_log_weight_of_sums_rows_in_order_and_detects_reuse():
    la = np.log(np.arange(1.0, 19.0)).reshape(2, 3, 3)
    p = MultiSensorProblem.from_log_eta([-1.0, -2.0], la)
    g = np.array([[[1, 2], [2, 0]], [[-1, -1], [0, 0]], [[1, 2], [1, 1]], [[0, 2], [2, 2]]])
    got = p.log_weight_of(g)
    want = [la[0, 1, 2] + la[1, 2, 0], -1.0 + la[1, 0, 0], -inf, -inf]
    assert_array_equal(got, want)  # bit for bit: the same left-to-right sum
    assert p.log_weight_of(g[0]) == got[0]
    assert_array_equal(p.cost_of(g), -got)
    assert_array_equal(p.is_feasible(g), [True, True, False, False])
    assert p.log_weight_of(np.zeros((0, 2, 2), dtype=int)).shape == (0,)


def test_forbidden_options_are_infeasible():
    a = np.ones((2, 2, 2))
    a[0, 1, 1] = 0.0
    p = MultiSensorProblem.from_eta([0.0, 1.0], a)
    assert p.log_weight_of([[-1, -1], [0, 0]]) == -inf
    assert p.log_weight_of([[1, 1], [0, 0]]) == -inf
    assert p.is_feasible([[1, 0], [0, 1]])


def test_is_feasible_out_of_range_and_mixed_rows_are_false_not_errors():
    p = MultiSensorProblem.from_eta([1.0, 1.0], np.ones((2, 3, 2)))
    g = [[[3, 0], [0, 0]], [[0, 2], [0, 0]], [[-2, 0], [0, 0]], [[-1, 0], [0, 0]],
         [[2.0, 1.0], [0, 0]]]
    assert p.is_feasible(g).tolist() == [False, False, False, False, True]


@pytest.mark.parametrize("gamma, err, match", [
    ([[0, 0]], ValueError, r"gamma must have shape \(P, V\) = \(2, 2\) or \(n, P, V\) = "
                           r"\(n, 2, 2\), got shape \(1, 2\)"),
    ([[[0, 0, 0], [0, 0, 0]]], ValueError, r"got shape \(1, 2, 3\)"),
    ([[3, 0], [0, 0]], ValueError, r"gamma\[0, 0, 0\] = 3 is outside \[-1, M_1\] = \[-1, 2\] "
                                   r"for sensor 0"),
    ([[0, 0], [0, -3]], ValueError, r"gamma\[0, 1, 1\] = -3 is outside \[-1, M_2\] = \[-1, 1\]"),
    ([[0, -1], [0, 0]], ValueError, r"gamma\[0, 0\] = \[0, -1\] mixes -1 with other values: a "
                                    r"row is either dead \(every entry -1\) or alive"),
    ([[0.5, 0], [0, 0]], TypeError, r"gamma must be an integer array of shape \(P, V\) or "
                                    r"\(n, P, V\), got dtype float64"),
    ([[True, False], [False, False]], TypeError, "got dtype bool"),
])
def test_bad_gamma_messages(gamma, err, match):
    p = MultiSensorProblem.from_eta([1.0, 1.0], np.ones((2, 3, 2)))
    with pytest.raises(err, match=match):
        p.log_weight_of(gamma)


# ---------------------------------------------------------------- counting
# spec §1.5, the size table (|Gamma|; every weight positive)
SIZE_TABLE = [
    (3, (4, 4), 6728), (4, (4, 4), 67744), (2, (16, 16), 75108), (3, (5, 5), 21488),
    (5, (4, 4), 527232), (3, (4, 4, 4), 417176), (2, (6, 6, 6), 80194), (4, (5, 5), 330896),
    (4, (8, 8), 12664112), (3, (5, 5, 5), 2605478),
]


@pytest.mark.parametrize("P, M, n", SIZE_TABLE)
def test_size_table_of_the_spec(P, M, n):
    assert count_feasible_all_positive(P, M) == n
    assert synthetic.uniform(P, M).n_feasible() == n


def test_count_reduces_to_single_sensor_formula():
    for P in range(5):
        for M in range(6):
            want = sum(math.comb(P, k) * math.comb(M, k) * math.factorial(k) * 2 ** (P - k)
                       for k in range(min(P, M) + 1))
            assert count_feasible_all_positive(P, (M,)) == want


@given(ms_problems())
def test_n_feasible_equals_brute_force(problem):
    g = brute_force(problem)
    assert problem.n_feasible() == len(g)
    assert problem.is_feasible(g).all() if len(g) else True


@pytest.mark.parametrize("name, problem", MS_CASES, ids=MS_CASE_IDS)
def test_cases_n_feasible(name, problem):
    assert problem.n_feasible() == len(brute_force(problem))


def test_counting_dp_refuses_beyond_its_limits():
    a = np.ones((5, 41, 41))
    a[0, 1, 1] = 0.0
    with pytest.raises(ValueError, match=r"problem too large to count exactly: 80 reachable "
                                         r"measurements with forbidden tuples exceed the 62-bit"):
        MultiSensorProblem.from_eta(np.ones(5), a).n_feasible()
    b = np.ones((6, 21, 21))
    b[0, 1, 1] = 0.0
    with pytest.raises(ValueError, match=r"problem too large to count exactly: (more than "
                                         r"2097152 reachable sets|the counting DP over used measurements needs more than 5e\+06 steps)"):
        MultiSensorProblem.from_eta(np.ones(6), b).n_feasible()


# ---------------------------------------------------------------- V = 1 is the single sensor
@pytest.mark.parametrize("name, sp", CASES, ids=CASE_IDS)
def test_single_sensor_round_trip_weights_and_count(name, sp):
    mp = MultiSensorProblem.from_assignment_problem(sp)
    assert mp.n_rows == sp.n_rows and mp.n_meas == (sp.n_meas,)
    assert mp.to_assignment_problem() == sp
    assert mp.n_feasible() == sp.n_feasible()
    # every single-sensor option of every row, as gamma, has the same weight
    P, M = sp.n_rows, sp.n_meas
    if P == 0:
        return
    rng = np.random.default_rng(0)
    gam = rng.integers(-1, M + 1, size=(200, P))
    cols = sp.gamma_to_cols(gam)
    assert_array_equal(mp.log_weight_of(gam[:, :, None]), sp.log_weight_of(cols))
    assert_array_equal(mp.is_feasible(gam[:, :, None]), sp.is_feasible(cols))
    assert_array_equal(mp.surrogate().log_eta_alive, mp.log_eta_alive)


@given(problems())
def test_single_sensor_property(sp):
    mp = MultiSensorProblem.from_assignment_problem(sp)
    assert mp.n_feasible() == sp.n_feasible()
    assert MultiSensorProblem.from_assignment_problem(mp.to_assignment_problem()) == mp


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize("dead, alive, err, match", [
    ([1.0], [1.0], ValueError, r"log_eta_alive must have shape \(P, M_1\+1, \.\.\., M_V\+1\) with "
                               r"at least one sensor, got 1-D shape \(1,\)"),
    ([1.0, 1.0], [[1.0]], ValueError, r"log_eta_dead must have shape \(P,\) = \(1,\) to match "
                                      r"log_eta_alive of shape \(1, 1\), got shape \(2,\)"),
    ([1.0], np.ones((1, 2, 0)), ValueError, r"log_eta_alive of shape \(1, 2, 0\) has an empty "
                                            r"sensor axis"),
    ([np.nan], [[1.0]], ValueError, r"eta_dead contains NaN at \(0,\)"),
    ([1.0], [[1.0, np.nan]], ValueError, r"eta_alive contains NaN at \(0, 1\)"),
    ([1.0], [[1.0, -0.5]], ValueError, r"eta_alive has a negative entry at \(0, 1\); weights "
                                       r"must be >= 0"),
    ([-1.0], [[1.0]], ValueError, r"eta_dead has a negative entry at \(0,\)"),
    ([1.0], [[inf, 1.0]], ValueError, r"eta_alive contains inf at \(0, 0\); weights must be "
                                      r"finite"),
    ([0.0, 1.0], [[0.0, 0.0], [1.0, 1.0]], ValueError,
     r"row 0 has no positive weight: it can be neither dead nor alive, so no assignment is "
     r"feasible"),
    ([0.0, 0.0], [[0.0, 1.0], [0.0, 1.0]], ValueError,
     r"no feasible assignment: rows \[0, 1\] can be neither dead nor missed by every sensor "
     r"and cannot all be given tuples with distinct measurements"),
    (["a"], [[1.0]], TypeError, r"eta_dead must be a numeric array, got dtype <U1"),
    ([1.0], [[1.0 + 1j]], TypeError, r"eta_alive must be real, got dtype complex128"),
    ([1.0], [[1.0], [1.0, 2.0]], TypeError, r"eta_alive must be a numeric array, could not "
                                            r"convert"),
])
def test_bad_eta_messages(dead, alive, err, match):
    with pytest.raises(err, match=match):
        MultiSensorProblem.from_eta(dead, alive)


def test_bad_log_eta_messages():
    with pytest.raises(ValueError, match=r"log_eta_alive contains \+inf at \(0, 1\); a weight "
                                         r"must be finite"):
        MultiSensorProblem.from_log_eta([0.0], [[0.0, inf]])
    with pytest.raises(ValueError, match=r"log_eta_dead contains NaN at \(0,\)"):
        MultiSensorProblem.from_log_eta([np.nan], [[0.0]])


def test_must_detect_rows_that_fit_are_accepted():
    a = np.zeros((2, 3, 3))
    a[0, 1, 1] = a[0, 2, 2] = 1.0
    a[1, 1, 1] = 1.0  # row 1 can only take (1, 1): row 0 must take (2, 2)
    p = MultiSensorProblem.from_eta([0.0, 0.0], a)
    assert p.n_feasible() == 1


@pytest.mark.parametrize("kwargs, err, match", [
    (dict(theta=np.ones((1, 2))), TypeError, r"theta must be a sequence of V arrays of shape "
                                             r"\(P, M_v\+1\), one per sensor, got ndarray"),
    (dict(theta=[]), ValueError, r"theta must hold at least one sensor's \(P, M_v\+1\) array"),
    (dict(theta=[np.ones((2, 2))]), ValueError, r"theta\[0\] must have shape \(P, M_1\+1\) with "
                                                r"P = 1, got shape \(2, 2\)"),
    (dict(pbar_s=[0.5, 0.5]), ValueError, r"pbar_s must have shape \(P,\) = \(1,\) to match "
                                          r"eta_dead, got shape \(2,\)"),
    (dict(eta_dead=[[0.5]]), ValueError, r"eta_dead must be 1-D with shape \(P,\), got shape "
                                         r"\(1, 1\)"),
    (dict(coupling=np.ones((1, 3))), ValueError, r"coupling must have shape \(P, M_1\+1, \.\.\., "
                                                 r"M_V\+1\) = \(1, 2\), got shape \(1, 3\)"),
    (dict(coupling=-np.ones((1, 2))), ValueError, r"coupling has a negative entry"),
    (dict(pbar_s=[np.nan]), ValueError, r"pbar_s contains NaN"),
    (dict(theta=[[[1.0, -1.0]]]), ValueError, r"theta\[0\] has a negative entry at \(0, 1\)"),
])
def test_bad_factor_messages(kwargs, err, match):
    args = dict(eta_dead=[0.5], pbar_s=[0.5], theta=[np.ones((1, 2))], coupling=None)
    args.update(kwargs)
    with pytest.raises(err, match=match):
        MultiSensorProblem.from_factors(**args)


def test_from_factors_refuses_a_table_too_large_before_building_it():
    # V = 40 sensors of one measurement each: 2 * 2**40 entries (16 TiB) used to be attempted
    d, s, th = [0.5, 0.5], [0.5, 0.5], [np.ones((2, 2))] * 40
    with pytest.raises(ValueError, match=(
            r"^V = 40 sensors with M = \(1, 1, 1, 1, \.\.\., 1\) \(40 sensors\) give a weight "
            r"table of shape \(2, 2, 2, 2, \.\.\., 2\) \(41 axes\): 2199023255552 entries, "
            r"16\.0 TiB \(17592186044416 bytes\) of float64, more than MAX_TABLE_ENTRIES = "
            r"134217728 entries, 1\.0 GiB \(1073741824 bytes\)$")):
        MultiSensorProblem.from_factors(d, s, th)
    # V = 64 used to reach numpy's "maximum supported dimension"
    with pytest.raises(ValueError, match=r"^V = 64 sensors .* 36893488147419103232 entries, "
                                         r"256\.0 EiB .* more than MAX_TABLE_ENTRIES"):
        MultiSensorProblem.from_factors(d, s, [np.ones((2, 2))] * 64)
    # a tiny table with too many axes: 64 sensors without measurements
    with pytest.raises(ValueError, match=r"^V = 64 sensors with M = \(0, 0, 0, 0, \.\.\., 0\) "
                                         r"\(64 sensors\) give a weight table of shape \(2, 1, 1, "
                                         r"1, \.\.\., 1\) \(65 axes\): 2 entries, 16 bytes of "
                                         r"float64, but with 65 axes, more than the 64 of a numpy "
                                         r"array \(at most 63 sensors\)$"):
        MultiSensorProblem.from_factors(d, s, [np.ones((2, 1))] * 64)
    assert MultiSensorProblem.from_factors(d, s, [np.ones((2, 1))] * 63).n_sensors == 63
    assert msp.MAX_TABLE_ENTRIES == 2**27


def test_table_size_limit_is_inclusive(monkeypatch):
    monkeypatch.setattr(msp, "MAX_TABLE_ENTRIES", 2**10)
    th = [np.ones((1, 2))] * 10
    assert MultiSensorProblem.from_factors([0.5], [0.5], th).shape == (1,) + (1,) * 10
    with pytest.raises(ValueError, match=r"2048 entries, 16\.0 KiB \(16384 bytes\) of float64, "
                                         r"more than MAX_TABLE_ENTRIES = 1024 entries"):
        MultiSensorProblem.from_factors([0.5] * 2, [0.5] * 2, [np.ones((2, 2))] * 10)


def test_bad_raw_constructor_factors():
    with pytest.raises(ValueError, match="log_s and log_theta must be given together or not at "
                                         "all"):
        MultiSensorProblem([0.0], [[0.0]], log_s=[0.0])
    with pytest.raises(ValueError, match=r"log_theta must hold one array per sensor \(V = 1\), "
                                         r"got 2"):
        MultiSensorProblem([0.0], [[0.0]], [0.0], [[[0.0]], [[0.0]]])
    with pytest.raises(ValueError, match=r"log_theta\[0\] must have shape \(P, M_1\+1\) = "
                                         r"\(1, 1\), got \(1, 2\)"):
        MultiSensorProblem([0.0], [[0.0]], [0.0], [[[0.0, 0.0]]])
    with pytest.raises(ValueError, match=r"log_s must have shape \(P,\) = \(1,\), got \(2,\)"):
        MultiSensorProblem([0.0], [[0.0]], [0.0, 0.0], [[[0.0]]])


def test_conversion_messages():
    with pytest.raises(ValueError, match="only a one-sensor problem converts to an "
                                         "AssignmentProblem, this one has V = 2 sensors"):
        MultiSensorProblem.from_eta([1.0], np.ones((1, 1, 1))).to_assignment_problem()
    with pytest.raises(TypeError, match="problem must be a rankedassign.AssignmentProblem, got "
                                        "MultiSensorProblem"):
        MultiSensorProblem.from_assignment_problem(
            MultiSensorProblem.from_eta([1.0], np.ones((1, 1))))


def test_empty_problem():
    p = MultiSensorProblem.from_eta(np.zeros(0), np.zeros((0, 3, 2)))
    assert p.n_feasible() == 1
    assert p.log_weight_of(np.zeros((0, 2), dtype=int)) == 0.0
    assert p.to_assignment_problem if p.n_sensors == 1 else True


def test_single_sensor_problem_from_single_layout():
    sp = AssignmentProblem.from_eta([[2.0, 0.5], [0.1, 3.0]], [0.2, 0.3], [0.1, 0.1])
    mp = MultiSensorProblem.from_assignment_problem(sp)
    assert_allclose(np.exp(mp.log_eta_alive), [[0.2, 2.0, 0.5], [0.3, 0.1, 3.0]], rtol=1e-15)
    assert_allclose(np.exp(mp.log_eta_dead), [0.1, 0.1], rtol=1e-15)
