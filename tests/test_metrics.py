"""Tests of rankedassign.metrics: OSPA, OSPA(2) and tracks_to_array."""

import itertools
import math
import re

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from naive import ospa as brute_ospa
from naive import ospa2 as naive_ospa2
from numpy.testing import assert_allclose, assert_array_equal

from rankedassign.metrics import (
    OSPA2Result,
    OSPAResult,
    gospa,
    ospa,
    ospa2,
    track_coverage,
    tracks_to_array,
)

coord = st.floats(-50, 50, allow_nan=False, allow_infinity=False)


def point_sets(max_n=4, d=2):
    return st.integers(0, max_n).flatmap(
        lambda n: arrays(np.float64, (n, d), elements=coord)
    )


cutoffs = st.floats(0.5, 80.0)
orders = st.sampled_from([1.0, 2.0, 3.5])


# --------------------------------------------------------------------------- OSPA properties
@given(point_sets(), cutoffs, orders)
def test_ospa_zero_on_identical_sets(X, c, p):
    r = ospa(X, X, c, p)
    assert_allclose([r.value, r.localisation, r.cardinality], 0.0, atol=1e-9)


@given(point_sets(), point_sets(), cutoffs, orders)
def test_ospa_symmetric_and_bounded(X, Y, c, p):
    a = ospa(X, Y, c, p)
    b = ospa(Y, X, c, p)
    assert_allclose(a.value, b.value, rtol=1e-12, atol=1e-12)
    assert 0.0 <= a.value <= c * (1 + 1e-12)
    # value^p = localisation^p + cardinality^p
    assert_allclose(a.value**p, a.localisation**p + a.cardinality**p, rtol=1e-9, atol=1e-9)


@given(point_sets(3), point_sets(3), point_sets(3), cutoffs, orders)
def test_ospa_triangle_inequality(X, Y, Z, c, p):
    xy = ospa(X, Y, c, p).value
    yz = ospa(Y, Z, c, p).value
    xz = ospa(X, Z, c, p).value
    assert xz <= xy + yz + 1e-9


@given(point_sets(4), point_sets(4), cutoffs, orders)
def test_ospa_matches_brute_force(X, Y, c, p):
    assert_allclose(ospa(X, Y, c, p).value, brute_ospa(X, Y, c, p), rtol=1e-9, atol=1e-12)


def test_ospa_hand_values():
    r = ospa([[0.0, 0.0], [10.0, 0.0]], [[0.0, 3.0]], c=100.0, p=1)
    assert isinstance(r, OSPAResult)
    assert_allclose(r, (51.5, 1.5, 50.0), rtol=1e-12)
    assert ospa([], [], 5.0, 1) == (0.0, 0.0, 0.0)
    assert_allclose(ospa([[1.0, 2.0]], np.empty((0, 2)), 5.0, 2), (5.0, 0.0, 5.0), rtol=1e-12)
    # cut-off applies per pair
    assert_allclose(ospa([[0.0, 0.0]], [[1e6, 0.0]], 7.0, 1).value, 7.0, rtol=1e-12)


@pytest.mark.parametrize("p", [1.0, 2.0, 3.5, 1e5])
@pytest.mark.parametrize("empty", [[], np.zeros(0), np.zeros((0, 0)), np.zeros((0, 3))],
                         ids=["list", "shape (0,)", "shape (0, 0)", "shape (0, 3)"])
def test_ospa_of_an_empty_set_against_points_is_c(empty, p):
    # [] and shape (0,) used to give a numpy broadcast error against 3-D points
    X = np.array([[0.0, 0.0, 0.0], [1.0, 2.0, 3.0]])
    assert ospa(X, empty, 7.0, p) == (7.0, 0.0, 7.0)
    assert ospa(empty, X, 7.0, p) == (7.0, 0.0, 7.0)
    assert ospa(empty, [], 7.0, p) == (0.0, 0.0, 0.0)
    assert ospa(empty, np.zeros((0, 3)), 7.0, p) == (0.0, 0.0, 0.0)


