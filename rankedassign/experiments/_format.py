"""Number and table formatting shared by the report sections.

One unit throughout the report: errors and fractions are percentages (``%``) and differences of
percentages are percentage points (``pp``). :func:`pm` chooses the decimals from the standard
error (two significant digits of it), so a tiny error such as the diagonal family's is shown
with as many digits as it needs instead of as ``0.000``.
"""

from __future__ import annotations

import math

from .paper import Z_LIMIT, agrees, distance_in_se


def finite(x) -> bool:
    return x is not None and not (isinstance(x, float) and not math.isfinite(x))


def decimals_for(x, se=None, *, least: int = 2, most: int = 8) -> int:
    """Decimals that show two significant digits of ``se`` (or three of ``x`` without one)."""
    tiny = finite(se) and finite(x) and se <= 1e-9 * abs(x)  # a zero up to rounding
    ref, sig = (se, 2) if finite(se) and se > 0 and not tiny else (x, 3)
    if not finite(ref) or ref == 0:
        return least
    return max(least, min(most, sig - 1 - math.floor(math.log10(abs(ref)))))


def num(x, digits: int | None = None) -> str:
    """A number with ``digits`` decimals (default: :func:`decimals_for`); ``–`` if missing."""
    if not finite(x):
        return "–"
    return f"{x:.{decimals_for(x) if digits is None else digits}f}"


def pm(x, se, digits: int | None = None, *, n_runs: int | None = None) -> str:
    """``x ± se`` with the same decimals for both (chosen from ``se`` unless given).

    Without a finite ``se`` the cell says why when it can: ``n_runs == 1`` gives
    ``"x (1 run)"``, never ``"x ± nan"``.

    Examples
    --------
    >>> from rankedassign.experiments._format import pm
    >>> pm(21.43, 4.6), pm(21.43, float("nan"), 1, n_runs=1), pm(0.5, None)
    ('21.4 ± 4.6', '21.4 (1 run)', '0.500')
    """
    if not finite(x):
        return "–"
    d = decimals_for(x, se) if digits is None else digits
    if finite(se):
        return f"{x:.{d}f} ± {se:.{d}f}"
    return f"{x:.{d}f} (1 run)" if n_runs == 1 else f"{x:.{d}f}"


def pm_count(x, se, *, n_runs: int | None = None) -> str:
    """A mean count ``x ± se`` with thousands separators, as :func:`pm` otherwise.

    Counts (observations, sweeps, assignments) are shown without decimals unless the
    standard error needs them (two significant digits of it), so a column of large counts
    stays as readable as :func:`integer` made it.

    Examples
    --------
    >>> from rankedassign.experiments._format import pm_count
    >>> pm_count(12345.6, 789.0), pm_count(3.25, 0.42), pm_count(250000.0, 0.0)
    ('12,346 ± 789', '3.25 ± 0.42', '250,000 ± 0')
    >>> pm_count(9120.0, None, n_runs=1), pm_count(9120.0, None), pm_count(None, 1.0)
    ('9,120 (1 run)', '9,120', '–')
    """
    if not finite(x):
        return "–"
    d = decimals_for(x, se, least=0)
    if finite(se):
        return f"{x:,.{d}f} ± {se:,.{d}f}"
    return f"{x:,.0f} (1 run)" if n_runs == 1 else f"{x:,.0f}"


def runs_note(counts) -> str:
    """How many runs stand behind a table's means, and what its ``±`` is, in one sentence.

    Parameters
    ----------
    counts : iterable of int
        The number of runs of every row (or cell) of the table.

    Returns
    -------
    str
        ``"3 Monte Carlo runs per row; ± is one standard error over the runs."``, with the
        range when the rows differ, and a warning for rows of fewer than 3 runs, whose
        standard error is itself too uncertain to lean on.

    Examples
    --------
    >>> from rankedassign.experiments._format import runs_note
    >>> print(runs_note([2, 2]))  # doctest: +NORMALIZE_WHITESPACE
    2 Monte Carlo runs per row; ± is one standard error over the runs (with 2 runs a rough
    one: the standard error itself is uncertain by about 71 %).
    >>> runs_note([1, 3]).endswith('a row of one run has none ("1 run").')
    True
    """
    counts = sorted({int(c) for c in counts if c is not None})
    if not counts:
        return ""
    lo, hi = counts[0], counts[-1]
    head = (plural(lo, "Monte Carlo run") if lo == hi
            else f"{lo:,} to {plural(hi, 'Monte Carlo run')}")
    text = f"{head} per row; ± is one standard error over the runs"
    if lo == 1:
        return text + '; a row of one run has none ("1 run").'
    if lo < 3:
        # the relative standard error of a standard deviation from n runs is about
        # 1/sqrt(2 (n - 1)): 71 % at n = 2
        rel = 100 / math.sqrt(2 * (lo - 1))
        return text + (f" (with {lo} runs a rough one: the standard error itself is "
                       f"uncertain by about {rel:.0f} %).")
    return text + "."


def integer(x) -> str:
    return "–" if not finite(x) else f"{x:,.0f}"


def plural(n: int, word: str, words: str | None = None) -> str:
    """``"1 Monte Carlo run"``, ``"2 Monte Carlo runs"``."""
    return f"{n:,} {word if n == 1 else (words or word + 's')}"


def table(header: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


def versus(ours: float, se, paper: float) -> str:
    """The distance to the paper's number in standard errors, flagged in words beyond the limit.

    Examples
    --------
    >>> from rankedassign.experiments._format import versus
    >>> versus(41.0, 0.25, 40.27), versus(43.0, 0.25, 40.27), versus(1.0, None, 0.0)
    ('+2.9 SE', '+10.9 SE — differs from the paper', 'no SE (one run)')
    >>> versus(0.0358, 0.00075, 0.04)
    "-5.6 SE (within the paper's rounding)"
    """
    z = distance_in_se(ours, se, paper)
    if z is None:
        return "no SE (one run)"
    text = f"{z:+.1f} SE" if math.isfinite(z) else f"{'+' if z > 0 else '-'}inf SE (SE 0)"
    if not agrees(ours, se, paper):
        return f"{text} — differs from the paper"
    if abs(z) > Z_LIMIT:
        return f"{text} (within the paper's rounding)"
    return text


__all__ = ["Z_LIMIT", "decimals_for", "num", "pm", "pm_count", "runs_note", "integer", "plural",
           "table", "versus"]
