"""The multi-sensor adaptive-birth problem (Trezza, Bucci & Varshney 2022): one kind.

The state is one measurement tuple ``J = (j^(1), ..., j^(V))`` (``0`` missed), with no
constraint between tuples. Files in their roles, as in every kind's folder:

* :mod:`~rankedassign.adaptive_birth.problem` — :class:`AdaptiveBirthProblem`, and
  :func:`birth_from_samples`, which turns sampled tuples into LMB birth components;
* :mod:`~rankedassign.adaptive_birth.synthetic` — the study's families;
* :mod:`~rankedassign.adaptive_birth.prepare` — a sampler call's shared inputs;
* :mod:`~rankedassign.adaptive_birth.reference` — the pure-Python row update;
* :mod:`~rankedassign.adaptive_birth._kernels` — its numba twin and the compiled driver;
* :mod:`~rankedassign.adaptive_birth.tempered` — tempered Gibbs sampling of Zanella & Roberts
  (:func:`rankedassign.sample_tempered`), its kernel in
  :mod:`~rankedassign.adaptive_birth._tempered_kernels`.

:data:`KIND` is the record the samplers and the oracle dispatch on (:mod:`rankedassign.kinds`).

Examples
--------
>>> from rankedassign.adaptive_birth import KIND, synthetic
>>> KIND.name, synthetic.make_family("uniform", 3, 2).n_feasible()
('adaptive_birth', 27)
"""

from ..engine.kind import DrawRule, Kind
from . import _kernels, prepare, reference, synthetic, tempered
from .problem import SENSOR_ORDERS, AdaptiveBirthProblem, BirthLMB, birth_from_samples

__all__ = ["AdaptiveBirthProblem", "BirthLMB", "birth_from_samples", "SENSOR_ORDERS",
           "synthetic", "KIND"]

#: The adaptive-birth kind: one row update per sensor, a tuple per state.
KIND = Kind(
    name="adaptive_birth",
    problem_type=AdaptiveBirthProblem,
    prepare=prepare.prepare,
    new_work=reference.new_work,
    sweep=reference.sweep,
    drivers={"chains": _kernels.run_chains},
    options={"sensor_order": "'random' (default: a fresh permutation per sweep) or 'fixed'"},
    temper=prepare.temper,
    draws={"herded": DrawRule(_kernels.run_chains_herded, reference.new_herd_work,
                              reference.herd_sweep, prepare.herd_inputs)},
    tempered=tempered.sample_tempered,
)
