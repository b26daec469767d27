"""``rankedassign reproduce``: run the studies and write the report directory atomically."""

from __future__ import annotations

import dataclasses
import datetime
import functools
import os
import platform
import sys
import tempfile
import time
import warnings
from contextlib import ExitStack
from pathlib import Path
from typing import NamedTuple

from .._version import __version__
from ..validation import MAX_MC
from . import _interrupts, _outdir
from ._executor import SchedulerError, dask_executor, local_executor
from ._progress import compile_wait, warm_description
from .precompile import warm_studies
from .registry import (
    Config,
    ReproduceError,
    default_study_names,
    get_study,
    run_study,
    study_names,
    warm_study,
)
from .report import render_report, write_csv, write_json

__all__ = ["reproduce", "check_output", "check_settings", "StudyFailed"]

_MANIFEST = _outdir.MANIFEST


class StudyFailed(ReproduceError):
    """A study raised an error; the report of the studies that finished before it was kept."""


def check_output(out, force: bool = False) -> OutputState:
    """Check, before any study runs, that a report can be written to ``out``.

    Parameters
    ----------
    out : str or path
        The report directory.
    force : bool, optional
        Whether an earlier report in ``out`` may be replaced.

    Returns
    -------
    OutputState
        What was found at ``out`` (``before``: its fingerprint, or None if it does not exist;
        ``names``: its entries), checked again when the finished report replaces it.

    Raises
    ------
    ReproduceError
        With a one-line message: ``out`` is a file or a symbolic link; it exists without
        ``force``; it is not recognised as an earlier report by its content (a manifest of
        this program's schema and nothing but the files that report wrote), ``force`` or
        not; it is a mount point (it could not be replaced); a parent is not a directory or
        cannot be created; the parent directory is not writable.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from rankedassign.experiments import ReproduceError, check_output
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "notes.txt"
    >>> _ = f.write_text("x")
    >>> try:
    ...     check_output(f / "report")
    ... except ReproduceError as exc:
    ...     print(str(exc).endswith("notes.txt', is a file, not a directory"))
    True
    """
    out = Path(out)
    where = f"cannot write the report to {str(out)!r}"
    before = names = None
    if out.is_symlink():
        raise ReproduceError(
            f"output path {str(out)!r} is a symbolic link; --force replaces only an earlier "
            "report directory: choose another --out"
        )
    if out.exists():
        if not out.is_dir():
            raise ReproduceError(
                f"output path {str(out)!r} is a file, not a directory; --force replaces only "
                "an earlier report directory: choose another --out"
            )
        if not force:
            raise ReproduceError(
                f"output directory {str(out)!r} exists; use --force to replace it"
            )
        why = _outdir.not_a_report(out)
        if why is not None:
            # --force replaces earlier reports only, never a directory with anything else in it
            raise ReproduceError(f"refusing to replace {str(out)!r}: {why}")
        if os.path.ismount(out):
            raise ReproduceError(
                f"cannot replace {str(out)!r}: it is a mount point and cannot be moved"
            )
        before = _outdir.fingerprint(out)
        names = {name for name, *_ in before[2]}
    parent = out.parent
    for p in (parent, *parent.parents):
        if p.exists() or p.is_symlink():
            if not p.is_dir():
                raise ReproduceError(f"{where}: a parent, {str(p)!r}, is a file, not a directory")
            break
    with _interrupts.critical():  # the probe directory is never left behind
        try:
            parent.mkdir(parents=True, exist_ok=True)
            probe = tempfile.mkdtemp(prefix=f".{out.name}.probe-", dir=parent)
        except OSError as exc:
            raise ReproduceError(f"{where}: {exc.strerror or exc}") from None
        os.rmdir(probe)
    return OutputState(before, names)


class OutputState(NamedTuple):
    """What :func:`check_output` found at the report directory.

    Attributes
    ----------
    before : tuple or None
        Its fingerprint (device, inode, entries with mode, size and mtime), or None if it did
        not exist.
    names : set of str or None
        The names of its entries (the files of the earlier report).
    """

    before: tuple | None
    names: set | None


