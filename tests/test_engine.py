"""The chain driver of :mod:`rankedassign.engine._kernels` with named kernel records.

A kind hands the driver named tuples (its ``data`` and its workspace record); the parallel
speculation must keep every write its sweep makes through them. numba's parfor pass drops a
write to an array read from an attribute of a named tuple inside a ``prange`` body (the body's
copy of the record is rebuilt by calling the record's class, which its alias analysis does
not link to the loop's arguments, so the write looks dead; numba issue #7135). The driver
therefore calls one compiled function per chain from its ``prange`` loop; these tests keep
the reproducer and the driver's behaviour.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pytest
from numba import config, prange
from numpy.testing import assert_array_equal

from rankedassign.engine._kernels import Rules, make_driver, next_uniform
from rankedassign.numba_options import CACHE, jit


class _Work(NamedTuple):
    count: np.ndarray
    other: np.ndarray


class _Data(NamedTuple):
    p: float


@jit(cache=False, inline="always")
def _bump(work, b):
    work.count[b, 0] += 1


@jit(cache=False, parallel=True)
def _bump_in_prange(work, n):
    for b in prange(n):
        _bump(work, b)


@jit(cache=False)
def _bump_called(work, b):
    work.count[b, 0] += 1


@jit(cache=False, parallel=True)
def _bump_by_call_in_prange(work, n):
    for b in prange(n):
        _bump_called(work, b)


def _work(nb):
    return _Work(count=np.zeros((nb, 1), dtype=np.int64), other=np.zeros((nb, 1)))


@pytest.mark.skipif(config.DISABLE_JIT, reason="numba's parfor pass only")
@pytest.mark.xfail(strict=True, reason="numba #7135: a write through a named tuple's "
                   "attribute in a prange body is dropped (numba 0.68.1, measured: counts "
                   "[0, 0, 0, 0], expected [1, 1, 1, 1]); an XPASS means numba fixed it and the "
                   "driver's per-chain call (engine._kernels._speculate) may go")
def test_numba_keeps_a_write_through_a_named_tuple_attribute_in_a_prange_body():
    work = _work(4)
    _bump_in_prange(work, 4)
    assert work.count[:, 0].tolist() == [1, 1, 1, 1]


def test_a_function_called_from_the_prange_body_keeps_its_writes():
    """The driver's workaround (:func:`rankedassign.engine._kernels._speculate`)."""
    work = _work(4)
    _bump_by_call_in_prange(work, 4)
    assert work.count[:, 0].tolist() == [1, 1, 1, 1]


# A toy kind whose sweep depends on a counter kept in its workspace record: the state is the
# counter's parity, flipped only when a uniform says so. A speculation that lost the
# workspace writes would give other states than the sequential run.
@jit(cache=False)
def _alloc(data, nb):
    return _Work(count=np.zeros((nb, 1), dtype=np.int64), other=np.zeros((nb, 1)))


@jit(cache=False)
def _reset(data, work, b, x0):
    work.count[b, 0] = x0[0]


@jit(cache=False, inline="always")
def _sweep(data, work, b, zkeys, state, h, rs):
    if next_uniform(rs) < data.p:
        work.count[b, 0] += 1
    new = work.count[b, 0] % 2
    if new != state[0]:
        h ^= zkeys[0, state[0]] ^ zkeys[0, new]
        state[0] = new
    return h


_RUN = make_driver("engine_test_counter", _alloc, _reset, _sweep, work=_Work, cache=False)