def test_ospa_refuses_an_empty_set_of_another_dimension():
    X = np.array([[0.0, 0.0, 0.0]])
    with pytest.raises(ValueError, match=r"^X and Y must have the same point dimension, got 3 and "
                                         r"2 \(Y empty: an empty set without a dimension is \[\] "
                                         r"or shape \(0, 0\)\)$"):
        ospa(X, np.zeros((0, 2)), 7.0, 1)
    with pytest.raises(ValueError, match=r"^X and Y must have the same point dimension, got 2 and "
                                         r"3 \(X empty"):
        ospa(np.zeros((0, 2)), X, 7.0, 1)
    with pytest.raises(ValueError, match=r"got 2 and 3 \(X and Y empty"):
        ospa(np.zeros((0, 2)), np.zeros((0, 3)), 7.0, 1)
    with pytest.raises(ValueError, match=r"^X and Y must have the same point dimension, got 3 and "
                                         r"2$"):
        ospa(X, [[0.0, 0.0]], 7.0, 1)


@pytest.mark.parametrize("p", [1.0, 2.0, 1e5])
def test_ospa2_of_no_tracks_against_tracks_is_c_whatever_the_empty_side_dimension(p):
    X = np.array([[[0.0, 0.0]], [[1.0, 1.0]]])
    for none in (np.zeros((2, 0, 0)), np.zeros((2, 0, 2)), np.zeros((2, 0, 5))):
        assert_array_equal(ospa2(X, none, 7.0, p, 2).value, [7.0, 7.0])
        assert_array_equal(ospa2(none, X, 7.0, p, 2).value, [7.0, 7.0])
        assert_array_equal(ospa2(none, none, 7.0, p, 2).value, [0.0, 0.0])


@pytest.mark.parametrize(
    ("args", "exc", "match"),
    [
        (([[0.0]], [[0.0]], -1.0, 1), ValueError, r"c must be > 0.0, got -1.0"),
        (([[0.0]], [[0.0]], 0.0, 1), ValueError, r"c must be > 0.0, got 0.0"),
        (([[0.0]], [[0.0]], np.inf, 1), ValueError, r"c must be a finite real number, got inf"),
        (([[0.0]], [[0.0]], 1.0, 0.5), ValueError, r"p must be >= 1.0, got 0.5"),
        (([[0.0]], [[0.0]], 1.0, np.inf), ValueError, r"p must be a finite real number, got inf"),
        (([[0.0]], [[0.0]], 1.0, np.nan), ValueError, r"p must be a finite real number, got nan"),
        (([[0.0]], [[np.nan]], 1.0, 1), ValueError, "Y contains NaN or inf"),
        (([[0.0, 1.0]], [[0.0]], 1.0, 1), ValueError, "same point dimension"),
        (([0.0, 1.0], [[0.0]], 1.0, 1), ValueError, "X must be 2-D"),
        (([[0.0]], [[0.0]], "a", 1), TypeError, r"c must be a real number, got str 'a'"),
        (([[0.0]], [[0.0]], 1.0, True), TypeError, r"p must be a real number, got bool True"),
        (([["a"]], [[0.0]], 1.0, 1), TypeError, r"X must be a numeric array, got dtype <U1"),
        (([[0.0], [1.0, 2.0]], [[0.0]], 1.0, 1), TypeError, r"X must be a numeric array, could not convert"),
        (([[0.0]], [[1j]], 1.0, 1), TypeError, r"Y must be real, got dtype complex128"),
    ],
)
def test_ospa_errors(args, exc, match):
    with pytest.raises(exc, match=match):
        ospa(*args)


# --------------------------------------------------------------------------- OSPA(2)
def track_arrays(max_scans=6, max_tracks=3, d=2):
    """Random NaN-padded track arrays with arbitrary (possibly gappy) domains."""

    @st.composite
    def build(draw):
        K = draw(st.integers(1, max_scans))
        n = draw(st.integers(0, max_tracks))
        vals = draw(arrays(np.float64, (K, n, d), elements=coord))
        mask = draw(arrays(np.bool_, (K, n)))
        vals[~mask] = np.nan
        return vals

    return build()


