"""Reference (pure Python) ≡ numba kernels ≡ parallel kernels, bit for bit.

The pure-Python samplers of :mod:`rankedassign.reference` are the specification; every field
of the numba result (except the count of discarded speculative sweeps) must be identical to
theirs for the same problem, options and ``rng``, on any number of threads.
"""

import numpy as np
import pytest
from cases import CASE_IDS, CASES, problems
from hypothesis import given
from hypothesis import strategies as st
from numpy.testing import assert_array_equal

import oracle
from rankedassign import AssignmentProblem, kinds, reference, sample_original, sample_short_chains
from rankedassign.engine import _kernels as _rng_kernels
from rankedassign.engine import rng as _rng
from rankedassign.engine._kernels import Rules
from rankedassign.single import _kernels
from rankedassign.single import prepare as single_prepare
from rankedassign.single import reference as single_reference
from rankedassign.validation import STALE_READINGS, STALL_READINGS

INF = np.inf


def _driver_args(problem, start, scan, seed, n_chains, chain_length, rules):
    """Positional arguments of the compiled single-sensor driver, up to ``batch, workers``."""
    prep = kinds.prepare(problem, start, scan, seed)
    zk = _rng_kernels.zobrist_keys(problem.n_rows, prep.n_values, np.uint64(_rng.ZOBRIST_SEED))
    # read-only, as the samplers pass them: the driver's signature is then the precompiled
    # one (writable keys compiled the whole single-sensor driver again, 10 s of CPU)
    zk.setflags(write=False)
    return (prep.data, zk, prep.x0, np.uint64(prep.base), n_chains, chain_length, rules)


# ------------------------------------------------------------------------------ RNG
@pytest.mark.parametrize("seed", [0, 1, 2**63 - 1, 0xDEADBEEF12345678])
def test_rng_streams_agree_bit_for_bit(seed):
    n = 20_000
    for chain in (0, 1, 7, 10_000):
        state = _rng.chain_state(seed, chain)
        assert int(_rng_kernels.chain_state(np.uint64(seed), chain)) == state
        g = _rng.SplitMix64(state)
        py = np.array([g.uniform() for _ in range(n)])
        nb = _rng_kernels.uniform_stream(np.uint64(state), n)
        assert_array_equal(py.view(np.uint64), nb.view(np.uint64))


def test_rng_known_values_and_range():
    # SplitMix64 from state 0: first outputs of the published generator.
    g = _rng.SplitMix64(0)
    assert [hex(g.next_u64()) for _ in range(3)] == [
        "0xe220a8397b1dcdaf",
        "0x6e789e6aa1b965f4",
        "0x6c45d188009454f",
    ]
    u = _rng_kernels.uniform_stream(np.uint64(12345), 100_000)
    assert u.min() >= 0.0 and u.max() < 1.0
    # every uniform is a multiple of 2**-53
    assert_array_equal(u * 2.0**53, np.floor(u * 2.0**53))


def test_base_key_from_generator_advances_it():
    gen = np.random.default_rng(5)
    a = _rng.base_key(gen)
    b = _rng.base_key(gen)
    assert a != b
    assert a == _rng.base_key(np.random.default_rng(5))


def test_zobrist_keys_match_python_stream():
    keys = _rng_kernels.zobrist_keys(3, 4, np.uint64(_rng.ZOBRIST_SEED))
    g = _rng.SplitMix64(_rng.ZOBRIST_SEED)
    expected = np.array([g.next_u64() for _ in range(12)], dtype=np.uint64).reshape(3, 4)
    assert_array_equal(keys, expected)
    assert len(np.unique(keys)) == 12


# ------------------------------------------------------------------------------ problems
@st.composite
def wide_problems(draw, max_rows=5):
    """Problems with more than ``max(M_DIRECT, 2 P)`` measurements, so rows draw from prefix sums: runs of
    gated-out (+inf) measurements, ties, and rows whose cheapest measurement dominates."""
    P = draw(st.integers(1, max_rows))
    M = draw(st.integers(max(single_prepare.M_DIRECT, 2 * P) + 1, max(single_prepare.M_DIRECT, 2 * P) + 24))
    cost = st.one_of(st.floats(-4.0, 30.0, allow_nan=False), st.just(INF), st.just(INF),
                     st.sampled_from([0.0, 2.5]))
    D = np.array(draw(st.lists(cost, min_size=P * M, max_size=P * M)), float).reshape(P, M)
    miss = np.array(draw(st.lists(st.floats(-3, 30), min_size=P, max_size=P)), float)
    dead = np.array(draw(st.lists(st.one_of(st.floats(-3, 30), st.just(INF)), min_size=P,
                                  max_size=P)), float)
    return AssignmentProblem.from_cost(AssignmentProblem._assemble(D, miss, dead))