@pytest.mark.skipif(config.DISABLE_JIT, reason="compiled signatures only")
def test_a_sequential_run_compiles_no_speculation():
    """A run without speculation (``batch == 0``, one worker: the filters' case) has a slice
    of its own that never calls the parallel loop, so its first call compiles neither the loop
    nor the second copy of the kind's sweep (:func:`_speculate_chain`); a speculative run
    afterwards compiles them and gives the same bits. A run that never fills its unique
    set compiles no growth either (``U`` grows between slices, from Python; the runs that
    grow it are in ``tests/test_interrupt.py``)."""
    # The module's driver while nothing has compiled any of it, which the file's order (this
    # test before the others that run it) makes the usual case; a driver of its own otherwise
    # (its whole compile again, 11 s of CPU).
    run = _RUN
    if any(kernel.signatures for kernel in _RUN.kernels.values()):
        run = make_driver("engine_test_sequential", _alloc, _reset, _sweep, work=_Work,
                          cache=False)
    zkeys = np.array([[1, 2]], dtype=np.uint64)
    args = (_Data(p=0.5), zkeys, np.zeros(1, np.int32), np.uint64(7), 40, 5, Rules(0, 0, 0, 0))
    seq = run(*args, 0, 1)
    k = run.kernels
    assert len(k["new_run"].signatures) == 1
    assert len(k["run_slice_sequential"].signatures) == 1
    assert len(k["advance"].signatures) == 1
    for name in ("run_slice", "speculate", "speculate_chain", "grow_run"):
        assert not k[name].signatures, name
    par = run(*args, 4, 2)
    assert len(k["speculate_chain"].signatures) == 1
    assert_array_equal(par[0], seq[0])
    assert_array_equal(par[1], seq[1])
    assert_array_equal(par[2][:6], seq[2][:6])  # (the last counter: sweeps speculated in vain)


@pytest.mark.parametrize("budget", [3, 1 << 16])
def test_speculation_keeps_the_writes_of_a_kind_with_named_records(budget):
    zkeys = np.array([[1, 2]], dtype=np.uint64)
    args = (_Data(p=0.5), zkeys, np.zeros(1, np.int32), np.uint64(7), 200, 5,
            Rules(0, 0, 0, 0))
    states, counts, ctr = _RUN(*args, 0, 1, budget=budget)
    assert states.shape == (2, 1) and int(counts.sum()) == 1000
    for batch, workers in ((2, 2), (7, 2), (64, 3)):
        s, c, k = _RUN(*args, batch, workers, budget=budget)
        assert_array_equal(s, states)
        assert_array_equal(c, counts)
        assert_array_equal(k[:6], ctr[:6])  # (the last counter: sweeps speculated in vain)


@pytest.mark.skipif(config.DISABLE_JIT, reason="compiled signatures only")
def test_the_parallel_speculation_compiles_the_chain_once():
    """numba's parallel lowering types the ``prange`` index as ``uint64`` where the loop's
    typing saw ``int64``; the driver passes an ``int64`` so that the chain's function, with the
    kind's whole sweep written into it, is compiled once and not twice (a first run of the
    multi-sensor herded sampler compiled 137 s of CPU without it, 105 s with it)."""
    # The module's driver, not a new one: a driver of its own compiled the toy kind's whole
    # driver a second time in every test run (9 s of CPU). Every call of _RUN in this module
    # passes the same argument types, sequential and parallel, so one signature each is the
    # claim whichever of its tests ran before.
    zkeys = np.array([[1, 2]], dtype=np.uint64)
    _RUN(_Data(p=0.5), zkeys, np.zeros(1, np.int32), np.uint64(7), 20, 5, Rules(0, 0, 0, 0),
         4, 2)
    chain = _RUN.kernels["speculate_chain"]
    assert len(chain.signatures) == 1, chain.signatures
    assert len(_RUN.kernels["advance"].signatures) == 1


@pytest.mark.skipif(config.DISABLE_JIT or not CACHE, reason="numba's on-disk cache only")
def test_a_kind_defined_elsewhere_leaves_the_cache_of_the_engine_alone(tmp_path):
    """Every engine function compiled for a kind's records is compiled for that kind, with its
    cache setting: the toy kind above (its records live in this test module, cache off) must
    not enter a cached index of the engine, which a process that cannot import this module
    then fails to read (``ModuleNotFoundError: No module named 'test_engine'``)."""
    test_speculation_keeps_the_writes_of_a_kind_with_named_records(3)
    root = Path(__file__).resolve().parents[1]
    code = ("from rankedassign import sample_original, sample_short_chains, synthetic\n"
            "p = synthetic.random(rng=0)\n"
            "sample_original(p, 3, rng=0)\n"
            "sample_short_chains(p, 3, 2, tau_stall=1, rng=0, workers=2)\n")
    subprocess.run([sys.executable, "-c", code], cwd=tmp_path, check=True,
                   env={**os.environ, "PYTHONPATH": str(root)})


