"""Seeding and executors of rankedassign.experiments (no sampler needed)."""

import operator

import numpy as np
import pytest
from numpy.testing import assert_array_equal

from rankedassign.experiments import (
    SchedulerError,
    child_seed,
    dask_executor,
    local_executor,
    run_seed,
    run_tasks,
)


@pytest.mark.parametrize("seed", [0, 1, 12345])
def test_run_seed_is_spawn_by_index(seed):
    children = np.random.SeedSequence(seed).spawn(6)
    for r, ss in enumerate(children):
        assert_array_equal(run_seed(seed, r).generate_state(4), ss.generate_state(4))


def test_child_seed_is_spawn_and_order_free():
    parent = run_seed(3, 2)
    kids = run_seed(3, 2).spawn(4)
    # Request in reverse order: the names, not the order, decide the streams.
    for k in (3, 1, 0, 2):
        assert_array_equal(child_seed(parent, k).generate_state(3), kids[k].generate_state(3))
    nested = child_seed(parent, 1, 2).generate_state(2)
    assert_array_equal(nested, kids[1].spawn(3)[2].generate_state(2))
    assert not np.array_equal(child_seed(parent, 0).generate_state(2),
                              child_seed(parent, 1).generate_state(2))


def test_run_tasks_serial_keeps_order():
    assert run_tasks(operator.sub, [(5, 1), (1, 5), (0, 0)], progress=False) == [4, -4, 0]
    assert run_tasks(operator.add, [], progress=False) == []


def test_run_tasks_process_pool_matches_serial():
    tasks = [(i, 10 * i) for i in range(7)]
    serial = run_tasks(operator.add, tasks, progress=False)
    with local_executor(2) as ex:
        assert ex is not None
        assert run_tasks(operator.add, tasks, executor=ex, progress=False) == serial


def test_run_tasks_propagates_errors():
    with pytest.raises(ZeroDivisionError):
        run_tasks(operator.truediv, [(1, 1), (1, 0)], progress=False)


def test_local_executor_serial_and_bad_workers():
    with local_executor(1) as ex:
        assert ex is None
    with pytest.raises(ValueError, match="workers must be a positive integer, got 0"):
        with local_executor(0):
            pass


def test_dask_unreachable_scheduler():
    with pytest.raises(SchedulerError, match="could not connect to the Dask scheduler"):
        with dask_executor("tcp://127.0.0.1:9", timeout=1.0):
            pass
