"""Where Monte Carlo runs execute: in-process, a local process pool, or a Dask cluster.

Every study splits its work into independent *tasks* (one Monte Carlo run of one matrix family,
one tracking run of one association method, ...). A task is a module-level function called with
plain, picklable arguments; its random streams come only from the study seed and the run index
(:func:`run_seed`), never from the executor, so a study gives bit-identical numbers whether it
runs serially, on ``N`` local processes or on a Dask cluster.
"""

from __future__ import annotations

import _multiprocessing
import ctypes
import ctypes.util
import multiprocessing
import os
import selectors
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import (
    FIRST_COMPLETED,
    Executor,
    Future,
    ProcessPoolExecutor,
    as_completed,
    wait,
)
from contextlib import contextmanager
from multiprocessing import resource_tracker
from typing import Any

import numba
import numpy as np
from tqdm.auto import tqdm

from . import _interrupts

__all__ = [
    "run_seed",
    "child_seed",
    "local_executor",
    "dask_executor",
    "run_tasks",
    "SchedulerError",
]


#: Seconds :func:`dask_executor` waits for a scheduler by default.
DASK_CONNECT_TIMEOUT = 10.0


class SchedulerError(RuntimeError):
    """The Dask scheduler given by the user could not be reached."""


def run_seed(seed: int, run: int) -> np.random.SeedSequence:
    """Seed sequence of Monte Carlo run ``run`` of a study seeded with ``seed``.

    Identical to ``np.random.SeedSequence(seed).spawn(n)[run]`` for any ``n > run``, but
    computed without spawning the ``run`` earlier children, so a worker can rebuild it from two
    integers.

    Parameters
    ----------
    seed : int
        Non-negative study seed (the ``--seed`` of ``rankedassign reproduce``).
    run : int
        Non-negative Monte Carlo run index.

    Returns
    -------
    numpy.random.SeedSequence

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.experiments import run_seed
    >>> a = run_seed(7, 3).generate_state(2)
    >>> b = np.random.SeedSequence(7).spawn(5)[3].generate_state(2)
    >>> bool((a == b).all())
    True
    """
    return np.random.SeedSequence(int(seed), spawn_key=(int(run),))


def child_seed(parent: np.random.SeedSequence, *keys: int) -> np.random.SeedSequence:
    """A named child stream of ``parent``: independent of the order children are requested in.

    ``child_seed(s, k)`` equals ``s.spawn(k + 1)[k]`` on a fresh ``s``; several keys nest.

    Parameters
    ----------
    parent : numpy.random.SeedSequence
    *keys : int
        Non-negative integers naming the child.

    Returns
    -------
    numpy.random.SeedSequence

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.experiments import child_seed, run_seed
    >>> s = run_seed(0, 1)
    >>> bool((child_seed(s, 2).generate_state(1) == s.spawn(3)[2].generate_state(1)).all())
    True
    """
    return np.random.SeedSequence(
        parent.entropy,
        spawn_key=tuple(parent.spawn_key) + tuple(int(k) for k in keys),
        pool_size=parent.pool_size,
    )


def _worker_init() -> None:  # pragma: no cover - runs in child processes
    # Numba's own thread pool stays at one thread per worker process: the processes already
    # use every core, and nested parallelism would oversubscribe the machine.
    numba.set_num_threads(1)
    # Ctrl-C reaches the whole process group: the parent alone handles it and ends the workers
    # (a worker would otherwise print a traceback of its own).
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    # A parent that is killed (SIGKILL) cannot end its workers, and a worker inside a long
    # compiled kernel would run on as an orphan: on Linux the kernel ends it with its parent.
    _die_with_parent()


def _die_with_parent() -> None:  # pragma: no cover - runs in child processes
    if not sys.platform.startswith("linux"):
        return
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or None, use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    except (OSError, AttributeError):
        return
    if os.getppid() == 1:  # the parent died before prctl took effect
        os._exit(1)


