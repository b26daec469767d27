"""oracle: exact ground truth for the ranked-assignment problem of :mod:`rankedassign`.

Enumeration of every feasible assignment, Murty's k-best ranked assignment, the exact
normalising constant and association marginals by dynamic programming (a subset DP, or a
frontier DP per connected component for gated problems), and the exact truncation error of a
set of sampled assignments.

The same functions (:mod:`oracle.exact`) accept a multi-sensor problem
(:class:`rankedassign.multisensor.MultiSensorProblem`: enumeration, a row DP over
used-measurement masks, :class:`MultiSensorMarginals`) or an adaptive-birth problem
(:class:`rankedassign.adaptive_birth.AdaptiveBirthProblem`: the dense tuple tensor).
:func:`surrogate_log_normalizer` is the exact normaliser of the MM-Gibbs surrogate target, and
:mod:`oracle.multisensor.transition` and :mod:`oracle.adaptive_birth` build the exact one-sweep
transition matrices of the multi-sensor and adaptive-birth Gibbs samplers on tiny problems.
The oracle has one folder per problem kind, named as the kind (:mod:`oracle.single`,
:mod:`oracle.multisensor`, :mod:`oracle.adaptive_birth`).

Examples
--------
>>> from rankedassign import synthetic
>>> import oracle
>>> p = synthetic.diagonal()
>>> oracle.murty(p, 1).assignments.tolist()
[[0, 1, 2, 3]]
>>> round(oracle.best_mass(p, 1), 5)
0.99577
>>> from rankedassign.multisensor import synthetic as ms_synthetic
>>> q = ms_synthetic.random(3, (3, 3), rng=0)        # sensor-separable: the surrogate is exact
>>> bool(abs(oracle.surrogate_log_normalizer(q) - oracle.log_normalizer(q)) < 1e-9)
True
"""

from . import adaptive_birth, multisensor, single
from ._result import Ranked
from .exact import best_mass, enumerate_assignments, log_normalizer, marginals, truncation_error
from .multisensor import MultiSensorMarginals, surrogate_log_normalizer
from .single import murty

__all__ = [
    "MultiSensorMarginals",
    "Ranked",
    "adaptive_birth",
    "best_mass",
    "enumerate_assignments",
    "log_normalizer",
    "marginals",
    "multisensor",
    "murty",
    "single",
    "surrogate_log_normalizer",
    "truncation_error",
]
