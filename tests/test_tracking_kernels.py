"""The LMB filter's compiled kernels against their plain-numpy twins (``tracking.reference``).

``reduce_mixtures`` (pruning, merging by each of the three rules, cap) is checked on random
mixtures with hypothesis: ties in weight and position, empty and single-component mixtures,
dropped tracks. The likelihood, cost-matrix, marginal and cardinality kernels repeat numpy's
operations in numpy's order, so they must agree with their twins bit for bit: that is what
keeps the filter's numbers independent of which of the two computes them.
"""

import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st
from numpy.testing import assert_allclose, assert_array_equal

from rankedassign.tracking import _kernels, reference
from rankedassign.tracking._kernels import MERGE_RULES

RULES = sorted(MERGE_RULES.values())


# --------------------------------------------------------------------------- mixtures
@st.composite
def mixtures(draw):
    """Tracks of 0-5 components: weights from a small set (ties), positions on a coarse grid
    (coincident components), SPD covariances ``L Lᵀ`` with small integer ``L``."""
    n_tracks = draw(st.integers(0, 4))
    sizes = draw(st.lists(st.integers(0, 5), min_size=n_tracks, max_size=n_tracks))
    C = sum(sizes)
    offsets = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
    raw = np.array(draw(st.lists(st.sampled_from([1.0, 2.0, 3.0, 1e-6]), min_size=C,
                                 max_size=C)))
    w = np.empty(C)
    for t in range(n_tracks):
        a, b = offsets[t], offsets[t + 1]
        w[a:b] = raw[a:b] / raw[a:b].sum()
    m = np.array(draw(st.lists(st.lists(st.sampled_from([0.0, 0.5, 1.0, 3.0]), min_size=4,
                                        max_size=4), min_size=C, max_size=C))).reshape(C, 4)
    P = np.empty((C, 4, 4))
    for c in range(C):
        diag = draw(st.lists(st.sampled_from([0.5, 1.0, 2.0]), min_size=4, max_size=4))
        low = draw(st.lists(st.sampled_from([-1.0, 0.0, 1.0]), min_size=6, max_size=6))
        L = np.diag(diag)
        L[np.tril_indices(4, -1)] = low
        P[c] = L @ L.T
    keep = np.array(draw(st.lists(st.booleans(), min_size=n_tracks, max_size=n_tracks)),
                    dtype=bool)
    return offsets, w, m, P, keep


def _distances(m, P, rule):
    """Every pairwise merging statistic of one track's components (reference formulas)."""
    n = m.shape[0]
    out = []
    for j in range(n):
        cand = np.array([i for i in range(n) if i != j], dtype=np.int64)
        if cand.size:
            out.append(reference._merge_distances(m, P, j, cand, rule))
    return np.concatenate(out) if out else np.empty(0)


@given(mixtures(), st.sampled_from(RULES), st.sampled_from([0.0, 1e-5, 0.2]),
       st.sampled_from([0.0, 1.0, 4.0, 30.0]), st.integers(1, 4))
def test_reduce_mixtures_matches_reference(mix, rule, elim, thr, cap):
    offsets, w, m, P, keep = mix
    # a statistic within rounding of the threshold may be decided either way by two
    # summation orders: such draws are not a disagreement between the two implementations
    for t in range(offsets.size - 1):
        a, b = offsets[t], offsets[t + 1]
        d = _distances(m[a:b], P[a:b], rule)
        assume(not np.any((np.abs(d - thr) < 1e-9 * (1 + thr)) & (d != 0)))
    got = _kernels.reduce_mixtures(offsets, w, m, P, keep, elim, thr, cap, rule)
    want = reference.reduce_mixtures(offsets, w, m, P, keep, elim, thr, cap, rule)
    assert_array_equal(got[0], want[0])
    for g, e in zip(got[1:], want[1:], strict=True):
        assert g.shape == e.shape
        assert_allclose(g, e, rtol=1e-12, atol=1e-12)
    # weights renormalised per kept track, in decreasing order, at most `cap` components
    # (a track given no component keeps none)
    kept = np.flatnonzero(keep)
    for t in range(got[0].size - 1):
        seg = got[1][got[0][t]:got[0][t + 1]]
        given_any = offsets[kept[t] + 1] > offsets[kept[t]]
        assert (1 if given_any else 0) <= seg.size <= cap
        if seg.size:
            assert_allclose(seg.sum(), 1.0, rtol=1e-12)
            assert np.all(np.diff(seg) <= 0)


