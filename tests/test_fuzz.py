"""Fuzz of every public function of rankedassign and oracle: bad input is a clear error.

Each call either returns a correct result or raises ``TypeError`` (the wrong kind of value) or
``ValueError`` (a value out of range) from inside the library with a message that names the
problem -- never another exception, a warning (the suite runs with ``-W error``), a crash deep
in numpy, SciPy or a numba kernel, or a silent wrong answer. Hypothesis draws extreme values:
huge and tiny floats, NaN, inf, empty shapes, wrong dtypes, huge integers. Shapes stay tiny so
that every valid problem can be checked against brute force.
"""

from __future__ import annotations

import itertools
import math
import os
from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import array_shapes, arrays
from numpy.testing import assert_allclose, assert_array_equal

import oracle
from rankedassign import AssignmentProblem, metrics, sample_original, sample_short_chains
from rankedassign.single import synthetic
from rankedassign.single.problem import COST_LIMIT

inf = np.inf
nan = np.nan

# Reproducible and without a deadline (a loaded machine must not fail a test); the number of
# examples comes from the active profile.
FUZZ = settings(
    deadline=None,
    # no "explain" phase: it traces every line, which makes the pure-Python sampler crawl
    phases=[Phase.explicit, Phase.reuse, Phase.generate, Phase.target, Phase.shrink],
    database=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much,
                           HealthCheck.data_too_large],
)

LIBRARY_DIRS = tuple(
    os.path.dirname(m.__file__) + os.sep for m in (oracle, metrics)  # oracle/, rankedassign/
)


# --------------------------------------------------------------------------- the contract
def call(f, *args, **kwargs):
    """Call ``f``; return its result, or the ``TypeError``/``ValueError`` it raised.

    Any other exception propagates (and fails the test). A ``TypeError``/``ValueError`` must
    carry a message and be raised by the library's own code (its last frame in
    ``rankedassign/`` or ``oracle/``), not by numpy, SciPy or a kernel underneath.
    """
    try:
        return f(*args, **kwargs)
    except (TypeError, ValueError) as exc:
        tb = exc.__traceback__
        while tb.tb_next is not None:
            tb = tb.tb_next
        where = tb.tb_frame.f_code.co_filename
        assert where.startswith(LIBRARY_DIRS), (
            f"{type(exc).__name__} raised outside the library, in {where}: {exc}"
        )
        assert len(str(exc)) > 10, f"uninformative message {str(exc)!r}"
        return exc


def ok(result) -> bool:
    return not isinstance(result, (TypeError, ValueError))


# --------------------------------------------------------------------------- strategies
SPECIAL_FLOATS = [0.0, -0.0, 5e-324, -5e-324, 2.2250738585072014e-308, 1e-300, 0.5, 1.0,
                  1e300, 2.0**1019, 2.0**1020, 1.7976931348623157e308, -1.7976931348623157e308,
                  -1e300, inf, -inf, nan]
HUGE_INTS = [2**31, 2**53 + 1, 2**62, 2**62 + 1, 2**63 - 1, 2**63, 2**64, 10**30, -1,
             -(2**63) - 1, -(10**30), 10**400]
WRONG = [None, "a", "", b"x", 1j, [], {}, (), True, False, 2.5, 3.0, nan, np.float64(inf),
         Fraction(1, 3), Decimal("1.5"), np.array([1, 2]), np.int64(3), np.uint64(2**63),
         np.bool_(True), object()]

floats_any = st.one_of(st.floats(), st.sampled_from(SPECIAL_FLOATS))
ints_any = st.one_of(st.integers(-3, 30), st.sampled_from(HUGE_INTS), st.integers())
anything = st.one_of(floats_any, ints_any, st.sampled_from(WRONG))


@st.composite
def arrays_any(draw, max_dims=3, max_side=4):
    """Array-likes of every kind: float (with extremes), int (with huge ones), bool,
    complex, strings, objects, ragged lists, scalars."""
    kind = draw(st.sampled_from(["float", "float", "int", "bool", "complex", "str", "object",
                                 "ragged", "pyint", "uint64", "scalar"]))
    shape = draw(array_shapes(min_dims=0, max_dims=max_dims, min_side=0, max_side=max_side))
    if kind == "float":
        return draw(arrays(np.float64, shape, elements=floats_any))
    if kind == "int":
        return draw(arrays(np.int64, shape))
    if kind == "uint64":
        return draw(arrays(np.uint64, shape))
    if kind == "bool":
        return draw(arrays(np.bool_, shape))
    if kind == "complex":
        return draw(arrays(np.complex128, shape, elements=st.complex_numbers(max_magnitude=9)))
    if kind == "str":
        return np.full(shape, "1.5")
    if kind == "object":
        return np.full(shape, None, dtype=object)
    if kind == "ragged":
        return [[0.0, 1.0], [2.0]]
    if kind == "pyint":
        n = math.prod(shape)
        vals = draw(st.lists(st.sampled_from(HUGE_INTS + [0, 1, 2]), min_size=n, max_size=n))
        return np.array(vals, dtype=object).reshape(shape).tolist()
    return draw(anything)


