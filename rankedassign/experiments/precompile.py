"""Compile every kernel the studies and the samplers use, on every core, into numba's cache.

numba compiles a kernel the first time it is called with a new signature, one kernel after
another in one thread, and keeps the result in its on-disk cache
(:mod:`rankedassign.numba_options`). On a fresh installation that is minutes of waiting spread
over the first calls. :func:`precompile` does it up front and side by side: the tiny tasks of
every registered study (:attr:`~rankedassign.experiments.Study.warm`) and the samplers'
:func:`~rankedassign.warmup` become one queue of tasks on a pool of worker processes, the first
task of each study's kernel group first and the largest study's first of all, so that the
workers compile disjoint sets of kernels at once. A study whose one tiny task compiles much
(the tempering study's, every sampler of a problem kind) cuts its kernels finer
(:attr:`~rankedassign.experiments.Study.warm_units`, one sampler on one kind): those units go
out before every tiny task, longest first, and the study's tiny tasks last. Later processes
(the studies of ``rankedassign reproduce``, the test suite, a notebook) load the kernels from
the cache.

``rankedassign precompile`` runs it from the command line; CI runs it before its test tiers.
"""

from __future__ import annotations

import os
import sys
import time

from tqdm.auto import tqdm

from ..samplers import warmup
from ._executor import _prerequisites, _run_after, local_executor, run_tasks
from .registry import Config, get_study, run_warm_item, study_names, warm_plan

__all__ = ["precompile", "warm_studies"]

#: Studies whose kernels take longest to compile, started first so that the pool's other
#: worker takes the many short ones meanwhile (measured on 2 cores, empty cache: the herded
#: and tempered samplers of every kind took 153 s of the 292 s of a first reproduction).
_LONGEST_FIRST = ("tempering_herding", "glmb_tracking", "tracking", "multisensor",
                  "multisensor_tracking")
#: Within a study, the kernel groups (:attr:`~rankedassign.experiments.Study.warm_group`) that
#: take longest, first: the multi-sensor herded and tempered drivers are the largest kernels.
_GROUPS_FIRST = ("multisensor", "adaptive_birth")


def _task(study: str | None, args: tuple, unit: bool = False) -> None:
    """One item of the queue: a tiny task or warm unit of ``study``
    (:func:`~rankedassign.experiments.registry.run_warm_item`), or with ``study`` None the
    samplers' :func:`~rankedassign.warmup`."""
    if study is None:
        warmup()
    else:
        run_warm_item(study, args, unit)


def warm_studies(studies, config, executor) -> float:
    """Warm several studies at once on ``executor``'s workers; returns the seconds taken.

    The studies' warm plan (:func:`~rankedassign.experiments.registry.warm_plan`, longest
    first) goes out as one queue, so that the workers compile the kernels of different
    studies side by side and no two compile the same kernels at once (``rankedassign
    reproduce`` does this before its first study; each study's own warm-up then loads them).

    Parameters
    ----------
    studies : sequence of str
        Registered study names.
    config : Config or None
        Their settings (their tiny form runs).
    executor : concurrent.futures.Executor
        The workers.

    Returns
    -------
    float
        Wall time in seconds.
    """
    t0 = time.perf_counter()
    order = sorted(studies, key=lambda s: (_LONGEST_FIRST.index(s)
                                           if s in _LONGEST_FIRST else len(_LONGEST_FIRST)))
    items, after = warm_plan(order, config, groups_first=_GROUPS_FIRST)
    run_tasks(_task, items, executor=executor, progress=False, after=after)
    return time.perf_counter() - t0


def _queue(studies, config) -> tuple[list[tuple[str | None, tuple, bool]], list]:
    """Every study's warm units and tiny tasks as ``(study, args, unit)``, longest first, and
    what each waits for (:func:`~rankedassign.experiments.registry.warm_plan`).

    The studies' warm plan in the order of :data:`_LONGEST_FIRST`, with the samplers'
    warm-up second: it is long, and the later tasks of every worker need some of it.
    """
    order = sorted(studies, key=lambda s: (_LONGEST_FIRST.index(s)
                                           if s in _LONGEST_FIRST else len(_LONGEST_FIRST)))
    items, after = warm_plan(order, config, groups_first=_GROUPS_FIRST)
    at = min(1, len(items))

    def shift(a):
        if a is None:
            return None
        return tuple(j + (j >= at) for j in a) if isinstance(a, tuple) else a + (a >= at)

    after = [shift(a) for a in after]
    return items[:at] + [(None, (), False)] + items[at:], after[:at] + [None] + after[at:]


def precompile(workers: int | None = None, *, studies=None, progress: bool = True) -> float:
    """Compile (or load from the cache) every kernel of the studies and samplers.

    Parameters
    ----------
    workers : int, optional
        Worker processes compiling side by side (default: the CPUs, at most 4: each worker
        holds its own copy of numba's compiler, about 0.5 GB). ``1`` compiles in this process.
    studies : sequence of str, optional
        Registered study names (default: all of them).
    progress : bool, optional
        Show a progress bar on stderr, one step per tiny task.

    Returns
    -------
    float
        Wall time in seconds.

    Notes
    -----
    The kernels land in numba's on-disk cache, keyed by the sources of :mod:`rankedassign` and
    :mod:`oracle` (:func:`rankedassign.numba_options.source_digest`): a second call, or any
    later process of the same installation, compiles nothing.

    Examples
    --------
    >>> from rankedassign.experiments.precompile import precompile
    >>> precompile(1, studies=["table1"], progress=False) >= 0.0
    True
    """
    names = study_names() if studies is None else tuple(studies)
    for name in names:
        get_study(name)  # an unknown name fails here, before any work
    if workers is None:
        workers = max(1, min(4, os.cpu_count() or 1))
    t0 = time.perf_counter()
    queue, after = _queue(names, Config.quick())
    desc = f"compiling kernels ({workers} process{'es' if workers > 1 else ''})"
    bar = tqdm(total=len(queue), desc=desc, disable=not progress, file=sys.stderr)
    try:
        with local_executor(workers) as executor:
            if executor is None:
                for study, args, unit in queue:
                    bar.set_postfix_str(_label(study), refresh=True)
                    _task(study, args, unit)
                    bar.update()
            else:
                _run_pool(executor, queue, after, bar, t0)
    finally:
        bar.close()
    return time.perf_counter() - t0


def _label(study: str | None) -> str:
    return "samplers" if study is None else study


def _run_pool(executor, queue, after, bar, t0: float) -> None:
    """Run the queue on the pool, each item once the items it waits for have finished; once
    a second (on a terminal), the bar names what is compiling and for how long, so a long
    compile shows that it is alive."""
    # a terminal gets a line that ticks every second; a log file (CI) one line in 30 s
    tick = 1.0 if sys.stderr.isatty() else 30.0

    def status(running):
        names = sorted({_label(queue[i][0]) for i in running})
        bar.set_postfix_str(f"{', '.join(names) or 'starting'}; "
                            f"{time.perf_counter() - t0:.0f} s", refresh=True)

    # a failing task fails the whole run, with its own traceback
    _run_after(executor, _task, queue, _prerequisites(after, len(queue)), bar, tick=tick,
               status=status)
