"""Command-line interface: ``rankedassign``.

Every failure the user can cause ends with a one-line message on stderr and exit status 2, never
a traceback; an interrupted ``reproduce`` (Ctrl-C or SIGTERM) ends with status 130 (143) and
leaves no partial report behind. The signal is recorded and acted on at a safe point (see
:mod:`rankedassign.experiments._interrupts`); a second one ends the process at once, after
removing the run's lock and partial report.
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import signal
import sys
import warnings
from pathlib import Path

import numpy as np

from . import experiments
from ._version import __version__
from .experiments import _interrupts
from .experiments.precompile import precompile
from .single import synthetic
from .validation import MAX_MC


def _cmd_demo(args) -> int:
    rng = np.random.default_rng(args.seed)
    for name, prob in (
        ("diagonal", synthetic.diagonal()),
        ("uniform", synthetic.uniform()),
        ("random", synthetic.random(rng=rng)),
    ):
        best = prob.cost_of(prob.all_missed())
        print(
            f"{name:9s} shape {prob.shape}  |Gamma| = {prob.n_feasible():,}  "
            f"cost(all missed) = {best:.4f}"
        )
    return 0


def _int_at_least(text: str, minimum: int, what: str) -> int:
    """``text`` as an int of at least ``minimum``, else argparse's error naming ``what``."""
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be {what}, got {text!r}") from None
    if v < minimum:
        raise argparse.ArgumentTypeError(f"must be {what}, got {text!r}")
    return v


def _positive_int(text: str) -> int:
    return _int_at_least(text, 1, "a positive integer")


def _mc(text: str) -> int:
    v = _positive_int(text)
    if v > MAX_MC:
        raise argparse.ArgumentTypeError(
            f"must be at most {MAX_MC} (a study keeps every run's record in memory), got {text!r}"
        )
    return v


def _seed(text: str) -> int:
    return _int_at_least(text, 0, "a non-negative integer")


# A settings file is {study: {setting: value}}, values at most lists of lists: 4 levels.
# Deeper is not a settings file; refused before anything walks it recursively.
_MAX_CONFIG_DEPTH = 16
# A settings file is a few kilobytes; this is not read whole beyond 16 MiB.
_MAX_CONFIG_BYTES = 1 << 24


def _depth(value) -> int:
    """Nesting depth of JSON data (a scalar is 0), without recursion."""
    deepest, stack = 0, [(value, 1)]
    while stack:
        v, d = stack.pop()
        items = v.values() if isinstance(v, dict) else v if isinstance(v, list) else None
        if items is None:
            continue
        deepest = max(deepest, d)
        if d > _MAX_CONFIG_DEPTH:
            break
        stack.extend((x, d + 1) for x in items)
    return deepest


def _read_config(path: str) -> dict:
    """The overrides in the ``--config`` file ``path``: a JSON object of studies."""
    try:
        with open(path, "rb") as f:
            data = f.read(_MAX_CONFIG_BYTES + 1)
    except OSError as exc:
        raise experiments.ReproduceError(f"cannot read --config {path!r}: {exc}") from None
    if len(data) > _MAX_CONFIG_BYTES:
        raise experiments.ReproduceError(
            f"config file {path!r} is larger than {_MAX_CONFIG_BYTES >> 20} MiB; a settings "
            "file is a JSON object of a few studies' settings")
    try:
        overrides = json.loads(data)
    except RecursionError:
        overrides = None
    except (UnicodeDecodeError, ValueError) as exc:
        raise experiments.ReproduceError(f"cannot read --config {path!r}: {exc}") from None
    if overrides is None and data.strip() != b"null" or _depth(overrides) > _MAX_CONFIG_DEPTH:
        raise experiments.ReproduceError(
            f"config file {path!r} is nested too deeply (more than {_MAX_CONFIG_DEPTH} levels); "
            'a settings file is a JSON object of studies, e.g. {"table1": {"n_mc": 5}}')
    if not isinstance(overrides, dict):
        kind = {list: "an array", str: "a string", bool: "a boolean", type(None): "null"}.get(
            type(overrides), "a number")
        raise experiments.ReproduceError(
            f"config file {path!r} must hold a JSON object of studies, e.g. "
            f'{{"table1": {{"n_mc": 5}}}}, not {kind}')
    return overrides


