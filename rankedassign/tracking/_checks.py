"""Checks at the boundaries of the δ-GLMB filters: a prior.

Both δ-GLMB filters (:class:`~rankedassign.tracking.GLMBFilter` and
:class:`~rankedassign.tracking.MultiSensorGLMBFilter`) call :func:`check_prior` on the
arguments of ``set_prior``; what a custom truncation returns is checked by
:func:`rankedassign.tracking.association.check_hypotheses`.
The rule of :mod:`rankedassign.validation` holds: the wrong kind of value is a
``TypeError``, a value of the right kind out of range a ``ValueError``, and every message names
the truncation or the track and the field.
"""

from __future__ import annotations

import numbers

import numpy as np

from ..validation import float_array
from .models import _spd

# Labels are packed as ``birth scan * 2**32 + index`` into an int64 key (the estimates, the
# hysteresis memory): the index must fit 32 bits and the scan 31.
LABEL_SCAN_LIMIT = 2**31
LABEL_INDEX_LIMIT = 2**32


def _label_text(labels, t: int) -> str:
    return f"track {t}, label ({labels[t][0]}, {labels[t][1]})"


def _check_labels(labels, max_birth_index) -> np.ndarray:
    """The prior's labels as an ``(T, 2)`` int64 array (see :func:`check_prior`)."""
    try:
        given = np.asarray(labels)
    except ValueError:  # numpy: "inhomogeneous shape"
        raise ValueError(f"labels must be pairs (birth scan, index) of ints, got the ragged "
                         f"sequence {labels!r}") from None
    if given.size == 0:
        return np.empty((0, 2), dtype=np.int64)
    if given.ndim != 2 or given.shape[1] != 2:
        raise ValueError(f"labels must have shape (T, 2), one pair (birth scan, index) per "
                         f"track, got shape {given.shape}")
    # the given objects themselves: numpy turns [0, True] into ints and [0, 1.5] into floats
    if isinstance(labels, np.ndarray):
        flat = labels.reshape(-1).tolist()
    else:
        flat = np.asarray(labels, dtype=object).reshape(-1)
    for i, x in enumerate(flat):
        if isinstance(x, (bool, np.bool_)) or not isinstance(x, numbers.Integral):
            raise TypeError(f"labels must be pairs of ints, got {type(x).__name__} {x!r} in "
                            f"labels[{i // 2}]")
    big = [int(x) for x in flat]
    for i, x in enumerate(big):
        limit = LABEL_SCAN_LIMIT if i % 2 == 0 else LABEL_INDEX_LIMIT
        if not 0 <= x < limit:
            what = "birth scan" if i % 2 == 0 else "index"
            raise ValueError(
                f"labels[{i // 2}] = ({big[i - i % 2]}, {big[i - i % 2 + 1]}): its {what} must "
                f"be an int in [0, 2**{limit.bit_length() - 1}) (labels are packed into 64 "
                f"bits), got {x}")
    out = np.array(big, dtype=np.int64).reshape(-1, 2)
    seen: dict = {}
    for t, key in enumerate(map(tuple, out.tolist())):
        if key in seen:
            raise ValueError(f"labels must be distinct: labels[{seen[key]}] and labels[{t}] are "
                             f"both {key}")
        seen[key] = t
    for t, (scan, index) in enumerate(out.tolist()):
        if scan >= 1 and (max_birth_index is None or 1 <= index <= max_birth_index):
            if max_birth_index is None:
                births, above = "the adaptive births of scan k are labelled (k, 1..n)", ""
            else:
                births = f"the births of scan k are labelled (k, 1..{max_birth_index})"
                above = f" or an index above {max_birth_index}"
            raise ValueError(
                f"labels[{t}] = ({scan}, {index}) is a label the filter gives a birth: "
                f"{births} from scan 1 on; label a prior's tracks with birth scan 0 (as "
                f"(0, {t + 1})){above}")
    return out


