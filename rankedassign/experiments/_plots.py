"""matplotlib helpers of the report's plots (Agg figures, no pyplot state), and the check every
plot of the report passes (:func:`figure_problems`).

A plot of the report is finished when someone can read it at a glance: no overlapping labels,
no empty panels, the legend outside the data, at most about six series per panel, axes that
show all the data, and series that stay distinct in greyscale. :func:`series_style` and
:func:`bar_style` give each series a colour *and* a line style and marker (or a hatch), so a
greyscale print still tells them apart; :func:`legend_below` puts one legend for the whole
figure under the panels; :func:`figure_problems` measures a drawn figure with matplotlib's own
geometry (text bounding boxes, the artists of every axes, the legend's box against the data
points in display coordinates) and lists what a reader would trip over.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["figure", "series_style", "bar_style", "legend_below", "figure_problems",
           "MAX_SERIES", "LEGEND_SHARE"]

#: Okabe & Ito's colour-blind-safe palette (black first: the reference series).
PALETTE = ("#000000", "#E69F00", "#0072B2", "#009E73", "#D55E00", "#56B4E9", "#CC79A7",
           "#999999")
#: Line styles and markers cycled beside the colours: in greyscale two series still differ in
#: their dashes or their markers.
LINESTYLES = ("-", "--", "-.", ":", (0, (6, 2)), (0, (3, 1, 1, 1, 1, 1)))
MARKERS = ("o", "s", "^", "D", "v", "X", "P", "*")
HATCHES = ("", "//", "..", "xx", "\\\\", "oo", "--", "++")
#: Most series one panel of the report shows (more are split into panels or figures).
MAX_SERIES = 6
#: Largest share of a panel's plotted points that a legend may cover.
LEGEND_SHARE = 0.02


def figure(ncols: int = 1, width: float = 6.0, height: float = 4.0, *, nrows: int = 1,
           squeeze_row: bool = True):
    """A constrained-layout figure with ``nrows`` × ``ncols`` axes.

    Returns ``(fig, axes)``: ``axes`` is the one row (1-D) when ``nrows == 1`` and
    ``squeeze_row``, else the 2-D array.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width * ncols, height * nrows), layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False)
    return fig, (axes[0] if nrows == 1 and squeeze_row else axes)


def series_style(i: int, *, markers: bool = True) -> dict:
    """Keyword arguments of ``Axes.plot`` for the ``i``-th series of a panel.

    Colour, line style and marker all change with ``i`` (the first six pairs of line style and
    marker are distinct), so the series differ in colour and in greyscale.
    """
    style = {"color": PALETTE[i % len(PALETTE)], "ls": LINESTYLES[i % len(LINESTYLES)],
             "lw": 1.4}
    if markers:
        style.update(marker=MARKERS[i % len(MARKERS)], ms=4)
    return style


def bar_style(i: int) -> dict:
    """Keyword arguments of ``Axes.bar`` for the ``i``-th group: colour and hatch."""
    return {"color": PALETTE[(i + 1) % len(PALETTE)], "hatch": HATCHES[i % len(HATCHES)],
            "edgecolor": "0.15", "linewidth": 0.5}


def legend_below(fig, axes=None, *, ncol: int | None = None, fontsize: float = 8, title=None):
    """One legend for the whole figure, below the panels (outside every axes).

    The entries are the labelled artists of ``axes`` (default: every axes of ``fig``), each
    label once, in order of first appearance. Needs a constrained-layout figure, which makes
    room for it. Returns the legend (None if nothing is labelled).
    """
    seen: dict = {}
    for ax in (fig.axes if axes is None else axes):
        for h, lab in zip(*ax.get_legend_handles_labels(), strict=True):
            seen.setdefault(lab, h)
    if not seen:
        return None
    n = len(seen)
    ncol = ncol or (n if n <= 4 else math.ceil(n / math.ceil(n / 4)))
    return fig.legend(list(seen.values()), list(seen), loc="outside lower center", ncol=ncol,
                      fontsize=fontsize, frameon=False, title=title, title_fontsize=fontsize)


