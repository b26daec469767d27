"""The problem kinds, registered once: what the samplers and the oracle dispatch on.

Each kind is a folder of the package (:mod:`rankedassign.single`,
:mod:`rankedassign.multisensor`, :mod:`rankedassign.adaptive_birth`) that defines its
:class:`~rankedassign.engine.kind.Kind` record as ``KIND``; :data:`KINDS` lists them. A new
kind is a new folder and one entry here.

Examples
--------
>>> from rankedassign import synthetic
>>> kind_of(synthetic.diagonal()).name
'single'
>>> prep = prepare(synthetic.diagonal(), "all_missed", "systematic", 0)
>>> prep.kind, prep.driver, prep.x0.tolist(), prep.n_values
('single', 'direct', [16, 16, 16, 16], 18)
"""

from __future__ import annotations

import dataclasses

from . import adaptive_birth, multisensor, single
from .engine.kind import Kind
from .engine.result import Prepared
from .validation import check_beta

__all__ = ["KINDS", "Kind", "kind_of", "kind_named", "herded_rule", "prepare"]

#: Every problem kind, in the order error messages list them.
KINDS: tuple[Kind, ...] = (single.KIND, multisensor.KIND, adaptive_birth.KIND)

_BY_NAME = {kind.name: kind for kind in KINDS}


def kind_of(problem) -> Kind:
    """The kind of a problem (matched on its type, subclasses included).

    Parameters
    ----------
    problem : object
        A problem of one of the :data:`KINDS`.

    Returns
    -------
    Kind

    Raises
    ------
    TypeError
        If ``problem`` is of no known kind; the message lists the problem types.

    Examples
    --------
    >>> kind_of([[1.0]])
    Traceback (most recent call last):
    ...
    TypeError: problem must be one of (AssignmentProblem, MultiSensorProblem,
    AdaptiveBirthProblem), got list; build one with AssignmentProblem.from_cost / from_eta
    """
    for kind in KINDS:
        if isinstance(problem, kind.problem_type):
            return kind
    names = ", ".join(kind.problem_type.__name__ for kind in KINDS)
    raise TypeError(
        f"problem must be one of ({names}), got {type(problem).__name__}; build one with "
        "AssignmentProblem.from_cost / from_eta"
    )


def kind_named(name: str) -> Kind:
    """The kind called ``name`` (:attr:`Prepared.kind <rankedassign.engine.result.Prepared>`).

    Parameters
    ----------
    name : str
        One of the kinds' names.

    Returns
    -------
    Kind

    Examples
    --------
    >>> kind_named("multisensor").problem_type.__name__
    'MultiSensorProblem'
    """
    return _BY_NAME[name]


def herded_rule(kind: Kind):
    """The kind's herded draw (:attr:`Kind.draws <rankedassign.engine.kind.Kind>`).

    Parameters
    ----------
    kind : Kind

    Returns
    -------
    rankedassign.engine.kind.DrawRule

    Raises
    ------
    TypeError
        If the kind has none; the message names its problem type and the kinds that herd.

    Examples
    --------
    >>> herded_rule(kind_named("single")).driver.__name__
    'run_chains_single_herded'
    """
    rule = kind.draws.get("herded")
    if rule is None:
        have = ", ".join(k.problem_type.__name__ for k in KINDS if "herded" in k.draws)
        raise TypeError(f"the herded draw is not implemented for a "
                        f"{kind.problem_type.__name__} yet (it is for: {have})")
    return rule


def prepare(problem, start, scan, rng, beta=1.0, **options) -> Prepared:
    """Validate a sampler call's problem and options; build its :class:`Prepared` inputs.

    Parameters
    ----------
    problem : AssignmentProblem, MultiSensorProblem or AdaptiveBirthProblem
        The problem; its kind (:func:`kind_of`) does the preparation.
    start, scan, rng
        As in :func:`rankedassign.sample_original`.
    beta : float, optional
        Inverse temperature in ``(0, 1]`` (default 1). With ``beta < 1`` the chains run on the
        kind's tempered problem (:attr:`Kind.temper <rankedassign.engine.kind.Kind>`: every
        row conditional raised to ``beta``) and the result's costs are those of ``problem``
        itself; ``beta = 1`` prepares ``problem`` as it is, so its draws are unchanged.
    **options
        The kind's options (:attr:`Kind.options <rankedassign.engine.kind.Kind>`): none for an
        :class:`~rankedassign.AssignmentProblem`; ``method`` and ``survival_power`` for a
        :class:`~rankedassign.multisensor.MultiSensorProblem`; ``sensor_order`` for an
        :class:`~rankedassign.adaptive_birth.AdaptiveBirthProblem`.

    Returns
    -------
    Prepared

    Raises
    ------
    TypeError
        If ``problem`` is of no known kind, or an option does not apply to it.
    ValueError
        If ``beta`` is not a real number in ``(0, 1]``, or the kind cannot temper the call
        (:attr:`Kind.temper <rankedassign.engine.kind.Kind>`).
    """
    kind = kind_of(problem)
    beta = check_beta(beta)
    if beta == 1.0:
        return kind.prepare(problem, start, scan, rng, options)
    prep = kind.prepare(kind.temper(problem, beta, options), start, scan, rng, options)
    # the costs of the result are the problem's own: prepare it once more for its to_result
    # (seed 0: the caller's rng is drawn from once, by the tempered preparation)
    own = kind.prepare(problem, start, scan, 0, options)
    return dataclasses.replace(prep, problem=problem, to_result=own.to_result)
