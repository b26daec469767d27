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
from concurrent.futures import FIRST_COMPLETED, wait

from tqdm.auto import tqdm

from ..samplers import warmup
from ._executor import _signals_held, local_executor
from .registry import Config, get_study, run_warm_unit, study_config, study_names

__all__ = ["precompile"]

#: Studies whose kernels take longest to compile, started first so that the pool's other
#: worker takes the many short ones meanwhile (measured on 2 cores, empty cache: the herded
#: and tempered samplers of every kind took 153 s of the 292 s of a first reproduction).
_LONGEST_FIRST = ("tempering_herding", "glmb_tracking", "tracking", "multisensor")
#: Within a study, the kernel groups (:attr:`~rankedassign.experiments.Study.warm_group`) that
#: take longest, first: the multi-sensor herded and tempered drivers are the largest kernels.
_GROUPS_FIRST = ("multisensor", "adaptive_birth")


def _task(study: str | None, args: tuple, unit: bool = False) -> None:
    """One tiny task of ``study`` (``None``: the samplers' :func:`~rankedassign.warmup`), or
    with ``unit`` one of its :attr:`~rankedassign.experiments.Study.warm_units`."""
    if study is None:
        warmup()
    elif unit:
        run_warm_unit(*args)
    else:
        get_study(study).task(*args)


def _queue(studies, config) -> list[tuple[str | None, tuple, bool]]:
    """Every study's warm units and tiny tasks as ``(study, args, unit)``, longest first.

    First the warm units (:attr:`~rankedassign.experiments.Study.warm_units`), then the first
    tiny task of each kernel group, then the rest. The tiny tasks of a study with warm units
    are all among the rest: its units compile every kernel they need, and a tiny task that
    started beside a unit compiling the same kernels would compile them again.
    """
    order = sorted(studies, key=lambda s: (_LONGEST_FIRST.index(s)
                                           if s in _LONGEST_FIRST else len(_LONGEST_FIRST)))
    units: list = []
    leaders: list = []
    rest: list = [(None, (), False)]
    for name in order:
        st = get_study(name)
        if st.warm is None:
            continue
        tiny = st.warm(study_config(config, st))
        tasks = list(st.tasks(tiny, 0))
        if st.warm_units is not None:
            units += [(name, unit, True) for unit in st.warm_units(tiny)]
            rest += [(name, args, False) for args in tasks]
            continue
        group = st.warm_group or id
        seen: set = set()
        first: list = []
        for args in tasks:
            key = group(args)
            if key in seen:
                rest.append((name, args, False))
            else:
                first.append((_GROUPS_FIRST.index(key) if key in _GROUPS_FIRST
                              else len(_GROUPS_FIRST), len(first), (name, args, False)))
            seen.add(key)
        leaders += [item for *_, item in sorted(first, key=lambda t: t[:2])]
    # the samplers' warm-up after the longest first item: it is short and every worker's
    # later tasks need some of it
    head = units + leaders
    return head[:1] + rest[:1] + head[1:] + rest[1:]


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
    queue = _queue(names, Config.quick())
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
                _run_pool(executor, queue, bar, t0)
    finally:
        bar.close()
    return time.perf_counter() - t0


def _label(study: str | None) -> str:
    return "samplers" if study is None else study


def _run_pool(executor, queue, bar, t0: float) -> None:
    """Run the queue on the pool; once a second (on a terminal), the bar names what is
    compiling and for how long, so a long compile shows that it is alive."""
    with _signals_held():
        futures = {executor.submit(_task, *item): item for item in queue}
    pending = set(futures)
    # a terminal gets a line that ticks every second; a log file (CI) one line in 30 s
    tick = 1.0 if sys.stderr.isatty() else 30.0
    try:
        while pending:
            done, pending = wait(pending, timeout=tick, return_when=FIRST_COMPLETED)
            for fut in done:
                fut.result()  # a failing task fails the whole run, with its own traceback
            bar.update(len(done))
            running = sorted({_label(futures[f][0]) for f in pending if f.running()})
            bar.set_postfix_str(f"{', '.join(running) or 'starting'}; "
                                f"{time.perf_counter() - t0:.0f} s", refresh=True)
    except BaseException:
        for fut in futures:
            fut.cancel()
        raise