# ------------------------------------------------------------------------------------ checks
def _densify(xy: np.ndarray, step: float = 3.0) -> np.ndarray:
    """Points every ``step`` pixels along a polyline in display coordinates (its vertices
    included), so that a legend lying across a segment between two vertices is seen."""
    ok = np.isfinite(xy).all(axis=1)
    out = [xy[ok]]
    for a, b in zip(xy[:-1], xy[1:], strict=True):
        if not (np.isfinite(a).all() and np.isfinite(b).all()):
            continue
        n = int(np.hypot(*(b - a)) // step)
        if n > 1:
            t = np.linspace(0.0, 1.0, n + 1)[1:-1, None]
            out.append(a + t * (b - a))
    return np.concatenate(out)


def _data_points(ax, *, dense: bool = False) -> np.ndarray:
    """Display coordinates of the data an axes shows: line vertices (with ``dense``, points
    every few pixels along the drawn lines), scatter offsets, bar ends and error-bar ends;
    shape (n, 2), finite rows only."""
    from matplotlib.collections import LineCollection, PathCollection
    from matplotlib.container import BarContainer
    from matplotlib.patches import Rectangle

    pts = []
    for line in ax.get_lines():
        if not line.get_visible() or line.get_transform() != ax.transData:
            continue  # reference lines in axes coordinates (axhline) span the axes anyway
        xy = np.column_stack([np.asarray(line.get_xdata(), dtype=float),
                              np.asarray(line.get_ydata(), dtype=float)])
        xy = line.get_transform().transform(xy)
        drawn = line.get_linestyle() not in ("None", "none", "", " ")
        pts.append(_densify(xy) if dense and drawn else xy)
    for coll in ax.collections:
        if not coll.get_visible():
            continue
        if isinstance(coll, PathCollection) and len(coll.get_offsets()):
            pts.append(coll.get_offset_transform().transform(np.asarray(coll.get_offsets())))
        elif isinstance(coll, LineCollection):  # error bars
            for seg in coll.get_segments():
                if len(seg):
                    pts.append(coll.get_transform().transform(np.asarray(seg, dtype=float)))
    for cont in ax.containers:
        if isinstance(cont, BarContainer):
            # a bar's datum is its end (the base is the axis, or clipped on a log scale)
            flat = getattr(cont, "orientation", "vertical") == "horizontal"
            for p in cont.patches:
                if isinstance(p, Rectangle) and p.get_visible():
                    x, y, w, h = p.get_x(), p.get_y(), p.get_width(), p.get_height()
                    end = [x + w, y + h / 2] if flat else [x + w / 2, y + h]
                    pts.append(ax.transData.transform([end]))
    if not pts:
        return np.empty((0, 2))
    xy = np.concatenate(pts)
    return xy[np.isfinite(xy).all(axis=1)]


def _has_data(ax) -> bool:
    from matplotlib.container import BarContainer

    if any(line.get_visible() and np.isfinite(np.asarray(line.get_ydata(), dtype=float)).any()
           for line in ax.get_lines()):
        return True
    if any(isinstance(c, BarContainer) for c in ax.containers):
        return True
    return bool(ax.images) or any(c.get_visible() and (len(c.get_offsets()) or c.get_paths())
                                  for c in ax.collections)


def _series(ax) -> list:
    """The series of a panel: data lines of two points or more, and bar groups."""
    from matplotlib.container import BarContainer, ErrorbarContainer

    caps = set()
    for cont in ax.containers:
        if isinstance(cont, ErrorbarContainer):
            caps.update(cont[1] or ())
    lines = [line for line in ax.get_lines()
             if line.get_visible() and line.get_transform() == ax.transData
             and len(line.get_xdata()) >= 2 and line not in caps]
    return lines + [c for c in ax.containers if isinstance(c, BarContainer)]


def _name(ax, i: int) -> str:
    title = ax.get_title() or ax.get_title("left") or ax.get_ylabel()
    return f"axes {i} ({title.splitlines()[0]!r})" if title else f"axes {i}"


def figure_problems(fig, *, max_series: int = MAX_SERIES,
                    legend_share: float = LEGEND_SHARE) -> list[str]:
    """What a reader would trip over in ``fig``, measured with matplotlib's geometry.

    The figure is drawn on an Agg canvas and checked for: tick labels of one axis that
    overlap, and axes titles that overlap each other; a visible axes without data (only
    text, or nothing); more than ``max_series`` series in one axes; two line series of one
    axes with the same line style and marker (they would merge in greyscale), two bar groups
    with the same hatch; data outside the axes' limits (clipped); a legend whose box covers
    more than ``legend_share`` of the data points
    of the axes it lies on.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        A finished figure (as saved).
    max_series : int, optional
        Most series per axes.
    legend_share : float, optional
        Largest share of an axes' data points (display coordinates) that a legend may cover.

    Returns
    -------
    list of str
        One sentence per problem; empty when the figure passes.

    Examples
    --------
    >>> from rankedassign.experiments._plots import figure, figure_problems
    >>> fig, (ax, empty) = figure(2)
    >>> _ = ax.plot([0, 1, 2], [0, 1, 4])
    >>> figure_problems(fig)
    ['axes 1: no data']
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    problems = []
    axes = [ax for ax in fig.axes if ax.get_visible()]
    for i, ax in enumerate(axes):
        name = _name(ax, i)
        for axis, which in ((ax.xaxis, "x"), (ax.yaxis, "y")):
            boxes = [(t.get_text(), t.get_window_extent(renderer))
                     for t in axis.get_ticklabels(which="both")
                     if t.get_visible() and t.get_text().strip()]
            for a in range(len(boxes)):
                for b in range(a + 1, len(boxes)):
                    (ta, ba), (tb, bb) = boxes[a], boxes[b]
                    # a pixel of slack: labels that touch at an edge are not overlapping
                    if (min(ba.x1, bb.x1) - max(ba.x0, bb.x0) > 1
                            and min(ba.y1, bb.y1) - max(ba.y0, bb.y0) > 1):
                        problems.append(f"{name}: {which} tick labels {ta!r} and {tb!r} "
                                        "overlap")
        if not _has_data(ax):
            problems.append(f"{name}: no data")
            continue
        series = _series(ax)
        if len(series) > max_series:
            problems.append(f"{name}: {len(series)} series (at most {max_series})")
        looks: dict = {}
        for s in series:
            if hasattr(s, "get_linestyle"):
                key = ("line", str(s.get_linestyle()), str(s.get_marker()))
            else:
                key = ("bars", s.patches[0].get_hatch() if s.patches else None)
            if key in looks:
                problems.append(f"{name}: series {looks[key]!r} and {s.get_label()!r} look "
                                "the same in greyscale")
            looks[key] = s.get_label()
        pts = _data_points(ax)
        box = ax.bbox
        outside = ((pts[:, 0] < box.x0 - 1.5) | (pts[:, 0] > box.x1 + 1.5)
                   | (pts[:, 1] < box.y0 - 1.5) | (pts[:, 1] > box.y1 + 1.5))
        if outside.any():
            problems.append(f"{name}: {int(outside.sum())} of {len(pts)} data points outside "
                            "the axes")
    titles = [(ax.title.get_text(), ax.title.get_window_extent(renderer)) for ax in axes
              if ax.title.get_visible() and ax.title.get_text().strip()]
    for a in range(len(titles)):
        for b in range(a + 1, len(titles)):
            (ta, ba), (tb, bb) = titles[a], titles[b]
            if (min(ba.x1, bb.x1) - max(ba.x0, bb.x0) > 1
                    and min(ba.y1, bb.y1) - max(ba.y0, bb.y0) > 1):
                problems.append(f"titles {ta!r} and {tb!r} overlap")
    legends = [(ax.get_legend(), [ax]) for ax in axes if ax.get_legend() is not None]
    legends += [(leg, axes) for leg in fig.legends]
    for leg, where in legends:
        lb = leg.get_window_extent(renderer)
        for i, ax in enumerate(axes):
            if ax not in where:
                continue
            pts = _data_points(ax, dense=True)
            if not len(pts):
                continue
            inside = ((pts[:, 0] >= lb.x0) & (pts[:, 0] <= lb.x1)
                      & (pts[:, 1] >= lb.y0) & (pts[:, 1] <= lb.y1))
            share = inside.mean()
            if share > legend_share:
                problems.append(f"{_name(ax, i)}: the legend covers {100 * share:.0f} % of its "
                                "data points")
    return problems
