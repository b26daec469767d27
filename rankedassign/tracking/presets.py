"""Every model preset by name, linear and non-linear: :func:`make_model`, :func:`make_scenario`.

The linear presets (``"paper"``, ``"paper-var"``, ``"vo"``) are those of
:mod:`rankedassign.tracking.models` and :mod:`rankedassign.tracking.scenario`; the non-linear
ones (``"vo-ekf"``, ``"vo-ukf"``: Vo's coordinated-turn, bearing–range examples) those of
:mod:`rankedassign.tracking.nonlinear.vo`. This module sits above both (the non-linear layer
is built on the linear models and the scenario's records), so that one name serves every
preset; :mod:`rankedassign.tracking` exports these two functions.
"""

from __future__ import annotations

from ..validation import check_choice
from .models import PRESETS as LINEAR_PRESETS
from .models import make_model as _make_linear_model
from .nonlinear.vo import (
    NONLINEAR_PRESETS,
    NonlinearModel,
    generate_nonlinear_measurements,
    make_nonlinear_model,
    vo_truth,
)
from .scenario import Scenario, check_n_scans
from .scenario import make_scenario as _make_linear_scenario

__all__ = ["ALL_PRESETS", "make_model", "make_scenario"]

#: Every preset :func:`make_model` and :func:`make_scenario` build.
ALL_PRESETS = (*LINEAR_PRESETS, *NONLINEAR_PRESETS)


def make_model(preset: str = "paper"):
    """The model of any preset, linear or non-linear.

    Parameters
    ----------
    preset : {"paper", "paper-var", "vo", "vo-ekf", "vo-ukf"}
        A linear preset (:func:`rankedassign.tracking.models.make_model`) or one of Vo's
        non-linear examples with his EKF or UKF
        (:func:`rankedassign.tracking.nonlinear.make_nonlinear_model`).

    Returns
    -------
    Model or NonlinearModel
        Either is accepted by :class:`~rankedassign.tracking.LMBFilter` and
        :class:`~rankedassign.tracking.GLMBFilter`.

    Raises
    ------
    ValueError
        On an unknown preset.

    Examples
    --------
    >>> from rankedassign.tracking import make_model
    >>> type(make_model("vo")).__name__, type(make_model("vo-ekf")).__name__
    ('Model', 'NonlinearModel')
    >>> make_model("vo-ukf").filter
    UnscentedKalmanFilter(alpha=1.0, beta=2.0, kappa=2.0, augmented=True)
    """
    preset = check_choice(preset, "preset", ALL_PRESETS)
    if preset in NONLINEAR_PRESETS:
        return make_nonlinear_model(preset)
    return _make_linear_model(preset)


def make_scenario(preset: str = "paper", *, rng=None, n_scans: int = 100,
                  n_targets: int | None = None) -> Scenario:
    """A preset's model, its truth and simulated measurements, linear or non-linear.

    Parameters
    ----------
    preset : {"paper", "paper-var", "vo", "large", "vo-ekf", "vo-ukf"}
        The linear presets draw the truth of spec §8, ``"large"`` ``n_targets`` targets at
        constant density (:func:`rankedassign.tracking.scenario.make_scenario`); ``"vo-ekf"``
        and ``"vo-ukf"``
        Vo's ten CT targets (:func:`~rankedassign.tracking.nonlinear.vo_truth`) and his
        bearing–range measurements with clutter uniform in (bearing, range)
        (:func:`~rankedassign.tracking.nonlinear.generate_nonlinear_measurements`).
    rng : optional
        Randomness of the measurements.
    n_scans : int
        Number of scans (default 100, Vo's run length for his examples).
    n_targets : int, optional
        The targets of the ``"large"`` scenario (only there).

    Returns
    -------
    Scenario
        For a non-linear preset the truth's states are 5-D ``[p_x, v_x, p_y, v_y, ω]`` and the
        measurements ``[bearing, range]``.

    Examples
    --------
    >>> from rankedassign.tracking import make_scenario
    >>> sc = make_scenario("vo-ekf", rng=0, n_scans=3)
    >>> sc.truth.states.shape, sc.scans[0].z.shape[1]
    ((3, 10, 5), 2)
    """
    preset = check_choice(preset, "preset", (*ALL_PRESETS, "large"))
    if preset not in NONLINEAR_PRESETS:
        # the linear presets and "large" (which checks n_targets)
        return _make_linear_scenario(preset, rng=rng, n_scans=n_scans, n_targets=n_targets)
    if n_targets is not None:
        raise ValueError(f"n_targets is an option of the 'large' scenario only (preset "
                         f"{preset!r} has Vo's ten targets)")
    n_scans = check_n_scans(n_scans)
    model: NonlinearModel = make_nonlinear_model(preset)
    truth = vo_truth(model, n_scans)
    return Scenario(preset, model, truth, generate_nonlinear_measurements(truth, model, rng=rng))
