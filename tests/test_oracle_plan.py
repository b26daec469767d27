"""The compiled planning of the frontier DP against its pure-Python specification.

:mod:`oracle.single.dp` plans with :mod:`oracle._kernels.plan`; :mod:`oracle.single._plan_reference`
(NumPy and SciPy: connected components, reverse Cuthill–McKee, breadth-first distances) is the
specification. The plan decides the order of every floating-point sum of the DP, so the two must
agree element for element, not approximately: same components, same candidate chosen, same
width and operation count, same operations.
"""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from numpy.testing import assert_array_equal
from test_oracle_sparse import banded, gated, permuted

from oracle.single import _plan_reference as ref
from oracle.single import dp


def assert_same_plan(finite):
    """Components, and for every component the order, width, work and operations."""
    comps, isolated = dp._components(finite)
    want, want_iso = ref._components(finite)
    assert_array_equal(isolated, want_iso)
    assert len(comps) == len(want)
    for (rows, meas), (w_rows, w_meas) in zip(comps, want, strict=True):
        assert_array_equal(rows, w_rows)
        assert_array_equal(meas, w_meas)
        sub = finite[np.ix_(rows, meas)]
        order, width, work = dp._frontier_order(sub)
        w_order, w_width, w_work = ref._frontier_order(sub)
        assert_array_equal(order, w_order)
        assert (width, work) == (w_width, w_work)
        if width <= 12:
            ops, row_in_slot = dp._frontier_ops(sub, order, width)
            w_ops, w_row_in_slot = ref._frontier_ops(sub, w_order, w_width)
            assert_array_equal(ops, w_ops)
            assert_array_equal(row_in_slot, w_row_in_slot)


@st.composite
def gate_matrices(draw, max_rows=12, max_meas=16):
    """Random gate matrices of a drawn density: several components, isolated rows and
    measurements, many equal degrees (the ties every order must break the same way)."""
    P = draw(st.integers(1, max_rows))
    K = draw(st.integers(1, max_meas))
    density = draw(st.floats(0.05, 0.6))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    return rng.random((P, K)) < density


@given(gate_matrices())
def test_property_plan_equals_the_reference(finite):
    assert_same_plan(finite)


@given(gate_matrices(max_rows=8, max_meas=10))
def test_property_order_of_a_disconnected_graph(finite):
    # _frontier_order is also defined on a graph of several components (Cuthill–McKee then
    # starts again from the next node by degree); every row and measurement is kept
    finite = finite[finite.any(axis=1)][:, finite[finite.any(axis=1)].any(axis=0)]
    if finite.size == 0:
        return
    order, width, work = dp._frontier_order(finite)
    w_order, w_width, w_work = ref._frontier_order(finite)
    assert_array_equal(order, w_order)
    assert (width, work) == (w_width, w_work)


@pytest.mark.parametrize("seed", range(4))
def test_tracking_like_and_banded_problems(seed):
    rng = np.random.default_rng(seed)
    p = gated(rng)
    assert_same_plan(np.isfinite(p.compact_cost[:, :p.n_meas]))
    q = banded(20, 50, 4, rng)
    q = permuted(q, rng.permutation(20), rng.permutation(50))
    assert_same_plan(np.isfinite(q.compact_cost[:, :50]))


def test_regular_graph_all_degrees_tied():
    # every row gates 3 measurements, every measurement 3 rows: the start of reverse
    # Cuthill–McKee is decided by NumPy's argsort among equal degrees alone
    P = 24
    finite = np.zeros((P, P), dtype=bool)
    for i in range(P):
        finite[i, [i, (i + 5) % P, (i + 11) % P]] = True
    assert_same_plan(finite)


def test_huge_work_is_summed_as_numpy_sums_it():
    # 60 rows active at every step: each step costs (3 + 60) 2^60, beyond 2^53, where a sum
    # in step order and NumPy's pairwise sum may differ; the NumPy value is kept
    finite = np.ones((60, 9), dtype=bool)
    finite[0, 0] = False
    order, width, work = dp._frontier_order(finite)
    w_order, w_width, w_work = ref._frontier_order(finite)
    assert_array_equal(order, w_order)
    assert (width, work) == (w_width, w_work)
    assert dp._profile(finite, order) == ref._profile(finite, order)
