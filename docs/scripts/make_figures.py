"""Regenerate every figure of the documentation site from the project's own code.

Run from the repository root::

    python docs/scripts/make_figures.py            # all figures into docs/figures/
    python docs/scripts/make_figures.py --only discovery --out /tmp/figs

Each figure is produced by one function below, registered in ``FIGURES`` under the file name
(without ``.png``) it writes. The configurations are small on purpose (the whole script runs in
well under a minute on a laptop); the full-size studies are ``rankedassign reproduce``'s job.
Every random draw comes from a fixed seed, so the figures are reproducible.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # run from a source checkout without installing

from rankedassign import synthetic  # noqa: E402

SEED = 20230627
DPI = 110


def cost_matrix_diagonal(out: Path) -> None:
    """Heatmap of the paper's diagonal cost matrix in the ``P x (M + 2P)`` layout."""
    prob = synthetic.diagonal()
    C = prob.cost
    P, M = prob.n_rows, prob.n_meas
    fig, ax = plt.subplots(figsize=(9.0, 2.9))
    masked = np.ma.masked_invalid(np.where(np.isfinite(C), C, np.nan))
    cmap = plt.get_cmap("viridis").copy()
    cmap.set_bad("white")
    im = ax.imshow(masked, cmap=cmap, aspect="equal")
    for x in (M - 0.5, M + P - 0.5):
        ax.axvline(x, color="black", lw=1.2)
    ax.set_xticks(range(prob.n_cols))
    ax.set_xticklabels([str(c) for c in range(prob.n_cols)], fontsize=7)
    ax.set_yticks(range(P))
    ax.set_ylabel("row i (label)")
    ax.set_xlabel("column c")
    for c0, c1, label in (
        (0, M, "measurements 0..M-1"),
        (M, M + P, "missed M+i"),
        (M + P, M + 2 * P, "dead M+P+i"),
    ):
        ax.text((c0 + c1 - 1) / 2, -0.65, label, ha="center", va="bottom", fontsize=8)
    for i in range(P):
        for c in range(prob.n_cols):
            if np.isfinite(C[i, c]) and (c < M and c == i or c >= M):
                ax.text(c, i, f"{C[i, c]:.2f}", ha="center", va="center", fontsize=5.5,
                        color="white" if C[i, c] < 2 else "black")
    cb = fig.colorbar(im, ax=ax, fraction=0.025, pad=0.01)
    cb.set_label("cost = -ln eta", fontsize=8)
    ax.set_title("Diagonal family (4 x 24): white = +inf (forbidden)", fontsize=9, pad=20)
    fig.tight_layout()
    fig.savefig(out, dpi=DPI)
    plt.close(fig)


FIGURES = {
    "cost_matrix_diagonal": cost_matrix_diagonal,
}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "figures")
    parser.add_argument("--only", nargs="*", choices=sorted(FIGURES), default=None)
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    for name in args.only or FIGURES:
        t0 = time.perf_counter()
        FIGURES[name](args.out / f"{name}.png")
        print(f"{name}.png  {time.perf_counter() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
