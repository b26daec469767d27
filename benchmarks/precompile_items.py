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
    """Run the queue on ``workers`` processes; print one line per item and the totals."""
    from concurrent.futures import as_completed

    from rankedassign.experiments import precompile as pc
    from rankedassign.experiments._executor import local_executor
    from rankedassign.experiments.registry import Config, study_names

    queue = pc._queue(study_names(), Config.quick())
    start = time.time()
    rows, cpus = [], [0.0] * len(queue)
    with local_executor(workers) as ex:
        futures = [ex.submit(timed, *item) for item in queue]
        for fut in as_completed(futures):
            label, what, t0, t1, pid, cpu = fut.result()
            rows.append((t0 - start, t1 - start, label, what, pid, cpu))
            cpus[futures.index(fut)] = cpu
    wall = time.time() - start
    for t0, t1, label, what, pid, cpu in sorted(rows):
        print(f"{t0:7.1f} {t1:7.1f} {t1 - t0:7.1f} cpu {cpu:6.1f}  {pid}  {label:18s} {what}")
    free = [0.0] * workers  # the queue in order, each item on the first free worker
    for cpu in cpus:
        free[free.index(min(free))] += cpu
    print(f"wall {wall:.1f} s; CPU of the items {sum(cpus):.1f} s; "
          f"replayed on {workers} idle workers {max(free):.1f} s")


if __name__ == "__main__":
    main()