_PR_SET_PDEATHSIG = 1


class _Dropped(Future):
    """A cancelled future that ignores the result or exception a pool sets on it."""

    def __init__(self):
        super().__init__()
        self.cancel()

    def set_result(self, result):
        pass

    def set_exception(self, exception):
        pass


def _end_workers(ex: ProcessPoolExecutor) -> None:
    """End the pool's worker processes now (SIGTERM, then SIGKILL after a grace period).

    A worker inside a long compiled kernel would otherwise finish its task before the pool's
    shutdown returns.
    """
    # the pool's processes (CPython keeps them in _processes; 3.14 adds terminate_workers,
    # which does the same without the grace period)
    procs = list((getattr(ex, "_processes", None) or {}).values())
    # CPython 3.11's pool sets BrokenProcessPool on every pending item when a worker dies,
    # cancelled ones included, which raises InvalidStateError in its management thread (a
    # traceback on stderr). The cancelled items' futures (nobody waits for them) become ones
    # that ignore it. They are not removed: the management thread may be about to look up
    # an item by the id it has just taken from its queue (a KeyError traceback).
    pending = getattr(ex, "_pending_work_items", None)
    if isinstance(pending, dict):
        for item in list(pending.values()):
            if item.future.cancelled():
                item.future = _Dropped()
    for p in procs:
        if p.is_alive():
            p.terminate()
    for p in procs:
        p.join(timeout=2.0)
        if p.is_alive():  # pragma: no cover - a worker that ignores SIGTERM
            p.kill()
            p.join(timeout=2.0)


def _semaphore_names(ex: ProcessPoolExecutor) -> tuple[str, ...]:
    """The names of the pool's named semaphores (its two queues' locks and the call queue's
    size semaphore), read once.

    Read when the pool is made: the shutdown drops the queues from the pool before their
    finalisers have run, so a second signal during the shutdown would not find them there.
    CPython's private attributes are read defensively; where they differ the tuple is empty.
    """
    names = []
    for q in (getattr(ex, "_call_queue", None), getattr(ex, "_result_queue", None)):
        for attr in ("_rlock", "_wlock", "_sem"):
            name = getattr(getattr(getattr(q, attr, None), "_semlock", None), "name", None)
            if isinstance(name, str):
                names.append(name)
    return tuple(names)


def _forget_semaphores(names: tuple[str, ...]) -> None:
    """Unlink the named semaphores and strike them off the resource tracker's list.

    For a process about to end by ``os._exit`` (a second signal): the semaphores'
    finalisers, which do this, do not run, and the resource tracker would report them as
    leaked (and unlink them itself). A finaliser may also have been stopped halfway, between
    its unlink and its message to the tracker, when the signal arrived; which half it did is
    not known here. So every name is unlinked where it still exists, and then sent as
    ``REGISTER`` followed by ``UNREGISTER`` in one write: the tracker keeps a set of names,
    so the pair leaves the name off the list whether or not it was still on it (a lone
    ``UNREGISTER`` of a name no longer listed makes the tracker print a ``KeyError``
    traceback). Writes of at most ``PIPE_BUF`` bytes to a pipe are atomic, so no other
    thread's message falls between the two. Runs in a signal handler, so it writes the
    tracker's pipe directly instead of through ``resource_tracker.unregister``, which takes
    a lock.
    """
    fd = getattr(getattr(resource_tracker, "_resource_tracker", None), "_fd", None)
    for name in names:
        try:
            _multiprocessing.sem_unlink(name)
        except (OSError, AttributeError):
            pass  # already unlinked (by its finaliser), or no such call on this platform
        if isinstance(fd, int):
            try:
                os.write(fd, f"REGISTER:{name}:semaphore\nUNREGISTER:{name}:semaphore\n"
                         .encode("ascii"))
            except OSError:
                pass