@st.composite
def truth_estimate_pairs(draw):
    a = draw(track_arrays())
    K = a.shape[0]
    n = draw(st.integers(0, 3))
    b = draw(arrays(np.float64, (K, n, 2), elements=coord))
    mask = draw(arrays(np.bool_, (K, n)))
    b[~mask] = np.nan
    return a, b


@given(truth_estimate_pairs(), cutoffs, orders)
def test_ospa2_window_one_equals_ospa(pair, c, p):
    X, Y = pair
    res = ospa2(X, Y, c, p, window=1)
    for k in range(X.shape[0]):
        x = X[k][~np.isnan(X[k]).any(axis=1)]
        y = Y[k][~np.isnan(Y[k]).any(axis=1)]
        o = ospa(x, y, c, p)
        assert_allclose(
            [res.value[k], res.localisation[k], res.cardinality[k]], o, rtol=1e-10, atol=1e-10
        )


@given(truth_estimate_pairs(), cutoffs, orders, st.integers(1, 4), st.sampled_from([0, 1, 2]))
def test_ospa2_symmetric_bounded(pair, c, p, window, r):
    X, Y = pair
    a = ospa2(X, Y, c, p, window, weight_power=r)
    b = ospa2(Y, X, c, p, window, weight_power=r)
    assert_allclose(a.value, b.value, rtol=1e-10, atol=1e-10)
    assert np.all(a.value >= 0) and np.all(a.value <= c * (1 + 1e-12))


@given(track_arrays(), cutoffs, orders, st.integers(1, 4))
def test_ospa2_truth_against_itself_is_zero(X, c, p, window):
    for base in ("euclidean", "lp"):
        assert_allclose(ospa2(X, X, c, p, window, base=base).value, 0.0, atol=1e-9)


@given(track_arrays(), cutoffs, orders, st.integers(1, 4))
def test_ospa2_against_no_estimates_is_c_where_truth_exists(X, c, p, window):
    # spec §10.7: c wherever some truth exists in the window, 0 where none does.
    K = X.shape[0]
    empty = np.full((K, 0, 2), np.nan)
    res = ospa2(X, empty, c, p, window)
    exists = ~np.isnan(X).any(axis=2)
    in_window = np.array([exists[max(0, k - window + 1) : k + 1].any() for k in range(K)])
    assert_allclose(res.value, np.where(in_window, c, 0.0), rtol=1e-12)
    assert_allclose(res.cardinality, np.where(in_window, c, 0.0), rtol=1e-12)
    assert_allclose(res.localisation, 0.0, atol=0)


@given(truth_estimate_pairs(), cutoffs, orders, st.integers(1, 4), st.sampled_from([0, 1, 2]),
       st.sampled_from(["euclidean", "lp"]))
def test_ospa2_matches_naive_reference(pair, c, p, window, r, base):
    X, Y = pair
    got = ospa2(X, Y, c, p, window, weight_power=r, base=base).value
    assert_allclose(got, naive_ospa2(X, Y, c, p, window, r, base), rtol=1e-9, atol=1e-9)


def test_ospa2_hand_example():
    truth = np.array([[[0.0, 0.0]], [[1.0, 0.0]], [[2.0, 0.0]]])
    est = np.array([[[np.nan, np.nan]], [[1.0, 3.0]], [[2.0, 3.0]]])
    res = ospa2(truth, est, c=10.0, p=1, window=2)
    assert isinstance(res, OSPA2Result)
    assert_allclose(res.value, [10.0, 6.5, 3.0], rtol=1e-12)
    assert_allclose(res.cardinality, [10.0, 0.0, 0.0], rtol=1e-12)
    # Weights w_t = (t - k + N)^r: at k = 2 (1-based 2) with N = 2, r = 1 the older scan has
    # weight 1 and the newer 2: (1 * 10 + 2 * 3) / 3.
    res1 = ospa2(truth, est, c=10.0, p=1, window=2, weight_power=1)
    assert_allclose(res1.value[1], (10.0 + 2 * 3.0) / 3, rtol=1e-12)


