"""The oracle of the single-sensor kind (:mod:`rankedassign.single`).

* :mod:`~oracle.single.enumerate` — every feasible assignment, best first;
* :mod:`~oracle.single.murty` — Murty's k-best ranked assignment;
* :mod:`~oracle.single.dp` — the exact normaliser and marginals by dynamic programming;
* :mod:`~oracle.single.truncation` — the exact truncation error and the best-``k`` mass.

The public entry points are the functions of :mod:`oracle` (:mod:`oracle.exact`), which call
these for an :class:`~rankedassign.AssignmentProblem`.
"""

from .dp import log_normalizer, marginals
from .enumerate import enumerate_assignments
from .murty import murty
from .truncation import best_mass, truncation_error

__all__ = ["enumerate_assignments", "log_normalizer", "marginals", "truncation_error",
           "best_mass", "murty"]
