"""The record a problem kind hands to the engine: how to prepare it, sweep it and run it.

A *problem kind* (single-sensor ranked assignment, multi-sensor, adaptive birth) is one folder
of the package with the same files in the same roles (``problem``, ``synthetic``, ``prepare``,
``reference``, ``_kernels``) and one :class:`Kind` record in its ``__init__``. The samplers
(:mod:`rankedassign.samplers`, :mod:`rankedassign.reference`) and the exact oracle
(:mod:`oracle`) dispatch on that record through :func:`rankedassign.kinds.kind_of`; no other
table names a kind. The engine itself imports no kind.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, NamedTuple

import numpy as np

__all__ = ["Kind", "DrawRule", "DrawInputs"]


class DrawInputs(NamedTuple):
    """What a :class:`DrawRule`'s ``inputs`` returns for one sampler call.

    Attributes
    ----------
    data : named tuple
        The compiled driver's data record (the Gibbs inputs followed by the draw's own).
    tally : ndarray, shape (2,), int64
        The array the run's tallies ``[keys created, fall-back draws]`` accumulate in.
    make_ref : callable
        ``make_ref() -> (ref_data, ref_tally)``: the same for the reference (built only when
        it runs).
    chain_bytes : int
        Bytes of one chain's workspace (bounds how many chains are simulated at once).
    """

    data: Any
    tally: np.ndarray
    make_ref: Callable
    chain_bytes: int


@dataclass(frozen=True)
class DrawRule:
    """A row update of a kind other than its Gibbs draw (the herded draw), in both forms.

    Attributes
    ----------
    driver : callable
        The compiled chain driver (:func:`rankedassign.engine._kernels.make_driver`).
    new_work, sweep : callable
        The reference row update, as :attr:`Kind.new_work` and :attr:`Kind.sweep`.
    inputs : callable
        ``inputs(prep, settings, chain_length) -> DrawInputs``: from the kind's
        :class:`~rankedassign.engine.result.Prepared` Gibbs inputs, the driver's data record,
        the run's tally, the reference's inputs and the bytes of one chain's workspace
        (:class:`DrawInputs`).
    """

    driver: Callable = field(repr=False)
    new_work: Callable = field(repr=False)
    sweep: Callable = field(repr=False)
    inputs: Callable = field(repr=False)


@dataclass(frozen=True)
class Kind:
    """One problem kind, as the samplers and the oracle see it.

    Attributes
    ----------
    name : str
        Identifier (``"single"``, ``"multisensor"``, ``"adaptive_birth"``); also the name of
        the kind's folder in :mod:`rankedassign` and in :mod:`oracle`.
    problem_type : type
        The problem class of the kind; :func:`rankedassign.kinds.kind_of` matches on it.
    prepare : callable
        ``prepare(problem, start, scan, rng, options) -> Prepared``: validates a sampler call's
        arguments and builds the inputs shared by both backends
        (:class:`rankedassign.engine.result.Prepared`); ``options`` is the dict of the kind's
        options (see ``options``).
    new_work : callable
        Reference row update, part 1: ``new_work(data, x) -> work``, the bookkeeping of a
        chain started at the list ``x`` (:func:`rankedassign.engine.reference.run_chains`).
    sweep : callable
        Reference row update, part 2: ``sweep(data, work, x, g)``, one sweep in place drawing
        from the stream ``g``.
    drivers : mapping of str to callable
        The compiled chain drivers (:func:`rankedassign.engine._kernels.make_driver`), keyed
        by :attr:`Prepared.driver <rankedassign.engine.result.Prepared.driver>`; a kind with
        one row update has one (``"chains"``), the single-sensor kind two (``"direct"`` and
        ``"prefix"`` draws).
    options : mapping of str to str
        The kind's sampler options (keyword arguments of :func:`rankedassign.sample_original`
        and :func:`rankedassign.sample_short_chains` beyond the common ones), each with a one
        line description; empty for the single-sensor kind.
    temper : callable
        ``temper(problem, beta, options) -> problem``: the problem whose row conditionals are
        those of ``problem`` raised to ``beta`` (its weights to the power ``beta``), for the
        samplers' ``beta`` option; it may refuse an option whose target cannot be tempered so.
    draws : mapping of str to DrawRule
        Row updates beside the Gibbs draw (``"herded"``: :func:`rankedassign.sample_herded`);
        empty where the kind has none yet.
    tempered : callable or None
        The kind's tempered Gibbs sampler of Zanella & Roberts
        (:func:`rankedassign.sample_tempered` dispatches to it): ``tempered(problem, n_steps,
        *, beta, start, rng, backend, **options) -> TemperedResult``
        (:class:`rankedassign.engine.tempered.TemperedResult`), keyword options its own;
        None where the kind has none.

    Examples
    --------
    >>> from rankedassign.kinds import KINDS
    >>> [k.name for k in KINDS]
    ['single', 'multisensor', 'adaptive_birth']
    >>> sorted(KINDS[1].options)
    ['method', 'survival_power']
    """

    name: str
    problem_type: type
    prepare: Callable = field(repr=False)
    new_work: Callable = field(repr=False)
    sweep: Callable = field(repr=False)
    drivers: Mapping[str, Callable] = field(repr=False)
    options: Mapping[str, str] = field(default_factory=dict)
    temper: Callable | None = field(default=None, repr=False)
    draws: Mapping[str, DrawRule] = field(default_factory=dict, repr=False)
    tempered: Callable | None = field(default=None, repr=False)

    def __post_init__(self):
        object.__setattr__(self, "drivers", MappingProxyType(dict(self.drivers)))
        object.__setattr__(self, "draws", MappingProxyType(dict(self.draws)))
        object.__setattr__(self, "options", MappingProxyType(dict(self.options)))
