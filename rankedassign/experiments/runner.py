"""``rankedassign reproduce``: run the studies and write the report directory atomically."""

from __future__ import annotations

import datetime
import os
import platform
import shutil
import sys
import tempfile
import time
from contextlib import ExitStack
from pathlib import Path

from .. import warmup
from .._version import __version__
from ._executor import dask_executor, local_executor
from .config import Table1Config, TrackingConfig
from .registry import Config, ReproduceError, get_study, run_study, study_names
from .report import render_report, write_csv, write_json
from .table1 import table1_task
from .tracking import tracking_task

__all__ = ["reproduce", "check_output"]

_MANIFEST = "manifest.json"


def check_output(out, force: bool = False) -> None:
    """Check, before any study runs, that a report can be written to ``out``.

    Parameters
    ----------
    out : str or path
        The report directory.
    force : bool, optional
        Whether an earlier report in ``out`` may be replaced.

    Raises
    ------
    ReproduceError
        With a one-line message: ``out`` is a file; it exists without ``force``; it holds
        something other than an earlier report; a parent is not a directory or cannot be
        created; the parent directory is not writable; ``out`` cannot be moved away (needed to
        replace it).

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
    if out.exists() or out.is_symlink():
        if not out.is_dir():
            raise ReproduceError(
                f"output path {str(out)!r} is a file, not a directory; --force replaces only "
                "an earlier report directory: choose another --out"
            )
        if not force:
            raise ReproduceError(
                f"output directory {str(out)!r} exists; use --force to replace it"
            )
        if any(out.iterdir()) and not (out / _MANIFEST).exists():
            # --force replaces earlier reports only, never an unrelated non-empty directory.
            raise ReproduceError(
                f"refusing to replace {str(out)!r}: it is not empty and holds no {_MANIFEST} "
                "of an earlier report"
            )
    parent = out.parent
    for p in (parent, *parent.parents):
        if p.exists() or p.is_symlink():
            if not p.is_dir():
                raise ReproduceError(f"{where}: a parent, {str(p)!r}, is a file, not a directory")
            break
    try:
        parent.mkdir(parents=True, exist_ok=True)
        probe = Path(tempfile.mkdtemp(prefix=f".{out.name}.probe-", dir=parent))
    except OSError as exc:
        raise ReproduceError(f"{where}: {exc.strerror or exc}") from None
    try:
        if force and out.is_dir():
            # Replacing needs out to move away: try it now, not after the studies.
            try:
                os.replace(out, probe / out.name)
            except OSError as exc:
                raise ReproduceError(
                    f"cannot replace {str(out)!r}: it cannot be moved ({exc.strerror or exc})"
                ) from None
            os.replace(probe / out.name, out)
    finally:
        shutil.rmtree(probe, ignore_errors=True)


def compile_kernels() -> None:
    """Compile (or load from numba's cache) every kernel the studies use, in this process.

    Run before the worker processes start, so that on a first run they load the compiled
    kernels from the on-disk cache instead of each compiling them while the progress bars
    stand still.
    """
    warmup()
    table1_task(Table1Config(n_mc=1, families=("random",), original_obs=10, n_chains=2),
                0, 0, "random")
    tiny = TrackingConfig(n_mc=1, n_scans=2, original_obs=5, n_chains=2)
    for method in ("original", "proposed"):
        tracking_task(tiny, 0, 0, method)


def _study_list(studies) -> list[str]:
    names = study_names()
    chosen = list(names if not studies else studies)
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
    studies : sequence of str, optional
        Registered study names (:func:`~rankedassign.experiments.study_names`: ``"table1"``,
        ``"sweep"``, ``"tracking"``, ``"tracking_var"``, ``"ablation"``, ``"optimum"``,
        ``"random_readings"``); default: all, in that order.
    mode : {"quick", "full"}
        ``"full"``: the paper's settings (100 Monte Carlo runs); ``"quick"``: the same per-run
        settings with fewer runs and sweep points (a few minutes on two cores).
    out : str or path, optional
        Report directory. It is written in a hidden temporary directory beside it and renamed
        into place at the end, so a failed or interrupted run never leaves a complete-looking
        report. Checked before any study runs (:func:`check_output`).
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
        Replace ``out`` if it holds an earlier report.
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
        or replaced (checked before any study runs); if the finished report cannot be moved
        into place at the end, the message names the directory it was kept in.
    SchedulerError
        The Dask scheduler cannot be reached.

    Notes
    -----
    Files: ``report.md``; per study ``<study>.json`` (summary), ``<study>.csv`` and
    ``<study>_runs.json`` (per-run records); PNG plots; ``config.json``; ``manifest.json``
    (written last; ``force`` only ever replaces a directory holding one).

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
    studies = _study_list(studies)
    if mode not in ("quick", "full"):
        raise ReproduceError(f"mode must be 'quick' or 'full', got {mode!r}")
    for name, v in (("mc", mc), ("workers", workers)):
        if v is not None and (isinstance(v, bool) or not isinstance(v, int) or v < 1):
            raise ReproduceError(f"{name} must be a positive integer, got {v!r}")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ReproduceError(f"seed must be a non-negative integer, got {seed!r}")
    cfg = config if config is not None else Config(mode)
    if mc is not None:
        cfg = cfg.with_mc(mc)
    out = Path(out)
    check_output(out, force)

    def say(text):
        if progress:
            print(text, file=sys.stderr, flush=True)

    started = datetime.datetime.now(datetime.timezone.utc)
    results: dict = {}
    seconds: dict = {}
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.partial-", dir=out.parent))
    # mkdtemp makes the directory private (0700); give the report the usual permissions.
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o777 & ~umask)
    try:
        with ExitStack() as stack:
            t0 = time.perf_counter()
            say("preparing the compiled kernels (numba compiles them on the first run, "
                "which takes a minute or two; later runs load them from its cache) ...")
            compile_kernels()
            say(f"kernels ready in {time.perf_counter() - t0:.0f} s")
            if dask_scheduler is not None:
                executor = stack.enter_context(dask_executor(dask_scheduler))
                where = f"dask {dask_scheduler}"
            else:
                executor = stack.enter_context(local_executor(workers))
                n = workers or os.cpu_count() or 1
                where = "serial (in-process)" if executor is None else f"{n} local processes"
            for i, study in enumerate(studies, 1):
                t0 = time.perf_counter()
                res, runs = run_study(
                    study, cfg, seed=seed, executor=executor, progress=progress,
                    return_runs=True, desc=f"[{i}/{len(studies)}] {study}",
                )
                seconds[study] = time.perf_counter() - t0
                results[study] = res
                _write_study(tmp, study, res, runs)
        meta = {
            "command": command or "rankedassign.experiments.reproduce(...)",
            "version": __version__,
            "mode": cfg.mode,
            "seed": seed,
            "studies": studies,
            "executor": where,
            "started": started.strftime("%Y-%m-%d %H:%M:%S"),
            "seconds": seconds,
            "python": platform.python_version(),
            "platform": platform.platform(),
            "cpu_count": os.cpu_count(),
        }
        write_json(tmp / "config.json", cfg.to_dict())
        (tmp / "report.md").write_text(render_report(results, cfg, meta))
        write_json(tmp / _MANIFEST, meta)  # last file: marks a complete report
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    _replace(tmp, out)
    say(f"report written to {out / 'report.md'}")
    return results


def _write_study(tmp: Path, name: str, res, runs) -> None:
    st = get_study(name)
    write_json(tmp / f"{name}.json", res)
    write_json(tmp / f"{name}_runs.json", runs)
    write_csv(tmp / f"{name}.csv", st.csv_rows(res))
    if st.plot is not None:
        st.plot(res, tmp)


def _replace(tmp: Path, out: Path) -> None:
    """Move the finished report into place (replacing an earlier one); never lose it.

    If the move fails, the earlier report is put back and the finished one is kept under a
    visible name beside ``out``, which the raised :class:`ReproduceError` names.
    """
    old = None
    moved = False
    try:
        if out.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{out.name}.old-", dir=out.parent))
            os.replace(out, old / out.name)
            moved = True
        os.replace(tmp, out)
    except OSError as exc:
        if moved and not out.exists():
            try:
                os.replace(old / out.name, out)
                moved = False
            except OSError:
                pass
        stamp = datetime.datetime.now().strftime("%Y%m%d-%H%M%S")
        kept = out.parent / f"{out.name}.new-{stamp}"
        try:
            os.replace(tmp, kept)
        except OSError:
            kept = tmp
        earlier = ("" if not moved else
                   f"; the earlier report is in {str(old / out.name)!r}")
        if old is not None and not moved:
            shutil.rmtree(old, ignore_errors=True)
        raise ReproduceError(
            f"could not move the finished report into {str(out)!r} ({exc.strerror or exc}); "
            f"it is kept in {str(kept)!r}{earlier}"
        ) from None
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
