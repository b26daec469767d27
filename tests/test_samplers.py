"""Public sampler API: results, edge cases, stall/stale semantics, parameter validation."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from numpy.testing import assert_array_equal

from rankedassign import (
    AssignmentProblem,
    SamplerResult,
    kinds,
    reference,
    sample_original,
    sample_short_chains,
    samplers,
)
from rankedassign.engine import reference as engine_reference
from rankedassign.engine import result as _sampling
from rankedassign.engine import rng as _rng
from rankedassign.single import prepare as single_prepare
from rankedassign.single import reference as single_reference
from rankedassign.single import synthetic
from rankedassign.validation import STALE_READINGS, STALL_READINGS

INF = np.inf
PAPER = dict(tau_stall=5, tau_stale=25)  # paper's synthetic study: N_S = 10 000, N_C = 25


def small_problem():
    return AssignmentProblem.from_eta(
        [[2.0, 0.5, 0.1], [0.3, 3.0, 0.0]], [0.2, 0.3], [0.1, 0.4]
    )


def assert_same(a, b):
    assert_array_equal(a.assignments, b.assignments)
    assert_array_equal(a.costs.view(np.uint64), b.costs.view(np.uint64))
    assert_array_equal(a.counts, b.counts)
    assert (a.n_observations, a.n_row_updates, a.n_chains_run, a.stop_reason) == (
        b.n_observations, b.n_row_updates, b.n_chains_run, b.stop_reason)


# ------------------------------------------------------------------------------ result object
def test_result_is_frozen_readonly_and_has_len_and_repr():
    res = sample_original(small_problem(), 30, rng=0)
    assert isinstance(res, SamplerResult)
    assert len(res) == res.assignments.shape[0]
    with pytest.raises(AttributeError):
        res.n_observations = 3
    with pytest.raises(ValueError, match="read-only"):
        res.counts[0] = 7
    r = repr(res)
    assert r.startswith("SamplerResult(n_unique=") and "n_observations=30" in r


def test_same_rng_same_result_and_generator_is_consumed():
    p = synthetic.random(rng=3)
    assert_same(sample_original(p, 500, rng=9), sample_original(p, 500, rng=9))
    a = sample_original(p, 500, rng=9)
    b = sample_original(p, 500, rng=10)
    assert not np.array_equal(a.counts, b.counts) or len(a) != len(b)
    gen = np.random.default_rng(9)
    first = sample_original(p, 500, rng=gen)
    second = sample_original(p, 500, rng=gen)  # the generator advanced: a new stream
    assert_same(first, sample_original(p, 500, rng=np.random.default_rng(9)))
    assert not np.array_equal(first.counts, second.counts) or len(first) != len(second)
    # the seed goes through SeedSequence like any other default_rng input
    assert_same(sample_original(p, 50, rng=np.random.SeedSequence(4)),
                sample_original(p, 50, rng=4))


@pytest.mark.parametrize("family", ["diagonal", "uniform", "random"])
def test_paper_families_reference_equals_numba(family):
    p = {"diagonal": synthetic.diagonal(), "uniform": synthetic.uniform(),
         "random": synthetic.random(rng=17)}[family]
    for scan in ("systematic", "random"):
        assert_same(reference.sample_original(p, 300, scan=scan, rng=2),
                    sample_original(p, 300, scan=scan, rng=2))
        ref = reference.sample_short_chains(p, 60, 25, scan=scan, rng=2, **PAPER)
        for workers in (1, 2):
            assert_same(ref, sample_short_chains(p, 60, 25, scan=scan, rng=2, workers=workers,
                                                 **PAPER))


def test_large_problem_reference_equals_numba():
    p = synthetic.random(R=30, M=100, rng=5)
    assert_same(reference.sample_original(p, 40, rng=1), sample_original(p, 40, rng=1))
    ref = reference.sample_short_chains(p, 8, 5, tau_stall=2, rng=1, stall="chain-local")
    assert_same(ref, sample_short_chains(p, 8, 5, tau_stall=2, rng=1, stall="chain-local",
                                         workers=2))


# ------------------------------------------------------------------------------ prefix property
@given(n=st.integers(0, 300), seed=st.integers(0, 2**32),
       scan=st.sampled_from(["systematic", "random"]))
def test_original_shorter_run_is_a_prefix(n, seed, scan):
    p = synthetic.random(R=3, M=4, rng=1)
    short = sample_original(p, n, rng=seed, scan=scan)
    long = sample_original(p, 2 * n, rng=seed, scan=scan)
    k = len(short)
    # the unique list of n sweeps is a prefix of the unique list of 2n sweeps (same stream);
    # counts can only grow
    assert_array_equal(long.assignments[:k], short.assignments)
    assert_array_equal(long.costs[:k], short.costs)
    assert (long.counts[:k] >= short.counts).all()
    assert long.n_observations == 2 * short.n_observations


def test_short_chains_without_termination_prefix_in_chains():
    p = synthetic.random(rng=8)
    a = sample_short_chains(p, 50, 10, rng=3)
    b = sample_short_chains(p, 100, 10, rng=3, workers=2)
    assert_array_equal(b.assignments[: len(a)], a.assignments)
    assert (b.counts[: len(a)] >= a.counts).all()
    assert (a.n_chains_run, b.n_chains_run) == (50, 100)
    assert (a.n_observations, b.n_observations) == (500, 1000)


# ------------------------------------------------------------------------------ edge cases
def test_zero_budgets_return_only_the_start_state():
    p = small_problem()
    for res in (
        sample_original(p, 0, rng=1),
        sample_short_chains(p, 0, 25, rng=1),
        sample_short_chains(p, 10, 0, rng=1),
        sample_short_chains(p, 10, 0, rng=1, workers=2),
        reference.sample_short_chains(p, 10, 0, rng=1),
    ):
        assert_array_equal(res.assignments, p.all_missed()[None, :])
        assert_array_equal(res.counts, [0])
        assert res.n_observations == 0 and res.n_row_updates == 0
        assert_array_equal(res.costs, [p.cost_of(p.all_missed())])
    # a zero-length chain adds nothing, so the stale rule counts it
    for backend in ("numba", "python"):
        res = sample_short_chains(p, 10, 0, tau_stale=3, rng=1, backend=backend)
        assert (res.n_chains_run, res.stop_reason) == (3, "stale")
        res = sample_short_chains(p, 10, 0, tau_stale=3, stale="literal-multiset", rng=1,
                                  backend=backend)
        assert (res.n_chains_run, res.stop_reason) == (4, "stale")
        res = sample_short_chains(p, 10, 0, tau_stale=3, stale="literal-set", rng=1,
                                  backend=backend)
        assert (res.n_chains_run, res.stop_reason) == (10, "budget")
    # a billion empty chains return at once (they used to be looped over, for minutes)
    res = sample_short_chains(p, 10**9, 0, rng=1, workers=2)
    assert (res.n_chains_run, res.n_observations, res.stop_reason) == (10**9, 0, "budget")


def test_zero_length_closed_form_equals_the_loop():
    """The closed form for empty chains equals the generic driver run over them."""
    p = small_problem()
    prep = kinds.prepare(p, "all_missed", "systematic", 1)
    kind = kinds.kind_named("single")
    for stale in sorted(STALE_READINGS):
        for tau in (None, 1, 2, 5, 12):
            _, _, n_obs, chains, fired = engine_reference.run_chains(
                kind.sweep, kind.new_work, prep.ref_data, prep.x0.tolist(), prep.base, 10, 0,
                tau_stale=tau, stale=stale)
            assert (chains, fired) == _sampling.zero_length_run(10, tau, stale)
            assert n_obs == 0


def test_no_rows():
    p = AssignmentProblem.from_cost(np.zeros((0, 3)))
    for start in ("all_missed", "all_dead", "lsap"):
        res = sample_original(p, 7, rng=0, start=start)
        assert res.assignments.shape == (1, 0)
        assert_array_equal(res.counts, [7])
        assert_array_equal(res.costs, [0.0])
        assert res.n_row_updates == 0
    res = sample_short_chains(p, 5, 4, tau_stall=2, tau_stale=2, rng=0, workers=2)
    assert res.assignments.shape == (1, 0)
    # every chain stalls after 2 repeats and adds nothing: stale after 2 chains
    assert (res.n_observations, res.n_chains_run, res.stop_reason) == (4, 2, "stale")


def test_no_measurements():
    p = AssignmentProblem.from_eta(np.zeros((2, 0)), [0.5, 0.2], [0.5, 0.8])
    res = sample_original(p, 2000, rng=0)
    assert len(res) == 4  # each row missed or dead, independently
    assert p.is_feasible(res.assignments).all()
    # rows are independent here: P(row 1 dead) = 0.8 (binomial sd 0.009; 6 sd = 0.054)
    dead1 = res.counts[res.assignments[:, 1] == p.all_dead()[1]].sum() / 2000
    assert abs(dead1 - 0.8) < 0.054


def test_starts():
    p = small_problem()
    assert_array_equal(sample_original(p, 0, start="all_dead").assignments[0], p.all_dead())
    lsap = sample_original(p, 0, start="lsap").assignments[0]
    assert_array_equal(lsap, [0, 1])  # eta 2.0 * 3.0 is the best
    explicit = np.array([2, 0])
    res = sample_original(p, 5, start=explicit, rng=0)
    assert_array_equal(res.assignments[0], explicit)
    res = sample_short_chains(p, 5, 5, start=[2, 6], rng=0)
    assert_array_equal(res.assignments[0], [2, 6])


def test_start_counts_visits_back_to_it():
    # all-missed is overwhelmingly likely: the start state is revisited and counted
    p = AssignmentProblem.from_eta([[1e-6]], [1.0], [1e-6])
    res = sample_original(p, 50, rng=0)
    assert_array_equal(res.assignments, [[1]])
    assert_array_equal(res.counts, [50])


def test_random_scan_visits_rows_in_random_order():
    # With two rows competing for one measurement, the systematic scan lets row 0 choose
    # first every sweep; the random scan does not. Both target the same pi.
    p = AssignmentProblem.from_eta([[5.0], [5.0]], [1.0, 1.0], [0.0 + 1e-9, 1e-9])
    a = sample_original(p, 50, rng=1, scan="systematic")
    b = sample_original(p, 50, rng=1, scan="random")
    assert not (np.array_equal(a.assignments, b.assignments)
                and np.array_equal(a.counts, b.counts))


# ------------------------------------------------------------------------------ stall / stale
def constant_problem():
    """One row that can only be missed: every sweep returns the start state."""
    return AssignmentProblem.from_cost([[0.0, INF]])


@pytest.mark.parametrize("stall", ["global-consecutive", "global-cumulative", "chain-local"])
def test_stall_on_constant_chain(stall):
    p = constant_problem()
    res = sample_short_chains(p, 4, 10, tau_stall=3, stall=stall, rng=0)
    # every observation repeats x0: all three readings stop each chain after 3 observations
    assert (res.n_observations, res.n_chains_run, res.stop_reason) == (12, 4, "budget")
    assert_array_equal(res.counts, [12])
    res = sample_short_chains(p, 4, 10, tau_stall=3, tau_stale=2, stall=stall, rng=0)
    assert (res.n_observations, res.n_chains_run, res.stop_reason) == (6, 2, "stale")


def test_stale_readings_on_constant_chain():
    p = constant_problem()
    run = lambda stale, tau, **kw: sample_short_chains(  # noqa: E731
        p, 6, 4, tau_stale=tau, stale=stale, rng=0, **kw)
    # consecutive and cumulative agree when no chain ever contributes
    assert run("consecutive", 3).n_chains_run == 3
    assert run("cumulative", 3).n_chains_run == 3
    # the literal set reading |U| - n_u is always 0: never fires
    res = run("literal-set", 1)
    assert (res.n_chains_run, res.stop_reason) == (6, "budget")
    # multiset: after chain c, (c + 4c) - 1 duplicates -> 4 after chain 1, 9 after chain 2
    assert run("literal-multiset", 4).n_chains_run == 1
    assert run("literal-multiset", 5).n_chains_run == 2
    assert run("literal-multiset", 5).n_observations == 8


def test_tau_none_disables_rules():
    p = synthetic.diagonal()
    res = sample_short_chains(p, 200, 25, tau_stall=None, tau_stale=None, rng=0)
    assert (res.n_observations, res.n_chains_run, res.stop_reason) == (5000, 200, "budget")
    res = sample_short_chains(p, 200, 25, tau_stall=5, tau_stale=None, rng=0)
    assert res.stop_reason == "budget" and res.n_chains_run == 200
    assert res.n_observations < 5000  # stall cuts chains
    res = sample_short_chains(p, 200, 25, tau_stall=None, tau_stale=3, rng=0)
    assert res.n_observations == 25 * res.n_chains_run  # no chain cut short


def _expected_run(problem, n_chains, chain_length, tau_stall, tau_stale, stall, stale, seed):
    """Independent re-implementation of the stopping logic of spec §3.2 on trajectories
    generated chain by chain with the reference sweep (the same streams as the samplers).
    Each counter is recomputed from the whole history, not updated incrementally."""
    prep = kinds.prepare(problem, "all_missed", "systematic", seed)
    x0 = tuple(prep.x0.tolist())
    found = [x0]          # U in discovery order
    visits = {x0: 0}
    observations = []     # every observation, all chains, in order
    completed = []        # per completed chain: did it add something new to U?
    for c in range(n_chains):
        g = _rng.SplitMix64(_rng.chain_state(prep.base, c))
        x = list(x0)
        work = single_reference.new_work(prep.ref_data, x)
        traj = [x0]
        known = []        # known[t-1]: was observation t of this chain already in U?
        for j in range(1, chain_length + 1):
            single_reference.sweep(prep.ref_data, work, x, g)
            s = tuple(x)
            traj.append(s)
            observations.append(s)
            known.append(s in visits)
            if s not in visits:
                found.append(s)
                visits[s] = 0
            visits[s] += 1
            if tau_stall is None:
                continue
            if stall == "global-cumulative":
                value = sum(known)
            elif stall == "global-consecutive":  # length of the trailing run of repeats
                value = len(known) - (max(t for t, k in enumerate(known) if not k) + 1
                                      if not all(known) else 0)
            else:  # chain-local: repeats among x[0..j]
                value = (j + 1) - len(set(traj))
            if value >= tau_stall:
                break
        completed.append(not all(known))
        if tau_stale is None:
            continue
        if stale == "consecutive":
            value = len(completed) - (max(t for t, a in enumerate(completed) if a) + 1
                                      if any(completed) else 0)
        elif stale == "cumulative":
            value = completed.count(False)
        elif stale == "literal-set":
            value = len(set(found)) - len(found)
        else:  # every completed chain's x0 once, plus every observation
            multiset = [x0] * len(completed) + observations
            value = len(multiset) - len(set(multiset))
        if value >= tau_stale:
            return found, visits, len(observations), len(completed), "stale"
    return found, visits, len(observations), len(completed), "budget"


@pytest.mark.parametrize("stall", sorted(STALL_READINGS))
@pytest.mark.parametrize("stale", sorted(STALE_READINGS))
def test_stall_and_stale_match_their_definitions(stall, stale):
    # P = 2, M = 1 with a dominant assignment: repeats are frequent, both rules fire.
    p = AssignmentProblem.from_eta([[6.0], [2.0]], [1.0, 0.5], [0.3, 0.5])
    for seed in range(6):
        for tau_stall, tau_stale in ((2, 3), (3, 2), (1, 5), (None, 4), (4, None)):
            found, visits, n_obs, n_chains, reason = _expected_run(
                p, 40, 6, tau_stall, tau_stale, stall, stale, seed)
            for workers in (1, 2):
                res = sample_short_chains(p, 40, 6, tau_stall=tau_stall, tau_stale=tau_stale,
                                          stall=stall, stale=stale, rng=seed, workers=workers)
                compact = single_prepare.to_compact(p, res.assignments)
                assert [tuple(r) for r in compact.tolist()] == found
                assert_array_equal(res.counts, [visits[s] for s in found])
                assert (res.n_observations, res.n_chains_run, res.stop_reason) == (
                    n_obs, n_chains, reason)


def test_paper_diagonal_stops_by_stale():
    p = synthetic.diagonal()
    for seed in range(3):
        res = sample_short_chains(p, 10_000, 25, rng=seed, **PAPER)
        assert res.stop_reason == "stale"
        assert res.n_observations < 250_000 // 10
        # the dominant assignment gamma = (1, 2, 3, 4) is found
        assert [0, 1, 2, 3] in res.assignments.tolist()


@pytest.mark.heavy_python
def test_paper_uniform_never_stale():
    # pi is uniform on 76 848 assignments: with 10 000 x 25 = 250 000 sweeps nearly every
    # chain still finds something new, so the consecutive stale rule never fires (spec §3.5).
    # The global stall does fire once U holds most of Gamma; the chain-local stall never
    # does (a chain of 25 sweeps almost never revisits one of 76 848 states). The full paper
    # run takes well under a second with the kernels.
    p = synthetic.uniform()
    res = sample_short_chains(p, 10_000, 25, rng=0, workers=2, **PAPER)
    assert res.stop_reason == "budget"
    assert res.n_chains_run == 10_000
    assert 100_000 < res.n_observations < 250_000
    assert len(res) > 0.8 * p.n_feasible()
    local = sample_short_chains(p, 10_000, 25, rng=0, stall="chain-local", **PAPER)
    assert (local.stop_reason, local.n_observations) == ("budget", 250_000)


# ------------------------------------------------------------------------------ validation
ORIG, SHORT = "sample_original", "sample_short_chains"
BAD = [
    (ORIG, ("cost", 5), {}, TypeError,
     r"problem must be one of \(AssignmentProblem.*\), got ndarray"),
    (SHORT, (None, 5, 5), {}, TypeError, r"problem must be one of \(AssignmentProblem.*NoneType"),
    (ORIG, ("p", -1), {}, ValueError, "n_obs must be an int >= 0, got -1"),
    (ORIG, ("p", 2.5), {}, TypeError, "n_obs must be an int, got float 2.5"),
    (ORIG, ("p", True), {}, TypeError, "n_obs must be an int, got bool True"),
    (ORIG, ("p", 2**63), {}, ValueError, r"n_obs must be an int <= 4611686018427387904 \(2\*\*62\), got 9223372036854775808"),
    (ORIG, ("p", 2**64), {}, ValueError, r"n_obs must be an int <= .* got 18446744073709551616"),
    (ORIG, ("p", 5), dict(scan="sideways"), ValueError, "unknown scan 'sideways'"),
    (ORIG, ("p", 5), dict(start="best"), ValueError, "unknown start 'best'"),
    (ORIG, ("p", 5), dict(start=[0, 0]), ValueError, r"start assignment \[0, 0\] is infeasible"),
    (ORIG, ("p", 5), dict(start=[0, 99]), ValueError, "is infeasible"),
    (ORIG, ("p", 5), dict(start=[0]), ValueError, r"shape \(P,\) = \(2,\), got \(1,\)"),
    (ORIG, ("p", 5), dict(start=[0.0, 1.0]), TypeError, "or an integer array of column"),
    (ORIG, ("p", 5), dict(method="exact"), TypeError,
     r"unexpected option\(s\) \['method'\] for an AssignmentProblem"),
    (SHORT, ("p", -3, 5), {}, ValueError, "n_chains must be an int >= 0, got -3"),
    (SHORT, ("p", 3, -5), {}, ValueError, "chain_length must be an int >= 0, got -5"),
    (SHORT, ("p", 3.0, 5), {}, TypeError, "n_chains must be an int, got float 3.0"),
    (SHORT, ("p", 3, 10**30), {}, ValueError, "chain_length must be an int <= "),
    (SHORT, ("p", 3, 5), dict(tau_stall=0), ValueError,
     r"tau_stall must be None \(off\) or an int >= 1, got 0"),
    (SHORT, ("p", 3, 5), dict(tau_stale=-2), ValueError,
     r"tau_stale must be None \(off\) or an int >= 1, got -2"),
    (SHORT, ("p", 3, 5), dict(tau_stale=1.5), TypeError, "tau_stale must be None or an int, got float"),
    (SHORT, ("p", 3, 5), dict(tau_stall=10**30), ValueError, "tau_stall must be an int <= "),
    (SHORT, ("p", 3, 5), dict(stall="local"), ValueError, "unknown stall reading 'local'"),
    (SHORT, ("p", 3, 5), dict(stale="set"), ValueError, "unknown stale reading 'set'"),
    (SHORT, ("p", 3, 5), dict(workers=0), ValueError, "workers must be an int >= 1, got 0"),
    (SHORT, ("p", 3, 5), dict(workers=2.0), TypeError, "workers must be an int, got float"),
    (SHORT, ("p", 3, 5), dict(scan=None), ValueError, "unknown scan None"),
]


@pytest.mark.parametrize("backend", ["numba", "python"])
@pytest.mark.parametrize("name, args, kwargs, exc, match", BAD)
def test_bad_parameters(name, args, kwargs, exc, match, backend):
    p = small_problem()
    args = tuple({"p": p, "cost": p.cost}.get(a, a) if isinstance(a, str) else a for a in args)
    with pytest.raises(exc, match=match):
        getattr(samplers, name)(*args, backend=backend, **kwargs)


@pytest.mark.parametrize("name, args", [(ORIG, (5,)), (SHORT, (3, 5))])
def test_unknown_backend(name, args):
    with pytest.raises(ValueError, match=r"unknown backend 'cuda'; expected one of \('numba', "
                                         r"'python'\)"):
        getattr(samplers, name)(small_problem(), *args, backend="cuda")


def test_infeasible_all_missed_and_all_dead_name_the_rows():
    p = AssignmentProblem.from_eta([[1.0], [1.0], [1.0]], [0.5, 0.0, 0.0], [0.5, 0.5, 0.0])
    with pytest.raises(ValueError, match=r"start='all_missed' is infeasible: rows \[1, 2\].*"
                                         r"start='all_dead' or start='lsap'"):
        sample_original(p, 3)
    with pytest.raises(ValueError, match=r"start='all_dead' is infeasible: rows \[2\]"):
        sample_short_chains(p, 3, 3, start="all_dead", backend="python")
    res = sample_original(p, 20, start="lsap", rng=0)
    assert p.is_feasible(res.assignments).all()


def test_memory_does_not_grow_with_chain_length():
    """A run of a few thousand sweeps allocates nothing in proportion to ``chain_length``
    (regression: a histogram of chain lengths took 8 GB for chain_length = 10**9, and
    10**10 raised MemoryError). The peak resident size of the process is checked, with a
    margin of 200 MB for compilation and the interpreter."""
    import resource

    p = synthetic.random(rng=0)
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss  # KiB on Linux
    for workers in (1, 2):
        res = sample_short_chains(p, 100, 10**10, tau_stall=5, rng=0, workers=workers)
        assert res.n_chains_run == 100 and res.n_observations < 10_000
    grown_mib = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) / 1024
    assert grown_mib < 200, f"peak memory grew by {grown_mib:.0f} MiB"