@st.composite
def layouts(draw, max_rows=3, max_meas=3, values=floats_any):
    """Cost matrices in the paper's layout with arbitrary (often extreme or invalid) values
    where the layout allows a value, and ``+inf`` elsewhere."""
    P = draw(st.integers(0, max_rows))
    M = draw(st.integers(0, max_meas))
    C = np.full((P, M + 2 * P), inf)
    rows = np.arange(P)
    C[:, :M] = draw(arrays(np.float64, (P, M), elements=values))
    C[rows, M + rows] = draw(arrays(np.float64, (P,), elements=values))
    C[rows, M + P + rows] = draw(arrays(np.float64, (P,), elements=values))
    return C


extreme_costs = st.one_of(
    st.floats(-2.0**1019, 2.0**1019),
    st.sampled_from([0.0, 5e-324, -5e-324, 1e-300, -2.0**1018, 2.0**1018, 1.0, inf]),
)
moderate_costs = st.one_of(st.floats(-30, 30), st.just(inf))


@st.composite
def problems(draw, max_rows=3, max_meas=3, values=extreme_costs):
    """Valid problems (of tiny size) with extreme finite costs and forbidden pairs."""
    C = draw(layouts(max_rows, max_meas, values))
    try:
        return AssignmentProblem.from_cost(C)
    except ValueError:
        # a row with no finite entry, no feasible assignment, or too large: make it valid
        P = C.shape[0]
        M = C.shape[1] - 2 * P
        C[np.arange(P), M + np.arange(P)] = 0.0
        C[np.isfinite(C)] = np.clip(C[np.isfinite(C)], -(2.0**1018) / max(P, 1),
                                    2.0**1018 / max(P, 1))
        return AssignmentProblem.from_cost(C)


def brute_force(problem):
    """Every feasible assignment (column indices) by brute force."""
    P = problem.n_rows
    choices = [np.flatnonzero(np.isfinite(problem.cost[i])) for i in range(P)]
    out = [cols for cols in itertools.product(*choices)
           if len([c for c in cols if c < problem.n_meas])
           == len({c for c in cols if c < problem.n_meas})]
    return np.array(out, dtype=np.int64).reshape(len(out), P)


def left_to_right(problem, a):
    """Cost of one assignment, summed row by row as ``cost_of`` documents."""
    s = 0.0
    for i, j in enumerate(a):
        s += float(problem.cost[i, j])
    return s


# --------------------------------------------------------------------------- problem
@FUZZ
@given(st.one_of(arrays_any(), layouts()))
def test_fuzz_from_cost(cost):
    for build in (AssignmentProblem, AssignmentProblem.from_cost,
                  AssignmentProblem.from_vo_layout):
        p = call(build, cost)
        if ok(p):
            # valid: the layout holds, every assignment's cost is finite and right
            assert p.cost.dtype == np.float64 and not p.cost.flags.writeable
            assert not np.isnan(p.cost).any() and not np.isneginf(p.cost).any()
            finite = np.isfinite(p.cost)
            assert np.where(finite, np.abs(p.cost), 0).max(axis=1, initial=0).sum() <= COST_LIMIT
            if p.n_rows <= 3 and p.n_meas <= 3:
                a = brute_force(p)
                assert len(a) == p.n_feasible() >= 1
                costs = p.cost_of(a)
                assert np.isfinite(costs).all()
                assert costs.tolist() == [left_to_right(p, x) for x in a]


@FUZZ
@given(arrays_any(), arrays_any(max_dims=2), arrays_any(max_dims=2))
def test_fuzz_from_eta_and_log_eta(D, m, d):
    for build in (AssignmentProblem.from_eta, AssignmentProblem.from_log_eta):
        p = call(build, D, m, d)
        if ok(p):
            assert p.shape == (p.n_rows, p.n_meas + 2 * p.n_rows)


@FUZZ
@given(layouts(values=st.one_of(st.floats(min_value=0.0), st.sampled_from(SPECIAL_FLOATS))))
def test_fuzz_from_eta_extreme_weights(C):
    # weights from 0 to the largest double, subnormals, and the invalid inf / nan
    P = C.shape[0]
    M = C.shape[1] - 2 * P
    rows = np.arange(P)
    D, m, d = C[:, :M], C[rows, M + rows], C[rows, M + P + rows]
    p = call(AssignmentProblem.from_eta, D, m, d)
    if ok(p):
        # -ln of a double is within [-710, 745]: every weight is representable as a cost
        assert np.all(np.abs(p.compact_cost[np.isfinite(p.compact_cost)]) < 746)
        assert_array_equal(np.isfinite(p.compact_cost),
                           np.column_stack([D, m, d]) > 0 if P else np.zeros((0, M + 2)))


