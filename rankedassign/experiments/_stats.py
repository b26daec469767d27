"""Statistics the studies share: paired differences and their Student-t intervals."""

from __future__ import annotations

import math

import numpy as np

__all__ = ["t95", "paired_interval"]


def t95(n: int) -> float:
    """The Student-t quantile 0.975 with ``n − 1`` degrees of freedom (``n >= 2`` pairs).

    Examples
    --------
    >>> round(t95(2), 3), round(t95(21), 3)
    (12.706, 2.086)
    """
    from scipy.stats import t  # here: scipy.stats takes 0.3 s to import

    return float(t.ppf(0.975, n - 1))


def paired_interval(d) -> tuple[float, float, float]:
    """Mean of paired differences ``d`` and its 95 % Student-t interval.

    Parameters
    ----------
    d : array_like
        One difference per pair (the same measurements on both sides of each).

    Returns
    -------
    (mean, low, high) : tuple of float
        ``low`` and ``high`` are NaN with fewer than two pairs.

    Examples
    --------
    >>> [round(v, 3) for v in paired_interval([1.0, 2.0, 3.0])]
    [2.0, -0.484, 4.484]
    """
    d = np.asarray(d, dtype=float)
    m = float(d.mean())
    if d.size < 2:
        return m, math.nan, math.nan
    h = t95(d.size) * float(d.std(ddof=1)) / math.sqrt(d.size)
    return m, m - h, m + h
