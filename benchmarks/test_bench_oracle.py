"""Oracle speed: enumeration, Murty (numba vs the SciPy-per-subproblem reference), exact DPs.

Run the timings with::

    python -m pytest benchmarks/test_bench_oracle.py --benchmark-enable

(in the default suite each runs once as a smoke test). Benchmarks sharing a group (for
example ``murty 20x90 k=1000``) differ only in the method, so the numba / SciPy ratio reads
off one table. Problems: the paper's ``4 x 24`` random matrix (``synthetic.random(rng=0)``),
a tracking-sized ``P = 20, M = 50`` matrix (``synthetic.random(R=20, M=50, rng=0)``), for
the subset DP ``P = 16, M = 100``, and for the frontier DP two gated problems beyond the subset
DP's reach: a synthetic one (:func:`gated_problem`, 22 rows and 57 measurements in one connected
component) and the largest problem the LMB filter meets on the paper's scenario (exact
association, ``rng=0``, first 70 scans; a component of about 30 rows and 60 measurements).

The Murty targets are ratios against :func:`textbook_murty`, the plain algorithm of spec §5.1
written here (one :func:`scipy.optimize.linear_sum_assignment` per subproblem, every subproblem
a cost matrix of its own, nothing shared between subproblems), on a dense ``20 x 20`` problem
(``synthetic.random(R=20, M=20, rng=0)``: every pair allowed) for ``k = 100`` and on the GLMB
layout ``P = 20, M = 50`` (``20 x 90``) for ``k = 1000``. A third case, without a target,
times the square case of ``fastmurty``'s own benchmark (:func:`square_problem`). Each case is
timed on seeds 0 (the targets' problem), 1 and 2, the square case on seeds 0 to 9, one group
per case and seed. The groups take
Motro's C ``fastmurty`` (sparse and dense input) when a build of it is named in the environment
(:mod:`_fastmurty`; skipped otherwise), so the C state of the art sits in the same table.
"""

import heapq
import math

import _fastmurty
import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment

from oracle import enumerate_assignments, log_normalizer, marginals
from oracle.single import murty
from rankedassign import AssignmentProblem
from rankedassign.single import synthetic

PROBLEMS = {
    "4x24": lambda: synthetic.random(rng=0),
    "20x90": lambda: synthetic.random(R=20, M=50, rng=0),
}


def square_problem(n=20, seed=0):
    """The square case of ``fastmurty``'s own benchmark in this project's layout.

    Its example draws an ``n x n`` matrix ``U(0, 1) - (n + 1)`` whose rows may stay unassigned
    at cost 0 ("so that misses are never picked"); here that is an ``n x (n + 2n)`` problem:
    the ``n x n`` block on the measurement columns, cost 0 on each row's missed column and no
    dead column (``+inf``).
    """
    rng = np.random.default_rng(seed)
    cost = np.full((n, 3 * n), np.inf)
    cost[:, :n] = rng.random((n, n)) - (n + 1)
    cost[np.arange(n), n + np.arange(n)] = 0.0
    return AssignmentProblem.from_cost(cost)


# (group, problem of a seed, k, seeds) of the Murty targets against the textbook SciPy Murty,
# and the square case of fastmurty's own benchmark (no target: the C library's home ground,
# for comparison); the targets are on seed 0, the other seeds check that a comparison is not
# one problem's. The square case takes ten seeds: its time varies by 1.6x from seed to seed,
# and the C library's by about as much, but not on the same seeds.
TEXTBOOK_CASES = {
    "dense 20x20 k=100": (lambda seed: synthetic.random(R=20, M=20, rng=seed), 100, range(3)),
    "GLMB 20x50 k=1000": (lambda seed: synthetic.random(R=20, M=50, rng=seed), 1000, range(3)),
    "square 20x20 k=100": (lambda seed: square_problem(20, seed), 100, range(10)),
}
GROUP_SEEDS = [(group, seed) for group in sorted(TEXTBOOK_CASES)
               for seed in TEXTBOOK_CASES[group][2]]


