"""oracle: exact ground truth for the ranked-assignment problem of :mod:`rankedassign`.

Enumeration of every feasible assignment, Murty's k-best ranked assignment, the exact
normalising constant and association marginals by dynamic programming (a subset DP, or a
frontier DP per connected component for gated problems), and the exact truncation error of a
set of sampled assignments.

Examples
--------
>>> from rankedassign import synthetic
>>> import oracle
>>> p = synthetic.diagonal()
>>> oracle.murty(p, 1).assignments.tolist()
[[0, 1, 2, 3]]
>>> round(oracle.best_mass(p, 1), 5)
0.99577
"""

from ._result import Ranked
from .dp import log_normalizer, marginals
from .enumerate import enumerate_assignments
from .murty import murty
from .truncation import best_mass, truncation_error

__all__ = [
    "Ranked",
    "best_mass",
    "enumerate_assignments",
    "log_normalizer",
    "marginals",
    "murty",
    "truncation_error",
]
