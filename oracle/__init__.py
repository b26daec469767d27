"""oracle: exact ground truth for the ranked-assignment problem of :mod:`rankedassign`.

Enumeration of every feasible assignment, Murty's k-best ranked assignment, the exact
normalising constant and association marginals by subset dynamic programming, and the exact
truncation error of a set of sampled assignments.
"""

__all__: list[str] = []
