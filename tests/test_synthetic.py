"""Tests of rankedassign.single.synthetic: the paper's diagonal, uniform and random matrices."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal

from rankedassign.single import synthetic
from rankedassign.single.synthetic import eta_from_parameters


def test_diagonal_documented_values():
    # spec §1.6: eta(-1) = 0.0199, eta(0) = 0.019504, eta_ii = 48.0298, eta_ij = 9.606e-4
    d, m, x = synthetic.diagonal().eta()
    assert_allclose(x, 0.0199, rtol=1e-12)
    assert_allclose(m, 0.0199 * 0.0 + 0.9801 * (1 - 0.9801), rtol=1e-12)
    assert_allclose(np.diag(d[:, :4]), 0.9801 * 0.9801 * 50, rtol=1e-12)
    off = d.copy()
    off[np.arange(4), np.arange(4)] = np.nan
    assert_allclose(off[~np.isnan(off)], 0.9801 * 0.9801 * 1e-3, rtol=1e-12)
    assert_allclose(d[0, 0], 48.0298, rtol=1e-6)
    assert_allclose(m[0], 0.019504, rtol=1e-4)


def test_diagonal_best_solution_mass():
    # spec §1.6 [verified]: Z = 5.3442e6 and gamma = (1, 2, 3, 4) carries 99.577 % of Z.
    # Z by brute force over the rows (4 x 24 is small enough for itertools here).
    import itertools

    p = synthetic.diagonal()
    cc = p.compact_cost
    w = np.exp(-cc)
    M = p.n_meas
    Z = 0.0
    for g in itertools.product(range(M + 2), repeat=4):
        meas = [k for k in g if k < M]
        if len(meas) == len(set(meas)):
            Z += np.prod([w[i, k] for i, k in enumerate(g)])
    best = np.exp(-p.cost_of([0, 1, 2, 3]))
    assert_allclose(Z, 5.3442e6, rtol=1e-4)
    assert_allclose(best / Z, 0.99577, rtol=1e-5)


def test_diagonal_pd_switch():
    d, m, x = synthetic.diagonal(pbar_d="pd").eta()
    assert_allclose(m, 0.9801 * 0.01, rtol=1e-12)
    assert_allclose(d[0, 0], 0.9801 * 0.99 * 50, rtol=1e-12)


def test_uniform_all_finite_entries_equal():
    p = synthetic.uniform()
    C = p.cost
    assert_array_equal(C[np.isfinite(C)], 0.5)
    assert np.isfinite(C).sum() == 4 * 16 + 8
    assert p.cost_of(p.all_missed()) == p.cost_of([0, 1, 2, 3]) == 2.0


def test_random_is_reproducible_and_in_range():
    a = synthetic.random(rng=7)
    assert a == synthetic.random(rng=np.random.default_rng(7))
    assert a != synthetic.random(rng=8)
    d, m, x = a.eta()
    # Pbar_S = r P_s in (1e-6, 1); Pbar_D = r P_d
    assert ((x > 0) & (x < 1)).all()
    assert (d >= 0).all() and (d <= 50).all()


@given(st.integers(0, 2**32 - 1), st.sampled_from(["row", "matrix"]), st.sampled_from(["r_pd", "pd"]))
def test_random_matches_its_documented_draw_order(seed, gran, pbar_d):
    p = synthetic.random(rng=seed, granularity=gran, pbar_d=pbar_d)
    g = np.random.default_rng(seed)
    r = g.uniform(1e-3, 1.0, size=4)
    n = 4 if gran == "row" else 1
    ps = np.broadcast_to(g.uniform(1e-3, 1.0, size=n), (4,))
    pd = np.broadcast_to(g.uniform(1e-3, 1.0, size=n), (4,))
    q = g.uniform(0, 50, size=(4, 16))
    pbs = r * ps
    pbd = r * pd if pbar_d == "r_pd" else pd
    d, m, x = p.eta()
    assert_allclose(x, 1 - pbs, rtol=1e-12)
    assert_allclose(m, pbs * (1 - pbd), rtol=1e-12)
    assert_allclose(d, (pbs * pbd)[:, None] * q, rtol=1e-12)


def test_matrix_granularity_shares_ps_pd():
    p = synthetic.random(rng=3, granularity="matrix", pbar_d="pd")
    d, m, x = p.eta()
    pbs = 1 - x
    pd = 1 - m / pbs
    assert_allclose(pd, pd[0], rtol=1e-9)


def test_newborn_rows():
    p = synthetic.diagonal(R=2, B=2, M=5)
    assert p.shape == (4, 13)
    d, m, x = p.eta()
    # persisting rows: Pbar_S = r P_s = 0.9801; newborn rows: Pbar_S = r_B = 0.99
    assert_allclose(x, [0.0199, 0.0199, 0.01, 0.01], rtol=1e-12)
    assert_allclose(d[2, 2], 0.99 * 0.99 * 0.99 * 50, rtol=1e-12)
    q = synthetic.random(R=1, B=3, M=2, rng=0)
    assert q.shape == (4, 10)
    e_d, e_m, e_x = eta_from_parameters([0.5, 0.5], [0.5, 0.5], [1.0, 1.0], [[1.0], [1.0]],
                                        n_persisting=1, pbar_d="pd")
    assert_allclose(e_x, [0.75, 0.5])
    assert_allclose(e_m, [0.0, 0.0])


@pytest.mark.parametrize("family", [synthetic.diagonal, synthetic.uniform, synthetic.random])
def test_sizes_and_degenerate(family):
    assert family(R=0, M=3).shape == (0, 3)
    assert family(R=2, M=0).shape == (2, 4)


@pytest.mark.parametrize(
    ("call", "exc", "match"),
    [
        (lambda: synthetic.diagonal(R=-1), ValueError, r"R must be an int >= 0, got -1"),
        (lambda: synthetic.uniform(M=2.5), TypeError, r"M must be an int, got float 2.5"),
        (lambda: synthetic.uniform(M=4.0), TypeError, r"M must be an int, got float 4.0"),
        (lambda: synthetic.random(B=True), TypeError, r"B must be an int, got bool True"),
        (lambda: synthetic.random(R="4"), TypeError, r"R must be an int, got str '4'"),
        (lambda: synthetic.uniform(R=2**63), ValueError,
         r"R must be an int <= 4611686018427387904 \(2\*\*62\), got 9223372036854775808"),
        (lambda: synthetic.uniform(R=10**30), ValueError, r"R must be an int <= 4611686018427387904"),
        (lambda: synthetic.diagonal(R=2**62), ValueError,
         r"R = 4611686018427387904, B = 0, M = 16 give a 4611686018427387904 x "
         r"9223372036854775824 cost matrix of \d+ entries, more than the 134217728 \(2\*\*27\)"),
        (lambda: synthetic.random(R=10, M=2**27), ValueError, r"more than the 134217728"),
        (lambda: synthetic.diagonal(pbar_d="x"), ValueError,
         r"unknown pbar_d 'x'; expected one of \('r_pd', 'pd'\)"),
        (lambda: synthetic.diagonal(pbar_d=None), ValueError, r"unknown pbar_d None"),
        (lambda: synthetic.random(granularity="col"), ValueError,
         r"unknown granularity 'col'; expected one of \('row', 'matrix'\)"),
        (lambda: synthetic.random(rng=-1), ValueError, r"rng -1 is not a valid seed"),
        (lambda: synthetic.random(rng=1.5), TypeError,
         r"rng must be None, an int, a SeedSequence, a BitGenerator or a Generator, got float 1.5"),
        (lambda: synthetic.random(rng="seed"), TypeError, r"rng must be None, an int.*got str"),
        (lambda: synthetic.random(rng=object()), TypeError, r"rng must be None, an int.*got object"),
    ],
)
def test_bad_arguments(call, exc, match):
    with pytest.raises(exc, match=match):
        call()


def test_huge_seeds_are_seeds():
    assert synthetic.random(rng=2**64) == synthetic.random(rng=2**64)
    assert synthetic.random(rng=10**30).shape == (4, 24)


@pytest.mark.parametrize(
    ("args", "kwargs", "exc", "match"),
    [
        (([0.5], [0.5], [0.5], [[1.0]]), {"pbar_d": "x"}, ValueError, r"unknown pbar_d 'x'"),
        ((0.5, [0.5], [0.5], [[1.0]]), {}, ValueError, r"r must be 1-D, got shape \(\)"),
        (([0.5], [0.5], [0.5], [1.0]), {}, ValueError, r"q must be 2-D, got shape \(1,\)"),
        (([0.5], [0.5, 0.5], [0.5], [[1.0]]), {}, ValueError,
         r"p_s must have shape \(P,\) = \(1,\) like r, got \(2,\)"),
        (([0.5], [0.5], [0.5], [[1.0], [1.0]]), {}, ValueError,
         r"q must have shape \(P, M\) with P = 1 rows like r, got \(2, 1\)"),
        (([1.5], [0.5], [0.5], [[1.0]]), {}, ValueError, r"r must hold probabilities in \[0, 1\], got 1.5"),
        (([0.5], [-0.1], [0.5], [[1.0]]), {}, ValueError, r"p_s must hold probabilities in \[0, 1\], got -0.1"),
        (([0.5], [0.5], [np.inf], [[1.0]]), {}, ValueError, r"p_d must hold probabilities in \[0, 1\], got inf"),
        (([np.nan], [0.5], [0.5], [[1.0]]), {}, ValueError, r"r contains NaN"),
        (([0.5], [0.5], [0.5], [[-1.0]]), {}, ValueError, r"q must hold finite likelihood ratios >= 0, got -1.0"),
        (([0.5], [0.5], [0.5], [[np.inf]]), {}, ValueError, r"q must hold finite likelihood ratios >= 0, got inf"),
        ((["a"], [0.5], [0.5], [[1.0]]), {}, TypeError, r"r must be a numeric array, got dtype <U1"),
        (([0.5], [0.5], [0.5], [[1j]]), {}, TypeError, r"q must be real, got dtype complex128"),
        (([0.5], [0.5], [0.5], [[1.0], [1.0, 2.0]]), {}, TypeError, r"q must be a numeric array, could not convert"),
        (([0.5], [0.5], [0.5], [[1.0]]), {"n_persisting": 2}, ValueError,
         r"n_persisting must be an int <= 1, got 2"),
        (([0.5], [0.5], [0.5], [[1.0]]), {"n_persisting": -1}, ValueError,
         r"n_persisting must be None \(every row persists\) or an int >= 0, got -1"),
        (([0.5], [0.5], [0.5], [[1.0]]), {"n_persisting": 1.0}, TypeError,
         r"n_persisting must be None or an int, got float 1.0"),
    ],
)
def test_eta_from_parameters_bad_arguments(args, kwargs, exc, match):
    with pytest.raises(exc, match=match):
        eta_from_parameters(*args, **kwargs)


def test_eta_from_parameters_edges():
    # no rows, no measurements, probabilities 0 and 1 exactly
    d, m, x = eta_from_parameters(np.zeros(0), np.zeros(0), np.zeros(0), np.zeros((0, 3)))
    assert d.shape == (0, 3) and m.shape == x.shape == (0,)
    d, m, x = eta_from_parameters([1.0, 0.0], [1.0, 1.0], [1.0, 0.5], np.zeros((2, 0)),
                                  n_persisting=0)
    assert_array_equal(x, [0.0, 1.0])
    assert_array_equal(m, [0.0, 0.0])
