"""Tests of rankedassign.multisensor.synthetic: the families of the multi-sensor spec §6.5 and
the linear-Gaussian psibar (stacked vs information form)."""

import itertools

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal
from scipy.stats import multivariate_normal

from rankedassign.multisensor import MultiSensorProblem, synthetic
from rankedassign.multisensor.synthetic import SIZES, log_psi_linear_gaussian
from rankedassign.single import synthetic as single


@pytest.mark.parametrize("name, n", [("A", 67744), ("B", 75108), ("C", 417176)])
def test_canonical_sizes(name, n):
    P, M = SIZES[name]
    for fam in (synthetic.diagonal(P, M), synthetic.uniform(P, M), synthetic.random(P, M, rng=0),
                synthetic.random_coupled(P, M, rng=0), synthetic.geometric(P, M, rng=0)):
        assert isinstance(fam, MultiSensorProblem)
        assert fam.shape == (P, *M)
        assert fam.n_feasible() == n
        assert fam.log_s is not None and len(fam.log_theta) == len(M)


def test_diagonal_weights():
    p = synthetic.diagonal(2, (3, 2, 2))
    d, a = p.eta()
    s, pd = 0.99 * 0.99, 0.99
    assert_allclose(d, 1 - s, rtol=1e-15)
    assert_allclose(a[0, 0, 0, 0], s * (1 - pd) ** 3, rtol=1e-14)
    assert_allclose(a[0, 1, 1, 1], s * (pd * 50) ** 3, rtol=1e-14)
    assert_allclose(a[1, 2, 2, 0], s * (pd * 50) ** 2 * (1 - pd), rtol=1e-14)
    assert_allclose(a[1, 1, 2, 2], s * (pd * 1e-3) * (pd * 50) ** 2, rtol=1e-14)
    assert_array_equal(p.surrogate().log_eta_alive, p.log_eta_alive)


def test_uniform_weights_are_all_equal():
    p = synthetic.uniform(3, (2, 2, 2))
    assert (p.log_eta_alive == -0.5).all() and (p.log_eta_dead == -0.5).all()
    assert_allclose(np.exp(p.log_s), np.exp(-0.5), rtol=1e-15)
    assert all((t == 0).all() for t in p.log_theta)


def test_random_is_reproducible_separable_and_in_range():
    a, b = synthetic.random(3, (4, 5), rng=5), synthetic.random(3, (4, 5), rng=5)
    assert a == b
    assert a != synthetic.random(3, (4, 5), rng=6)
    assert_allclose(a.surrogate().log_eta_alive, a.log_eta_alive, rtol=1e-14, atol=1e-14)
    s = np.exp(a.log_s)
    assert ((s >= 1e-6) & (s <= 1)).all()
    assert_allclose(np.exp(a.log_eta_dead), 1 - s, rtol=1e-13)
    th = np.exp(a.log_theta[1])
    pd = 1 - th[:, 0]
    assert ((pd >= 1e-3) & (pd <= 1)).all()
    assert ((th[:, 1:] >= 0) & (th[:, 1:] <= 50 * pd[:, None])).all()


def test_random_coupled_couples_only_multi_detection_tuples():
    p = synthetic.random_coupled(2, (3, 2, 2), sigma=1.0, rng=4)
    q = synthetic.random(2, (3, 2, 2), rng=4)
    assert p.log_s is not None
    assert_allclose(p.surrogate().log_eta_alive, q.log_eta_alive, rtol=1e-14, atol=1e-14)
    ratio = p.log_eta_alive - q.log_eta_alive
    n_det = sum(np.indices((4, 3, 3))[v] > 0 for v in range(3))
    assert_allclose(ratio[:, n_det < 2], 0.0, atol=1e-13)
    assert (np.abs(ratio[:, n_det >= 2]) > 1e-6).all()
    assert synthetic.random_coupled(2, (3, 2), sigma=0.0, rng=9) == synthetic.random(2, (3, 2),
                                                                                       rng=9)


@pytest.mark.parametrize("pbar_d", ["pd", "r_pd"])
def test_one_sensor_families_are_the_single_sensor_ones(pbar_d):
    pairs = [
        (synthetic.diagonal(4, (16,), pbar_d=pbar_d), single.diagonal(pbar_d=pbar_d)),
        (synthetic.uniform(4, (16,)), single.uniform()),
        (synthetic.random(3, (7,), pbar_d=pbar_d, rng=11), single.random(R=3, M=7, pbar_d=pbar_d,
                                                                        rng=11)),
    ]
    for mp, sp in pairs:
        back = mp.to_assignment_problem()
        assert_allclose(back.compact_cost, sp.compact_cost, rtol=1e-13, atol=1e-13)


def test_geometric_true_detections_dominate():
    p = synthetic.geometric(3, (4, 4), sigma_p=2.0, sigma_z=1.0, p_d=0.95, rng=3)
    best = [[1, 1], [2, 2], [3, 3]]
    assert p.is_feasible(best)
    la = p.log_eta_alive
    for n in range(3):
        assert la[n, n + 1, n + 1] == la[n].max()