def textbook_murty(problem, k):
    """Murty (1968) as spec §5.1 writes it: one full SciPy LSAP per subproblem.

    Each node keeps its own copy of the cost matrix with its fixings and forbidden pairs
    written in as ``+inf``; each child is solved from scratch by
    :func:`scipy.optimize.linear_sum_assignment` (no duals or partial assignment inherited);
    rows are partitioned in natural order. Returns the ``min(k, |Gamma|)`` best costs.
    """
    C = np.array(problem.cost)
    P = problem.n_rows
    rows = np.arange(P)

    def solve(Cn):
        try:
            return linear_sum_assignment(Cn)[1]
        except ValueError:  # "cost matrix is infeasible"
            return None

    s = solve(C)
    heap = [(C[rows, s].sum(), 0, s, C, np.zeros(P, dtype=bool))]
    count = 0
    costs = []
    while heap and len(costs) < k:
        cost, _, s, Cn, fixed = heapq.heappop(heap)
        costs.append(cost)
        Cw = Cn.copy()
        fixed = fixed.copy()
        for r in np.flatnonzero(~fixed):
            Cx = Cw.copy()
            Cx[r, s[r]] = np.inf  # child: forbid (r, s[r]) on top of the earlier fixings
            sx = solve(Cx)
            if sx is not None:
                count += 1
                heapq.heappush(heap, (Cx[rows, sx].sum(), count, sx, Cx, fixed.copy()))
            keep = Cw[r, s[r]]  # fix (r, s[r]) for the later children
            Cw[r, :] = np.inf
            Cw[:, s[r]] = np.inf
            Cw[r, s[r]] = keep
            fixed[r] = True
    return np.array(costs)


@pytest.fixture(scope="module", autouse=True)
def _compiled():
    """Compile (or load) every oracle kernel once, outside the timings."""
    tiny = synthetic.random(R=2, M=3, rng=0)
    enumerate_assignments(tiny)
    murty(tiny, 5)
    log_normalizer(tiny)
    marginals(tiny)


def test_bench_enumerate_4x24(benchmark):
    problem = PROBLEMS["4x24"]()
    benchmark.group = "enumerate 4x24"
    r = benchmark(enumerate_assignments, problem)
    assert len(r.costs) == 76_848


@pytest.mark.parametrize("method", ["numba", "scipy"])
@pytest.mark.parametrize("k", [100, 1000])
@pytest.mark.parametrize("size", sorted(PROBLEMS))
def test_bench_murty(benchmark, size, k, method):
    problem = PROBLEMS[size]()
    benchmark.group = f"murty {size} k={k}"
    benchmark.extra_info.update(P=problem.n_rows, M=problem.n_meas, k=k, method=method)
    r = benchmark(murty, problem, k, backend=method)
    assert len(r.costs) == k


@pytest.mark.parametrize("method", ["oracle", "textbook-scipy", "fastmurty-sparse",
                                    "fastmurty-dense"])
@pytest.mark.parametrize("group, seed", GROUP_SEEDS)
def test_bench_murty_vs_textbook(benchmark, group, seed, method):
    make, k, _ = TEXTBOOK_CASES[group]
    problem = make(seed)
    benchmark.group = f"murty {group} seed={seed}"
    benchmark.extra_info.update(P=problem.n_rows, M=problem.n_meas, k=k, seed=seed,
                                method=method)
    if method == "oracle":
        costs = benchmark(murty, problem, k).costs
    elif method == "textbook-scipy":
        costs = benchmark(textbook_murty, problem, k)
    else:  # the C library, when a build of it is given (see _fastmurty.py)
        kind = method.split("-")[1]
        path = _fastmurty.library_path(kind)
        if path is None:
            pytest.skip(f"set {_fastmurty.ENV[kind]} to a {kind} build of fastmurty to compare")
        fm = _fastmurty.FastMurty(path, kind)
        try:
            benchmark(fm.prepare(problem, k))
            costs = problem.cost_of(fm.check())  # complete, allowed; costs summed as ours
        finally:
            fm.close()
    # both rank the same k costs (the textbook sums in another order: compare to rounding)
    np.testing.assert_allclose(np.sort(costs), murty(problem, k).costs, rtol=1e-12, atol=1e-12)


def test_bench_log_normalizer_16x100(benchmark):
    problem = synthetic.random(R=16, M=100, rng=0)
    benchmark.group = "subset DP 16x100"
    z = benchmark(log_normalizer, problem)
    assert math.isfinite(z)


def test_bench_marginals_16x100(benchmark):
    problem = synthetic.random(R=16, M=100, rng=0)
    benchmark.group = "subset DP 16x100"
    m = benchmark(marginals, problem)
    assert m.shape == (16, 102)