def check_settings(config: Config) -> None:
    """Check the settings of every study in ``config`` again, before any study runs.

    Each study's settings type checks its fields when it is made; this runs those checks
    once more on the objects that will run, so that a record changed after it was made (or a
    settings type registered by another package) fails here, naming the study, and not after
    the studies before it have run for minutes.

    Parameters
    ----------
    config : Config
        The settings of the run.

    Raises
    ------
    ReproduceError
        ``"settings of study '<name>': <field> must ..., got <value>"`` for the first study
        (in run order) whose settings are refused.

    Examples
    --------
    >>> import dataclasses
    >>> from rankedassign.experiments import Config, ReproduceError
    >>> from rankedassign.experiments.runner import check_settings
    >>> cfg = Config.quick()
    >>> object.__setattr__(cfg.tracking, "ospa_p", 0.5)  # bypasses the check on creation
    >>> try:
    ...     check_settings(cfg)
    ... except ReproduceError as exc:
    ...     print(exc)
    settings of study 'tracking': ospa_p must be >= 1.0, got 0.5
    """
    for name in study_names():
        try:
            dataclasses.replace(config[name])  # runs the type's __post_init__ checks again
        except (TypeError, ValueError) as exc:
            raise ReproduceError(f"settings of study {name!r}: {exc}") from None


def _study_list(studies) -> list[str]:
    names = study_names()
    if isinstance(studies, str):
        if studies not in ("all", "paper"):
            raise ReproduceError(
                f"studies must be 'paper', 'all' or a sequence of study names, got {studies!r}")
        studies = names if studies == "all" else default_study_names()
    chosen = list(default_study_names() if not studies else studies)
    for s in chosen:
        get_study(s)  # raises for an unknown name
    return [s for s in names if s in chosen]  # run order, no duplicates


def reproduce(
    studies=None,
    mode: str = "quick",
    out="rankedassign-report",
    *,
    config: Config | None = None,
    seed: int = 0,
    mc: int | None = None,
    workers: int | None = None,
    dask_scheduler: str | None = None,
    force: bool = False,
    progress: bool = True,
    command: str | None = None,
) -> dict:
    """Run studies of the paper and write ``out/report.md`` with plots, JSON and CSV.

    Parameters
    ----------
    studies : sequence of str, "paper" or "all", optional
        Registered study names (:func:`~rankedassign.experiments.study_names`), run in the
        registry's order; ``"all"``: every registered study; ``"paper"`` (the default): the
        paper's studies (:func:`~rankedassign.experiments.default_study_names`:
        ``"table1"``, ``"sweep"``, ``"tracking"``, ``"tracking_var"``, ``"ablation"``,
        ``"optimum"``, ``"random_readings"``); the studies of the later methods
        (``"glmb_tracking"``, ``"nonlinear_tracking"``, ``"scaling"``, ``"multisensor"``,
        ``"adaptive_birth"``, ``"multisensor_tracking"``, ``"tempering_herding"``) run when
        named or with ``"all"``. The default used to be every study: leaving ``studies``
        out warns (``FutureWarning``) for one release; pass ``"paper"`` or ``"all"``.
    mode : {"quick", "full"}
        ``"full"``: the paper's settings (100 Monte Carlo runs); ``"quick"``: the same per-run
        settings with fewer runs and sweep points (see the README for its measured time).
    out : str or path, optional
        Report directory. It is written in a hidden temporary directory beside it and renamed
        into place atomically at the end, so a failed or interrupted run never leaves a
        complete-looking report. Checked before any study runs (:func:`check_output`), and
        locked for the run (``.<out>.lock`` beside it).
    config : Config, optional
        Settings to use instead of ``mode``'s.
    seed : int, optional
        Study seed; Monte Carlo run ``r`` uses ``np.random.SeedSequence(seed).spawn(n)[r]``.
    mc : int, optional
        Override the number of Monte Carlo runs of every study.
    workers : int, optional
        Local worker processes (default: number of CPUs; 1 runs in this process).
    dask_scheduler : str, optional
        Address of a Dask scheduler; runs go to its cluster instead of local processes.
    force : bool, optional
        Replace ``out`` if it is an earlier report (recognised by its content, see
        :func:`check_output`).
    progress : bool, optional
        Progress bars on stderr (with the study's place in the run, e.g. ``[2/6] sweep``).
    command : str, optional
        Command line recorded in the report.

    Returns
    -------
    dict
        ``{study: summary}`` as returned by :func:`~rankedassign.experiments.run_study`.

    Raises
    ------
    ReproduceError
        Unknown study or mode, non-positive count, an output location that cannot be written
        or replaced (checked before any study runs), another run writing to the same ``out``
        (it holds ``out``'s lock); if ``out`` appeared or changed while the run worked, or the
        finished report cannot be moved into place, the message names the directory the
        finished report was kept in.
    StudyFailed
        A study raised an error: the later ones are not run, and the report of the studies that
        finished before it is written (its manifest says which study failed and how) to
        ``out``, or, if ``out`` holds an earlier report, to a visible directory beside it that
        the message names.
    SchedulerError
        The Dask scheduler cannot be reached.

    Notes
    -----
    Files: ``report.md``; per study ``<study>.json`` (summary), ``<study>.csv`` and
    ``<study>_runs.json`` (per-run records); PNG plots; ``config.json``; ``manifest.json``
    (written last, with the schema ``rankedassign-report/1`` and the list of the report's
    files; ``force`` only ever replaces a directory that holds such a manifest and nothing but
    the files it lists). Partial reports of runs that were killed are removed by the next run
    into the same ``out`` (it holds the lock, so they are provably dead).

    References
    ----------
    .. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from rankedassign.experiments import Config, config_from_dict, reproduce
    >>> cfg = config_from_dict(Config.quick(), {"table1": {"n_mc": 1, "families": ["diagonal"],
    ...     "original_obs": 200, "n_chains": 8}})
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "report"
    >>> res = reproduce(["table1"], out=out, config=cfg, workers=1, progress=False)
    >>> sorted(p.name for p in out.iterdir())[:4]
    ['config.json', 'manifest.json', 'report.md', 'table1.csv']
    """
    if studies is None:
        warnings.warn("reproduce() without studies now runs the paper's seven studies, no "
                      "longer every study: pass studies='paper' for these, or studies='all' "
                      "for every study", FutureWarning, stacklevel=2)
    studies = _study_list(studies)
    if mode not in ("quick", "full"):
        raise ReproduceError(f"mode must be 'quick' or 'full', got {mode!r}")
    for name, v in (("mc", mc), ("workers", workers)):
        if v is not None and (isinstance(v, bool) or not isinstance(v, int) or v < 1):
            raise ReproduceError(f"{name} must be a positive integer, got {v!r}")
    if mc is not None and mc > MAX_MC:
        raise ReproduceError(f"mc must be at most {MAX_MC} (a study keeps every run's record "
                             f"in memory), got {mc}")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ReproduceError(f"seed must be a non-negative integer, got {seed!r}")
    cfg = config if config is not None else Config(mode)
    if not isinstance(cfg, Config):
        raise ReproduceError(f"config must be a Config, got {type(cfg).__name__}")
    if mc is not None:
        cfg = cfg.with_mc(mc)
    check_settings(cfg)
    out = Path(out)
    command = command or "rankedassign.experiments.reproduce(...)"

    def say(text):
        if progress:
            print(text, file=sys.stderr, flush=True)

    check_output(out, force)  # the plain errors first; it also makes the parent directory
    # The lock is held from the authoritative check until the finished report is in place, so
    # a run that starts later into the same out is refused and told which run holds it.
    _interrupts.check()
    with _outdir.run_lock(out, command) as lock, _interrupts.on_hard_exit(lock.release):
        state = check_output(out, force)
        for note in [*lock.notes, *_outdir.remove_stale_partials(out)]:
            print(f"rankedassign reproduce: note: {note}", file=sys.stderr, flush=True)
        results, failure = _run_studies(studies, cfg, out, seed=seed, workers=workers,
                                        dask_scheduler=dask_scheduler, progress=progress,
                                        command=command, say=say, state=state)
    if failure is not None:
        study, error, where = failure
        raise StudyFailed(
            f"study {study!r} failed ({error}); the report of the studies that finished "
            f"before it ({', '.join(results)}) was written to {str(where)!r}"
        )
    say(f"report written to {out / 'report.md'}")
    return results