def _error(message: str) -> int:
    print(f"rankedassign reproduce: error: {message}", file=sys.stderr)
    return 2


def available_cpus() -> int:
    """CPUs this process may run on (its affinity mask where the platform has one)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # pragma: no cover - platforms without affinity
        return max(1, os.cpu_count() or 1)


def _cmd_reproduce(args) -> int:
    names = experiments.study_names()
    unknown = [s for s in args.studies if s not in names]
    if unknown:
        return _error(f"unknown study {unknown[0]!r}; choose from {', '.join(names)}")
    if args.all and args.studies:
        return _error("--all runs every study; name studies or give --all, not both")
    workers = args.workers
    if workers is not None and args.dask_scheduler is None and workers > available_cpus():
        n = available_cpus()
        print(f"rankedassign reproduce: note: --workers {workers} is more than the {n} "
              f"CPU{'s' if n != 1 else ''} available; using {n}", file=sys.stderr)
        workers = n
    mode = "full" if args.full else "quick"
    config = None
    # SIGINT and SIGTERM are recorded and acted on at safe points (experiments._interrupts);
    # a second one ends the process at once, after removing the lock and the partial report
    guard = _interrupts.deferred_interrupts(
        "rankedassign reproduce: {signal} again: stopped at once; the lock and the partial "
        "report were removed, no report written\n")
    try:
        guard.__enter__()
        if args.config is not None:
            with warnings.catch_warnings():
                # a deprecated setting's warning is for the user who wrote the file: shown
                # on stderr (Python hides DeprecationWarning outside __main__ by default)
                warnings.simplefilter("always", DeprecationWarning)
                config = experiments.config_from_dict(experiments.Config(mode),
                                                      _read_config(args.config))
        experiments.reproduce(
            "all" if args.all else (args.studies or "paper"),
            mode,
            args.out,
            config=config,
            seed=args.seed,
            mc=args.mc,
            workers=workers,
            dask_scheduler=args.dask_scheduler,
            force=args.force,
            progress=not args.quiet,
            command=shlex.join(["rankedassign", *args.argv]),
        )
    except experiments.StudyFailed as exc:
        print(f"rankedassign reproduce: error: {exc}", file=sys.stderr)
        return 1
    except (experiments.ReproduceError, experiments.SchedulerError) as exc:
        return _error(str(exc))
    except KeyboardInterrupt:
        print("rankedassign reproduce: interrupted; no report written", file=sys.stderr)
        return 130
    except _interrupts.Terminated:
        print("rankedassign reproduce: terminated (SIGTERM); no report written",
              file=sys.stderr)
        return 128 + signal.SIGTERM
    else:
        signum = _interrupts.pending()
        if signum is not None:  # it came while the finished report was moved into place
            print(f"rankedassign reproduce: {signal.Signals(signum).name} received as the run "
                  f"was finishing; the report is complete in {str(Path(args.out))!r}",
                  file=sys.stderr)
            return 128 + signum
    finally:
        guard.__exit__(None, None, None)
    return 0


def _cmd_precompile(args) -> int:
    workers = args.workers
    if workers is not None and workers > available_cpus():
        workers = available_cpus()
    try:
        secs = precompile(workers, studies=args.studies or None, progress=not args.quiet)
    except experiments.ReproduceError as exc:
        print(f"rankedassign precompile: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("rankedassign precompile: interrupted", file=sys.stderr)
        return 130
    print(f"rankedassign precompile: kernels ready in {secs:.1f} s", file=sys.stderr)
    return 0


def _study_command(sub, name: str, names, help: str, description: str, default: str = "all"):
    """A sub-command taking study names (``default`` says which run when none is given)."""
    cmd = sub.add_parser(name, help=help, description=description)
    cmd.add_argument("studies", nargs="*", metavar="STUDY",
                     help=f"{', '.join(names)} (default: {default})")
    return cmd


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``rankedassign`` command."""
    parser = argparse.ArgumentParser(
        prog="rankedassign",
        description=(
            "Ranked assignment for labeled RFS trackers: Gibbs samplers (original and "
            "short-chain with stall/stale), exact oracle, LMB filter, paper reproduction."
        ),
    )
    names = experiments.study_names()
    parser.add_argument("--version", action="version", version=f"rankedassign {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    demo = sub.add_parser("demo", help="print the paper's synthetic matrices and their sizes")
    demo.add_argument("--seed", type=_seed, default=0, help="seed of the random matrix")
    demo.set_defaults(func=_cmd_demo)

    paper = experiments.default_study_names()
    later = [n for n in names if n not in paper]
    rep = _study_command(
        sub, "reproduce", names,
        "run the paper's studies and write a report (markdown, PNG, JSON, CSV)",
        "Reproduce the studies of Trezza, Bucci & Varshney (2023): "
        + "; ".join(f"{s.name} ({s.title})" for s in map(experiments.get_study, paper))
        + ". The studies of the methods after it run when named or with --all: "
        + "; ".join(f"{s.name} ({s.title})" for s in map(experiments.get_study, later))
        + ". Without --full every study runs the paper's per-run settings with fewer Monte "
        "Carlo runs.",
        default="the paper's studies, " + ", ".join(paper))
    rep.add_argument("--all", action="store_true",
                     help="run every study: the paper's and those of the later methods")
    size = rep.add_mutually_exclusive_group()
    size.add_argument("--quick", action="store_true", help="fewer Monte Carlo runs (default)")
    size.add_argument("--full", action="store_true", help="the paper's settings (100 runs)")
    rep.add_argument("--mc", type=_mc, metavar="N",
                     help="Monte Carlo runs of every study (overrides the mode)")
    rep.add_argument("--seed", type=_seed, default=0, metavar="S", help="study seed (default 0)")
    rep.add_argument("--out", default="rankedassign-report", metavar="DIR",
                     help="report directory (default ./rankedassign-report)")
    rep.add_argument("--workers", type=_positive_int, metavar="N",
                     help="local worker processes (default: number of CPUs; 1 = in-process; "
                          "more than the CPUs available is capped to them, with a note)")
    rep.add_argument("--dask-scheduler", metavar="ADDRESS",
                     help="run on a Dask cluster, e.g. tcp://host:8786")
    rep.add_argument("--config", metavar="FILE",
                     help='JSON per-study overrides, e.g. {"table1": {"n_mc": 5}}')
    rep.add_argument("--force", action="store_true", help="replace an earlier report in DIR")
    rep.add_argument("--quiet", action="store_true", help="no progress bars")
    rep.set_defaults(func=_cmd_reproduce)

    pre = _study_command(
        sub, "precompile", names,
        "compile every kernel into numba's cache, on every core (first use)",
        "Compile the kernels of every study and sampler side by side in worker processes "
        "into numba's on-disk cache, so that later runs (reproduce, the tests, your own "
        "scripts) load them instead of compiling them one by one.")
    pre.add_argument("--workers", type=_positive_int, metavar="N",
                     help="worker processes (default: the CPUs, at most 4)")
    pre.add_argument("--quiet", action="store_true", help="no progress bar")
    pre.set_defaults(func=_cmd_precompile)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``rankedassign`` console script.

    Parameters
    ----------
    argv : list of str, optional
        Arguments (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        Process exit code.
    """
    parser = build_parser()
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version and usage errors (code 2)
        return int(exc.code or 0)
    args.argv = argv
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    return int(args.func(args))


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