@FUZZ
@given(problems(), arrays_any(max_dims=3))
def test_fuzz_assignment_methods(p, a):
    cost = call(p.cost_of, a)
    feas = call(p.is_feasible, a)
    logw = call(p.log_weight_of, a)
    gamma = call(p.cols_to_gamma, a)
    cols = call(p.gamma_to_cols, a)
    # the validation is shared: the same input is accepted or refused alike
    assert ok(feas) == ok(cost) or (ok(feas) and isinstance(cost, ValueError))
    if ok(cost):
        assert ok(logw)
        assert_array_equal(np.asarray(logw), -np.asarray(cost))
        assert_array_equal(np.isfinite(np.asarray(cost)), np.asarray(feas))
    if ok(gamma):
        assert_array_equal(p.gamma_to_cols(gamma), np.asarray(a, dtype=np.int64))
    if ok(cols):
        assert_array_equal(p.cols_to_gamma(cols), np.asarray(a, dtype=np.int64))


@FUZZ
@given(problems())
def test_fuzz_problem_methods_on_extreme_costs(p):
    a = brute_force(p)
    assert p.n_feasible() == len(a)
    assert_array_equal(p.is_feasible(a), True)
    costs = p.cost_of(a)
    assert np.isfinite(costs).all()
    assert costs.tolist() == [left_to_right(p, x) for x in a]
    assert_array_equal(p.gamma_to_cols(p.cols_to_gamma(a)), a)
    assert AssignmentProblem.from_vo_layout(p.to_vo_layout()) == p
    assert hash(p) == hash(AssignmentProblem.from_cost(p.cost))
    d, m, x = p.eta()  # may be inf for very negative costs: documented
    assert d.shape == (p.n_rows, p.n_meas) and m.shape == x.shape == (p.n_rows,)
    assert repr(p) == f"AssignmentProblem(P={p.n_rows}, M={p.n_meas})"
    assert (p == "x") is False


# --------------------------------------------------------------------------- synthetic
@FUZZ
@given(st.sampled_from([synthetic.diagonal, synthetic.uniform, synthetic.random]),
       st.one_of(st.integers(0, 3), anything), st.one_of(st.integers(0, 2), anything),
       st.one_of(st.integers(0, 4), anything))
def test_fuzz_synthetic_sizes(family, R, B, M):
    p = call(family, R, B, M)
    if ok(p):
        P = R + B
        assert p.shape == (P, M + 2 * P)
        assert p.n_feasible() >= 1


@FUZZ
@given(st.sampled_from([synthetic.diagonal, synthetic.random]), anything)
def test_fuzz_synthetic_pbar_d(family, pbar_d):
    r = call(family, 2, 1, 3, pbar_d=pbar_d)
    assert ok(r) == (isinstance(pbar_d, str) and pbar_d in ("r_pd", "pd"))


@FUZZ
@given(anything, st.one_of(anything, st.sampled_from(["row", "matrix"])))
def test_fuzz_synthetic_random_rng_and_granularity(rng, granularity):
    r = call(synthetic.random, 2, 0, 2, granularity=granularity, rng=rng)
    if ok(r):
        assert r.shape == (2, 6)
        if isinstance(rng, int):
            assert r == synthetic.random(2, 0, 2, granularity=granularity, rng=rng)


@FUZZ
@given(arrays_any(max_dims=2), arrays_any(max_dims=2), arrays_any(max_dims=2),
       arrays_any(max_dims=3), st.one_of(st.none(), ints_any, anything),
       st.one_of(st.sampled_from(["r_pd", "pd"]), anything))
def test_fuzz_eta_from_parameters(r, p_s, p_d, q, n_persisting, pbar_d):
    out = call(synthetic.eta_from_parameters, r, p_s, p_d, q, n_persisting=n_persisting,
               pbar_d=pbar_d)
    if ok(out):
        d, m, x = out
        assert (d >= 0).all() and (m >= 0).all() and (x >= 0).all()
        assert np.isfinite(d).all() and (m <= 1).all() and (x <= 1).all()


# --------------------------------------------------------------------------- metrics
def exact_log_ospa_1d(xs, ys, c, p):
    """``ln(value / c)`` from exact rationals (points in 1-D, ``p`` an int)."""
    if len(xs) > len(ys):
        xs, ys = ys, xs
    m, n = len(xs), len(ys)
    if n == 0:
        return None
    cf = Fraction(c)
    best = min(sum((min(cf, abs(Fraction(xs[i]) - Fraction(ys[j]))) / cf) ** p
                   for i, j in enumerate(perm))
               for perm in itertools.permutations(range(n), m))
    t = best + (n - m)
    if t == 0:
        return -math.inf
    return (math.log(t.numerator) - math.log(t.denominator) - math.log(n)) / p


@FUZZ
@given(st.one_of(arrays_any(max_dims=2), st.lists(st.lists(floats_any, min_size=1,
                                                            max_size=2), max_size=3)),
       st.one_of(arrays_any(max_dims=2), st.lists(st.lists(floats_any, min_size=1,
                                                            max_size=2), max_size=3)),
       st.one_of(floats_any, anything), st.one_of(floats_any, anything))
