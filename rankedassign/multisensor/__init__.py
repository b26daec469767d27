"""Multi-sensor ranked assignment (Vo, Vo & Beard 2019) and adaptive birth (Trezza et al. 2022).

A row takes ``-1`` (dead) or a tuple with one entry per sensor (``0`` missed, ``j >= 1``
measurement ``j`` of that sensor); every sensor's measurements are used at most once. See
:class:`MultiSensorProblem` and the families of :mod:`rankedassign.multisensor.synthetic`;
the exact oracle (enumeration, row DP over used-measurement masks, the separable surrogate's
normaliser) is the companion package :mod:`oracle`, whose public functions accept either
problem type. The samplers :func:`rankedassign.sample_original` and
:func:`rankedassign.sample_short_chains` accept a :class:`MultiSensorProblem` with the option
``method`` (``"exact"``, ``"mm"``, ``"mm-fixed"``, ``"componentwise"``; see
:mod:`rankedassign.multisensor.prepare`).

Files in their roles, as in every kind's folder: :mod:`~rankedassign.multisensor.problem`,
:mod:`~rankedassign.multisensor.synthetic`, :mod:`~rankedassign.multisensor.prepare`,
:mod:`~rankedassign.multisensor.reference` (pure Python) and
:mod:`~rankedassign.multisensor._kernels` (numba). :data:`KIND` is the record the samplers and
the oracle dispatch on (:mod:`rankedassign.kinds`). Tempered Gibbs sampling of Zanella &
Roberts on the exact posterior (:func:`rankedassign.sample_tempered`) is
:mod:`~rankedassign.multisensor.tempered`, with its numba twin
:mod:`~rankedassign.multisensor._tempered_kernels`. The adaptive-birth problem, whose state is
one measurement tuple, is a kind of its own: :mod:`rankedassign.adaptive_birth`.

Examples
--------
>>> from rankedassign.multisensor import MultiSensorProblem, synthetic
>>> p = synthetic.diagonal()
>>> isinstance(p, MultiSensorProblem), p.n_sensors, p.n_feasible()
(True, 2, 67744)
"""

from ..engine.kind import DrawRule, Kind
from . import _kernels, prepare, reference, synthetic, tempered
from .prepare import METHODS
from .problem import MultiSensorProblem, count_feasible_all_positive

__all__ = ["MultiSensorProblem", "count_feasible_all_positive", "synthetic", "METHODS", "KIND"]

#: The multi-sensor kind: one compiled sweep serves every ``method``.
KIND = Kind(
    name="multisensor",
    problem_type=MultiSensorProblem,
    prepare=prepare.prepare,
    new_work=reference.new_work,
    sweep=reference.sweep,
    drivers={"chains": _kernels.run_chains},
    options={
        "method": "conditional of a row: 'exact', 'mm' (default), 'mm-fixed' or "
                  "'componentwise' (rankedassign.multisensor.prepare.METHODS)",
        "survival_power": "1 (default) or 'V': the survival factor's exponent",
    },
    temper=prepare.temper,
    draws={"herded": DrawRule(_kernels.run_chains_herded, reference.new_herd_work,
                              reference.herd_sweep, prepare.herd_inputs)},
    tempered=tempered.sample_tempered,
)