def test_ospa2_lp_base_matches_compute_ospa2_convention():
    # A 3-4-5 offset: Euclidean 5, L1 (p = 1) 7; with p = 2 the lp base uses 9 + 16 = 25 = 5^2.
    truth = np.array([[[0.0, 0.0]]])
    est = np.array([[[3.0, 4.0]]])
    assert_allclose(ospa2(truth, est, 100.0, 1, 1).value, [5.0], rtol=1e-12)
    assert_allclose(ospa2(truth, est, 100.0, 1, 1, base="lp").value, [7.0], rtol=1e-12)
    assert_allclose(ospa2(truth, est, 100.0, 2, 1, base="lp").value, [5.0], rtol=1e-12)
    # lp averages d^p over time: distances 5 and c = 10 (absent), p = 2 -> sqrt((25 + 100) / 2)
    truth2 = np.array([[[0.0, 0.0]], [[0.0, 0.0]]])
    est2 = np.array([[[3.0, 4.0]], [[np.nan, np.nan]]])
    got = ospa2(truth2, est2, 10.0, 2, 2, base="lp").value[1]
    assert_allclose(got, np.sqrt((25.0 + 100.0) / 2), rtol=1e-12)
    # Euclidean averages d over time, then raises to p: (5 + 10) / 2
    assert_allclose(ospa2(truth2, est2, 10.0, 2, 2).value[1], 7.5, rtol=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "exc", "match"),
    [
        ({"estimates": np.zeros((2, 1, 2))}, ValueError, "same number of scans"),
        ({"estimates": np.zeros((3, 1, 3))}, ValueError, "same state dimension"),
        ({"estimates": np.array([[[0.0, np.nan]]] * 3)}, ValueError, r"estimates\[0, 0\] is partly NaN"),
        ({"c": -1.0}, ValueError, r"c must be > 0.0, got -1.0"),
        ({"p": 0.0}, ValueError, r"p must be >= 1.0, got 0.0"),
        ({"window": 0}, ValueError, r"window must be an int >= 1, got 0"),
        ({"window": 2**63}, ValueError, r"window must be an int <= 4611686018427387904 \(2\*\*62\), got 9223372036854775808"),
        ({"window": 1.5}, TypeError, r"window must be an int, got float 1.5"),
        ({"window": True}, TypeError, r"window must be an int, got bool True"),
        ({"base": "manhattan"}, ValueError, r"unknown base 'manhattan'; expected one of \('euclidean', 'lp'\)"),
        ({"weight_power": -1}, ValueError, r"weight_power must be >= 0.0, got -1.0"),
        ({"weight_power": np.nan}, ValueError, r"weight_power must be a finite real number, got nan"),
        ({"weight_power": "1"}, TypeError, r"weight_power must be a real number, got str '1'"),
        ({"truth": np.full((3, 1, 2), np.inf)}, ValueError, r"truth contains inf"),
        ({"truth": [[["x"]]]}, TypeError, r"truth must be a numeric array, got dtype <U1"),
        ({"truth": np.zeros((3, 2))}, ValueError, "truth must be 3-D"),
    ],
)
def test_ospa2_errors(kwargs, exc, match):
    args = {
        "truth": np.zeros((3, 1, 2)),
        "estimates": np.zeros((3, 1, 2)),
        "c": 10.0,
        "p": 1,
        "window": 2,
    }
    args.update(kwargs)
    with pytest.raises(exc, match=match):
        ospa2(**args)


# --------------------------------------------------------------------------- tracks_to_array
def test_tracks_to_array_orders_by_first_appearance():
    est = [
        {},
        {"b": [1.0, 2.0, 3.0, 4.0]},
        {"a": [5.0, 6.0, 7.0, 8.0], "b": [0.0, 0.0, 0.0, 0.0]},
    ]
    arr, labels = tracks_to_array(est, dims=(0, 2), return_labels=True)
    assert labels == ["b", "a"]
    assert arr.shape == (3, 2, 2)
    assert np.isnan(arr[0]).all()
    assert_array_equal(arr[1, 0], [1.0, 3.0])
    assert np.isnan(arr[1, 1]).all()
    assert_array_equal(arr[2], [[0.0, 0.0], [5.0, 7.0]])
    full = tracks_to_array(est)
    assert full.shape == (3, 2, 4)


