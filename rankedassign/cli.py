"""Command-line interface: ``rankedassign``."""

from __future__ import annotations

import argparse
import sys

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
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    return int(args.func(args))


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