@pytest.mark.parametrize("seed", range(4))
def test_sort_cap_normalise_orders_as_a_stable_argsort(seed):
    # the kernel's insertion sort against numpy's stable sort, on more components than the
    # hypothesis mixtures reach, with many ties, in and out of order, and a cap
    rng = np.random.default_rng(seed)
    n, start = 60, 3
    ow = rng.integers(1, 6, n + start + 2) / 8.0
    if seed % 2:
        ow[start:start + n] = np.sort(ow[start:start + n])[::-1]  # nearly sorted: ties only
    om = rng.standard_normal((ow.size, 4))
    oP = rng.standard_normal((ow.size, 4, 4))
    order = start + np.argsort(-ow[start:start + n], kind="stable")[:25]
    tot = 0.0
    for x in ow[order]:  # the kernel's sum, in order (numpy's pairwise sum may round apart)
        tot += x
    want_w, want_m, want_P = ow[order] / tot, om[order], oP[order]
    stop = _kernels._sort_cap_normalise(ow, om, oP, start, start + n, 25)
    assert stop == start + 25
    assert_array_equal(ow[start:stop], want_w)
    assert_array_equal(om[start:stop], want_m)
    assert_array_equal(oP[start:stop], want_P)


@pytest.mark.parametrize("impl", [_kernels.reduce_mixtures, reference.reduce_mixtures],
                         ids=["kernel", "reference"])
def test_reduce_mixtures_empty_and_single(impl):
    # no track at all
    off, w, m, P = impl(np.zeros(1, dtype=np.int64), np.empty(0), np.empty((0, 4)),
                        np.empty((0, 4, 4)), np.empty(0, dtype=bool), 1e-5, 4.0, 10, 0)
    assert_array_equal(off, [0])
    assert w.shape == (0,) and m.shape == (0, 4) and P.shape == (0, 4, 4)
    # one track of one component: kept as it is (weight renormalised to 1), or dropped
    P1 = 2.0 * np.eye(4)[None]
    for rule in RULES:
        off, w, m, P = impl(np.array([0, 1]), np.array([0.3]), np.ones((1, 4)), P1,
                            np.array([True]), 0.5, 4.0, 10, rule)
        assert_array_equal(off, [0, 1])
        assert_array_equal(w, [1.0])
        assert_array_equal(P, P1)
    off, w, *_ = impl(np.array([0, 1]), np.array([1.0]), np.ones((1, 4)), P1,
                      np.array([False]), 1e-5, 4.0, 10, 0)
    assert_array_equal(off, [0])
    assert w.size == 0


# --------------------------------------------------------------------------- bit for bit
def _scan(seed, C=9, M=7, T=4):
    rng = np.random.default_rng(seed)
    sizes = rng.multinomial(C - T, np.ones(T) / T) + 1
    offsets = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
    m = rng.normal(0.0, 50.0, (C, 4))
    A = rng.normal(0.0, 10.0, (C, 4, 4))
    P = A @ A.transpose(0, 2, 1) + 25.0 * np.eye(4)
    R = np.array([[100.0, 15.0], [15.0, 64.0]])
    z = rng.normal(0.0, 60.0, (M, 2))
    w = rng.random(C) + 0.01
    r = rng.random(T) * 0.98 + 0.01
    return offsets, m, P, R, z, w, r


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize("use_gate", [True, False])
def test_likelihood_kernels_agree_bit_for_bit(seed, use_gate):
    offsets, m, P, R, z, w, r = _scan(seed)
    gate = 9.0
    got = _kernels.gate_and_distances(m, P, R, z, offsets, gate, use_gate)
    want = reference.gate_and_distances(m, P, R, z, offsets, gate, use_gate)
    for g, e in zip(got, want, strict=True):
        assert_array_equal(g, e)
    det, _, _, maha, gated = got
    used = np.flatnonzero(gated.any(axis=0))
    args = (maha, np.log(det), np.log(w), offsets, used, gated[:, used], np.log(r),
            math.log(0.98), math.log(1.25e-5))
    for g, e in zip(_kernels.detection_log_weights(*args), reference.detection_log_weights(*args),
                    strict=True):
        assert_array_equal(g, e)