def test_tracks_to_array_errors():
    with pytest.raises(ValueError, match="has 2 components, expected 4"):
        tracks_to_array([{1: [0.0] * 4}, {1: [0.0, 0.0]}])
    with pytest.raises(ValueError, match=r"dims \[0, 4\] out of range for states of length 4"):
        tracks_to_array([{1: [0.0] * 4}], dims=(0, 4))
    with pytest.raises(ValueError, match=r"dims\[1\] must be an int >= 0, got -1"):
        tracks_to_array([{1: [0.0] * 4}], dims=(0, -1))
    with pytest.raises(TypeError, match=r"dims\[0\] must be an int, got float 0.5"):
        tracks_to_array([{1: [0.0] * 4}], dims=(0.5,))  # once silently truncated to 0
    with pytest.raises(TypeError, match=r"dims must be a sequence of ints, got int"):
        tracks_to_array([{1: [0.0] * 4}], dims=0)
    with pytest.raises(TypeError, match=r"labelled_estimates must be a sequence \(one mapping per scan\), got dict"):
        tracks_to_array({1: [0.0]})
    with pytest.raises(TypeError, match=r"labelled_estimates\[1\] must be a mapping from track label to state, got list"):
        tracks_to_array([{}, [0.0]])
    with pytest.raises(TypeError, match=r"state of track 'a' at scan 0 must be a numeric array, got dtype <U3"):
        tracks_to_array([{"a": ["one", "two"]}])
    with pytest.raises(TypeError, match=r"return_labels must be a bool, got int 1"):
        tracks_to_array([{}], return_labels=1)
    assert tracks_to_array([{}, {}]).shape == (2, 0, 0)


# ---------------------------------------------------------------------------------- coverage
@given(track_arrays(), st.integers(0, 3))
def test_track_coverage_of_truth_by_itself_and_by_nothing(X, settle):
    alive = (~np.isnan(X).any(axis=2)).sum(axis=0)
    counted = alive > settle  # tracks with a scan left after the settling time
    full = track_coverage(X, X, 1e-9, settle=settle)
    none = track_coverage(X, np.full((X.shape[0], 0, 2), np.nan), 1.0, settle=settle)
    assert_array_equal(full[counted], 1.0)
    assert_array_equal(none[counted], 0.0)
    assert np.isnan(full[~counted]).all() and np.isnan(none[~counted]).all()


@given(truth_estimate_pairs(), st.floats(0.1, 100.0))
def test_track_coverage_matches_a_plain_loop(pair, radius):
    X, Y = pair
    got = track_coverage(X, Y, radius)
    for f in range(X.shape[1]):
        scans = [k for k in range(X.shape[0]) if not np.isnan(X[k, f]).any()]
        hit = [any(np.linalg.norm(y - X[k, f]) <= radius for y in Y[k]
                   if not np.isnan(y).any()) for k in scans]
        assert (np.isnan(got[f]) if not scans else got[f] == sum(hit) / len(scans))


def test_track_coverage_hand_case_and_labels_play_no_part():
    nan = np.nan
    truth = np.array([[[0.0, 0.0], [nan, nan]],
                      [[1.0, 0.0], [50.0, 50.0]],
                      [[2.0, 0.0], [51.0, 50.0]],
                      [[3.0, 0.0], [52.0, 50.0]]])
    # track 0 covers target 0 twice, then jumps onto target 1 (a label switch still covers)
    est = np.array([[[nan, nan]], [[1.5, 0.0]], [[2.0, 4.0]], [[52.0, 51.0]]])
    assert_array_equal(track_coverage(truth, est, 5.0), [0.5, 1 / 3])
    assert_array_equal(track_coverage(truth, est, 5.0, settle=1), [2 / 3, 0.5])
    assert_array_equal(track_coverage(truth, est, 4.0), [0.5, 1 / 3])  # the boundary counts
    assert_array_equal(track_coverage(truth, est, 3.9), [0.25, 1 / 3])


