"""matplotlib helpers of the report's plots (Agg figures, no pyplot state)."""

from __future__ import annotations


def figure(ncols: int = 1, width: float = 6.0, height: float = 4.0):
    """A constrained-layout figure with ``ncols`` axes in one row."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width * ncols, height), layout="constrained")
    axes = fig.subplots(1, ncols, squeeze=False)[0]
    return fig, axes