def test_fuzz_ospa(X, Y, c, p):
    r = call(metrics.ospa, X, Y, c, p)
    if ok(r):
        assert all(np.isfinite(v) and 0.0 <= v <= c for v in r)
        s = call(metrics.ospa, Y, X, c, p)
        assert_allclose(s, r, rtol=1e-12)


@FUZZ
@given(st.lists(st.integers(-2**20, 2**20), max_size=3),
       st.lists(st.integers(-2**20, 2**20), max_size=3),
       st.integers(-1070, 1020), st.integers(1, 1000), st.integers(-1074, 1023))
def test_fuzz_ospa_extreme_scales_against_the_exact_definition(xs, ys, ec, p, ex):
    # points scaled by 2**ex (subnormal to huge), cut-off 2**ec: the definition in exact
    # rational arithmetic is the judge
    scale = 2.0**ex
    xs = [x * scale for x in xs if math.isfinite(x * scale)]
    ys = [y * scale for y in ys if math.isfinite(y * scale)]
    c = 2.0**ec
    r = metrics.ospa(np.reshape(xs, (-1, 1)), np.reshape(ys, (-1, 1)), c, p)
    want = exact_log_ospa_1d(xs, ys, c, p)
    if want is None:
        assert r == (0.0, 0.0, 0.0)
    else:
        assert_allclose(r.value, c * math.exp(want), rtol=1e-12)


@st.composite
def track_arrays(draw, K=None, d=None):
    K = draw(st.integers(1, 4)) if K is None else K
    n = draw(st.integers(0, 3))
    d = draw(st.integers(0, 2)) if d is None else d
    vals = draw(arrays(np.float64, (K, n, d), elements=st.one_of(
        st.floats(-1e300, 1e300), st.sampled_from([5e-324, 1.7976931348623157e308]))))
    mask = draw(arrays(np.bool_, (K, n)))
    vals[~mask] = nan
    return vals


@FUZZ
@given(st.data(), st.one_of(floats_any, anything), st.one_of(floats_any, anything),
       st.one_of(st.integers(1, 5), ints_any, anything),
       st.one_of(st.floats(0, 3000), floats_any, anything),
       st.one_of(st.sampled_from(["euclidean", "lp"]), anything))
def test_fuzz_ospa2(data, c, p, window, r, base):
    truth = data.draw(st.one_of(track_arrays(K=3, d=2), arrays_any()))
    est = data.draw(st.one_of(track_arrays(K=3, d=2), arrays_any()))
    res = call(metrics.ospa2, truth, est, c, p, window, weight_power=r, base=base)
    if ok(res):
        for v in res:
            assert v.shape == (3,)
            assert np.isfinite(v).all() and (v >= 0).all() and (v <= c).all()


@FUZZ
@given(track_arrays(K=3, d=2), track_arrays(K=3, d=2), st.floats(1e-300, 1e300),
       st.sampled_from([1.0, 2.0, 150.0, 1e4, 1e300]), st.integers(1, 3),
       st.sampled_from([0.0, 1.0, 2000.0]))
def test_fuzz_ospa2_window_one_is_ospa_at_any_scale(truth, est, c, p, window, r):
    res = metrics.ospa2(truth, est, c, p, 1, weight_power=r)
    for k in range(3):
        x = truth[k][~np.isnan(truth[k]).any(axis=1)]
        y = est[k][~np.isnan(est[k]).any(axis=1)]
        assert_allclose([res.value[k], res.localisation[k], res.cardinality[k]],
                        metrics.ospa(x, y, c, p), rtol=1e-10, atol=0)
    both = metrics.ospa2(truth, est, c, p, window, weight_power=r)
    assert (both.value <= c).all() and (both.value >= 0).all()
    assert_allclose(metrics.ospa2(est, truth, c, p, window, weight_power=r).value,
                    both.value, rtol=1e-10)


# ------------------------------------------------------------------ measurement files, priors
FILE_TOKENS = ["0", "1", "3.0", "7", "-1", "1_000", "+3", "1e3", "nan", "inf", "", " ", "x",
               "\u0663", "0x10", "1000000000000", "9" * 30, "\x00", '"', "1.5", "-0.0", "5e-324"]


@FUZZ
@given(st.lists(st.lists(st.sampled_from(FILE_TOKENS), min_size=2, max_size=5), max_size=4),
       st.sampled_from(["scan,x,y", "scan,sensor,x,y", "x,y", ""]),
       st.sampled_from(["utf-8", "latin-1", "utf-16"]))