def test_the_records_that_extend_others_keep_their_fields_in_order():
    """A herded or tempered record is the Gibbs record's fields followed by its own (one flat
    record, built by concatenating keyword-built records): the orders must agree."""
    from rankedassign.adaptive_birth import _kernels as ab_kernels
    from rankedassign.adaptive_birth import _tempered_kernels as ab_tempered
    from rankedassign.adaptive_birth import prepare as ab_prepare
    from rankedassign.adaptive_birth.reference import RefData
    from rankedassign.engine._kernels import KeyTable
    from rankedassign.multisensor import _kernels as ms_kernels
    from rankedassign.multisensor import prepare as ms_prepare
    from rankedassign.single import _kernels as single_kernels
    from rankedassign.single import prepare as single_prepare

    table = KeyTable._fields
    assert single_kernels.HerdedWork._fields == (
        single_kernels.DirectWork._fields + ("cum",) + table)
    assert ms_kernels.MultiSensorHerdedWork._fields == (
        ms_kernels.MultiSensorWork._fields + ("cand",) + table)
    assert ab_kernels.AdaptiveBirthHerdedWork._fields == (
        ab_kernels.AdaptiveBirthWork._fields + table)
    gibbs = ms_prepare.MultiSensorData._fields
    assert ms_prepare.MultiSensorHerdedData._fields[:len(gibbs)] == gibbs
    gibbs = ab_prepare.AdaptiveBirthData._fields
    assert RefData._fields == gibbs
    assert ab_prepare.AdaptiveBirthHerdedData._fields[:len(gibbs)] == gibbs
    assert ab_tempered.AdaptiveBirthTemperedData._fields == gibbs + ("beta",)
    direct = single_prepare.DirectData._fields
    assert set(direct) <= set(single_prepare.PrefixData._fields)
    assert set(direct) <= set(single_prepare.HerdedData._fields)


def test_a_record_names_each_field_once():
    from rankedassign.engine.records import HerdedDraw, record

    with pytest.raises(ValueError, match="a record's parts name these fields twice: tally"):
        record(HerdedDraw, {"tally": np.ndarray})

    class X(record(HerdedDraw, {"beta": float})):
        """X."""

    assert X._fields == HerdedDraw._fields + ("beta",) and X.__doc__ == "X."
    assert repr(X(*range(6))).startswith("X(key_mode=0")


@pytest.mark.skipif(config.DISABLE_JIT, reason="compiled records only")
def test_numba_builds_and_reads_a_record_that_extends_another():
    from rankedassign.engine.records import record

    class X(record(_Data, {"q": float})):
        """X."""

    @jit(cache=False)
    def make_and_read(x):
        return X(p=x.p + 1.0, q=x.q * 2.0).q + x.p

    assert make_and_read(X(p=1.0, q=3.0)) == 7.0


@pytest.mark.parametrize("rules", [Rules(0, 0, 0, 0), Rules(1, 3, 1, 4), Rules(2, 5, 2, 3),
                                   Rules(3, 4, 4, 30), Rules(1, 2, 3, 2)])