def test_geometric_factors_are_single_sensor_psibar():
    p = synthetic.geometric(2, (3, 2, 2), rng=8)
    for v in range(3):
        # theta^(v) is psibar with sensor v alone, which is the slice of the joint psibar where
        # every other sensor missed, divided by their missed factors
        others = tuple(0 if w != v else slice(None) for w in range(3))
        joint = p.log_eta_alive[(slice(None), *others)] - p.log_s[:, None]
        miss = 2 * np.log1p(-0.9)
        assert_allclose(joint - miss, p.log_theta[v], rtol=1e-12, atol=1e-12)


# ---------------------------------------------------------------- closed form (1.5) / (1.6)
def _random_gaussian_case(rng, K, n, dims, M):
    w = rng.uniform(0.2, 1.0, K)
    w /= w.sum()
    means = rng.normal(0, 3, (K, n))
    covs = []
    for _ in range(K):
        A = rng.normal(0, 1, (n, n))
        covs.append(A @ A.T + n * np.eye(n))
    H, R, Z = [], [], []
    for d, m in zip(dims, M, strict=True):
        H.append(rng.normal(0, 1, (d, n)))
        B = rng.normal(0, 1, (d, d))
        R.append(B @ B.T + np.eye(d))
        Z.append(rng.normal(0, 3, (m, d)))
    p_d = rng.uniform(0.3, 0.95, len(dims))
    kappa = [rng.uniform(0.01, 0.1, m) for m in M]
    return w, means, np.array(covs), Z, H, R, p_d, kappa


@pytest.mark.parametrize("seed, K, n, dims, M", [
    (0, 1, 2, (2, 2), (4, 4)),
    (1, 2, 4, (2, 1, 3), (3, 2, 2)),
    (2, 3, 3, (1,), (5,)),
    (3, 1, 4, (2, 2, 2, 1), (2, 1, 2, 2)),
])
def test_stacked_and_information_forms_agree(seed, K, n, dims, M):
    args = _random_gaussian_case(np.random.default_rng(seed), K, n, dims, M)
    a = log_psi_linear_gaussian(*args, form="information")
    b = log_psi_linear_gaussian(*args, form="stacked")
    assert a.shape == tuple(m + 1 for m in M)
    assert_allclose(a, b, rtol=1e-9, atol=1e-9)


def test_geometric_stacked_and_information_forms_agree_on_family_sizes():
    # the family's own problems: the stored table (information form) equals the stacked form
    for name in ("A", "C"):
        P, M = SIZES[name]
        gen = np.random.default_rng(21)
        p = synthetic.geometric(P, M, rng=21)
        # rebuild the draws of geometric() to evaluate the stacked form on the same data
        means = gen.uniform(0.0, 100.0, size=(P, 2))
        truth = means + 5.0 * gen.standard_normal(size=(P, 2))
        Z = []
        for m in M:
            k = min(P, m)
            Z.append(np.vstack([truth[:k] + 2.0 * gen.standard_normal(size=(k, 2)),
                                gen.uniform(0.0, 100.0, size=(m - k, 2))]))
        V = len(M)
        for n in range(P):
            b = log_psi_linear_gaussian([1.0], means[n][None], 25.0 * np.eye(2)[None], Z,
                                        [np.eye(2)] * V, [4.0 * np.eye(2)] * V, [0.9] * V,
                                        [1e-3] * V, form="stacked")
            assert_allclose(p.log_eta_alive[n] - np.log(0.9), b, rtol=1e-9, atol=1e-9)


def test_one_sensor_closed_form_is_the_single_sensor_likelihood_ratio():
    rng = np.random.default_rng(5)
    w, means, covs, Z, H, R, p_d, kappa = _random_gaussian_case(rng, 2, 3, (2,), (4,))
    got = log_psi_linear_gaussian(w, means, covs, Z, H, R, p_d, kappa)
    want = [np.log(1 - p_d[0])]
    for j in range(4):
        lik = sum(w[k] * multivariate_normal(H[0] @ means[k], H[0] @ covs[k] @ H[0].T + R[0])
                  .pdf(Z[0][j]) for k in range(2))
        want.append(np.log(p_d[0] * lik / kappa[0][j]))
    assert_allclose(got, want, rtol=1e-12)