def test_fuzz_read_measurements(rows, header, encoding):
    import tempfile

    from rankedassign.tracking import read_measurements

    text = "\n".join([header, *(",".join(r) for r in rows)]) + "\n"
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "m.csv")
        with open(path, "wb") as f:
            f.write(text.encode(encoding, errors="replace"))
        try:
            scans = read_measurements(path)
        except ValueError as err:
            assert str(err).startswith(f"{path}, line "), err  # file and line, always
            return
    assert 1 <= len(scans) <= 10**6
    for z in scans:
        for a in (z if isinstance(z, tuple) else (z,)):
            assert a.dtype == np.float64 and a.shape[1:] == (2,) and np.isfinite(a).all()


@FUZZ
@given(st.one_of(anything, st.lists(st.lists(ints_any, min_size=2, max_size=2), max_size=2),
                 st.lists(st.lists(anything, min_size=2, max_size=2), min_size=2, max_size=2)),
       st.one_of(anything, arrays_any()), st.one_of(anything, arrays_any()),
       st.one_of(st.none(), anything, st.lists(st.lists(anything, max_size=2), max_size=2)))
def test_fuzz_glmb_set_prior(labels, means, covs, components):
    from rankedassign.tracking import GLMBFilter, Murty, make_model

    f = GLMBFilter(make_model("vo"), Murty(3))
    try:
        f.set_prior(labels, means, covs, components)
    except (TypeError, ValueError):
        assert f.n_tracks == 0  # nothing was set
        return
    # accepted: distinct labels that no birth takes, finite means, SPD covariances
    keys = [tuple(x) for x in f.labels.tolist()]
    assert len(set(keys)) == len(keys)
    assert all(0 <= a < 2**31 and 0 <= b < 2**32 and not (a >= 1 and 1 <= b <= 4)
               for a, b in keys)
    assert np.isfinite(f.m).all() and (np.linalg.eigvalsh(f.P) > 0).all()


@FUZZ
@given(st.data(), st.one_of(floats_any, anything), st.one_of(st.integers(0, 4), ints_any,
                                                            anything))
def test_fuzz_track_coverage(data, radius, settle):
    truth = data.draw(st.one_of(track_arrays(K=3, d=2), arrays_any()))
    est = data.draw(st.one_of(track_arrays(K=3, d=2), arrays_any()))
    res = call(metrics.track_coverage, truth, est, radius, settle=settle)
    if ok(res):
        assert res.ndim == 1
        fin = res[~np.isnan(res)]
        assert ((fin >= 0) & (fin <= 1)).all()


labels = st.one_of(st.integers(0, 3), st.text(max_size=2), st.tuples(st.integers(0, 2)))


@FUZZ
@given(st.one_of(
    st.lists(st.dictionaries(labels, st.one_of(
        st.lists(floats_any, min_size=2, max_size=2), arrays_any(max_dims=1)), max_size=3),
        max_size=3),
    anything, arrays_any()),
    st.one_of(st.none(), st.lists(st.one_of(st.integers(-1, 3), anything), max_size=3),
              anything),
    st.one_of(st.booleans(), anything))
def test_fuzz_tracks_to_array(est, dims, return_labels):
    res = call(metrics.tracks_to_array, est, dims=dims, return_labels=return_labels)
    if ok(res):
        arr, labs = res if return_labels else (res, None)
        assert arr.ndim == 3 and arr.shape[0] == len(est)
        if labs is not None:
            assert len(labs) == arr.shape[1]


# --------------------------------------------------------------------------- oracle
@FUZZ
@given(st.one_of(problems(), st.sampled_from(WRONG)), st.one_of(st.integers(-2, 50),
                                                                ints_any, anything))
def test_fuzz_oracle_ranking(p, k):
    exact = brute_force(p) if isinstance(p, AssignmentProblem) else None
    for f in (oracle.murty, lambda q, k: oracle.murty(q, k, backend="scipy"),
              lambda q, k: oracle.enumerate_assignments(q, limit=k)):
        r = call(f, p, k)
        if ok(r):
            assert isinstance(p, AssignmentProblem)
            n = len(r.costs)
            assert n <= len(exact)
            assert_array_equal(p.cost_of(r.assignments), r.costs)
            assert np.all(np.diff(r.costs) >= 0)
            assert len(np.unique(r.assignments, axis=0)) == n
            # the k best costs: equal, tie-aware, to the brute-force ranking
            best = np.sort(p.cost_of(exact))[:n]
            assert_array_equal(r.costs, best)


@FUZZ
@given(problems(values=st.one_of(extreme_costs, moderate_costs)))
def test_fuzz_oracle_normaliser_and_marginals(p):
    from scipy.special import logsumexp

    exact = brute_force(p)
    costs = p.cost_of(exact)
    lz = oracle.log_normalizer(p)
    want = logsumexp(-costs)
    # ln Z to within the rounding of the costs themselves (an ulp of the largest |cost|)
    assert_allclose(lz, want, rtol=1e-12, atol=1e-9 + 8 * np.spacing(np.abs(costs).max()))
    mg = oracle.marginals(p)
    assert mg.shape == (p.n_rows, p.n_meas + 2)
    assert np.isfinite(mg).all() and (mg >= 0).all()
    assert_allclose(mg.sum(axis=1), 1.0, rtol=1e-9)