def feasible_starts(problem):
    cc = problem.compact_cost
    M = problem.n_meas
    out = ["lsap"]
    if np.isfinite(cc[:, M]).all():
        out.append("all_missed")
    if np.isfinite(cc[:, M + 1]).all():
        out.append("all_dead")
    return out


def assert_same(a, b):
    assert_array_equal(a.assignments, b.assignments)
    assert_array_equal(a.costs.view(np.uint64), b.costs.view(np.uint64))  # bit equality
    assert_array_equal(a.counts, b.counts)
    assert a.n_observations == b.n_observations
    assert a.n_row_updates == b.n_row_updates
    assert a.n_chains_run == b.n_chains_run
    assert a.stop_reason == b.stop_reason


def assert_valid(problem, res):
    """Invariants every result satisfies."""
    assert res.assignments.dtype == np.int64 and res.counts.dtype == np.int64
    assert res.assignments.shape == (len(res), problem.n_rows)
    assert problem.is_feasible(res.assignments).all()
    assert_array_equal(res.costs, problem.cost_of(res.assignments))
    assert len({tuple(r) for r in res.assignments.tolist()}) == len(res)
    assert int(res.counts.sum()) == res.n_observations
    assert (res.counts[1:] >= 1).all()  # every state but the start was observed
    assert res.n_row_updates == res.n_observations * problem.n_rows
    for arr in (res.assignments, res.costs, res.counts):
        assert not arr.flags.writeable


# ------------------------------------------------------------------------------ equivalence
@given(data=st.data())
def test_original_reference_equals_numba(data):
    problem = data.draw(problems(max_rows=3, max_meas=3))
    start = data.draw(st.sampled_from(feasible_starts(problem)))
    scan = data.draw(st.sampled_from(["systematic", "random"]))
    n_obs = data.draw(st.integers(0, 120))
    seed = data.draw(st.integers(0, 2**32))
    kw = dict(start=start, scan=scan, rng=seed)
    ref = reference.sample_original(problem, n_obs, **kw)
    nb = sample_original(problem, n_obs, **kw)
    assert_same(ref, nb)
    assert_valid(problem, nb)
    assert nb.n_chains_run == 1 and nb.stop_reason == "budget"
    assert_same(ref, sample_original(problem, n_obs, backend="python", **kw))
    # the original sampler is the short-chain sampler with one chain and no termination
    assert_same(nb, sample_short_chains(problem, 1, n_obs, **kw))


@given(data=st.data())
def test_short_chains_reference_equals_numba_and_parallel(data):
    problem = data.draw(problems(max_rows=3, max_meas=3))
    kw = dict(
        tau_stall=data.draw(st.one_of(st.none(), st.integers(1, 4))),
        tau_stale=data.draw(st.one_of(st.none(), st.integers(1, 6))),
        stall=data.draw(st.sampled_from(sorted(STALL_READINGS))),
        stale=data.draw(st.sampled_from(sorted(STALE_READINGS))),
        start=data.draw(st.sampled_from(feasible_starts(problem))),
        scan=data.draw(st.sampled_from(["systematic", "random"])),
        rng=data.draw(st.integers(0, 2**32)),
    )
    n_chains = data.draw(st.integers(0, 40))
    chain_length = data.draw(st.integers(0, 8))
    ref = reference.sample_short_chains(problem, n_chains, chain_length, **kw)
    assert ref.n_speculative_discarded == 0
    assert_valid(problem, ref)
    for workers in (1, 2, 4):
        nb = sample_short_chains(problem, n_chains, chain_length, workers=workers, **kw)
        assert_same(ref, nb)
        if workers == 1:
            assert nb.n_speculative_discarded == 0
    assert_same(ref, sample_short_chains(problem, n_chains, chain_length, backend="python",
                                         **kw))


