"""The sparse route of OSPA(2) and GOSPA against the dense one: the same values.

The sparse route keeps only the pairs closer than the cut-off and solves the assignment one
connected component at a time; it is exact, so it is checked against the dense route to
1e-12 relative on small random scenes built to hit the corner cases: points on a grid (pairs
exactly at the cut-off, ties between assignments), empty sides, gaps in tracks, windows longer
than one scan, orders 1 and 2 (and orders whose costs underflow a double, where the sparse
route works in log space), both bases. The scenes of orders 1 and 2 run once more with every
component of three or more pairs sent to LAPJVsp, the solver of components above
``DENSE_COMPONENT_MAX`` entries.
"""

from __future__ import annotations

from unittest import mock

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from numpy.testing import assert_allclose

from rankedassign import metrics
from rankedassign.metrics import gospa, gospa_series, ospa2

# multiples of 10 m with cut-offs of 10, 20, 30 and 50 m: many pairs lie exactly at c (the
# 30-40-50 triangle among them) and many assignments tie
grid = st.integers(0, 6).map(lambda v: 10.0 * v)
cutoffs = st.sampled_from([10.0, 20.0, 30.0, 50.0])
orders = st.sampled_from([1.0, 2.0])


@st.composite
def gappy_tracks(draw, n_scans, max_tracks=5):
    n = draw(st.integers(0, max_tracks))
    a = draw(arrays(np.float64, (n_scans, n, 2), elements=grid))
    a[~draw(arrays(np.bool_, (n_scans, n)))] = np.nan  # absent: gaps anywhere in a track
    return a


@st.composite
def scenes(draw):
    K = draw(st.integers(1, 5))
    return draw(gappy_tracks(K)), draw(gappy_tracks(K))


def _every_component_to_lapjvsp():
    return mock.patch.object(metrics, "DENSE_COMPONENT_MAX", 0)


def _assert_same(dense, sparse):
    for a, b in zip(dense, sparse, strict=True):
        assert_allclose(b, a, rtol=1e-12, atol=1e-300)


@given(scenes(), cutoffs, orders, st.integers(1, 4), st.sampled_from([0, 1]),
       st.sampled_from(["euclidean", "lp"]))
def test_ospa2_sparse_equals_dense(pair, c, p, window, r, base):
    X, Y = pair
    dense = ospa2(X, Y, c, p, window, r, base, method="dense")
    _assert_same(dense, ospa2(X, Y, c, p, window, r, base, method="sparse"))
    with _every_component_to_lapjvsp():
        _assert_same(dense, ospa2(X, Y, c, p, window, r, base, method="sparse"))


@given(scenes(), cutoffs, st.sampled_from([300.0, 2000.0]), st.integers(1, 3),
       st.sampled_from(["euclidean", "lp"]))
def test_ospa2_sparse_equals_dense_where_the_costs_underflow(pair, c, p, window, base):
    # (d / c)^p below exp(-700): both routes work in log space (the dense route's bottleneck
    # rescaling, per component on the sparse one)
    X, Y = pair
    _assert_same(ospa2(X, Y, c, p, window, base=base, method="dense"),
                 ospa2(X, Y, c, p, window, base=base, method="sparse"))


@given(scenes(), cutoffs, orders)
def test_gospa_sparse_equals_dense(pair, c, p):
    X, Y = pair
    for k in range(X.shape[0]):
        x = X[k][~np.isnan(X[k]).any(axis=1)]
        y = Y[k][~np.isnan(Y[k]).any(axis=1)]
        dense = gospa(x, y, c, p, method="dense")
        for patch in (mock.MagicMock(), _every_component_to_lapjvsp()):
            with patch:
                sparse = gospa(x, y, c, p, method="sparse")
            # the value is unique; among tied optima the split into localisation, missed and
            # false points may differ, but each split adds up to the value
            assert_allclose(sparse.value, dense.value, rtol=1e-12, atol=0)
            assert sparse.n_missed - sparse.n_false == dense.n_missed - dense.n_false
            assert_allclose(sparse.value**p, sparse.localisation**p + sparse.missed**p
                            + sparse.false**p, rtol=1e-12)
    assert_allclose(gospa_series(X, Y, c, p, method="sparse").value,
                    gospa_series(X, Y, c, p, method="dense").value, rtol=1e-12, atol=0)