def check_prior(labels, means, covs, components, weights, *, max_birth_index, dim=4):
    """Validate the arguments of ``set_prior`` of the δ-GLMB filters.

    Parameters
    ----------
    labels : array_like of int, shape (T, 2)
        Distinct pairs ``(birth scan, index)`` of non-negative ints, the scan below ``2**31``
        and the index below ``2**32``. A label the filter gives a birth (scan ``k >= 1``,
        index ``1..max_birth_index``) is refused: the prior's tracks and the births would
        merge into one label.
    means : array_like, shape (T, 4)
        Finite means.
    covs : array_like, shape (T, 4, 4)
        Symmetric positive definite covariances.
    components : sequence of sequences of int or None
        Track indices of every component (ints, not bools or floats), distinct within one.
    weights : array_like, shape (H,), or None
        Finite non-negative numbers, not all zero.
    max_birth_index : int or None
        The number of birth tracks of every scan; None when it changes from scan to scan
        (adaptive birth), and then every label with a birth scan ``>= 1`` is refused.
    dim : int, optional
        State dimension ``d`` (default 4; a non-linear model's own, e.g. 5), the ``4`` of the
        shapes above.

    Returns
    -------
    labels : ndarray of int64, shape (T, 2)
    means : ndarray of float64, shape (T, 4)
    covs : ndarray of float64, shape (T, 4, 4)
    components : list of list of int
    weights : ndarray of float64, shape (H,)
        Not normalised.

    Raises
    ------
    TypeError
        On values of the wrong kind (float labels, string means, float track indices).
    ValueError
        On shapes that disagree, labels out of range, repeated or a birth's, a mean that is
        not finite or a covariance that is not SPD (the message names the track), a component
        with an index out of range or repeated, or weights that are negative, not finite or
        all zero.

    Examples
    --------
    >>> import numpy as np
    >>> check_prior([[0, 1]], np.zeros((1, 4)), [np.eye(4)], None, None,
    ...             max_birth_index=4)[0].tolist()
    [[0, 1]]
    >>> check_prior([[2, 1]], np.zeros((1, 4)), [np.eye(4)], None, None, max_birth_index=4)
    Traceback (most recent call last):
    ...
    ValueError: labels[0] = (2, 1) is a label the filter gives a birth: the births of scan k \
are labelled (k, 1..4) from scan 1 on; label a prior's tracks with birth scan 0 (as (0, 1)) or \
an index above 4
    """
    labels = _check_labels(labels, max_birth_index)
    T = labels.shape[0]
    means = float_array(means, "means")
    covs = float_array(covs, "covs")
    if means.shape != (T, dim) or covs.shape != (T, dim, dim):
        raise ValueError(f"means and covs must have shapes ({T}, {dim}) and ({T}, {dim}, "
                         f"{dim}), got {means.shape} and {covs.shape}")
    lab = labels.tolist()  # once: formatting each track's name from the array was O(T²)
    for t in range(T):
        if not np.isfinite(means[t]).all():
            raise ValueError(f"means[{t}] ({_label_text(lab, t)}) must be finite, "
                             f"got {means[t].tolist()}")
        _spd(covs[t], dim, f"covs[{t}] ({_label_text(lab, t)})")
    comps = _check_components(components, T)
    if weights is None:
        w = np.ones(len(comps))
    else:
        w = float_array(weights, "weights")
    if (w.shape != (len(comps),) or not np.isfinite(w).all() or (w < 0).any()
            or w.sum() <= 0):
        raise ValueError(f"weights must be {len(comps)} finite non-negative numbers, not "
                         f"all zero, got {w.tolist()}")
    return labels, means, covs, comps, w


def _check_components(components, T: int) -> list:
    """Every component as a list of Python ints (see :func:`check_prior`)."""
    if components is None:
        return [list(range(T))]
    if isinstance(components, (str, bytes, numbers.Number)) or not hasattr(components,
                                                                            "__iter__"):
        raise TypeError(f"components must be a sequence of sequences of track indices, got "
                        f"{type(components).__name__} {components!r}")
    comps = []
    for h, c in enumerate(components):
        if isinstance(c, (str, bytes, numbers.Number)) or not hasattr(c, "__iter__"):
            raise TypeError(f"components[{h}] must be a sequence of track indices (ints), got "
                            f"{type(c).__name__} {c!r}")
        out = []
        for i in c:
            if isinstance(i, (bool, np.bool_)) or not isinstance(i, numbers.Integral):
                raise TypeError(f"components[{h}] must hold track indices (ints), got "
                                f"{type(i).__name__} {i!r}")
            out.append(int(i))
        if len(set(out)) != len(out) or any(not 0 <= i < T for i in out):
            raise ValueError(f"component {out} must hold distinct track indices in [0, {T})")
        comps.append(out)
    if not comps:
        raise ValueError("components must hold at least one component (the empty set is [[]])")
    return comps