@FUZZ
@given(problems(values=st.one_of(extreme_costs, moderate_costs)), st.data())
def test_fuzz_truncation_error_and_best_mass(p, data):
    exact = brute_force(p)
    n = len(exact)
    idx = data.draw(st.lists(st.integers(0, n - 1), max_size=6))
    err = oracle.truncation_error(p, exact[idx].reshape(len(idx), p.n_rows))
    assert 0.0 <= err <= 1.0
    # exact weights relative to the best: exact rational sums of the double entries (cost_of
    # rounds each sum to a double, which at 2**53 already moves a weight by a factor e)
    C = p.cost
    costs = [sum((Fraction(float(C[i, j])) for i, j in enumerate(x)), Fraction(0))
             for x in exact]
    low = min(costs)
    w = [Decimal(math.exp(-float(c - low))) for c in costs]
    z = sum(w)
    kept = sum(w[i] for i in set(idx))
    assert abs(err - float(1 - kept / z)) <= 1e-9, (p.cost.tolist(), idx)
    k = data.draw(st.integers(0, n + 1))
    bm = oracle.best_mass(p, k)
    top = sorted(w, reverse=True)[:k]
    assert abs(bm - float(sum(top) / z)) <= 1e-9, (p.cost.tolist(), k)


@FUZZ
@given(st.one_of(problems(), st.sampled_from(WRONG)), st.one_of(arrays_any(), anything))
def test_fuzz_truncation_error_arguments(p, a):
    r = call(oracle.truncation_error, p, a)
    if ok(r):
        assert 0.0 <= r <= 1.0


@FUZZ
@given(st.one_of(problems(), st.sampled_from(WRONG)), st.one_of(ints_any, anything))
def test_fuzz_best_mass_arguments(p, k):
    r = call(oracle.best_mass, p, k)
    if ok(r):
        assert 0.0 <= r <= 1.0


@FUZZ
@given(st.sampled_from(WRONG))
def test_fuzz_oracle_refuses_non_problems(x):
    for f in (oracle.log_normalizer, oracle.marginals, oracle.enumerate_assignments,
              lambda q: oracle.murty(q, 1), lambda q: oracle.truncation_error(q, [[0]]),
              lambda q: oracle.best_mass(q, 1)):
        assert isinstance(call(f, x), TypeError)


@FUZZ
@given(problems(max_rows=2, max_meas=2), st.one_of(anything, st.sampled_from(["numba", "scipy"])))
def test_fuzz_murty_method(p, method):
    r = call(oracle.murty, p, 2, backend=method)
    assert ok(r) == (isinstance(method, str) and method in ("numba", "scipy"))


# --------------------------------------------------------------------------- samplers
# Argument handling only (the samplers' own checks belong to samplers.py). Counts that are
# valid but large (up to 2**62) would run for that long, so they are drawn only where no
# sweep is run (chain_length = 0) or where they must be refused.
SAMPLER_PROBLEM = synthetic.uniform(R=2, M=2)

sampler_counts = st.one_of(
    st.integers(-3, 4),
    st.sampled_from([2**63, 2**64, 10**30, -(2**63) - 1, -(10**30)]),
    st.sampled_from([None, "3", 2.0, 2.5, nan, inf, True, np.int64(3), np.uint64(2**63),
                     Fraction(3, 1), 3j]),
)


def _check_sampler_result(res, problem):
    a = res.assignments
    assert a.ndim == 2 and a.shape[1] == problem.n_rows
    assert problem.is_feasible(a).all()
    assert_array_equal(problem.cost_of(a), res.costs)


@FUZZ
@given(sampler_counts, st.sampled_from(["systematic", "random"]),
       st.sampled_from(["numba", "python"]))
def test_fuzz_sample_original_counts(n_obs, scan, backend):
    r = call(sample_original, SAMPLER_PROBLEM, n_obs, scan=scan, rng=0, backend=backend)
    if ok(r):
        _check_sampler_result(r, SAMPLER_PROBLEM)


@FUZZ
@given(sampler_counts, sampler_counts, st.one_of(st.none(), sampler_counts),
       st.one_of(st.none(), sampler_counts), st.one_of(st.integers(1, 3), sampler_counts))
def test_fuzz_sample_short_chains_counts(n_chains, chain_length, tau_stall, tau_stale,
                                         workers):
    r = call(sample_short_chains, SAMPLER_PROBLEM, n_chains, chain_length,
             tau_stall=tau_stall, tau_stale=tau_stale, rng=0, workers=workers)
    if ok(r):
        _check_sampler_result(r, SAMPLER_PROBLEM)


@FUZZ
@given(st.sampled_from([0, 1, 2**20, 2**40, 2**62, 2**63, 10**30]))
def test_fuzz_many_chains_of_length_zero_are_quick(n_chains):
    # no sweep is run, so any number of chains is either refused or done at once
    r = call(sample_short_chains, SAMPLER_PROBLEM, n_chains, 0, rng=0)
    if ok(r):
        assert r.n_observations == 0
        _check_sampler_result(r, SAMPLER_PROBLEM)