def _warm_all(studies, cfg, executor, *, progress, say) -> bool:
    """Every study's tiny tasks at once, on the local workers: they compile the kernels of
    different studies side by side while no two compile the same ones (measured from an empty
    cache, the paper's seven studies one after another waited 43 s for kernels where their
    compiling alone takes 38 s of CPU). Returns whether it finished; if not, the failure is
    left to each study's own warm-up, which runs it again and reports it as that study's
    failure."""
    what = f"the kernels of the {len(studies)} studies side by side"
    try:
        with compile_wait("all studies", what, enabled=progress):
            secs = warm_studies(studies, cfg, executor)
    except Exception:  # noqa: BLE001 - each study's own warm-up runs it again and reports it
        _interrupts.check()
        say("all studies: preparing the kernels together failed; each study prepares its own")
        return False
    say(f"all studies: kernels ready in {secs:.1f} s")
    return True


def _run_studies(studies, cfg, out, *, seed, workers, dask_scheduler, progress, command, say,
                 state):
    """Run the studies into a partial report beside ``out`` and move it into place.

    Returns ``(results, failure)``: ``failure`` is ``(study, message, where)`` of a study that
    raised an error, with the directory that holds the report of the studies before it
    (``out``, or a visible directory beside an earlier report, which it never replaces), else
    None; :class:`StudyFailed` if no study finished. An interrupt or any error
    outside a study removes the partial report and propagates.
    """
    started = datetime.datetime.now(datetime.timezone.utc)
    results: dict = {}
    seconds: dict = {}
    failure = None
    tmp = _outdir.new_partial(out, command)
    # a second signal ends the process at once: the partial report is removed first, until it
    # is complete and about to be moved into place
    cleanup = functools.partial(_outdir.remove_files, tmp)
    _interrupts.add_cleanup(cleanup)
    try:
        with ExitStack() as stack:
            say("preparing each study's compiled kernels before it starts (numba compiles "
                "them on the first run, later runs load them from its cache) ...")
            if dask_scheduler is not None:
                executor = stack.enter_context(dask_executor(dask_scheduler))
                where = f"dask {dask_scheduler}"
            else:
                executor = stack.enter_context(local_executor(workers))
                n = workers or os.cpu_count() or 1
                where = "serial (in-process)" if executor is None else f"{n} local processes"
            # with local workers every study's tiny tasks run once, all at once, here
            warmed = (dask_scheduler is None and executor is not None and len(studies) > 1
                      and _warm_all(studies, cfg, executor, progress=progress, say=say))
            for i, study in enumerate(studies, 1):
                tag = f"[{i}/{len(studies)}] {study}"
                _interrupts.check()  # a safe point between two studies
                try:
                    # The tiny tasks on the workers, disjoint kernel sets side by side; the
                    # study's tasks then load the kernels from the cache.
                    # the wait says what compiles and that it is alive (minutes, first run)
                    if warmed:
                        say(f"{tag}: kernels ready (prepared with the other studies)")
                    else:
                        with compile_wait(tag, warm_description(get_study(study), cfg[study]),
                                          enabled=progress):
                            secs = warm_study(study, cfg, executor=executor)
                        say(f"{tag}: kernels ready in {secs:.1f} s")
                    t0 = time.perf_counter()
                    res, runs = run_study(
                        study, cfg, seed=seed, executor=executor, progress=progress,
                        return_runs=True, desc=tag,
                    )
                except (ReproduceError, SchedulerError):
                    raise
                except Exception as exc:  # a study's own failure: keep what finished
                    # unless a signal caused it (an interrupt that surfaced as another error)
                    _interrupts.check()
                    failure = (study, f"{type(exc).__name__}: {exc}")
                    break
                seconds[study] = time.perf_counter() - t0
                results[study] = res
                _write_study(tmp, study, res, runs)
            _interrupts.check()
        meta = {
            "schema": _outdir.SCHEMA,
            "command": command,
            "version": __version__,
            "mode": cfg.mode,
            "seed": seed,
            "studies": list(results),
            "executor": where,
            "started": started.strftime("%Y-%m-%d %H:%M:%S"),
            "seconds": seconds,
            "python": platform.python_version(),
            "platform": platform.platform(),
            "cpu_count": os.cpu_count(),
        }
        if failure is not None:
            meta["failed"] = {"study": failure[0], "error": failure[1],
                              "not_run": studies[studies.index(failure[0]) + 1:]}
        write_json(tmp / "config.json", cfg.to_dict())
        (tmp / "report.md").write_text(render_report(results, cfg, meta))
        # last file: marks a complete report, and lists every file it holds
        meta["files"] = sorted({_MANIFEST, *(p.name for p in tmp.iterdir())} - {_outdir.OWNER})
        write_json(tmp / _MANIFEST, meta)
        if failure is not None and not results:
            raise StudyFailed(f"study {failure[0]!r} failed ({failure[1]}); no study finished, "
                              "nothing was written")
        # the last safe point: from here the report is moved into place, which a signal
        # does not cut short (it is recorded and acted on after the move)
        _interrupts.check()
    except BaseException:
        _outdir.remove_files(tmp)
        _interrupts.remove_cleanup(cleanup)
        raise
    _interrupts.remove_cleanup(cleanup)
    if failure is not None and state.before is not None:
        # an incomplete report never replaces an earlier complete one: it goes beside it
        (tmp / _outdir.OWNER).unlink(missing_ok=True)
        kept = _outdir.keep_beside(tmp, out, "incomplete")
        return results, (*failure, kept)
    for note in _outdir.place(tmp, out, state.before, state.names):
        print(f"rankedassign reproduce: note: {note}", file=sys.stderr, flush=True)
    return results, None if failure is None else (*failure, out)


def _write_study(tmp: Path, name: str, res, runs) -> None:
    st = get_study(name)
    write_json(tmp / f"{name}.json", res)
    write_json(tmp / f"{name}_runs.json", runs)
    write_csv(tmp / f"{name}.csv", st.csv_rows(res))
    if st.plot is not None:
        st.plot(res, tmp)
