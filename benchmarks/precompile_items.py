"""Time every item of ``rankedassign precompile``'s queue: wall and CPU per item, and the queue
replayed on two idle workers with each item taking its CPU time.

Run it from the checkout with an empty numba cache (the figures in ``benchmarks/README.md``,
"Precompile balance")::

    NUMBA_CACHE_DIR=$(mktemp -d) PYTHONPATH=.:benchmarks python -c \
        "import precompile_items; precompile_items.main()"

(imported, not run as a script, so that the pool's spawned workers find :func:`timed`). On a
loaded machine the wall times say little about the balance (each worker gets a fraction of a
core); the CPU per item, and the two-worker replay made from it, do.
"""

import os
import time


def timed(study, args, unit=False):
    """Run one queue item in a worker; its label, start and end (wall), pid and CPU."""
    from rankedassign.experiments.precompile import _label, _task

    t0, c0 = time.time(), time.process_time()
    _task(study, args, unit)
    return _label(study), _describe(args), t0, time.time(), os.getpid(), \
        time.process_time() - c0


def _describe(args):
    if args and callable(args[0]):
        return "unit " + args[0].__name__ + str(
            tuple(a for a in args[1:] if isinstance(a, (str, int, tuple))))
    return str(tuple(a for a in args if isinstance(a, (str, int))))


def main(workers=2):
    """Run the queue on ``workers`` processes, each item once the items it waits for have
    finished (as ``precompile`` does); print one line per item and the totals."""
    from rankedassign.experiments import precompile as pc
    from rankedassign.experiments._executor import local_executor, run_tasks
    from rankedassign.experiments.registry import Config, study_names

    queue, after = pc._queue(study_names(), Config.quick())
    start = time.time()
    with local_executor(workers) as ex:
        results = run_tasks(timed, queue, executor=ex, progress=False, after=after)
    wall = time.time() - start
    rows = [(t0 - start, t1 - start, label, what, pid, cpu)
            for label, what, t0, t1, pid, cpu in results]
    for t0, t1, label, what, pid, cpu in sorted(rows):
        print(f"{t0:7.1f} {t1:7.1f} {t1 - t0:7.1f} cpu {cpu:6.1f}  {pid}  {label:18s} {what}")
    # the queue replayed: each item, once what it waits for has ended, on the first free worker
    free, end = [0.0] * workers, [0.0] * len(queue)
    for i, row in enumerate(rows):
        w = free.index(min(free))
        waits = after[i] if isinstance(after[i], tuple) else () if after[i] is None else (after[i],)
        begin = max([free[w], *(end[j] for j in waits)])
        end[i] = free[w] = begin + row[-1]
    print(f"wall {wall:.1f} s; CPU of the items {sum(r[-1] for r in rows):.1f} s; "
          f"replayed on {workers} idle workers {max(end):.1f} s")