@contextmanager
def _signals_held() -> Iterator[None]:
    """Hold SIGINT and SIGTERM while worker processes start, and deliver them afterwards.

    ``ProcessPoolExecutor.submit`` spawns workers; a signal handled halfway through writing a
    worker's start-up data leaves the worker a truncated message (an ``EOFError`` traceback in
    the child, a leaked semaphore). Only the main thread can install handlers; elsewhere this
    does nothing.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []

    def hold(signum, frame):
        caught.append(signum)

    previous = {s: signal.signal(s, hold) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, signal.SIG_DFL if handler is None else handler)
        # delivered again in order: a second one counts (it ends a run at once, _interrupts)
        for signum in caught[:2]:
            signal.raise_signal(signum)


@contextmanager
def local_executor(workers: int | None = None) -> Iterator[Executor | None]:
    """A local process pool, or ``None`` (run in-process) when ``workers == 1``.

    Parameters
    ----------
    workers : int, optional
        Number of worker processes (default: ``os.cpu_count()``).

    Yields
    ------
    concurrent.futures.Executor or None
        A :class:`~concurrent.futures.ProcessPoolExecutor` using the ``spawn`` start method
        (numba's compiled state and ``fork`` do not mix safely), or ``None`` for serial runs.

    Examples
    --------
    >>> from rankedassign.experiments import local_executor
    >>> with local_executor(1) as ex:
    ...     print(ex)
    None
    """
    n = (os.cpu_count() or 1) if workers is None else int(workers)
    if n < 1:
        raise ValueError(f"workers must be a positive integer, got {workers}")
    if n == 1:
        yield None
        return
    ctx = multiprocessing.get_context("spawn")
    ex = ProcessPoolExecutor(max_workers=n, mp_context=ctx, initializer=_worker_init)
    semaphores = _semaphore_names(ex)

    def kill_workers():  # a second signal: no waiting, no locks (see _interrupts)
        for p in list((getattr(ex, "_processes", None) or {}).values()):
            try:
                os.kill(p.pid, signal.SIGKILL)
            except (OSError, TypeError, AttributeError):
                pass
        _forget_semaphores(semaphores)

    # registered until the pool is shut down: a second signal during the first one's cleanup
    # (ending the workers, the shutdown) must still find the pool's semaphores
    _interrupts.add_cleanup(kill_workers)
    try:
        # Every worker started, and through its start-up, before the first task: the pool
        # starts a process per submission only while none is idle, so a warm-up whose tasks
        # wait for one another would leave the others to start under the first study's tasks,
        # where a signal could meet a worker halfway through starting (a traceback from the
        # pool's management thread when the workers are ended).
        with _signals_held():
            started = [ex.submit(os.getpid) for _ in range(n)]
        wait(started)
        yield ex
    except BaseException:
        # an interrupt or an error: the workers' running tasks are not wanted any more
        _end_workers(ex)
        raise
    finally:
        try:
            ex.shutdown(wait=True, cancel_futures=True)
        finally:
            _interrupts.remove_cleanup(kill_workers)


@contextmanager
def dask_executor(address: str, *, timeout: float | None = None) -> Iterator[Executor]:
    """The executor of a :class:`distributed.Client` connected to ``address``.

    Parameters
    ----------
    address : str
        Scheduler address, e.g. ``"tcp://10.0.0.5:8786"``.
    timeout : float, optional
        Seconds to wait for the connection before giving up (default
        ``DASK_CONNECT_TIMEOUT``, 10 s).

    Yields
    ------
    concurrent.futures.Executor
        ``client.get_executor()``; the client is closed on exit.

    Raises
    ------
    SchedulerError
        If ``distributed`` is missing or the scheduler cannot be reached.

    Notes
    -----
    The workers import the task functions by name, so ``rankedassign`` must be installed in
    the workers' environment.

    Examples
    --------
    >>> from rankedassign.experiments import SchedulerError, dask_executor
    >>> try:
    ...     with dask_executor("tcp://127.0.0.1:9", timeout=0.5):
    ...         pass
    ... except SchedulerError as exc:
    ...     print(str(exc)[:37])
    could not connect to the Dask schedul
    """
    try:
        from distributed import Client
    except ImportError as exc:  # pragma: no cover - distributed is a test dependency
        raise SchedulerError(
            "--dask-scheduler needs the 'distributed' package: pip install 'rankedassign[dask]'"
        ) from exc
    if timeout is None:
        timeout = DASK_CONNECT_TIMEOUT
    _probe_scheduler(address, timeout)
    try:
        client = Client(address, timeout=timeout)
    except Exception as exc:  # noqa: BLE001 - any failure to connect is the user's address
        raise SchedulerError(
            f"could not connect to the Dask scheduler at {address!r} within {timeout:g} s: "
            f"{_one_line(exc)}"
        ) from None
    try:
        yield client.get_executor()
    finally:
        client.close()


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split()) or type(exc).__name__
    return text if len(text) <= 300 else text[:297] + "..."


_PROBE = """\
import sys
from distributed import Client
print("ready", flush=True)
Client(sys.argv[1], timeout=float(sys.argv[2])).close()
"""


def _probe_scheduler(address: str, timeout: float) -> None:
    """Connect to ``address`` once in a child process that is killed after ``timeout``.

    A server that is not a Dask scheduler can hang the client's handshake past its own
    timeout (an HTTP server) or make it allocate what its junk bytes announce as a frame
    length; in a child process either one ends with the process, within the time given.
    """
    proc = subprocess.Popen([sys.executable, "-c", _PROBE, address, repr(float(timeout))],
                            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    try:
        with selectors.DefaultSelector() as sel:  # importing distributed: allowed 60 s
            sel.register(proc.stdout, selectors.EVENT_READ)
            sel.select(timeout=60.0)
        proc.stdout.readline()
        t0 = time.monotonic()
        try:
            _, err = proc.communicate(timeout=timeout + 2.0)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.communicate()
            raise SchedulerError(
                f"could not connect to the Dask scheduler at {address!r} within {timeout:g} s: "
                f"no answer as a Dask scheduler after {time.monotonic() - t0:.0f} s"
            ) from None
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    if proc.returncode != 0:
        lines = [ln for ln in err.strip().splitlines() if ln.strip()]
        why = lines[-1].strip() if lines else f"exit status {proc.returncode}"
        raise SchedulerError(
            f"could not connect to the Dask scheduler at {address!r} within {timeout:g} s: "
            f"{_one_line(Exception(why))}"
        )


def run_tasks(
    fn: Callable[..., Any],
    tasks: Sequence[tuple],
    *,
    executor: Executor | None = None,
    progress: bool = True,
    desc: str = "",
    after: Sequence[int | tuple[int, ...] | None] | None = None,
) -> list[Any]:
    """Run ``fn(*task)`` for every task and return the results in task order.

    Parameters
    ----------
    fn : callable
        A module-level (picklable) function.
    tasks : sequence of tuple
        Positional arguments of each call.
    executor : concurrent.futures.Executor, optional
        Where to run; ``None`` runs the calls one after the other in this process.
    progress : bool, optional
        Show a tqdm progress bar on stderr.
    desc : str, optional
        Label of the progress bar.
    after : sequence, optional
        One entry per task: ``None``, or the index (or a tuple of indices) of earlier tasks
        that must have finished before this one goes to a worker. The warm-up uses it so
        that the tiny tasks which would compile the same kernels as a running one wait for
        it and then load them from numba's cache, instead of compiling them beside it on
        another core. Without an executor the tasks run in their order, which keeps every
        such condition.

    Returns
    -------
    list
        ``[fn(*t) for t in tasks]``, whatever order the calls finished in.

    Raises
    ------
    ValueError
        If ``after`` does not have one entry per task or names a task that is not earlier.

    Examples
    --------
    >>> from operator import add
    >>> from rankedassign.experiments import run_tasks
    >>> run_tasks(add, [(1, 2), (3, 4)], progress=False)
    [3, 7]
    >>> run_tasks(add, [(1, 2), (3, 4), (5, 6)], progress=False, after=[None, 0, (0, 1)])
    [3, 7, 11]
    """
    waits = _prerequisites(after, len(tasks))
    bar = tqdm(total=len(tasks), desc=desc, disable=not progress, file=sys.stderr)
    try:
        # _interrupts.check(): the safe points at which a recorded SIGINT/SIGTERM stops the
        # run (between tasks, at each progress step, while waiting for the workers)
        if executor is None:
            out = []
            for t in tasks:
                _interrupts.check()
                out.append(fn(*t))
                bar.update()
            _interrupts.check()
            return out
        if waits is not None:
            return _run_after(executor, fn, tasks, waits, bar)
        with _signals_held():
            futures = {executor.submit(fn, *t): i for i, t in enumerate(tasks)}
        results: list[Any] = [None] * len(tasks)
        if not futures:
            return results
        try:
            with _interrupts.stop_future() as stop:
                waited = set(futures) if stop is None else {*futures, stop}
                left = len(futures)
                for fut in as_completed(waited):
                    _interrupts.check()
                    results[futures[fut]] = fut.result()
                    bar.update()
                    left -= 1
                    if not left:
                        break
        except BaseException:
            for fut in futures:
                fut.cancel()
            raise
        return results
    finally:
        bar.close()


def _prerequisites(after, n: int) -> list[tuple[int, ...]] | None:
    """``after`` of :func:`run_tasks` checked and made tuples; None when there is none."""
    if after is None:
        return None
    after = list(after)
    if len(after) != n:
        raise ValueError(f"after has {len(after)} entries for {n} tasks; give one per task")
    out = []
    for i, a in enumerate(after):
        a = () if a is None else (a,) if isinstance(a, (int, np.integer)) else tuple(a)
        if any(not 0 <= j < i for j in a):
            raise ValueError(f"after[{i}] = {after[i]!r}: a task can only wait for an "
                             f"earlier task (indices 0 to {i - 1})")
        out.append(tuple(int(j) for j in a))
    return out


def _run_after(executor: Executor, fn, tasks, waits: list[tuple[int, ...]], bar, *,
               tick: float | None = None, status: Callable[[list[int]], None] | None = None
               ) -> list:
    """:func:`run_tasks` with prerequisites: a task goes to the executor once every task it
    waits for has finished, the ready ones in task order. With ``tick``, ``status`` gets the
    indices of the running tasks at least every ``tick`` seconds."""
    n = len(tasks)
    results: list[Any] = [None] * n
    left = [len(w) for w in waits]
    then: list[list[int]] = [[] for _ in range(n)]
    for i, w in enumerate(waits):
        for j in w:
            then[j].append(i)
    futures: dict = {}

    def submit(idx):
        with _signals_held():
            for i in idx:
                futures[executor.submit(fn, *tasks[i])] = i

    submit([i for i in range(n) if not left[i]])
    pending = set(futures)
    try:
        with _interrupts.stop_future() as stop:
            finished = 0
            while finished < n:
                done, _ = wait(pending if stop is None else {*pending, stop}, timeout=tick,
                               return_when=FIRST_COMPLETED)
                _interrupts.check()
                if status is not None:
                    status(sorted(futures[f] for f in pending if f.running()))
                if stop is not None and stop in done:
                    stop = None  # a recorded signal that check() let pass: wait on the tasks
                for fut in done - {stop}:
                    if fut not in futures:
                        continue
                    pending.discard(fut)
                    i = futures[fut]
                    results[i] = fut.result()
                    bar.update()
                    finished += 1
                    ready = []
                    for k in then[i]:
                        left[k] -= 1
                        if not left[k]:
                            ready.append(k)
                    before = set(futures)
                    submit(ready)
                    pending |= set(futures) - before
    except BaseException:
        for fut in futures:
            fut.cancel()
        raise
    return results
