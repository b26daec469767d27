"""The oracle's compiled entry points that other compiled code may call.

These are numba dispatchers, callable from Python and from inside another kernel. They take the
compact costs ``cc`` of one problem, shape ``(P, M + 2)`` with ``P >= 1`` (columns: the
measurements, the row's missed entry, its dead entry; ``+inf`` marks a forbidden pair, as
:attr:`rankedassign.AssignmentProblem.compact_cost`), check nothing, and return assignments as
columns of the ``P x (M + 2P)`` layout (``M + i`` missed, ``M + P + i`` dead for row ``i``):

* :func:`murty_compact_kernel` ``(cc, k)``: the ``min(k, |Γ|)`` best assignments and their
  costs, ``k >= 1``, bit for bit those of :func:`oracle.murty` on the same problem;
  :data:`murty_compact_inline` is the same kernel for a compiled caller to write into itself
  (numba's ``inline="always"``), so that its search is compiled only as part of the caller;
* :func:`count_slice` ``(cc, cap, used, opt, at, budget)``: counts feasible assignments by
  depth-first search, stopping past ``cap`` (start from ``used`` all False, ``opt`` all
  :data:`NO_OPTION`, ``at`` zero);
* :func:`enumerate_sorted_kernel` ``(cc, n)``: all ``n = |Γ|`` assignments sorted by cost,
  equal costs in lexicographic order, bit for bit those of :func:`oracle.enumerate_assignments`.

The δ-GLMB filter runs them for every component of a scan in one compiled loop
(:mod:`rankedassign.tracking.single._glmb_kernels`). Validation is the caller's: the public
functions of :mod:`oracle` check their input, these do not.

References
----------
.. [1] K. G. Murty, "An Algorithm for Ranking all the Assignments in Order of Increasing
   Cost", Operations Research 16(3):682–687, 1968.
.. [2] M. L. Miller, H. S. Stone, I. J. Cox, "Optimizing Murty's Ranked Assignment Method",
   IEEE Trans. Aerosp. Electron. Syst. 33(3):851–862, 1997.

Examples
--------
>>> import numpy as np
>>> from oracle.kernels import murty_compact_kernel
>>> cc = np.array([[0.5, 1.0, 2.0]])          # one row: measurement 0, missed, dead
>>> a, c = murty_compact_kernel(cc, 5)
>>> a.tolist(), c.tolist()
([[0], [1], [2]], [0.5, 1.0, 2.0])
"""

from __future__ import annotations

from ._kernels.enumeration import NO_OPTION, count_slice, enumerate_sorted_kernel
from ._kernels.murty import murty_compact_inline, murty_compact_kernel

__all__ = ["murty_compact_kernel", "murty_compact_inline", "count_slice", "enumerate_sorted_kernel",
           "NO_OPTION"]