def test_empty_sides_and_no_tracks():
    K = 3
    none = np.full((K, 0, 2), np.nan)
    some = np.array([[[0.0, 0.0]], [[np.nan, np.nan]], [[1.0, 0.0]]])
    for X, Y in ((none, none), (some, none), (none, some)):
        _assert_same(ospa2(X, Y, 5.0, 1, 2, method="dense"),
                     ospa2(X, Y, 5.0, 1, 2, method="sparse"))
    assert gospa([], [[1.0, 1.0]], 10.0, 1, method="sparse").value == 5.0
    assert gospa(np.zeros((0, 2)), np.zeros((0, 2)), 10.0, 1, method="sparse").value == 0.0


def test_auto_takes_the_sparse_route_above_the_threshold():
    X = np.array([[[0.0, 0.0], [100.0, 0.0]]])
    Y = np.array([[[3.0, 0.0], [100.0, 4.0]]])
    with mock.patch.object(metrics, "_ospa2_sparse", side_effect=RuntimeError("sparse")):
        ospa2(X, Y, 10.0, 1, 1)  # 2 x 2 pairs: dense
        with mock.patch.object(metrics, "SPARSE_MIN_PAIRS", 3), pytest.raises(
                RuntimeError, match="sparse"):
            ospa2(X, Y, 10.0, 1, 1)


def test_a_large_scene_by_the_sparse_route():
    # 5 000 targets one per 200 m x 200 m cell (within 10 m of its centre), 3 scans,
    # estimates 2 to 8 m off, one target in ten missed and 50 false tracks at cell corners
    # (over 127 m from every target): with c = 100 m every estimate pairs with its own target
    # and nothing else, so OSPA(2) and GOSPA are known in closed form. The dense route would
    # need arrays of 5 000 x ~4 550 pairs per scan.
    rng = np.random.default_rng(7)
    side = 71
    n = side * side - 41  # 5 000
    cells = np.stack(np.meshgrid(np.arange(side), np.arange(side)), -1).reshape(-1, 2)[:n]
    truth = np.broadcast_to(200.0 * cells + rng.uniform(-10.0, 10.0, (n, 2)), (3, n, 2)).copy()
    off = rng.uniform(2.0, 8.0, n)
    ang = rng.uniform(0.0, 2 * np.pi, n)
    est = truth + np.stack([off * np.cos(ang), off * np.sin(ang)], -1)
    missed = rng.random(n) < 0.1
    est = est[:, ~missed]
    false = 200.0 * rng.integers(0, side - 1, (50, 2)) + 100.0  # cell corners
    est = np.concatenate([est, np.broadcast_to(false, (3, 50, 2))], axis=1)
    c, p = 100.0, 1.0
    res = ospa2(truth, est, c, p, window=3)
    n_est = est.shape[1]
    # every estimate of a target at its distance, c for every other track of the larger side
    big = max(n, n_est)
    want = (off[~missed].sum() + c * (big - (~missed).sum())) / big
    assert_allclose(res.value, want, rtol=1e-12)
    g = gospa(truth[-1], est[-1], c, p)
    assert (g.n_missed, g.n_false) == (int(missed.sum()), 50)
    assert_allclose(g.localisation, off[~missed].sum(), rtol=1e-12)


def test_bad_method_and_an_underflowing_large_component_are_refused():
    X = np.zeros((1, 2, 2))
    with pytest.raises(ValueError, match=r"^unknown method 'fast'; expected one of \('auto', "
                                         r"'dense', 'sparse'\)$"):
        ospa2(X, X, 1.0, 1, 1, method="fast")
    with pytest.raises(ValueError, match=r"^unknown method 'lsap'"):
        gospa(X[0], X[0], 1.0, 1, method="lsap")
    with pytest.raises(ValueError, match=r"^unknown method 'lsap'"):
        gospa_series(X, X, 1.0, 1, method="lsap")
    # two truths and two estimates all within 1e-3 of each other, c = 1, p = 1000: every cost
    # underflows, and a component above DENSE_COMPONENT_MAX entries (here 0) cannot be solved
    # in log space on its dense matrix
    X = np.array([[[0.0, 0.0], [1e-3, 0.0]]])
    Y = np.array([[[0.0, 1e-3], [1e-3, 1e-3]]])
    with mock.patch.object(metrics, "DENSE_COMPONENT_MAX", 0), pytest.raises(
            ValueError, match=r"^the sparse route cannot solve a connected component of 2 x 2 "
                              r"tracks whose costs \(d/c\)\^p underflow a double \(below "
                              r"exp\(-700\)\): use method='dense' or a smaller order p$"):
        ospa2(X, Y, 1.0, 1000.0, 1, method="sparse")
