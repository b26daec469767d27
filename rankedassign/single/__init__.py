"""The single-sensor ranked-assignment problem (Vo, Vo & Hoang 2017): one kind of the package.

Files in their roles, as in every kind's folder:

* :mod:`~rankedassign.single.problem` — :class:`AssignmentProblem`, the ``P x (M + 2P)``
  cost matrix;
* :mod:`~rankedassign.single.synthetic` — the paper's synthetic families;
* :mod:`~rankedassign.single.prepare` — a sampler call's shared inputs;
* :mod:`~rankedassign.single.reference` — the pure-Python row update (specification);
* :mod:`~rankedassign.single._kernels` — its numba twin and the compiled chain drivers;
* :mod:`~rankedassign.single.tempered` — tempered Gibbs sampling of Zanella & Roberts
  (:func:`rankedassign.sample_tempered`), its kernel in
  :mod:`~rankedassign.single._tempered_kernels`.

:data:`KIND` is the record the samplers and the oracle dispatch on
(:mod:`rankedassign.kinds`).

Examples
--------
>>> from rankedassign.single import KIND, synthetic
>>> KIND.name, sorted(KIND.drivers), synthetic.diagonal().shape
('single', ['direct', 'prefix'], (4, 24))
"""

from ..engine.kind import DrawRule, Kind
from . import _kernels, prepare, reference, synthetic, tempered
from .problem import AssignmentProblem

__all__ = ["AssignmentProblem", "synthetic", "KIND"]

#: The single-sensor kind: rows draw with the direct sum or from prefix sums.
KIND = Kind(
    name="single",
    problem_type=AssignmentProblem,
    prepare=prepare.prepare,
    new_work=reference.new_work,
    sweep=reference.sweep,
    drivers={"direct": _kernels.run_chains, "prefix": _kernels.run_chains_prefix},
    temper=prepare.temper,
    draws={"herded": DrawRule(_kernels.run_chains_herded, reference.new_herd_work,
                              reference.herd_sweep, prepare.herd_inputs)},
    tempered=tempered.sample_tempered,
)