def test_all_missed_tuple_has_no_gaussian_factor():
    args = _random_gaussian_case(np.random.default_rng(9), 2, 2, (2, 2), (2, 3))
    a = log_psi_linear_gaussian(*args)
    assert_allclose(a[0, 0], np.log((1 - args[6][0]) * (1 - args[6][1])), rtol=1e-14)
    # and the partially missed tuples factor into (1 - P_D) times the other sensor alone
    one = log_psi_linear_gaussian(args[0], args[1], args[2], [args[3][1]], [args[4][1]],
                                  [args[5][1]], args[6][1:], [args[7][1]])
    assert_allclose(a[0, :], np.log(1 - args[6][0]) + one, rtol=1e-12)


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize("call, err, match", [
    (lambda: synthetic.diagonal(-1), ValueError, "P must be an int >= 0, got -1"),
    (lambda: synthetic.diagonal(2.0), TypeError, "P must be an int, got float 2.0"),
    (lambda: synthetic.uniform(2, 4), TypeError, r"M must be a sequence of measurement counts "
                                                 r"\(M_1, \.\.\., M_V\), got int 4"),
    (lambda: synthetic.uniform(2, ()), ValueError, "M must name at least one sensor, got an "
                                                   "empty sequence"),
    (lambda: synthetic.uniform(2, (3, -1)), ValueError, r"M\[1\] must be an int >= 0, got -1"),
    (lambda: synthetic.random(pbar_d="r"), ValueError, r"unknown pbar_d 'r'; expected one of "
                                                       r"\('pd', 'r_pd'\)"),
    (lambda: synthetic.random_coupled(sigma=-1.0), ValueError, "sigma must be >= 0.0, got -1.0"),
    (lambda: synthetic.geometric(region=0.0), ValueError, "region must be > 0.0, got 0.0"),
    (lambda: synthetic.geometric(sigma_z=(1.0, 2.0, 3.0)), ValueError,
     r"sigma_z must be a scalar or have shape \(V,\) = \(2,\), got \(3,\)"),
    (lambda: synthetic.geometric(sigma_z=-1.0), ValueError, r"sigma_z must be > 0, got "
                                                            r"\[-1.0, -1.0\]"),
    (lambda: synthetic.geometric(p_d=1.5), ValueError, r"p_d must lie in \[0, 1\], got"),
    (lambda: synthetic.geometric(kappa=0.0), ValueError, r"kappa must be > 0, got"),
    (lambda: synthetic.geometric(pbar_s=2.0), ValueError, "pbar_s must be <= 1.0, got 2.0"),
])
def test_bad_family_arguments(call, err, match):
    with pytest.raises(err, match=match):
        call()


@pytest.mark.parametrize("family", [synthetic.diagonal, synthetic.uniform, synthetic.random,
                                    synthetic.random_coupled, synthetic.geometric])
def test_families_refuse_a_table_too_large_before_drawing(family):
    # V = 40 (16 TiB) used to raise MemoryError, V = 64 numpy's "maximum supported dimension"
    with pytest.raises(ValueError, match=r"^V = 40 sensors .* 2199023255552 entries, 16\.0 TiB "
                                         r"\(17592186044416 bytes\) of float64, more than "
                                         r"MAX_TABLE_ENTRIES = 134217728 entries, 1\.0 GiB "
                                         r"\(1073741824 bytes\)$"):
        family(2, (1,) * 40)
    with pytest.raises(ValueError, match=r"^V = 64 sensors .* 256\.0 EiB"):
        family(2, (1,) * 64)
    with pytest.raises(ValueError, match=r"at most 63 sensors"):
        family(1, (0,) * 64)


def test_sensors_without_measurements_cost_no_detection_patterns():
    # 40 sensors that cannot detect: a table of (2, 4, 1, ..., 1), accepted; the closed form
    # used to visit all 2**41 detection patterns. Each such sensor only adds ln(1 - p_d).
    many = synthetic.geometric(2, (3,) + (0,) * 40, rng=0)
    one = synthetic.geometric(2, (3,), rng=0)
    assert many.shape == (2, 3) + (0,) * 40
    assert_allclose(many.log_eta_alive.reshape(2, 4),
                    one.log_eta_alive + 40 * np.log1p(-0.9), rtol=1e-13)


def test_bad_closed_form_arguments():
    base = ([1.0], [[0.0, 0.0]], [np.eye(2)], [np.zeros((1, 2))], [np.eye(2)], [np.eye(2)],
            [0.9], [1.0])
    with pytest.raises(ValueError, match=r"unknown form 'joint'; expected one of "
                                         r"\('information', 'stacked'\)"):
        log_psi_linear_gaussian(*base, form="joint")
    bad = list(base)
    bad[2] = [np.eye(3)]
    with pytest.raises(ValueError, match=r"means must have shape \(K, n\) and covs \(K, n, n\) "
                                         r"with K = 1 weights, got \(1, 2\) and \(1, 3, 3\)"):
        log_psi_linear_gaussian(*bad)
    bad = list(base)
    bad[4] = []
    with pytest.raises(ValueError, match="Z, H and R must hold one entry per sensor, got 1, 0, 1"):
        log_psi_linear_gaussian(*bad)
    bad = list(base)
    bad[4] = [np.eye(3)]
    with pytest.raises(ValueError, match=r"sensor 0: H must have shape \(d, 2\) and R \(d, d\), "
                                         r"got \(3, 3\) and \(2, 2\)"):
        log_psi_linear_gaussian(*bad)
    bad = list(base)
    bad[3] = [np.zeros((2, 3))]
    with pytest.raises(ValueError, match=r"sensor 0: Z must have shape \(M, d\) = \(M, 2\), got "
                                         r"\(2, 3\)"):
        log_psi_linear_gaussian(*bad)


def test_tuple_table_order_matches_closed_form_indexing():
    args = _random_gaussian_case(np.random.default_rng(2), 1, 2, (2, 2), (2, 1))
    a = log_psi_linear_gaussian(*args, form="stacked")
    for t in itertools.product(range(3), range(2)):
        assert np.isfinite(a[t])