def test_logaddexp_matches_numpy_on_edge_values():
    vals = np.array([-np.inf, -745.2, -30.0, -1e-300, 0.0, 1e-300, 2.5, 30.0, 709.0, np.inf])
    for x in vals:
        for y in vals:
            with np.errstate(invalid="ignore"):
                want = np.logaddexp(x, y)
            got = _kernels._logaddexp(x, y)
            assert (np.isnan(got) and np.isnan(want)) or got == want, (x, y, got, want)


@given(st.integers(0, 6), st.integers(0, 6), st.data())
def test_connected_groups_matches_scipy(T, M, data):
    flat = data.draw(st.lists(st.booleans(), min_size=T * M, max_size=T * M))
    gated = np.array(flat, dtype=bool).reshape(T, M)
    got = _kernels.connected_groups(gated)
    want = reference.connected_groups(gated)
    assert_array_equal(got[0], want[0])
    assert_array_equal(got[1], want[1])
    assert got[2] == want[2]


@pytest.mark.parametrize("seed", range(5))
def test_cost_matrix_and_marginal_kernels_agree_bit_for_bit(seed):
    rng = np.random.default_rng(seed)
    T, U = 6, 5
    log_det = np.where(rng.random((T, U)) < 0.6, rng.normal(0.0, 5.0, (T, U)), -np.inf)
    log_miss, log_dead = rng.normal(-3.0, 1.0, T), rng.normal(-0.1, 0.05, T)
    rows = np.sort(rng.choice(T, 4, replace=False)).astype(np.int64)
    cols = np.sort(rng.choice(U, 3, replace=False)).astype(np.int64)
    assert_array_equal(_kernels.group_cost_matrix(log_det, log_miss, log_dead, rows, cols),
                       reference.group_cost_matrix(log_det, log_miss, log_dead, rows, cols))
    P, M, H = 4, 3, 40
    a = np.empty((H, P), dtype=np.int64)
    for h in range(H):
        a[h] = [rng.choice([j for j in range(M)] + [M + i, M + P + i]) for i in range(P)]
    w = rng.random(H)
    w /= w.sum()
    assert_array_equal(_kernels.truncated_marginals(a, w, M),
                       reference.truncated_marginals(a, w, M))


@given(st.lists(st.floats(0.0, 1.0), max_size=12))
def test_cardinality_distribution_matches_reference(r):
    r = np.array(r, dtype=np.float64)
    assert_array_equal(_kernels.cardinality_distribution(r), reference.cardinality_distribution(r))


@pytest.mark.parametrize("seed", range(8))
def test_posterior_kernels_agree_bit_for_bit(seed):
    offsets, m, P, R, z, w, r = _scan(seed)
    rng = np.random.default_rng(100 + seed)
    T, C, U = offsets.size - 1, m.shape[0], z.shape[0]
    # sparse marginals: most pairs below the threshold, some tracks never missed
    rel = np.where(rng.random((T, U + 1)) < 0.4, rng.random((T, U + 1)), 0.0)
    lw, log_g = rng.normal(-8.0, 2.0, (C, U)), rng.normal(-7.0, 2.0, (T, U))
    got = _kernels.posterior_sources(offsets, rel, 1e-5, lw, log_g)
    want = reference.posterior_sources(offsets, rel, 1e-5, lw, log_g)
    for g, e in zip(got, want, strict=True):
        assert_array_equal(g, e)
    comp, track, meas, log_ratio, _ = got
    ratio = np.exp(log_ratio)
    Sinv = np.linalg.inv(P[:, [0, 2]][:, :, [0, 2]] + R)
    PHt = P[:, :, [0, 2]]
    K = PHt @ Sinv
    P_upd = P - K @ PHt.transpose(0, 2, 1)
    nu = rng.normal(0.0, 30.0, (C, U, 2))
    args = (comp, track, meas, ratio, rel, w, m, P, K, nu, P_upd)
    for g, e in zip(_kernels.posterior_components(*args), reference.posterior_components(*args),
                    strict=True):
        assert_array_equal(g, e)
