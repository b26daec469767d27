"""SIGINT and SIGTERM during a run: recorded, and acted on only where stopping is safe.

Python runs a signal handler in whatever frame the main thread is executing. A handler that
raises (Python's own ``KeyboardInterrupt``, or a SIGTERM handler raising an exception) therefore
raises *there*: inside a finaliser or a garbage-collector callback (numba disposes of compiled
code from ``weakref.finalize`` callbacks), the exception is "ignored" (Python prints
``Exception ignored in ...``) and the run goes on; inside ``threading``'s own code it can
break a lock's bookkeeping (CPython 3.11's ``Thread.join`` releases the joined thread's lock
when interrupted at the wrong moment and fails with ``RuntimeError: release unlocked lock``
when that thread ends in between).

While :func:`deferred_interrupts` is active, a first SIGINT or SIGTERM only *records* the
signal. The run then stops at the first safe place:

* the checks the runner makes (:func:`check`): before and after each study, between two
  tasks and at each progress step of :func:`~rankedassign.experiments.run_tasks`, and while
  it waits for worker processes (a watcher thread completes a future the wait includes);
* in the handler itself, at once, unless raising there is unsafe: when the frame it runs in
  is the run's own machinery (the runner, the registry, the executor, the report folder and
  its lock, the command line: they check explicitly, and a file made there must not be cut
  off from its removal), or when any frame of the stack is a finaliser (``__del__``, a
  ``weakref`` callback), ``threading``, ``queue``, ``concurrent.futures``,
  ``multiprocessing`` or ``logging`` code, numba's or llvmlite's machinery (compiling,
  disposing), tqdm, or the lock's code, or when it is the import machinery itself (a module
  being imported is interrupted like any code). So the long computations of the library,
  of numpy and of the plots are interrupted where they are, as before (between the slices of
  a long compiled call and after each kernel: :mod:`rankedassign.numba_options`,
  "Signals"), and nothing else is. Where it is unsafe the handler only records the signal
  and asks again a little later (a one-shot ``SIGALRM`` after :data:`RETRY` seconds), until
  a safe frame or a check comes.

The exception is ``KeyboardInterrupt`` for SIGINT and :class:`Terminated` for SIGTERM; the
run's ``finally`` blocks remove its partial report and its lock, and the command line exits
with 130 or 143. A second SIGINT or SIGTERM while the first is pending or being cleaned up
ends the process at once: the registered cleanups run (:func:`on_hard_exit`: the lock, the
partial report, the worker processes) and the process exits with ``128 + signal`` through
``os._exit``, whatever the main thread was doing.
"""

from __future__ import annotations

import concurrent.futures
import logging
import multiprocessing
import os
import queue
import signal
import sys
import threading
import weakref
from collections.abc import Callable, Iterator
from concurrent.futures import Future
from contextlib import contextmanager
from pathlib import Path

__all__ = ["Terminated", "deferred_interrupts", "check", "pending", "critical", "add_cleanup",
           "remove_cleanup", "on_hard_exit", "stop_future"]

#: Seconds between two attempts at raising a recorded interrupt when the handler ran in a
#: frame where raising is unsafe (a finaliser, threading code, numba's compiler).
RETRY = 0.05
#: Seconds between two looks of the watcher thread at the flag (pool waits).
WATCH = 0.05
_SIGNALS = (signal.SIGINT, signal.SIGTERM)


class Terminated(BaseException):
    """Raised in the main thread when a SIGTERM is acted on: handled like Ctrl-C."""


class _State:
    def __init__(self):
        self.active = False
        self.signum: int | None = None  # the first signal received
        self.raised = False  # its exception has been raised once
        self.message = ""  # printed on a hard exit
        self.critical = 0  # inside critical(): never raise
        self.cleanups: list[Callable[[], object]] = []


_state = _State()

_HERE = Path(__file__).resolve().parent
_PACKAGE = _HERE.parent  # rankedassign/


def _root(module_file: str | None) -> str | None:
    return None if module_file is None else str(Path(module_file).resolve().parent)