@pytest.mark.parametrize(
    ("args", "kwargs", "exc", "match"),
    [
        ((np.zeros((3, 1, 2)), np.zeros((2, 1, 2)), 1.0), {}, ValueError,
         "same number of scans, got 3 and 2"),
        ((np.zeros((3, 1, 2)), np.zeros((3, 1, 3)), 1.0), {}, ValueError,
         "same state dimension, got 2 and 3"),
        ((np.zeros((3, 2)), np.zeros((3, 1, 2)), 1.0), {}, ValueError,
         r"truth must be 3-D with shape \(n_scans, n_tracks, d\), got shape \(3, 2\)"),
        ((np.array([[[np.nan, 0.0]]]), np.zeros((1, 1, 2)), 1.0), {}, ValueError,
         r"truth\[0, 0\] is partly NaN"),
        ((np.zeros((3, 1, 2)), np.zeros((3, 1, 2)), 0.0), {}, ValueError,
         r"radius must be > 0.0, got 0.0"),
        ((np.zeros((3, 1, 2)), np.zeros((3, 1, 2)), np.inf), {}, ValueError,
         r"radius must be a finite real number, got inf"),
        ((np.zeros((3, 1, 2)), np.zeros((3, 1, 2)), "far"), {}, TypeError,
         r"radius must be a real number, got str 'far'"),
        ((np.zeros((3, 1, 2)), np.zeros((3, 1, 2)), 1.0), {"settle": -1}, ValueError,
         r"settle must be an int >= 0, got -1"),
        ((np.zeros((3, 1, 2)), np.zeros((3, 1, 2)), 1.0), {"settle": 1.5}, TypeError,
         r"settle must be an int, got float 1.5"),
    ],
)
def test_track_coverage_errors(args, kwargs, exc, match):
    with pytest.raises(exc, match=match):
        track_coverage(*args, **kwargs)


def test_nothing_reported_is_accepted_whatever_its_dimension():
    # tracks_to_array of a filter that reported nothing has shape (n_scans, 0, 0)
    X = np.array([[[0.0, 0.0]], [[np.nan, np.nan]], [[1.0, 1.0]]])
    none = tracks_to_array([{}, {}, {}])
    assert none.shape == (3, 0, 0)
    assert_array_equal(ospa2(X, none, 10.0, 1, 1).value, [10.0, 0.0, 10.0])
    assert_array_equal(ospa2(none, X, 10.0, 1, 1).value, [10.0, 0.0, 10.0])
    assert_array_equal(track_coverage(X, none, 1.0), [0.0])


# ------------------------------------------------------------------ extreme orders and ranges
# The definition (spec 7.3) in exact rational arithmetic: with u = min(c, d) / c,
#   (value / c)^p = (min_pi sum u^p + (n - m)) / n,
# compared in log space, ln(value / c) = (ln T - ln n) / p, which no order p can over- or
# underflow. Points lie on a grid of quarters in 1-D, so every distance is an exact double.
grid = st.integers(-80, 80).map(lambda k: k / 4)


def exact_log_ospa(X, Y, c, p):
    """``ln(value / c)``, ``ln(loc / c)``, ``ln(card / c)`` from exact rationals (p an int)."""
    from fractions import Fraction

    if len(X) > len(Y):
        X, Y = Y, X
    m, n = len(X), len(Y)
    cf = Fraction(c)
    best = None
    for perm in itertools.permutations(range(n), m):
        s = sum((min(cf, abs(Fraction(X[i]) - Fraction(Y[j]))) / cf) ** p
                for i, j in enumerate(perm))
        best = s if best is None or s < best else best

    def log(q):
        return -np.inf if q == 0 else (math.log(q.numerator) - math.log(q.denominator))

    ln_n = math.log(n)
    return ((log(best + (n - m)) - ln_n) / p, (log(best) - ln_n) / p,
            (log(Fraction(n - m)) - ln_n) / p)


