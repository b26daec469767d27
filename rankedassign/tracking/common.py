"""What the single- and multi-sensor filters share: scan checks, marginal checks, children,
log-sum-exp and the retained mass.

Both filter folders (:mod:`rankedassign.tracking.single`, :mod:`rankedassign.tracking.multisensor`)
import these; neither imports a private name of the other.
"""

from __future__ import annotations

import functools
import math
import numbers
from typing import NamedTuple

import numpy as np

from ..engine._kernels import zobrist_keys
from ..numba_options import interruptible
from ..validation import check_int, check_real
from .association import association_name

__all__ = ["BETA_TOL", "Children", "check_distribution", "check_measurements", "concat",
           "gate_threshold", "logsumexp", "retained_ratio", "zobrist_table"]

#: Largest ``|Σ_j β_ij − 1|`` the filters accept in the marginals an association returns
#: (the rounding of a normalised sum is some 1e-15; anything larger is a wrong distribution).
BETA_TOL = 1e-9


def gate_threshold(gate_prob: float, dim: int = 2) -> float:
    """χ² gate on the squared Mahalanobis distance for a ``dim``-dimensional measurement.

    Parameters
    ----------
    gate_prob : float
        Probability mass inside the gate, in ``(0, 1)``.
    dim : int
        Measurement dimension.

    Returns
    -------
    float
        ``χ²_dim⁻¹(gate_prob)``; for ``dim = 2`` exactly ``−2 ln(1 − gate_prob)``.

    Raises
    ------
    TypeError
        If ``gate_prob`` is not a real number or ``dim`` not an int.
    ValueError
        If ``gate_prob`` is outside ``(0, 1)`` or ``dim < 1``.

    Examples
    --------
    >>> from rankedassign.tracking import gate_threshold
    >>> round(gate_threshold(0.9999999), 3)
    32.236
    """
    gate_prob = check_real(gate_prob, "gate_prob")
    dim = check_int(dim, "dim", minimum=1)
    if not (0 < gate_prob < 1):
        raise ValueError(f"gate_prob must be in (0, 1), got {gate_prob}")
    if dim == 2:
        return -2.0 * math.log1p(-gate_prob)
    from scipy.stats import chi2  # here: scipy.stats takes 0.3 s to import

    return float(chi2.ppf(gate_prob, dim))


def check_measurements(z, name: str = "measurements", dim: int = 2) -> np.ndarray:
    """One scan's measurements as a float64 (M, dim) array; ``[]`` and (0, dim) give (0, dim).

    Parameters
    ----------
    z : array_like, shape (M, 2)
        The scan's measurements.
    name : str, optional
        Whose measurements they are, for the messages (the multi-sensor filters name the
        sensor).
    dim : int, optional
        Measurement dimension (default 2, positions; a non-linear model gives its own).

    Returns
    -------
    ndarray, shape (M, 2)
        A C-contiguous float64 copy.

    Raises
    ------
    TypeError
        If they are not real numbers.
    ValueError
        On a ragged sequence, a wrong shape or a value that is not finite.

    Examples
    --------
    >>> check_measurements([]).shape
    (0, 2)
    """
    try:
        a = np.asarray(z)
    except ValueError:  # numpy: "inhomogeneous shape"
        raise ValueError(
            f"{name} must be an (M, {dim}) array of real numbers, got a ragged sequence (rows of "
            "different lengths)"
        ) from None
    if a.dtype.kind == "O" and all(isinstance(v, numbers.Real) and not isinstance(v, bool)
                                   for v in a.reshape(-1)):
        a = a.astype(np.float64)  # e.g. Python ints beyond int64
    if a.dtype.kind not in "iuf":
        kind = {"b": "booleans", "U": "strings", "S": "bytes", "c": "complex numbers"}.get(
            a.dtype.kind, "objects")
        raise TypeError(f"{name} must be real numbers, got {kind} (dtype {a.dtype}) in a scan "
                        f"of shape {a.shape}")
    if a.shape == (0,):  # [] : a scan without measurements
        return np.empty((0, dim))
    if a.ndim != 2 or a.shape[1] != dim:
        empty = (f" (a scan without measurements is [] or shape (0, {dim}))" if a.size == 0
                 else "")
        raise ValueError(f"{name} must have shape (M, {dim}), got shape {a.shape}{empty}")
    if a.shape[0] == 0:
        return np.empty((0, dim))
    z = np.array(a, dtype=np.float64)  # a writable copy: one compiled variant of each kernel
    if not np.isfinite(z).all():
        i, j = np.argwhere(~np.isfinite(z))[0]
        raise ValueError(f"{name} must be finite, got {z[i, j]} at [{i}, {j}] in a scan of "
                         f"shape {z.shape}")
    return np.ascontiguousarray(z)


