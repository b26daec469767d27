"""GOSPA (α = 2) against an independent reference: LSAP on the padded (m + n) square matrix."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.optimize import linear_sum_assignment

from rankedassign.metrics import gospa, ospa

_BIG = 1e300


def _gospa_padded(X, Y, c, p):
    """GOSPA by the textbook construction, independent of :func:`gospa`.

    Rows: the m truths, then n "false" slots; columns: the n estimates, then m "missed" slots.
    Truth i to estimate j costs d^p where d < c (a pair at c or more is never better than a
    miss and a false, which cost the same); truth i to its own missed slot costs c^p / 2;
    a false slot j to estimate j costs c^p / 2; false slots to missed slots cost 0.
    """
    X, Y = np.asarray(X, float).reshape(-1, 2), np.asarray(Y, float).reshape(-1, 2)
    m, n = len(X), len(Y)
    if m + n == 0:
        return 0.0, 0.0, 0, 0
    C = np.full((m + n, n + m), _BIG)
    D = np.sqrt(((X[:, None, :] - Y[None, :, :]) ** 2).sum(-1))
    C[:m, :n] = np.where(D < c, D**p, _BIG)
    C[np.arange(m), n + np.arange(m)] = c**p / 2
    C[m + np.arange(n), np.arange(n)] = c**p / 2
    C[m:, n:] = 0.0
    r, k = linear_sum_assignment(C)
    total = C[r, k].sum()
    pairs = (r < m) & (k < n)
    loc = C[r[pairs], k[pairs]].sum()
    n_missed = int(((r < m) & (k >= n)).sum())
    n_false = int(((r >= m) & (k < n)).sum())
    return total ** (1 / p), loc, n_missed, n_false


@pytest.mark.parametrize("seed", range(40))
def test_gospa_matches_the_padded_reference(seed):
    rng = np.random.default_rng(seed)
    m, n = rng.integers(0, 7, size=2)
    X = rng.uniform(0, 100, (m, 2))
    Y = rng.uniform(0, 100, (n, 2))
    c = float(rng.choice([5.0, 20.0, 60.0, 500.0]))
    p = float(rng.choice([1.0, 2.0, 3.5]))
    r = gospa(X.reshape(m, 2), Y.reshape(n, 2), c=c, p=p)
    value, loc, n_missed, n_false = _gospa_padded(X, Y, c, p)
    assert_allclose(r.value, value, rtol=1e-10, atol=1e-10)
    assert (r.n_missed, r.n_false) == (n_missed, n_false)
    assert_allclose(r.localisation**p, loc, rtol=1e-10, atol=1e-10 * c**p)
    assert_allclose(r.missed**p, c**p / 2 * n_missed, rtol=1e-10)
    assert_allclose(r.false**p, c**p / 2 * n_false, rtol=1e-10)
    assert_allclose(r.value**p, r.localisation**p + r.missed**p + r.false**p, rtol=1e-10)


def test_gospa_hand_cases():
    assert gospa([], [], c=10.0, p=2) == (0.0, 0.0, 0.0, 0.0, 0, 0)
    # two truths, nothing estimated: 2 missed at c^p / 2 each
    r = gospa([[0.0, 0.0], [5.0, 5.0]], [], c=10.0, p=2)
    assert_allclose(r.value, np.sqrt(100.0))
    assert (r.n_missed, r.n_false, r.false) == (2, 0, 0.0)
    # one false estimate: c / 2^(1/p)
    r = gospa([], [[1.0, 1.0]], c=10.0, p=1)
    assert (r.value, r.false, r.n_false) == (5.0, 5.0, 1)
    # a pair beyond c is a miss and a false point
    r = gospa([[0.0, 0.0]], [[30.0, 40.0]], c=10.0, p=1)
    assert (r.value, r.localisation, r.n_missed, r.n_false) == (10.0, 0.0, 1, 1)
    # identical sets
    assert gospa([[1.0, 2.0]], [[1.0, 2.0]], c=10.0, p=1).value == 0.0


def test_gospa_with_equal_cardinality_and_close_points_is_unnormalised_ospa():
    # every pair closer than c: GOSPA^p = n OSPA^p
    X = [[0.0, 0.0], [10.0, 0.0], [0.0, 10.0]]
    Y = [[1.0, 0.0], [10.0, 2.0], [0.0, 13.0]]
    g = gospa(X, Y, c=100.0, p=2).value
    o = ospa(X, Y, c=100.0, p=2).value
    assert_allclose(g**2, 3 * o**2, rtol=1e-12)


def test_gospa_bad_input():
    with pytest.raises(ValueError, match=r"c must be > 0.0, got 0.0"):
        gospa([[0.0]], [[1.0]], c=0.0, p=1)
    with pytest.raises(ValueError, match=r"p must be >= 1.0, got 0.5"):
        gospa([[0.0]], [[1.0]], c=1.0, p=0.5)
    with pytest.raises(ValueError, match="X and Y must have the same point dimension, got 2 "
                                         "and 3"):
        gospa([[0.0, 1.0]], [[1.0, 2.0, 3.0]], c=1.0, p=1)


# ----------------------------------------------------------------------------- gospa_series
def test_gospa_series_is_gospa_per_scan():
    from rankedassign.metrics import gospa_series

    rng = np.random.default_rng(4)
    X = rng.uniform(0, 50, size=(7, 5, 2))
    Y = rng.uniform(0, 50, size=(7, 6, 2))
    X[rng.random((7, 5)) < 0.3] = np.nan
    Y[rng.random((7, 6)) < 0.4] = np.nan
    s = gospa_series(X, Y, c=20.0, p=2.0)
    for k in range(7):
        r = gospa(X[k][~np.isnan(X[k]).any(axis=1)], Y[k][~np.isnan(Y[k]).any(axis=1)],
                  c=20.0, p=2.0)
        assert (s.value[k], s.localisation[k], s.missed[k], s.false[k], s.n_missed[k],
                s.n_false[k]) == tuple(r)
    assert s.value.dtype == np.float64 and s.n_missed.dtype == np.int64


def test_gospa_series_bad_input():
    from rankedassign.metrics import gospa_series

    with pytest.raises(ValueError, match=r"truth and estimates must be \(n_scans, n, d\) arrays "
                                         r"with the same n_scans and d, got shapes \(2, 1, 2\) "
                                         r"and \(3, 1, 2\)"):
        gospa_series(np.zeros((2, 1, 2)), np.zeros((3, 1, 2)), 1.0, 1.0)
    with pytest.raises(ValueError, match=r"c must be"):
        gospa_series(np.zeros((2, 1, 2)), np.zeros((2, 1, 2)), 0.0, 1.0)
    bad = np.zeros((1, 1, 2))
    bad[0, 0, 1] = np.nan        # a point half NaN is an error, not an absent target
    with pytest.raises(ValueError):
        gospa_series(bad, np.zeros((1, 1, 2)), 1.0, 1.0)
