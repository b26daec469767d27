"""Run a filter on a preset scenario, of one sensor or several, and collect everything the
studies need.

The scan loop is :func:`~rankedassign.tracking.runner.run_filter`'s; this module simulates the
measurements (:mod:`rankedassign.tracking.scenario`,
:mod:`rankedassign.tracking.multisensor.scenario`) and builds the filter of the one table
(:mod:`rankedassign.tracking.filters`): it stands above the filters it runs.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..engine.rng import spawning_generator
from ..validation import check_bool
from .association import Association
from .filters import FILTERS as FILTER_TABLE
from .filters import make_filter, takes_grouping
from .multisensor.adaptive_birth import AdaptiveBirth
from .multisensor.scenario import MULTI_PRESETS, MultiSensorRun, make_multisensor_scenario
from .presets import make_scenario
from .runner import TIMING_KEYS, run_filter
from .scenario import ScenarioRun, check_n_scans

__all__ = ["FILTERS", "ScenarioRun", "TIMING_KEYS", "run_multisensor_scenario", "run_scenario"]


#: Names of the filters :func:`run_scenario` runs (the rows of
#: :data:`rankedassign.tracking.filters.FILTERS`, the one table).
FILTERS = tuple(FILTER_TABLE)


def run_scenario(
    preset: str = "paper",
    association: Association | None = None,
    *,
    rng=None,
    n_scans: int = 100,
    grouping: bool | None = None,
    extraction: str | None = None,
    sensors=None,
    filter="lmb",
    **filter_options,
) -> ScenarioRun:
    """Simulate a preset scenario and run the LMB filter on it.

    Parameters
    ----------
    preset : {"paper", "paper-var", "vo", "vo-ekf", "vo-ukf", "multi", "multi-bearing-range"}
        Model preset (:func:`~rankedassign.tracking.presets.make_model`: ``"vo-ekf"`` and
        ``"vo-ukf"`` are Vo's coordinated-turn, bearing–range examples); ``"multi"`` is the
        multi-sensor scenario, run by
        :func:`run_multisensor_scenario` (which
        returns a :class:`~rankedassign.tracking.multisensor.scenario.MultiSensorRun`).
    association : Association
        E.g. ``ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)``,
        ``OriginalGibbs(10_000)``, ``Murty(k)``, ``Exact()``. Required.
    rng : optional
        Anything :func:`numpy.random.default_rng` accepts. Two child streams are spawned from
        it: the first draws the measurements, the second drives the filter (one further child per
        scan, and per problem within a scan). The same ``rng`` therefore gives the same
        measurements whatever the association. A :class:`numpy.random.RandomState` is
        replaced by the Generator seeded with one draw from it
        (:func:`rankedassign.engine.rng.spawning_generator`).
    n_scans : int
        Number of scans (the paper: 100; at most
        :data:`~rankedassign.tracking.scenario.MAX_SCANS`).
    grouping : bool or None
        Solve independent groups of tracks separately (spec §6.5a). None (default): False,
        except for ``"multi"`` (True). Otherwise ``True`` or ``False`` (a string is refused).
    extraction : {"hysteresis", "map"} or None
        State extraction (spec 6.5): the paper's hysteresis or the MAP cardinality of Vo's
        code. None (default) takes the preset's own setting, which the preset's model carries
        (:attr:`Model.extraction <rankedassign.tracking.models.Model>`, from
        :data:`~rankedassign.tracking.models.PRESET_EXTRACTION`): hysteresis for ``"paper"``,
        MAP cardinality for ``"vo"`` (Vo's public example, which extracts by MAP cardinality),
        hysteresis for ``"multi"``. A filter built on ``make_model(preset)`` takes the same.
    sensors : sequence of int or None
        ``"multi"`` and ``"multi-bearing-range"`` only: the sensors the filter fuses (default
        ``(0, 1, 2)``, and both sensors of ``"multi-bearing-range"``); a sensor's
        measurements do not depend on which others are selected.
    filter : {"lmb", "glmb"}, filter class or filter object, optional
        The LMB filter (default) or the δ-GLMB filter
        (:class:`~rankedassign.tracking.GLMBFilter`; on ``"multi"``
        :class:`~rankedassign.tracking.MultiSensorGLMBFilter`), which takes no grouping, by
        name or class; a class of one's own (``cls(model, association, **options)``); or a
        filter object, run as it is (:func:`~rankedassign.tracking.filters.make_filter`).
        The measurements depend only on ``rng``, so every filter sees the same data.
    **filter_options
        Further keyword arguments of :class:`~rankedassign.tracking.LMBFilter` (``gate_prob``,
        ``theta_upper``, ``prune_track``, ``max_components``, ...) or of
        :class:`~rankedassign.tracking.GLMBFilter` (``h_upd``, ``h_max``, ...). On
        ``"vo-ekf"`` and ``"vo-ukf"`` with ``filter="lmb"`` or ``"glmb"`` they default to Vo's
        settings (:meth:`~rankedassign.tracking.nonlinear.VoFilterSettings.filter_options`).

    Returns
    -------
    ScenarioRun

    Raises
    ------
    TypeError
        If ``association`` is missing, not callable or of the other kind (a multi-sensor
        association for a single-sensor preset, or the reverse), or on an option of the wrong
        type (``grouping="no"``, ``n_scans=2.0``, ``rng="seed"``).
    ValueError
        On an unknown preset or a bad option (``n_scans`` above
        :data:`~rankedassign.tracking.scenario.MAX_SCANS`, with the memory it would need).

    Examples
    --------
    >>> from rankedassign.tracking import Exact, run_scenario
    >>> run = run_scenario("vo", Exact(), rng=1, n_scans=3, grouping=True)
    >>> run.truth.shape, run.n_meas.shape, sorted(run.timings), run.extraction
    ((3, 12, 2), (3,), ['association', 'cost', 'prediction', 'update'], 'map')
    """
    is_object = not isinstance(filter, (str, type))
    if association is None and not is_object:
        raise TypeError("run_scenario needs an association, e.g. "
                        "ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)")
    groups = takes_grouping(filter)
    if not groups and grouping:
        raise ValueError(f"filter={filter!r} runs without grouping (every component's problem "
                         f"is truncated whole), got grouping={grouping!r}")
    if grouping is not None:
        grouping = check_bool(grouping, "grouping")
    if preset in MULTI_PRESETS:
        return run_multisensor_scenario(
            association, rng=rng, n_scans=n_scans, sensors=sensors, preset=preset,
            grouping=True if grouping is None or not groups else grouping,
            extraction=extraction, filter=filter, **filter_options,
        )
    if sensors is not None:
        raise ValueError(f"sensors applies to the multi-sensor presets {MULTI_PRESETS} only, "
                         f"got preset {preset!r}")
    grouping = False if grouping is None else grouping
    check_n_scans(n_scans)
    parent = spawning_generator(rng)
    meas_rng, filter_rng = parent.spawn(2)
    scenario = make_scenario(preset, rng=meas_rng, n_scans=n_scans)
    # extraction None: the model's, which make_model set to the preset's (PRESET_EXTRACTION)
    settings = getattr(scenario.model, "settings", None)  # Vo's, for his non-linear presets
    if not is_object and settings is not None and filter in ("lmb", "glmb"):
        filter_options = {**settings.filter_options(filter), **filter_options}
    if not is_object:
        filter_options = {"extraction": extraction, **filter_options}
        if groups:
            filter_options["grouping"] = grouping
    filt = make_filter(filter, scenario.model, association, multi=False, **filter_options)
    run = run_filter(filt, [scan.z for scan in scenario.scans], rng=filter_rng)
    return ScenarioRun(
        scenario=scenario,
        # the position components the model names ([0, 2] for every preset so far)
        truth=scenario.truth.states[:, :, list(getattr(scenario.model, "position_indices",
                                                       (0, 2)))],
        **{f.name: getattr(run, f.name) for f in dataclasses.fields(ScenarioRun)
           if f.name not in ("scenario", "truth")},
    )


def run_multisensor_scenario(association=None, *, rng=None, n_scans: int = 100,
                             sensors=None, grouping: bool = True,
                             extraction: str | None = None, birth: str = "paper",
                             filter: str = "lmb", preset: str = "multi",
                             **filter_options) -> MultiSensorRun:
    """Simulate a multi-sensor scenario and run the multi-sensor LMB or δ-GLMB filter on it.

    Parameters
    ----------
    association : callable
        A multi-sensor association, e.g.
        ``ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, method="exact")``. Required.
    rng : optional
        Two child streams are spawned: the first draws the measurements
        (:func:`make_multisensor_scenario`), the second drives the filter (one child per scan).
        The same ``rng`` gives the same measurements whatever the association and sensors.
        A RandomState is replaced by the Generator seeded with one draw from it.
    n_scans : int
        Number of scans (default 100, at most
        :data:`~rankedassign.tracking.scenario.MAX_SCANS`).
    sensors : sequence of int or None
        The sensors the filter fuses (distinct indices into
        :data:`~rankedassign.tracking.multisensor.scenario.MULTI_SENSORS`, or the
        non-linear preset's); None: as
        :func:`~rankedassign.tracking.multisensor.scenario.make_multisensor_scenario`.
    grouping : bool
        One problem per group of tracks sharing gated measurements (default True); ``True``
        or ``False`` only.
    extraction : {"hysteresis", "map"} or None
        State extraction (spec 6.5). None (default): the model's, hysteresis for this
        preset (:attr:`MultiSensorModel.extraction
        <rankedassign.tracking.multisensor.MultiSensorModel>`).
    birth : {"paper", "narrow", "adaptive"} or AdaptiveBirth
        Birth model (:data:`~rankedassign.tracking.multisensor.scenario.BIRTHS`):
        ``"adaptive"`` is ``AdaptiveBirth()``; an
        :class:`~rankedassign.tracking.AdaptiveBirth` sets its parameters.
    filter : {"lmb", "glmb"}, filter class or filter object
        :class:`~rankedassign.tracking.multisensor.lmb.MultiSensorLMBFilter` (default) or
        :class:`~rankedassign.tracking.MultiSensorGLMBFilter`, by name or class (a class of
        the table stands for its row, so ``GLMBFilter`` builds the multi-sensor one), a class
        of one's own (``cls(model, association, **options)``), or a filter object, run as it
        is (:func:`~rankedassign.tracking.filters.make_filter`); the measurements are the same
        for all. The δ-GLMB filter takes no ``grouping`` (its components are truncated
        whole): it must be left at its default.
    preset : {"multi", "multi-bearing-range"}
        :data:`~rankedassign.tracking.multisensor.scenario.MULTI_PRESETS`; on
        ``"multi-bearing-range"`` the LMB and δ-GLMB options default
        to Vo's settings
        (:meth:`~rankedassign.tracking.nonlinear.VoFilterSettings.filter_options`).
    **filter_options
        Further options of the filter.

    Returns
    -------
    MultiSensorRun

    Raises
    ------
    TypeError
        If ``association`` is missing or single-sensor, or on an option of the wrong type
        (``sensors=5``, ``grouping="no"``, ``rng=1.5``).
    ValueError
        On a bad option (an out-of-range sensor, ``n_scans`` above
        :data:`~rankedassign.tracking.scenario.MAX_SCANS`, ...).

    Examples
    --------
    >>> from rankedassign.tracking import run_multisensor_scenario
    >>> from rankedassign.tracking import ShortChainGibbs
    >>> assoc = ShortChainGibbs(20, 5, tau_stall=5, tau_stale=10, method="exact")
    >>> run = run_multisensor_scenario(assoc, rng=1, n_scans=3, sensors=(0, 2))
    >>> run.truth.shape, run.n_meas.shape
    ((3, 12, 2), (3,))
    """
    if association is None:
        raise TypeError("run_multisensor_scenario needs an association, e.g. "
                        "ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)")
    grouping = check_bool(grouping, "grouping")
    groups = takes_grouping(filter)
    if not groups and not grouping:
        raise ValueError("grouping=False applies to the LMB filter only: the δ-GLMB filter "
                         "truncates every component's problem whole")
    n_scans = check_n_scans(n_scans)
    adaptive = birth if isinstance(birth, AdaptiveBirth) else (
        AdaptiveBirth() if birth == "adaptive" else None)
    if adaptive is not None:
        birth = "adaptive"
    meas_rng, filter_rng = spawning_generator(rng).spawn(2)
    scenario = make_multisensor_scenario(rng=meas_rng, n_scans=n_scans, sensors=sensors,
                                         birth=birth, preset=preset)
    settings = getattr(scenario.model, "settings", None)  # Vo's, for a non-linear preset
    if settings is not None and filter in ("lmb", "glmb"):
        filter_options = {**settings.filter_options(filter), **filter_options}
    if isinstance(filter, (str, type)):
        filter_options = {"extraction": extraction, "birth": adaptive, **filter_options}
        if groups:
            filter_options["grouping"] = grouping
    filt = make_filter(filter, scenario.model, association, multi=True,
                               **filter_options)
    run = run_filter(filt, [tuple(s.z for s in scans) for scans in scenario.scans],
                     rng=filter_rng)
    timings = dict(run.timings)
    timings.setdefault("birth", np.zeros(run.n_scans))  # a static birth takes no time
    fields = {f.name: getattr(run, f.name) for f in dataclasses.fields(MultiSensorRun)
              if f.name not in ("scenario", "truth", "timings")}
    return MultiSensorRun(scenario=scenario, truth=scenario.truth.positions, timings=timings,
                          **fields)