@given(st.lists(grid, max_size=3), st.lists(grid, min_size=1, max_size=3),
       st.sampled_from([0.25, 1.0, 3.0, 7.25]), st.integers(1, 3000))
def test_ospa_any_order_matches_the_exact_definition(xs, ys, c, p):
    X = np.array(xs, dtype=float).reshape(-1, 1)
    Y = np.array(ys, dtype=float).reshape(-1, 1)
    got = ospa(X, Y, c, p)
    want = exact_log_ospa(xs, ys, c, p)
    for g, w in zip(got, want, strict=True):
        # relative 1e-12 on the value: the p-th root undoes the p-th power's error
        assert_allclose(g, c * math.exp(w), rtol=1e-12, atol=0)


@pytest.mark.parametrize("p", [1, 2, 100, 134, 135, 200, 1000, 1e6, 1e300])
def test_ospa_large_order_one_pair_is_the_cut_off_distance(p):
    # the hardening issue: p = 200 gave 0.0 (underflow), p > ~134 an OverflowError
    r = ospa([[0, 0]], [[0.001, 0]], c=0.01, p=p)
    assert_allclose(r, (0.001, 0.001, 0.0), rtol=1e-12)
    assert_allclose(ospa([[0.0]], [[5.0]], c=2.0, p=p), (2.0, 2.0, 0.0), rtol=1e-15)
    # one unmatched point: value = c ((u^p + 1) / 2)^(1/p) -> c as p grows
    r = ospa([[0.0], [100.0]], [[0.5]], c=1.0, p=p)
    assert_allclose(r.cardinality, 2.0 ** (-1.0 / p), rtol=1e-14)
    assert r.localisation == pytest.approx(0.5 * 2.0 ** (-1.0 / p), rel=1e-13)
    assert r.cardinality <= r.value <= 1.0


def log_brute_ospa(X, Y, c, p):
    """``ln(value / c)`` by enumerating injections, every sum of p-th powers in log space."""
    from scipy.special import logsumexp

    X, Y = np.asarray(X, float), np.asarray(Y, float)
    if len(X) > len(Y):
        X, Y = Y, X
    m, n = len(X), len(Y)
    extra = [math.log(n - m)] if n > m else []
    best = np.inf
    # math.hypot scales before squaring: np.linalg.norm's sum of squares underflows to 0 for
    # coordinates of 1e-300 (hypothesis found X = [[0, 0]], Y = [[1e-300, 1e-300]])
    dist = [[math.hypot(*(X[i] - Y[j])) for j in range(n)] for i in range(m)]
    for perm in itertools.permutations(range(n), m):
        terms = [p * math.log(min(1.0, dist[i][j] / c)) if dist[i][j] > 0 else -np.inf
                 for i, j in enumerate(perm)]
        best = min(best, logsumexp(terms + extra) if terms + extra else -np.inf)
    return (best - math.log(n)) / p


@given(point_sets(3), point_sets(3), cutoffs, st.sampled_from([150.0, 700.0, 5000.0, 1e5]))
def test_ospa_large_order_matches_log_domain_brute_force(X, Y, c, p):
    # (d / c)^p underflows a double for most pairs here: the optimum is found among terms that
    # differ by thousands of orders of magnitude, and tends to the bottleneck matching.
    got = ospa(X, Y, c, p).value
    if len(X) == 0 and len(Y) == 0:
        assert got == 0.0
    else:
        assert_allclose(got, c * math.exp(log_brute_ospa(X, Y, c, p)), rtol=1e-10, atol=0)


