"""The paper's published numbers and the rule that compares ours with them.

Trezza, Bucci & Varshney (2023), Table I and §V-B, as restated in spec §3.4 and §3.6. A
reproduced number agrees with the paper's when it lies within three of its Monte Carlo standard
errors of the interval its printed value stands for (:func:`agrees`): the paper prints two
decimals, so its value is known to half a unit of the last digit.
"""

from __future__ import annotations

import math
from typing import NamedTuple

__all__ = [
    "PAPER_TABLE1",
    "PAPER_TOTALS",
    "PAPER_SWEEP_TOLERANCE_PCT",
    "PAPER_DECIMALS",
    "Z_LIMIT",
    "PaperCell",
    "distance_in_se",
    "agrees",
]


class PaperCell(NamedTuple):
    """One cell of the paper's Table I: ΔObs (%) and ΔError (percentage points).

    Attributes
    ----------
    delta_obs_pct : float
        ΔObs, the share of the original sampler's observations the short chains save, in
        percent (two decimals, as printed).
    delta_error_pp : float
        ΔError, the absolute difference of the mean truncation errors, in percentage points
        (two decimals, as printed).
    """

    delta_obs_pct: float
    delta_error_pp: float


#: The paper's Table I (spec §3.6): ``(family, criterion) -> PaperCell``.
PAPER_TABLE1 = {
    ("diagonal", "stall"): PaperCell(79.95, 0.04),
    ("diagonal", "stale"): PaperCell(99.29, 0.27),
    ("diagonal", "full"): PaperCell(99.93, 0.40),
    ("uniform", "stall"): PaperCell(40.27, 10.46),
    ("uniform", "stale"): PaperCell(0.00, 0.00),
    ("uniform", "full"): PaperCell(40.23, 10.45),
    ("random", "stall"): PaperCell(56.97, 6.34),
    ("random", "stale"): PaperCell(0.00, 0.00),
    ("random", "full"): PaperCell(56.96, 6.35),
}
#: Total observations over the 100 scans of the tracking study (spec §3.4, A13).
PAPER_TOTALS = {"original": 10_760_000, "proposed": 63_474}
#: The paper's statement on its sweep figure: at a fixed observation budget the truncation error
#: does not depend on the chain length by more than this (percentage points).
PAPER_SWEEP_TOLERANCE_PCT = 0.1
#: Decimals the paper prints in Table I.
PAPER_DECIMALS = 2
#: A number agrees with the paper's when it lies within this many standard errors of it.
Z_LIMIT = 3.0


def distance_in_se(ours: float, se: float | None, paper: float) -> float | None:
    """``(ours - paper) / se``; ``None`` without a standard error.

    A zero standard error gives 0 when the two agree to the paper's printed precision and
    ``±inf`` otherwise.

    Parameters
    ----------
    ours : float
        Our estimate (e.g. a mean ΔObs in % or ΔError in pp).
    se : float or None
        Its Monte Carlo standard error, ``None`` for a single run.
    paper : float
        The paper's printed value of the same quantity.

    Returns
    -------
    float or None
        ``(ours - paper) / se`` rounded to two decimals (signed: positive when ours is
        larger); 0 or ``±inf`` for ``se == 0`` as above; ``None`` if ``se`` is ``None``.

    Examples
    --------
    >>> from rankedassign.experiments.paper import distance_in_se
    >>> distance_in_se(41.0, 0.25, 40.27)
    2.92
    >>> distance_in_se(0.0, 0.0, 0.0)
    0.0
    """
    if se is None:
        return None
    diff = ours - paper
    if se == 0.0:
        if abs(diff) <= 0.5 * 10.0**-PAPER_DECIMALS:
            return 0.0
        return math.copysign(math.inf, diff)
    return round(diff / se, 2)


def agrees(ours: float, se: float | None, paper: float) -> bool | None:
    """Whether ``ours`` lies within :data:`Z_LIMIT` standard errors of ``paper``'s rounding
    interval, ``|ours - paper| <= 3 se + 0.005``.

    The paper prints two decimals, so its number stands for an interval half a unit of the last
    digit wide on either side; ``None`` without a standard error (one Monte Carlo run).

    Parameters
    ----------
    ours : float
        Our estimate (e.g. a mean ΔObs in % or ΔError in pp).
    se : float or None
        Its Monte Carlo standard error, ``None`` for a single run.
    paper : float
        The paper's printed value of the same quantity (:data:`PAPER_DECIMALS` decimals).

    Returns
    -------
    bool or None
        Whether ``|ours - paper| <= Z_LIMIT * se + 0.005``; ``None`` if ``se`` is ``None``.

    Examples
    --------
    >>> from rankedassign.experiments.paper import agrees
    >>> agrees(6.3, 2.7, 0.0), agrees(9.0, 2.7, 0.0), agrees(0.004, 0.0, 0.0)
    (True, False, True)
    """
    if se is None:
        return None
    return abs(ours - paper) <= Z_LIMIT * se + 0.5 * 10.0**-PAPER_DECIMALS
