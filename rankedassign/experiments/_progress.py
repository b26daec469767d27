"""The line ``reproduce`` shows while a study's kernels compile.

On the first run numba compiles each study's kernels before the study starts, and a study can
wait minutes for them (the herded samplers of ``tempering_herding`` the longest). A silent wait
that long looks like a hang, so :func:`compile_wait` names what compiles and, on a terminal,
keeps a spinner and the elapsed seconds ticking from a thread until the kernels are ready. On
anything else (a file, a pipe, a test's captured stream) it writes one plain line when the wait
begins and nothing more: carriage-return updates would fill a log with hundreds of lines.
"""

from __future__ import annotations

import shutil
import sys
import threading
import time
from contextlib import contextmanager

__all__ = ["compile_wait", "warm_description"]

_SPINNER = "|/-\\"


def warm_description(study, config) -> str:
    """What warming ``study`` compiles, in a few words: its kernel groups or its tiny tasks.

    Parameters
    ----------
    study : Study
        A registered study.
    config : object
        The study's own settings (their tiny form, :attr:`Study.warm`, is what runs).

    Returns
    -------
    str
        ``"kernels of <title>"`` followed by the warm groups (e.g. the problem kinds of
        ``tempering_herding``) or the number of tiny tasks; ``""`` for a study without a warm-up.

    Examples
    --------
    >>> from rankedassign.experiments import Config, get_study
    >>> from rankedassign.experiments._progress import warm_description
    >>> warm_description(get_study("glmb_tracking"), Config.quick().glmb_tracking)[:40]
    'kernels of δ-GLMB against LMB, exact, lo'
    """
    if study.warm is None:
        return ""
    tasks = list(study.tasks(study.warm(config), 0))
    text = f"kernels of {study.title}"
    if study.warm_group is None:
        return f"{text} ({len(tasks)} tiny task{'s' if len(tasks) != 1 else ''})"
    groups = list(dict.fromkeys(
        " ".join(map(str, g)) if isinstance(g, tuple) else str(g)
        for g in map(study.warm_group, tasks)))
    shown = ", ".join(groups[:6]) + (f" and {len(groups) - 6} more" if len(groups) > 6 else "")
    return f"{text}: {shown}"


@contextmanager
def compile_wait(tag: str, what: str, *, enabled: bool = True, stream=None,
                 interval: float = 0.5):
    """Show that ``what`` is compiling, and that the run is alive, until the block ends.

    Parameters
    ----------
    tag : str
        The study's place and name, e.g. ``"[12/12] tempering_herding"``.
    what : str
        What compiles (:func:`warm_description`).
    enabled : bool, optional
        False (``--quiet``): write nothing.
    stream : file, optional
        Where to write (default ``sys.stderr``).
    interval : float, optional
        Seconds between two updates of the ticking line (terminals only).

    Yields
    ------
    None

    Notes
    -----
    On a terminal the line is ``<tag>: compiling or loading <what> / 12 s`` with the spinner
    turning and the seconds counting, rewritten in place by a daemon thread, and erased when the
    block ends (the runner then prints how long it took). Elsewhere one line ending in ``...``
    is written when the block starts.

    Examples
    --------
    >>> import io
    >>> from rankedassign.experiments._progress import compile_wait
    >>> buf = io.StringIO()
    >>> with compile_wait("[1/1] table1", "kernels of Table I", stream=buf):
    ...     pass
    >>> print(buf.getvalue().strip())  # doctest: +NORMALIZE_WHITESPACE
    [1/1] table1: compiling or loading kernels of Table I (numba compiles them on the first
    run) ...
    """
    stream = sys.stderr if stream is None else stream
    if not enabled or not what:
        yield
        return
    text = f"{tag}: compiling or loading {what}"
    try:
        tty = stream.isatty()
    except (AttributeError, ValueError):
        tty = False
    if not tty:
        print(f"{text} (numba compiles them on the first run) ...", file=stream, flush=True)
        yield
        return
    stop = threading.Event()
    t0 = time.monotonic()
    # a line longer than the terminal wraps, and "\r" then rewrites only its last part
    room = max(20, shutil.get_terminal_size((100, 20)).columns - 12)
    if len(text) > room:
        text = text[:room - 1] + "…"

    def tick():
        i = 0
        while True:
            line = f"\r{text} {_SPINNER[i % len(_SPINNER)]} {time.monotonic() - t0:.0f} s"
            stream.write(line + "\x1b[K")  # erase what a longer line left behind
            stream.flush()
            i += 1
            if stop.wait(interval):
                return

    thread = threading.Thread(target=tick, name="rankedassign-compile-wait", daemon=True)
    thread.start()
    try:
        yield
    finally:
        stop.set()
        thread.join()
        stream.write("\r\x1b[K")
        stream.flush()