def test_ospa_extreme_coordinates_and_cut_offs():
    big = np.finfo(float).max
    # differences beyond the largest double are beyond any finite cut-off
    assert_allclose(ospa([[big]], [[-big]], 5.0, 1), (5.0, 5.0, 0.0), rtol=1e-15)
    assert_allclose(ospa([[0.0, 0.0]], [[1e200, 1e200]], 1e300, 2).value,
                    np.sqrt(2) * 1e200, rtol=1e-15)  # no overflow in the norm
    # c^p beyond the largest double (c = 1e308, p = 3): no overflow
    r = ospa([[0.0]], [[1e308], [-1e308]], c=1e308, p=3)
    assert_allclose(r, (1e308, 1e308 * 2 ** (-1 / 3), 1e308 * 2 ** (-1 / 3)), rtol=1e-14)
    # subnormal distances and cut-offs
    tiny = 5e-324
    assert_allclose(ospa([[0.0]], [[4 * tiny]], c=1e-300, p=1).value, 4 * tiny, rtol=0.3)
    assert_allclose(ospa([[0.0]], [[1.0]], c=tiny, p=1).value, tiny, rtol=1e-15)
    # zero-dimensional points: every distance is 0
    assert_allclose(ospa(np.zeros((2, 0)), np.zeros((3, 0)), 2.0, 1), (2 / 3, 0.0, 2 / 3),
                    rtol=1e-15)


@given(truth_estimate_pairs(), cutoffs, st.sampled_from([150.0, 700.0, 5000.0]),
       st.integers(1, 3), st.sampled_from(["euclidean", "lp"]))
def test_ospa2_large_order_window_one_equals_ospa(pair, c, p, window, base):
    X, Y = pair
    res = ospa2(X, Y, c, p, window=1, base=base)
    assert np.isfinite(res.value).all()
    assert np.all(res.value <= c * (1 + 1e-12))
    if base == "euclidean":
        for k in range(X.shape[0]):
            x = X[k][~np.isnan(X[k]).any(axis=1)]
            y = Y[k][~np.isnan(Y[k]).any(axis=1)]
            assert_allclose(list(res[0][k:k + 1]) + [res.localisation[k], res.cardinality[k]],
                            ospa(x, y, c, p), rtol=1e-10, atol=1e-300)


def test_ospa2_large_order_and_weight_power_by_hand():
    # one truth, one estimate at distance 1 then 3, c = 10, window 2
    truth = np.array([[[0.0, 0.0]], [[0.0, 0.0]]])
    est = np.array([[[1.0, 0.0]], [[3.0, 0.0]]])
    for p in (1, 300, 1e5):
        # euclidean: averages d (not d^p) over time, so the value is the mean distance 2
        assert_allclose(ospa2(truth, est, 10.0, p, 2).value, [1.0, 2.0], rtol=1e-13)
        # lp: averages d^p: ((1 + 3^p) / 2)^(1/p) = 3 (1/2 + 3^-p / 2)^(1/p)
        want = 3.0 * (0.5 + 0.5 * 3.0 ** -p) ** (1 / p)
        assert_allclose(ospa2(truth, est, 10.0, p, 2, base="lp").value, [1.0, want], rtol=1e-13)
    # weight power r = 2000: the newest scan weighs 2^2000 (beyond a double) against 1
    w = 2.0**-2000  # relative weight of the older scan, itself subnormal-free in log space
    assert_allclose(ospa2(truth, est, 10.0, 1, 2, weight_power=2000).value,
                    [1.0, (w * 1.0 + 3.0) / (w + 1.0)], rtol=1e-15)
    # window 2**62: the whole history
    assert_allclose(ospa2(truth, est, 10.0, 1, 2**62).value, [1.0, 2.0], rtol=1e-15)


@pytest.mark.parametrize("bad", [10**400, -(10**400)])
def test_an_int_beyond_the_floats_is_refused_as_infinite(bad):
    # found by the fuzz test: p = 10**400 raised OverflowError inside the argument check
    with pytest.raises(ValueError, match=re.escape("p must be a finite real number, got "
                                                   f"{'inf' if bad > 0 else '-inf'}")):
        ospa([], [], 1.0, bad)
    with pytest.raises(ValueError, match="c must be a finite real number"):
        gospa([], [], bad, 1.0)