def _unsafe_files() -> tuple[tuple[str, ...], tuple[str, ...]]:
    """Files and folders whose frames an exception must never be raised through."""
    files = [threading.__file__, weakref.__file__, queue.__file__, __file__,
             str(_HERE / "_outdir.py")]
    dirs = [_root(concurrent.futures.__file__), _root(multiprocessing.__file__),
            _root(logging.__file__)]
    for name in ("numba", "llvmlite", "tqdm"):
        mod = sys.modules.get(name)
        if mod is not None and getattr(mod, "__file__", None):
            dirs.append(_root(mod.__file__))
    return (tuple(str(Path(f).resolve()) for f in files),
            tuple(d for d in dirs if d))


# The run's own machinery, which checks explicitly (check()) at its safe points: an exception
# is never raised while it runs (between creating a file and recording it for removal, say).
_CHECKS_ITSELF = tuple(str((_HERE / f).resolve()) for f in
                       ("runner.py", "registry.py", "_executor.py", "_outdir.py",
                        "_interrupts.py")) + (str((_PACKAGE / "cli.py").resolve()),)
# Set when deferred_interrupts starts: what no frame of the stack may be.
_UNSAFE: tuple[tuple[str, ...], tuple[str, ...]] = ((), ())
_PATHS: dict[str, str] = {}


def _path(code) -> str:
    p = _PATHS.get(code.co_filename)
    if p is None:
        name = code.co_filename
        p = name if name.startswith("<") else str(Path(name).resolve())
        _PATHS[code.co_filename] = p
    return p


def _under(path: str, roots) -> bool:
    return any(path == r or path.startswith(r + os.sep) for r in roots)


def _may_raise_in(frame) -> bool:
    """Whether raising the interrupt in ``frame`` (the handler's) is safe (module docstring)."""
    if frame is None or _state.critical or _path(frame.f_code) in _CHECKS_ITSELF:
        return False
    if _path(frame.f_code).startswith("<frozen importlib"):
        # the import machinery's own lock handling; an exception from a module's code being
        # imported, which unwinds through it, is what imports are written for
        return False
    files, dirs = _UNSAFE
    if (frame.f_code.co_name == "_numba_unpickle" and frame.f_back is not None
            and _under(_path(frame.f_code), dirs)):
        # numba boxing a kernel's result for the code that called the kernel: its
        # ``with interruptible:`` turns the SystemError back into the interrupt
        frame = frame.f_back
        if _path(frame.f_code) in _CHECKS_ITSELF:
            return False
    f = frame
    while f is not None:
        code = f.f_code
        p = _path(code)
        if code.co_name == "__del__" or p in files or _under(p, dirs):
            return False
        f = f.f_back
    return True


def _exception(signum: int) -> BaseException:
    return KeyboardInterrupt() if signum == signal.SIGINT else Terminated()


def pending() -> int | None:
    """The first signal received inside :func:`deferred_interrupts` (acted on or not).

    Returns
    -------
    int or None
        ``signal.SIGINT`` or ``signal.SIGTERM`` once one arrived inside
        :func:`deferred_interrupts`, else None.
    """
    return _state.signum


def check() -> None:
    """A safe point: raise the interrupt of a signal that arrived, if one did.

    Raises
    ------
    KeyboardInterrupt
        After a SIGINT.
    Terminated
        After a SIGTERM.
    """
    signum = _state.signum
    if signum is not None:
        _state.raised = True
        _cancel_retry()
        raise _exception(signum)


def _cancel_retry() -> None:
    if _state.active and threading.current_thread() is threading.main_thread():
        signal.setitimer(signal.ITIMER_REAL, 0)


def _hard_exit(signum: int) -> None:
    for fn in reversed(_state.cleanups):
        try:
            fn()
        except BaseException:  # noqa: BLE001 - nothing may stop the exit
            pass
    try:
        sys.stderr.flush()
    except BaseException:  # noqa: BLE001
        pass
    if _state.message:
        try:
            os.write(2, _state.message.format(signal=signal.Signals(signum).name).encode())
        except OSError:
            pass
    os._exit(128 + signum)


