"""``rankedassign reproduce``: run the studies and write the report directory atomically."""

from __future__ import annotations

import dataclasses
import datetime
import os
import platform
import shutil
import sys
import tempfile
import time
from contextlib import ExitStack
from pathlib import Path

from .._version import __version__
from ._executor import dask_executor, local_executor
from .ablation import run_ablation
from .config import STUDIES, Config
from .optimum import run_optimum
from .report import render_report, write_csv, write_json, write_plots
from .sweep import run_sweep
from .table1 import run_table1
from .tracking import run_tracking, run_tracking_var

__all__ = ["reproduce", "ReproduceError", "config_from_dict"]

_RUNNERS = {
    "table1": run_table1,
    "sweep": run_sweep,
    "tracking": run_tracking,
    "tracking_var": run_tracking_var,
    "ablation": run_ablation,
    "optimum": run_optimum,
}
_MANIFEST = "manifest.json"


class ReproduceError(ValueError):
    """Bad input to :func:`reproduce` (unknown study, bad count, unusable output directory)."""


def config_from_dict(base: Config, overrides: dict) -> Config:
    """``base`` with per-study fields replaced, e.g. ``{"table1": {"n_mc": 3}}``.

    Parameters
    ----------
    base : Config
    overrides : dict
        ``{study: {field: value}}``; lists become tuples.

    Returns
    -------
    Config

    Examples
    --------
    >>> from rankedassign.experiments import Config, config_from_dict
    >>> config_from_dict(Config.quick(), {"sweep": {"chain_lengths": [5]}}).sweep.chain_lengths
    (5,)
    """
    if not isinstance(overrides, dict):
        raise ReproduceError(f"config overrides must be a mapping of studies, got {overrides!r}")
    changes = {}
    for study, fields in overrides.items():
        if study not in STUDIES:
            raise ReproduceError(f"config: unknown study {study!r}; choose from {STUDIES}")
        sub = getattr(base, study)
        known = {f.name for f in dataclasses.fields(sub)}
        if not isinstance(fields, dict) or not set(fields) <= known:
            bad = sorted(set(fields) - known) if isinstance(fields, dict) else fields
            raise ReproduceError(f"config: unknown setting(s) {bad} for study {study!r}")
        vals = {k: tuple(v) if isinstance(v, list) else v for k, v in fields.items()}
        try:
            changes[study] = dataclasses.replace(sub, **vals)
        except (TypeError, ValueError) as exc:
            raise ReproduceError(f"config for {study!r}: {exc}") from None
    return dataclasses.replace(base, **changes)


def _check_out(out: Path, force: bool) -> None:
    if not out.exists():
        return
    if not force:
        raise ReproduceError(f"output directory {str(out)!r} exists; use --force to replace it")
    if not out.is_dir():
        raise ReproduceError(f"output path {str(out)!r} exists and is not a directory")
    if any(out.iterdir()) and not (out / _MANIFEST).exists():
        # --force replaces earlier reports only, never an unrelated non-empty directory.
        raise ReproduceError(
            f"refusing to replace {str(out)!r}: it is not empty and holds no {_MANIFEST} of an "
            "earlier report"
        )


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
        Any of ``"table1"``, ``"sweep"``, ``"tracking"``, ``"tracking_var"``, ``"ablation"``,
        ``"optimum"`` (default: all, in that order).
    mode : {"quick", "full"}
        ``"full"``: the paper's settings (100 Monte Carlo runs); ``"quick"``: the same per-run
        settings with fewer runs and sweep points (about five minutes on two cores).
    out : str or path, optional
        Report directory. It is written in a hidden temporary directory beside it and renamed
        into place at the end, so a failed or interrupted run never leaves a complete-looking
        report.
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
        Progress bars on stderr.
    command : str, optional
        Command line recorded in the report.

    Returns
    -------
    dict
        ``{study: result}`` as returned by the ``run_*`` functions.

    Raises
    ------
    ReproduceError
        Unknown study or mode, non-positive count, existing output directory without ``force``.
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
    studies = list(STUDIES if not studies else studies)
    unknown = [s for s in studies if s not in STUDIES]
    if unknown:
        raise ReproduceError(
            f"unknown study {unknown[0]!r}; choose from {', '.join(STUDIES)}"
        )
    studies = [s for s in STUDIES if s in studies]  # run order, no duplicates
    if mode not in ("quick", "full"):
        raise ReproduceError(f"mode must be 'quick' or 'full', got {mode!r}")
    for name, v in (("mc", mc), ("workers", workers)):
        if v is not None and (isinstance(v, bool) or not isinstance(v, int) or v < 1):
            raise ReproduceError(f"{name} must be a positive integer, got {v!r}")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ReproduceError(f"seed must be a non-negative integer, got {seed!r}")
    cfg = config if config is not None else (Config.quick() if mode == "quick" else Config.full())
    if mc is not None:
        cfg = cfg.with_mc(mc)
    out = Path(out)
    _check_out(out, force)

    started = datetime.datetime.now(datetime.timezone.utc)
    results: dict = {}
    seconds: dict = {}
    with ExitStack() as stack:
        if dask_scheduler is not None:
            executor = stack.enter_context(dask_executor(dask_scheduler))
            where = f"dask {dask_scheduler}"
        else:
            executor = stack.enter_context(local_executor(workers))
            n = workers or os.cpu_count() or 1
            where = "serial (in-process)" if executor is None else f"{n} local processes"
        out.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.partial-", dir=out.parent))
        # mkdtemp makes the directory private (0700); give the report the usual permissions.
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o777 & ~umask)
        try:
            for study in studies:
                t0 = time.perf_counter()
                res, runs = _RUNNERS[study](
                    cfg, seed=seed, executor=executor, progress=progress, return_runs=True
                )
                seconds[study] = time.perf_counter() - t0
                results[study] = res
                _write_study(tmp, study, res, runs)
            meta = {
                "command": command or "rankedassign.experiments.reproduce(...)",
                "version": __version__,
                "mode": cfg.mode if config is not None else mode,
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
            _replace(tmp, out)
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)
            raise
    if progress:
        print(f"report written to {out / 'report.md'}", file=sys.stderr)
    return results


def _write_study(tmp: Path, study: str, res, runs) -> None:
    write_json(tmp / f"{study}.json", res)
    write_json(tmp / f"{study}_runs.json", runs)
    if study in ("tracking", "tracking_var"):
        cur = res["curves"]
        write_csv(tmp / f"{study}.csv",
                  [{k: cur[k][i] for k in cur} for i in range(len(cur["scan"]))])
    else:
        write_csv(tmp / f"{study}.csv", res)
    write_plots(study, res, tmp)


def _replace(tmp: Path, out: Path) -> None:
    """Move the finished report into place (replacing an earlier one)."""
    old = None
    if out.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{out.name}.old-", dir=out.parent))
        os.replace(out, old / out.name)
    os.replace(tmp, out)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