def check_distribution(association, arrays: dict, totals: np.ndarray, row: str) -> None:
    """Refuse association marginals that are not a distribution over each row's options.

    Parameters
    ----------
    association : object
        The association that returned them (named in the messages).
    arrays : dict
        A name for each returned array (``{"beta": beta}``).
    totals : ndarray, shape (P,)
        The total mass of every row.
    row : str
        The expression of a row's mass in the messages (``"beta[{i}, :].sum()"``).

    Raises
    ------
    ValueError
        On a marginal that is not finite or negative, or a row whose mass is not 1 within
        :data:`BETA_TOL`.

    Examples
    --------
    >>> import numpy as np
    >>> check_distribution(len, {"beta": np.ones((1, 2))}, np.array([2.0]), "beta[{i}, :].sum()")
    Traceback (most recent call last):
    ...
    ValueError: association len returned marginals that are not a distribution: \
beta[0, :].sum() = 2.0, not 1 (tolerance 1e-09)
    """
    who = association_name(association)
    for what, a in arrays.items():
        if not np.isfinite(a).all():
            at = tuple(int(k) for k in np.argwhere(~np.isfinite(a))[0])
            raise ValueError(f"association {who} returned a non-finite marginal: "
                             f"{what}{list(at)} = {a[at]}")
        if (a < 0).any():
            at = tuple(int(k) for k in np.argwhere(a < 0)[0])
            raise ValueError(f"association {who} returned a negative marginal: "
                             f"{what}{list(at)} = {a[at]}")
    off = np.abs(totals - 1.0)
    if (off > BETA_TOL).any():
        i = int(np.argmax(off > BETA_TOL))
        raise ValueError(
            f"association {who} returned marginals that are not a distribution: "
            f"{row.format(i=i)} = {float(totals[i])!r}, not 1 (tolerance {BETA_TOL})"
        )


def concat(parts: list, dtype) -> np.ndarray:
    return np.concatenate(parts).astype(dtype, copy=False) if parts else np.empty(0, dtype)


def logsumexp(a: np.ndarray) -> float:
    if a.size == 0:
        return -math.inf
    top = float(np.max(a))
    if not np.isfinite(top):
        return top
    return top + math.log(float(np.sum(np.exp(a - top))))


@functools.lru_cache(maxsize=64)
def zobrist_table(L: int, K: int, seed: np.uint64) -> np.ndarray:
    """Zobrist keys for states of at most ``L`` positions and values ``0..K − 1`` (cached).

    Parameters
    ----------
    L, K : int
        Positions (at least one key row is made) and values per position.
    seed : numpy.uint64
        The seed of the keys (each filter has its own).

    Returns
    -------
    ndarray of uint64, shape (max(L, 1), K)
        Read-only: the same array is returned to every caller with these arguments.
    """
    with interruptible:
        keys = zobrist_keys(max(L, 1), K, seed)
    keys.setflags(write=False)
    return keys


class Children(NamedTuple):
    """Every unique assignment of the scan as a child of its component (kernel layout).

    Attributes
    ----------
    comp : ndarray of int64, shape (N,)
        The parent component of every child, grouped by parent.
    cost : ndarray, shape (N,)
        ``Σ −ln η`` of its assignment.
    off : ndarray of int64, shape (N + 1,)
        CSR offsets of the rows that exist after the scan.
    entry : ndarray of int64
        Their predicted entries.
    meas : ndarray of int64
        Their measurements (columns of the shared terms; −1 missed).
    sweeps, row_updates : int
        The truncation's work.
    """

    comp: np.ndarray  # (N,) parent component
    cost: np.ndarray  # (N,) Σ −ln η
    off: np.ndarray  # (N + 1,) CSR offsets of the rows that exist after the scan
    entry: np.ndarray  # their predicted entries
    meas: np.ndarray  # their measurements (columns of the shared terms; −1 missed)
    sweeps: int
    row_updates: int


def retained_ratio(comp_w: np.ndarray, children: Children, log_Z: np.ndarray) -> float:
    """``Σ_h w_h K_h / Σ_h w_h Z_h`` (spec §4) from the exact ``ln Z_h`` of every component.

    ``K_h = Σ_{children of h} exp(−cost)``; the children are grouped by parent (as
    :class:`Children` holds them).

    Parameters
    ----------
    comp_w : ndarray, shape (H,)
        The components' weights.
    children : Children
        The scan's children.
    log_Z : ndarray, shape (H,)
        ``ln Z_h`` of every component's problem.

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> ch = Children(np.array([0]), np.array([0.0]), np.array([0, 0]), np.empty(0, np.int64),
    ...               np.empty(0, np.int64), 0, 0)
    >>> retained_ratio(np.ones(1), ch, np.array([np.log(2.0)]))
    0.5
    """
    H = comp_w.size
    log_K = np.full(H, -np.inf)
    if children.comp.size:
        # logsumexp(-cost) of every parent's run of children at once (a loop over thousands
        # of components a scan cost more than the rest of the mass)
        starts = np.flatnonzero(np.r_[True, children.comp[1:] != children.comp[:-1]])
        neg = -np.asarray(children.cost, dtype=np.float64)
        top = np.maximum.reduceat(neg, starts)
        finite = np.isfinite(top)
        shift = np.where(finite, top, 0.0)
        run = np.repeat(np.arange(starts.size), np.diff(np.r_[starts, neg.size]))
        total = np.add.reduceat(np.exp(neg - shift[run]), starts)
        with np.errstate(divide="ignore"):
            log_K[children.comp[starts]] = np.where(finite, shift + np.log(total), top)
    log_w = np.log(comp_w)
    return math.exp(logsumexp(log_w + log_K) - logsumexp(log_w + log_Z))
