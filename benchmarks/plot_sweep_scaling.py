"""Plot ns per sweep against M and P from a run of ``test_bench_sweep_scaling.py``.

Usage::

    python -m pytest benchmarks/test_bench_sweep_scaling.py --benchmark-enable \
        --benchmark-json=scaling.json
    python benchmarks/plot_sweep_scaling.py scaling.json docs/figures/sweep_scaling.png

Two panels (log-log): time per sweep (minimum over the rounds, divided by the sweeps per call)
against M at P = 50 and against P at M = 1000, for the direct sum on every row (*before*) and
the sampler as shipped (*after*, prefix sums where they are the cheaper rule).
"""

from __future__ import annotations

import json
import sys
from collections import defaultdict


def per_sweep(data: dict) -> dict:
    """``{(axis, rule): [(x, ns per sweep), ...]}`` from pytest-benchmark JSON contents.

    Examples
    --------
    >>> data = {"benchmarks": [{"name": "test_bench_sweep_against_M[direct-50]",
    ...     "stats": {"min": 2e-3}, "extra_info": {"sweeps": 1000, "P": 50, "M": 50,
    ...     "rule": "direct"}}]}
    >>> per_sweep(data)
    {('M', 'direct'): [(50, 2000.0)]}
    """
    out = defaultdict(list)
    for b in data["benchmarks"]:
        info = b.get("extra_info", {})
        if "rule" not in info:
            continue
        axis = "M" if "against_M" in b["name"] else "P"
        out[axis, info["rule"]].append((info[axis], b["stats"]["min"] / info["sweeps"] * 1e9))
    return {k: sorted(v) for k, v in out.items()}


def main(argv: list[str]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    src, dst = argv
    with open(src) as f:
        curves = per_sweep(json.load(f))
    fig, axes = plt.subplots(1, 2, figsize=(9.5, 3.8), constrained_layout=True)
    label = {"direct": "before: direct sum, O(M) per row",
             "auto": "after: prefix sums where cheaper, O(P + log M)"}
    for ax, axis, title in ((axes[0], "M", "P = 50"), (axes[1], "P", "M = 1000")):
        for rule, style in (("direct", "o--"), ("auto", "s-")):
            pts = curves.get((axis, rule), [])
            if pts:
                x, y = zip(*pts, strict=True)
                ax.loglog(x, [v / 1e3 for v in y], style, label=label[rule])
        ax.set_xlabel(f"{axis} ({'measurements' if axis == 'M' else 'rows'})")
        ax.set_ylabel("µs per sweep")
        ax.set_title(f"sweep cost against {axis}, {title}")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.savefig(dst, dpi=110)
    for (axis, rule), pts in sorted(curves.items()):
        print(axis, rule, ", ".join(f"{x}: {y / 1e3:.3g} µs" for x, y in pts))


if __name__ == "__main__":
    main(sys.argv[1:])