def gated_problem(rng, n_rows=22, n_meas=57, n_wide=4, side=2000.0, gate=300.0, wide_gate=900.0):
    """A tracking-like gated problem: rows (predicted tracks) and measurements at random 2-D
    positions in a ``side`` square, a third of the measurements near a track; an entry is
    finite iff within ``gate`` (``wide_gate`` for the first ``n_wide`` rows, the births), with a
    Gaussian likelihood (10 m, births 300 m) over a uniform clutter density of 50 per square.
    ``rng=1`` gives one connected component of 22 rows and 57 measurements, ~3 rows per
    measurement."""
    rows = rng.uniform(0, side, (n_rows, 2))
    meas = np.concatenate([rows[: n_meas // 3] + rng.normal(0, 10, (n_meas // 3, 2)),
                           rng.uniform(0, side, (n_meas - n_meas // 3, 2))])
    d = np.linalg.norm(rows[:, None] - meas[None], axis=2)
    wide = (np.arange(n_rows) < n_wide)[:, None]
    sigma = np.where(wide, 300.0, 10.0)
    log_eta = (np.log(0.9 * 0.98) - d**2 / (2 * sigma**2) - np.log(2 * np.pi * sigma**2)
               - np.log(50 / side**2))
    log_eta[d >= np.where(wide, wide_gate, gate)] = -np.inf
    return AssignmentProblem.from_log_eta(log_eta, np.full(n_rows, np.log(0.9 * 0.02)),
                                          np.full(n_rows, np.log(0.1)))


@pytest.fixture(scope="module")
def tracking_problem():
    """The scan problem of the paper's scenario with the largest connected component."""
    from rankedassign.tracking import Exact, run_scenario

    seen = []

    class Recording(Exact):
        def __call__(self, problem, rng):
            seen.append(problem)
            return super().__call__(problem, rng)

    run_scenario("paper", Recording(), rng=0, n_scans=70)

    def largest_component(p):
        from scipy.sparse.csgraph import connected_components

        fin = np.isfinite(p.compact_cost[:, : p.n_meas])
        _, lab = connected_components(np.block([[np.zeros((p.n_rows, p.n_rows)), fin],
                                                [fin.T, np.zeros((p.n_meas, p.n_meas))]]),
                                      directed=False)
        return int(np.bincount(lab[: p.n_rows]).max())

    return max(seen, key=largest_component)


@pytest.mark.parametrize("fn", [log_normalizer, marginals])
def test_bench_frontier_gated_22x57(benchmark, fn):
    problem = gated_problem(np.random.default_rng(1))
    benchmark.group = "frontier DP gated 22x57"
    benchmark.extra_info.update(P=problem.n_rows, M=problem.n_meas)
    out = benchmark(fn, problem)
    assert np.all(np.isfinite(out))


@pytest.mark.parametrize("fn", [log_normalizer, marginals])
def test_bench_frontier_tracking_scan(benchmark, fn, tracking_problem):
    benchmark.group = "frontier DP paper-scenario scan"
    benchmark.extra_info.update(P=tracking_problem.n_rows, M=tracking_problem.n_meas)
    out = benchmark(fn, tracking_problem)
    assert np.all(np.isfinite(out))


@pytest.mark.parametrize("fn", ["lbp", "exact"])
def test_bench_lbp_vs_exact_marginals_30x60(benchmark, fn):
    """Loopy belief propagation against the exact marginals it approximates, 30 tracks x 60
    measurements in a gate (target: LBP at least 10x faster)."""
    from rankedassign import lbp_marginals

    problem = gated_problem(np.random.default_rng(1), n_rows=30, n_meas=60)
    benchmark.group = "LBP vs exact marginals gated 30x60"
    benchmark.extra_info.update(P=problem.n_rows, M=problem.n_meas,
                                gated=int(np.isfinite(problem.compact_cost[:, :-2]).sum()))
    if fn == "lbp":
        lbp_marginals(problem)                     # compiled outside the timing
        out = benchmark(lambda: lbp_marginals(problem).marginals)
        err = float(np.abs(out - marginals(problem)).max())
        benchmark.extra_info["max_error"] = err
        assert err < 1e-3
    else:
        out = benchmark(marginals, problem)
    assert out.shape == (30, 62)
