"""Command-line interface: ``rankedassign``."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ._version import __version__


def _cmd_demo(args) -> int:
    import numpy as np

    from . import synthetic

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


def _positive_int(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a positive integer, got {text!r}") from None
    if v < 1:
        raise argparse.ArgumentTypeError(f"must be a positive integer, got {text!r}")
    return v


def _seed(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a non-negative integer, got {text!r}") from None
    if v < 0:
        raise argparse.ArgumentTypeError(f"must be a non-negative integer, got {text!r}")
    return v


def _error(message: str) -> int:
    print(f"rankedassign reproduce: error: {message}", file=sys.stderr)
    return 2


def _cmd_reproduce(args) -> int:
    import json
    import shlex

    from .experiments import (
        STUDIES,
        Config,
        ReproduceError,
        SchedulerError,
        config_from_dict,
        reproduce,
    )

    unknown = [s for s in args.studies if s not in STUDIES]
    if unknown:
        return _error(f"unknown study {unknown[0]!r}; choose from {', '.join(STUDIES)}")
    mode = "full" if args.full else "quick"
    config = None
    try:
        if args.config is not None:
            try:
                overrides = json.loads(Path(args.config).read_text())
            except (OSError, ValueError) as exc:
                return _error(f"cannot read --config {args.config!r}: {exc}")
            base = Config.full() if mode == "full" else Config.quick()
            config = config_from_dict(base, overrides)
        reproduce(
            args.studies,
            mode,
            args.out,
            config=config,
            seed=args.seed,
            mc=args.mc,
            workers=args.workers,
            dask_scheduler=args.dask_scheduler,
            force=args.force,
            progress=not args.quiet,
            command=shlex.join(["rankedassign", *args.argv]),
        )
    except (ReproduceError, SchedulerError) as exc:
        return _error(str(exc))
    except KeyboardInterrupt:
        print("rankedassign reproduce: interrupted; no report written", file=sys.stderr)
        return 130
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``rankedassign`` command."""
    parser = argparse.ArgumentParser(
        prog="rankedassign",
        description=(
            "Ranked assignment for labeled RFS trackers: Gibbs samplers (original and "
            "short-chain with stall/stale), exact oracle, LMB filter, paper reproduction."
        ),
    )
    parser.add_argument("--version", action="version", version=f"rankedassign {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    demo = sub.add_parser("demo", help="print the paper's synthetic matrices and their sizes")
    demo.add_argument("--seed", type=int, default=0, help="seed of the random matrix")
    demo.set_defaults(func=_cmd_demo)

    rep = sub.add_parser(
        "reproduce",
        help="run the paper's studies and write a report (markdown, PNG, JSON, CSV)",
        description=(
            "Reproduce the studies of Trezza, Bucci & Varshney (2023): table1 (Table I), "
            "sweep (error vs observations), tracking (LMB filter, OSPA(2)), tracking_var (the "
            "same with the birth covariance read as variances, one call per group), "
            "ablation (every stall/stale reading), optimum (error vs the best error for as "
            "many solutions). "
            "Without --full every study runs the paper's per-run settings with fewer Monte "
            "Carlo runs (a few minutes on two cores)."
        ),
    )
    rep.add_argument(
        "studies", nargs="*", metavar="STUDY",
        help="table1, sweep, tracking, tracking_var, ablation, optimum (default: all)",
    )
    size = rep.add_mutually_exclusive_group()
    size.add_argument("--quick", action="store_true", help="fewer Monte Carlo runs (default)")
    size.add_argument("--full", action="store_true", help="the paper's settings (100 runs)")
    rep.add_argument("--mc", type=_positive_int, metavar="N",
                     help="Monte Carlo runs of every study (overrides the mode)")
    rep.add_argument("--seed", type=_seed, default=0, metavar="S", help="study seed (default 0)")
    rep.add_argument("--out", default="rankedassign-report", metavar="DIR",
                     help="report directory (default ./rankedassign-report)")
    rep.add_argument("--workers", type=_positive_int, metavar="N",
                     help="local worker processes (default: number of CPUs; 1 = in-process)")
    rep.add_argument("--dask-scheduler", metavar="ADDRESS",
                     help="run on a Dask cluster, e.g. tcp://host:8786")
    rep.add_argument("--config", metavar="FILE",
                     help='JSON per-study overrides, e.g. {"table1": {"n_mc": 5}}')
    rep.add_argument("--force", action="store_true", help="replace an earlier report in DIR")
    rep.add_argument("--quiet", action="store_true", help="no progress bars")
    rep.set_defaults(func=_cmd_reproduce)
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