@FUZZ
@given(st.one_of(anything, st.sampled_from(["all_missed", "all_dead", "lsap", "x"]),
                 arrays_any(max_dims=2)),
       st.one_of(anything, st.sampled_from(["systematic", "random"])),
       st.one_of(anything, st.sampled_from(["numba", "python"])))
def test_fuzz_sampler_options(start, scan, backend):
    for f in (lambda: sample_original(SAMPLER_PROBLEM, 2, start=start, scan=scan, rng=0,
                                      backend=backend),
              lambda: sample_short_chains(SAMPLER_PROBLEM, 2, 2, start=start, scan=scan,
                                          rng=0, backend=backend)):
        r = call(f)
        if ok(r):
            _check_sampler_result(r, SAMPLER_PROBLEM)


@FUZZ
@given(st.one_of(anything, st.sampled_from(["global-consecutive", "x"])),
       st.one_of(anything, st.sampled_from(["consecutive", "x"])))
def test_fuzz_sampler_rule_names(stall, stale):
    r = call(sample_short_chains, SAMPLER_PROBLEM, 2, 2, tau_stall=1, tau_stale=1,
             stall=stall, stale=stale, rng=0)
    if ok(r):
        _check_sampler_result(r, SAMPLER_PROBLEM)


@FUZZ
@given(st.one_of(st.sampled_from(WRONG), problems(max_rows=2, max_meas=2)))
def test_fuzz_sampler_problem_argument(p):
    for f in (lambda: sample_original(p, 2, rng=0), lambda: sample_short_chains(p, 2, 2, rng=0)):
        r = call(f)
        if not isinstance(p, AssignmentProblem):
            assert isinstance(r, TypeError) and "problem" in str(r)
        elif ok(r):
            _check_sampler_result(r, p)
        else:  # a valid problem whose rows cannot all be missed: the default start is refused
            assert isinstance(r, ValueError) and "start='all_missed' is infeasible" in str(r)


@pytest.mark.parametrize("rng", [-1, 1.5, "seed", nan, 2**64, [1, -2], object()])
def test_fuzz_sampler_rng_argument(rng):
    for f in (lambda: sample_original(SAMPLER_PROBLEM, 2, rng=rng),
              lambda: sample_short_chains(SAMPLER_PROBLEM, 2, 2, rng=rng)):
        r = call(f)
        if isinstance(r, (TypeError, ValueError)):
            assert "rng" in str(r), f"the message does not name rng: {r}"
        else:
            _check_sampler_result(r, SAMPLER_PROBLEM)


# ============================================================================ the CLI, for real
# Real processes and real signals: the report directory is never lost, concurrent runs are
# refused, and a signal ends a run at every stage within seconds, cleanly.
import json  # noqa: E402
import signal  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

#: A table1 run whose first study lasts far longer than any test: one original chain of 10**10
#: sweeps per Monte Carlo run.
_LONG = {"table1": {"n_mc": 4, "families": ["random"], "original_obs": 10**10}}


class _Run:
    """``rankedassign reproduce ...`` in a child process, its stderr in a file."""

    def __init__(self, tmp_path, *args, name="run"):
        self.err_path = tmp_path / f"{name}.stderr"
        self._err = self.err_path.open("w")
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "rankedassign", "reproduce", *map(str, args)],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=self._err,
        )

    @property
    def err(self) -> str:
        return self.err_path.read_text()

    def wait_for(self, text: str, timeout: float = 600) -> None:
        deadline = time.monotonic() + timeout
        while text not in self.err:
            assert self.proc.poll() is None, self.err
            assert time.monotonic() < deadline, f"never saw {text!r}: {self.err}"
            time.sleep(0.2)

    def children(self) -> list[int]:
        """Pids of the run's child processes (Linux /proc)."""
        pids = []
        for stat_file in os.listdir("/proc"):
            if stat_file.isdigit():
                try:
                    with open(f"/proc/{stat_file}/stat") as fh:
                        fields = fh.read().rsplit(")", 1)[1].split()
                except OSError:
                    continue
                if int(fields[1]) == self.proc.pid:
                    pids.append(int(stat_file))
        return pids

    def wait(self, timeout: float = 300) -> int:
        try:
            return self.proc.wait(timeout=timeout)
        finally:
            if self.proc.poll() is None:
                self.proc.kill()
                self.proc.wait()
            self._err.close()


def _long_config(tmp_path):
    path = tmp_path / "long.json"
    path.write_text(json.dumps(_LONG))
    return path


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


needs_proc = pytest.mark.skipif(not os.path.isdir("/proc"), reason="needs Linux /proc")