def _on_signal(signum, frame):
    if _state.signum is not None:
        _hard_exit(signum)  # a second signal: the user wants out now
    _state.signum = signum
    if _may_raise_in(frame):
        _state.raised = True
        raise _exception(signum)
    signal.setitimer(signal.ITIMER_REAL, RETRY)


def _on_retry(signum, frame):
    if not _state.active or _state.signum is None or _state.raised:
        return  # (not active: the guard is ending; re-arming now would outlive its handler)
    if _may_raise_in(frame):
        _state.raised = True
        raise _exception(_state.signum)
    signal.setitimer(signal.ITIMER_REAL, RETRY)


@contextmanager
def deferred_interrupts(message: str = "") -> Iterator[None]:
    """Handle SIGINT and SIGTERM as the module docstring says, for the ``with`` block.

    Only in the main thread (elsewhere, and when active already, it does nothing). The
    previous handlers are restored and the state cleared on exit.

    Parameters
    ----------
    message : str, optional
        Written to stderr on a hard exit (second signal); ``{signal}`` is replaced by the
        signal's name.
    """
    if _state.active or threading.current_thread() is not threading.main_thread():
        yield
        return
    global _UNSAFE
    _UNSAFE = _unsafe_files()
    _state.__init__()
    _state.message = message
    previous = {s: signal.getsignal(s) for s in (*_SIGNALS, signal.SIGALRM)}
    _state.active = True
    try:
        signal.signal(signal.SIGALRM, _on_retry)
        for s in _SIGNALS:
            signal.signal(s, _on_signal)
        yield
    finally:
        # first stop re-arming, then cancel the timer, then give SIGALRM back: a retry that
        # re-armed after the cancel would fire under the previous (default: fatal) handler
        _state.active = False
        for s in _SIGNALS:
            signal.signal(s, signal.SIG_DFL if previous[s] is None else previous[s])
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM,
                      signal.SIG_DFL if previous[signal.SIGALRM] is None
                      else previous[signal.SIGALRM])
        _state.__init__()


@contextmanager
def critical() -> Iterator[None]:
    """A block that a signal never cuts short (it is recorded and acted on after it).

    For a file made and removed again within the block, where an exception in between would
    leave it behind.
    """
    _state.critical += 1
    try:
        yield
    finally:
        _state.critical -= 1


def add_cleanup(cleanup: Callable[[], object]) -> None:
    """Run ``cleanup`` if a second signal ends the process, until :func:`remove_cleanup`.

    ``cleanup`` runs in a signal handler, with the main thread stopped wherever it was: it must
    only remove files or end processes, and must not take locks. Cleanups run last-added
    first.
    """
    _state.cleanups.append(cleanup)


def remove_cleanup(cleanup: Callable[[], object]) -> None:
    """Forget ``cleanup`` (added by :func:`add_cleanup`); nothing if it is not there."""
    try:
        _state.cleanups.remove(cleanup)
    except ValueError:  # the state was cleared meanwhile
        pass


@contextmanager
def on_hard_exit(cleanup: Callable[[], object]) -> Iterator[None]:
    """:func:`add_cleanup` for the duration of the ``with`` block."""
    add_cleanup(cleanup)
    try:
        yield
    finally:
        remove_cleanup(cleanup)


@contextmanager
def stop_future() -> Iterator[Future | None]:
    """A future that completes when a signal is recorded, for waits on worker processes.

    Yields None outside :func:`deferred_interrupts` (no signal is recorded there). A watcher
    thread looks at the flag every :data:`WATCH` seconds; the signal handler itself never
    touches the future (its lock may be held by the very wait the handler interrupted).
    """
    if not _state.active:
        yield None
        return
    fut: Future = Future()
    done = threading.Event()

    def watch():
        while not done.wait(WATCH):
            if _state.signum is not None:
                fut.set_result(_state.signum)
                return

    t = threading.Thread(target=watch, name="rankedassign-interrupt-watch", daemon=True)
    t.start()
    try:
        yield fut
    finally:
        done.set()