@given(data=st.data())
def test_speculative_batches_of_any_size_replay_exactly(data):
    """The kernel's speculate-and-replay path equals the sequential path for every batch
    size (batches smaller than the run exercise the stale stop inside a later batch)."""
    problem = data.draw(problems(max_rows=2, max_meas=2))
    stall = data.draw(st.sampled_from(sorted(STALL_READINGS)))
    stale = data.draw(st.sampled_from(sorted(STALE_READINGS)))
    tau_stall = data.draw(st.integers(0, 3))
    tau_stale = data.draw(st.integers(0, 4))
    n_chains = data.draw(st.integers(1, 30))
    chain_length = data.draw(st.integers(0, 6))
    random_scan = data.draw(st.booleans())
    seed = data.draw(st.integers(0, 2**32))
    rules = Rules(STALL_READINGS[stall] if tau_stall else 0, tau_stall,
                  STALE_READINGS[stale] if tau_stale else 0, tau_stale)
    args = _driver_args(problem, "lsap", "random" if random_scan else "systematic", seed,
                        n_chains, chain_length, rules)
    u0, c0, k0 = _kernels.run_chains(*args, 0, 1)
    for batch, workers in ((1, 2), (2, 2), (3, 4), (7, 2), (7, 3), (64, 2)):
        u, c, k = _kernels.run_chains(*args, batch, workers)
        assert_array_equal(u, u0)
        assert_array_equal(c, c0)
        assert_array_equal(k[:6], k0[:6])
        # every simulated sweep was either used or discarded
        n_batches = -(-k[2] // batch) if k[2] else 0
        assert k[1] + k[6] <= n_batches * batch * chain_length
        assert k[6] >= 0


@given(data=st.data())
def test_prefix_sum_draws_reference_equals_numba_and_parallel(data):
    """Rows of wide problems draw from prefix sums: same bits in both implementations."""
    problem = data.draw(wide_problems())
    kw = dict(
        tau_stall=data.draw(st.one_of(st.none(), st.integers(1, 4))),
        tau_stale=data.draw(st.one_of(st.none(), st.integers(1, 6))),
        start=data.draw(st.sampled_from(feasible_starts(problem))),
        scan=data.draw(st.sampled_from(["systematic", "random"])),
        rng=data.draw(st.integers(0, 2**32)),
    )
    n_chains = data.draw(st.integers(1, 30))
    chain_length = data.draw(st.integers(1, 8))
    ref = reference.sample_short_chains(problem, n_chains, chain_length, **kw)
    nb = sample_short_chains(problem, n_chains, chain_length, **kw)
    assert_same(ref, nb)
    assert_valid(problem, nb)
    assert_same(ref, sample_short_chains(problem, n_chains, chain_length, workers=2, **kw))


@given(data=st.data())
def test_prefix_draw_equals_direct_draw(data):
    """The prefix-sum draw and the direct sum pick the same candidate for the same uniform,
    except where rounding puts ``target`` within a few ulps of a cumulative boundary (the two
    sums are associated differently once a held measurement lies before it)."""
    problem = data.draw(wide_problems(max_rows=1))
    prep = kinds.prepare(problem, "all_dead", "systematic", 0) \
        if np.isfinite(problem.compact_cost[0, -1]) else None
    if prep is None:
        return
    d = prep.ref_data
    M = d.M
    held = sorted(data.draw(st.sets(st.integers(0, M - 1), max_size=6)))
    owner = [-1] * M
    for k in held:
        owner[k] = 1  # held by "another row"
    for u in data.draw(st.lists(st.floats(0.0, 1.0, exclude_max=True), min_size=1,
                                max_size=20)) + [0.0, 0.5]:
        a = single_reference.draw_direct(d.W[0], d.cc[0], 0, owner, u)
        b = single_reference.draw_prefix(d.W[0], d.S[0], d.next_pos[0], d.cc[0], 0, owner, held, u)
        if a != b:  # only a rounding edge may separate them
            avail = [k for k in range(M + 2) if k >= M or owner[k] < 0]
            w = np.array([d.W[0][k] for k in avail])
            cum = np.cumsum(w)
            target = u * cum[-1]
            assert np.min(np.abs(cum - target)) <= 1e-12 * cum[-1], (a, b, u)
        assert d.W[0][b] > 0.0 and (b >= M or owner[b] < 0)


def test_cancellation_guard_draws_directly():
    """Row 0's dominant measurement is held by row 1 almost always; the rest of row 0's
    measurement weight is ~5e-10 of its total, so ``S[M] - held`` would cancel: the guard
    takes the direct sum. Both implementations agree and row 0 then draws every free
    measurement in proportion to its (tiny) weight."""
    M = single_prepare.M_DIRECT + 2
    D = np.full((2, M), 25.0)
    D[0, 0] = 0.0
    D[1, 0] = -30.0
    D[1, 1:] = INF
    p = AssignmentProblem.from_cost(AssignmentProblem._assemble(D, [25.0, 0.0], [INF, 0.0]))
    start = [M, 0]  # row 0 missed, row 1 on measurement 0
    ref = reference.sample_original(p, 300, rng=2, start=start)
    nb = sample_original(p, 300, rng=2, start=start)
    assert_same(ref, nb)
    held = nb.assignments[:, 1] == 0
    assert held.all()
    # with measurement 0 held, row 0's candidates 1..M-1 and missed are equally likely
    row0 = nb.assignments[held, 0]
    assert len(set(row0.tolist())) > 5 and (row0 != 0).all()


def test_parallel_discards_are_reported():
    from rankedassign.single import synthetic

    p = synthetic.diagonal()
    seq = sample_short_chains(p, 2000, 25, tau_stall=5, tau_stale=25, rng=11)
    par = sample_short_chains(p, 2000, 25, tau_stall=5, tau_stale=25, rng=11, workers=2)
    assert_same(seq, par)
    assert seq.n_speculative_discarded == 0
    # stall cuts chains short (the rest of each speculated chain is discarded) and the stale
    # stop discards the rest of its batch
    assert par.n_speculative_discarded > 0
    assert par.n_speculative_discarded % 1 == 0


# ------------------------------------------------------------------------------ underflow
def _underflow_problem():
    # Row 1 sits on measurement 0 (cost -2000); row 0's cheapest entry is that same
    # measurement (-800), every other entry of row 0 is > 745 above it, so all of row 0's
    # available shifted weights underflow to 0 and the exact fall-back draws row 0.
    C = np.array([
        [-800.0, 0.0, 0.0, INF, 1.0, INF],
        [-2000.0, 0.0, INF, 0.0, INF, 0.0],
    ])
    return AssignmentProblem.from_cost(C)


def test_underflow_fallback_reference_equals_numba():
    p = _underflow_problem()
    W = single_prepare.shifted_weights(p)
    assert W[0, 1] == 0.0 and W[0, 2] == 0.0 and W[0, 3] == 0.0  # underflowed
    start = np.array([2, 0])  # row 0 missed, row 1 on measurement 0
    for scan in ("systematic", "random"):
        ref = reference.sample_original(p, 500, start=start, scan=scan, rng=4)
        nb = sample_original(p, 500, start=start, scan=scan, rng=4)
        assert_same(ref, nb)
        assert_valid(p, nb)
        # row 1 never leaves measurement 0; row 0 visits its three available entries
        assert_array_equal(nb.assignments[:, 1], np.zeros(len(nb), dtype=np.int64))
        assert set(nb.assignments[:, 0].tolist()) == {1, 2, 4}
        par = sample_short_chains(p, 100, 5, start=start, scan=scan, rng=4, workers=2)
        assert_same(reference.sample_short_chains(p, 100, 5, start=start, scan=scan, rng=4), par)


def test_many_speculation_batches():
    # Hundreds of batches (batch = 1 and 3 chains): the batch-size ramp must saturate, not
    # overflow (regression: an unbounded doubling wrapped around after 63 batches).
    from rankedassign.single import synthetic

    p = synthetic.random(R=3, M=5, rng=2)
    args = _driver_args(p, "all_missed", "systematic", 6, 300, 4,
                        Rules(STALL_READINGS["global-consecutive"], 2, 0, 0))
    u0, c0, k0 = _kernels.run_chains(*args, 0, 1)
    for batch in (1, 3):
        u, c, k = _kernels.run_chains(*args, batch, 2)
        assert_array_equal(u, u0)
        assert_array_equal(c, c0)
        assert_array_equal(k[:6], k0[:6])
        assert k[2] == 300


# ------------------------------------------------------------------------------ the case table
@pytest.mark.parametrize("name", CASE_IDS)
def test_case_table_through_the_samplers(name):
    """Every hand-built hard case (degenerate shapes, all-forbidden rows, ties, a dominant
    assignment, huge cost ranges) through both samplers and both backends: identical results,
    valid states, and a long enough chain finds the best assignment the oracle ranks first."""
    problem = dict(zip(CASE_IDS, [p for _, p in CASES], strict=True))[name]
    for start in feasible_starts(problem):
        kw = dict(start=start, rng=7)
        ref = reference.sample_original(problem, 60, **kw)
        nb = sample_original(problem, 60, **kw)
        assert_same(ref, nb)
        assert_valid(problem, nb)
        sc = dict(tau_stall=3, tau_stale=5, **kw)
        assert_same(reference.sample_short_chains(problem, 40, 6, **sc),
                    sample_short_chains(problem, 40, 6, workers=2, **sc))
    long = sample_original(problem, 3000, start=feasible_starts(problem)[0], rng=1)
    best = oracle.enumerate_assignments(problem, limit=10**6).costs[0]
    assert long.costs.min() <= best + 1e-9 * max(1.0, abs(best))