@pytest.mark.e2e
def test_cli_force_never_deletes_a_folder_with_a_foreign_manifest(tmp_path):
    w = tmp_path / "w"
    (w / "src").mkdir(parents=True)
    (w / "manifest.json").write_text('{"name": "my-pwa"}')
    (w / "src" / "app.js").write_text("x")
    run = _Run(tmp_path, "table1", "--out", w, "--force")
    assert run.wait() == 2, run.err
    assert "refusing to replace" in run.err and "Traceback" not in run.err
    assert (w / "src" / "app.js").read_text() == "x"


@pytest.mark.e2e
@needs_proc
def test_cli_a_folder_made_at_out_during_the_run_survives(tmp_path):
    out = tmp_path / "r3"
    cfg = tmp_path / "c.json"
    cfg.write_text(json.dumps({"table1": {"n_mc": 40, "families": ["random"],
                                          "original_obs": 20_000, "n_chains": 800}}))
    run = _Run(tmp_path, "table1", "--config", cfg, "--out", out, "--workers", 1)
    run.wait_for("[1/1] table1")
    out.mkdir()
    (out / "t.tex").write_text("x")
    assert run.wait() == 2, run.err
    assert (out / "t.tex").read_text() == "x" and sorted(os.listdir(out)) == ["t.tex"]
    kept = [p for p in tmp_path.iterdir() if p.name.startswith("r3.new-")]
    assert len(kept) == 1 and (kept[0] / "manifest.json").exists()
    assert f"the finished report is kept in '{kept[0]}'" in run.err


@pytest.mark.e2e
@needs_proc
def test_cli_a_second_run_into_the_same_out_is_refused_and_names_the_first(tmp_path):
    out = tmp_path / "r"
    first = _Run(tmp_path, "table1", "--config", _long_config(tmp_path), "--out", out,
                 "--workers", 2, name="first")
    try:
        first.wait_for("[1/1] table1")
        second = _Run(tmp_path, "table1", "--out", out, "--quiet", name="second")
        assert second.wait(timeout=120) == 2, second.err
        assert f"another run is writing the report to '{out}' (pid {first.proc.pid} on " \
            in second.err
    finally:
        first.proc.send_signal(signal.SIGTERM)
        assert first.wait(timeout=60) == 128 + signal.SIGTERM, first.err
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "first.stderr", "long.json", "second.stderr"]


@pytest.mark.e2e
@needs_proc
@pytest.mark.parametrize(("sig", "code", "word"), [
    (signal.SIGTERM, 143, "terminated (SIGTERM)"), (signal.SIGINT, 130, "interrupted")])
def test_cli_a_signal_inside_a_long_kernel_ends_the_run_within_seconds(tmp_path, sig, code,
                                                                      word):
    # issue: with --workers 2 the parent needed a second SIGTERM after 200 s
    out = tmp_path / "r"
    run = _Run(tmp_path, "table1", "--config", _long_config(tmp_path), "--out", out,
               "--workers", 2)
    run.wait_for("[1/1] table1")
    time.sleep(2.0)  # the workers are inside the 10**10-sweep kernel
    workers = run.children()
    assert workers, "no worker processes"
    t0 = time.monotonic()
    run.proc.send_signal(sig)
    assert run.wait(timeout=60) == code, run.err
    latency = time.monotonic() - t0
    print(f"exit {code} {latency:.2f} s after the signal")
    assert latency < 15, f"{latency:.1f} s"
    assert f"{word}; no report written" in run.err and "Traceback" not in run.err
    time.sleep(0.5)
    assert not [p for p in workers if _alive(p)], "orphaned worker processes"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["long.json", "run.stderr"]


@pytest.mark.e2e
@needs_proc
def test_cli_sigkill_leaves_a_partial_report_that_the_next_run_removes(tmp_path):
    out = tmp_path / "r"
    run = _Run(tmp_path, "table1", "--config", _long_config(tmp_path), "--out", out,
               "--workers", 2, name="killed")
    run.wait_for("[1/1] table1")
    workers = run.children()
    run.proc.kill()
    run.wait()
    assert workers, "no worker processes"
    deadline = time.monotonic() + 10
    while [p for p in workers if _alive(p)] and time.monotonic() < deadline:
        time.sleep(0.2)
    # the workers were inside the 10**10-sweep kernel: they end with their parent (Linux)
    assert not [p for p in workers if _alive(p)], "orphaned worker processes"
    partial = [p for p in tmp_path.iterdir() if p.name.startswith(".r.partial-")]
    assert len(partial) == 1
    cfg = tmp_path / "tiny.json"
    cfg.write_text(json.dumps({"optimum": {"n_mc": 1, "original_obs": 500, "n_chains": 20}}))
    again = _Run(tmp_path, "optimum", "--config", cfg, "--out", out, "--workers", 1, "--quiet",
                 name="again")
    assert again.wait() == 0, again.err
    assert (f"note: removed '{partial[0]}', the partial report of an earlier run into the same "
            f"--out that was killed (pid {run.proc.pid})") in again.err
    assert not partial[0].exists() and (out / "manifest.json").exists()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]