def test_the_one_call_run_of_a_problem_is_the_sequential_driver(rules):
    """make_problem_runner's run (the δ-GLMB components') is run_chains with batch = 0, for
    every reading of the stall and stale rules."""
    from rankedassign.engine._kernels import problem_scratch, problem_states, zobrist_keys
    from rankedassign.single import synthetic
    from rankedassign.single._kernels import alloc_work, run_chains
    from rankedassign.single.prepare import DirectData, PrefixData, shifted_weights
    from rankedassign.tracking.single._glmb_kernels import _run_direct

    problem = synthetic.uniform(5, 1, 6)
    # The arrays' flags as the samplers pass them (a writable copy of the read-only compact
    # costs, read-only Zobrist keys): the kernels' signatures are then the ones the precompile
    # compiled, and this test loads them from the cache instead of compiling both drivers
    # again (12 s of CPU).
    cc = np.array(problem.compact_cost, dtype=np.float64, order="C")
    W = shifted_weights(problem)
    P, M = cc.shape[0], cc.shape[1] - 2
    x0 = np.where(np.isfinite(cc[:, M]), M, M + 1).astype(np.int32)
    zkeys = zobrist_keys(P, M + 2, np.uint64(3))
    zkeys.setflags(write=False)
    base = np.uint64(17)
    states, counts, ctr = run_chains(DirectData(W, cc, False), zkeys, x0, base, 40, 9, rules,
                                     0, 1)
    data = PrefixData(W, cc, np.zeros((P, 1)), np.zeros((P, 1), dtype=np.int64), False)
    scratch = problem_scratch(P, 40 * 9 + 1)
    n, n_obs = _run_direct(data, alloc_work(data, 1), zkeys, x0, base, 40, 9, rules, scratch)
    assert_array_equal(problem_states(scratch, P, n), states)
    assert_array_equal(scratch.counts[:n], counts)
    assert_array_equal(scratch.ctr, ctr)
    assert n_obs == counts.sum()


def test_a_problem_scratch_too_small_is_refused():
    from rankedassign.engine._kernels import _carve, problem_scratch

    with pytest.raises(ValueError, match="problem_scratch: the scratch is smaller than the "
                                         "problem"):
        _carve(problem_scratch(2, 4), 3, 4)


def test_every_open_addressing_table_walks_the_one_probe_sequence():
    """The unique set, the herded draw's key table and the tempered loop's unique set (and its
    rehash) all probe through ``engine._kernels.probe``: keys whose hashes share the home
    entry 6 of an 8-entry index land on 6, 7, then wrap to 0, 1; a hit is confirmed on the
    whole key (and on the row id in the key table)."""
    from rankedassign.engine._kernels import add_state, table_find, unique_set
    from rankedassign.engine._tempered_kernels import rehash, visit

    h = np.uint64(6 + 8 * 12345)  # home entry 6 of 8
    keys = [np.array([n], dtype=np.int32) for n in range(4)]
    by_entry = [3, 4, 0, 0, 0, 0, 1, 2]  # index + 1 of the key at each entry

    U = unique_set(1, 4)  # an index of 2 * 4 entries
    assert [add_state(U, k, h, n) for n, k in enumerate(keys)] == [(n, True) for n in range(4)]
    assert U.table[:, 1].tolist() == by_entry
    assert add_state(U, keys[2].copy(), h, 4) == (2, False)

    states, hashes = np.empty((4, 1), np.int32), np.empty(4, np.uint64)
    counts, table = np.zeros(4, np.int64), np.zeros(8, np.int64)
    n_u = 0
    for k in keys:
        n_u = visit(states, hashes, counts, table, k, h, n_u)
    assert table.tolist() == by_entry
    assert visit(states, hashes, counts, table, keys[1].copy(), h, n_u) == 4
    assert counts.tolist() == [1, 2, 1, 1]
    fresh = np.zeros(8, np.int64)
    rehash(hashes, n_u, fresh)
    assert fresh.tolist() == by_entry

    krow, kst = np.empty(4, np.int32), np.empty((4, 1), np.int32)
    tslot, thash = np.zeros(8, np.int64), np.zeros(8, np.uint64)
    for n, k in enumerate(keys):
        e = -1 - table_find(0, k, h, krow, kst, tslot, thash)
        tslot[e], thash[e], krow[n], kst[n] = n + 1, h, 0, k
    assert tslot.tolist() == by_entry
    assert table_find(0, keys[2].copy(), h, krow, kst, tslot, thash) == 2
    assert table_find(1, keys[2], h, krow, kst, tslot, thash) == -1 - 2  # another row: absent
