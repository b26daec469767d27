"""Multi-sensor ranked assignment (Vo, Vo & Beard 2019): the problem and its test families.

A row takes ``-1`` (dead) or a tuple with one entry per sensor (``0`` missed, ``j >= 1``
measurement ``j`` of that sensor); every sensor's measurements are used at most once. See
:class:`MultiSensorProblem` and the families of :mod:`rankedassign.multisensor.synthetic`;
the exact oracle (enumeration, row DP over used-measurement masks, the separable surrogate's
normaliser) is the companion package :mod:`oracle`, whose public functions accept either
problem type. The samplers :func:`rankedassign.sample_original` and
:func:`rankedassign.sample_short_chains` accept a :class:`MultiSensorProblem` with the option
``method`` (``"exact"``, ``"mm"``, ``"mm-fixed"``, ``"componentwise"``; see
:mod:`rankedassign.multisensor.sampling`).

Examples
--------
>>> from rankedassign.multisensor import MultiSensorProblem, synthetic
>>> p = synthetic.diagonal()
>>> isinstance(p, MultiSensorProblem), p.n_sensors, p.n_feasible()
(True, 2, 67744)
"""

from . import synthetic
from .problem import MultiSensorProblem, count_feasible_all_positive

__all__ = ["MultiSensorProblem", "count_feasible_all_positive", "synthetic"]
