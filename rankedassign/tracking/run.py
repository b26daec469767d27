"""Run the LMB filter on a preset scenario and collect everything the study needs."""

from __future__ import annotations

import numpy as np

from .._rng import spawning_generator
from ..metrics import tracks_to_array
from ..validation import check_bool, check_choice
from .association import Association
from .glmb import GLMBFilter
from .lmb import LMBFilter
from .models import PRESET_EXTRACTION
from .multisensor_scenario import run_multisensor_scenario
from .scenario import COUNTER_KEYS, ScenarioRun, check_n_scans, make_scenario

__all__ = ["ScenarioRun", "run_scenario"]

TIMING_KEYS = ("prediction", "cost", "association", "update")
#: Filters :func:`run_scenario` runs (``filter``).
FILTERS = ("lmb", "glmb")
#: Per-scan counters of :class:`ScanRecord` that :class:`ScenarioRun` keeps as arrays.
def run_scenario(
    preset: str = "paper",
    association: Association | None = None,
    *,
    rng=None,
    n_scans: int = 100,
    grouping: bool | None = None,
    extraction: str | None = None,
    sensors=None,
    filter: str = "lmb",
    **filter_options,
) -> ScenarioRun:
    """Simulate a preset scenario and run the LMB filter on it.

    Parameters
    ----------
    preset : {"paper", "paper-var", "vo", "multi"}
        Model preset (:func:`~rankedassign.tracking.models.make_model`); ``"multi"`` is the
        multi-sensor scenario, run by
        :func:`~rankedassign.tracking.multisensor_scenario.run_multisensor_scenario` (which
        returns a :class:`~rankedassign.tracking.multisensor_scenario.MultiSensorRun`).
    association : Association
        E.g. ``ShortChainGibbs(400, 25, 5, 10)``, ``OriginalGibbs(10_000)``, ``Murty(k)``,
        ``Exact()``. Required.
    rng : optional
        Anything :func:`numpy.random.default_rng` accepts. Two child streams are spawned from
        it: the first draws the measurements, the second drives the filter (one further child per
        scan, and per problem within a scan). The same ``rng`` therefore gives the same
        measurements whatever the association. A :class:`numpy.random.RandomState` is
        replaced by the Generator seeded with one draw from it
        (:func:`rankedassign._rng.spawning_generator`).
    n_scans : int
        Number of scans (the paper: 100; at most
        :data:`~rankedassign.tracking.scenario.MAX_SCANS`).
    grouping : bool or None
        Solve independent groups of tracks separately (spec §6.5a). None (default): False,
        except for ``"multi"`` (True). Otherwise ``True`` or ``False`` (a string is refused).
    extraction : {"hysteresis", "map"} or None
        State extraction (spec 6.5): the paper's hysteresis or the MAP cardinality of Vo's
        code. None (default) takes the preset's own setting
        (:data:`~rankedassign.tracking.models.PRESET_EXTRACTION`): hysteresis for ``"paper"``,
        MAP cardinality for ``"vo"`` (Vo's public example, which extracts by MAP cardinality).
    sensors : sequence of int or None
        ``"multi"`` only: the sensors the filter fuses (default ``(0, 1, 2)``); a sensor's
        measurements do not depend on which others are selected.
    filter : {"lmb", "glmb"}, optional
        The LMB filter (default) or the δ-GLMB filter
        (:class:`~rankedassign.tracking.glmb.GLMBFilter`, single-sensor presets, no grouping).
        The measurements depend only on ``rng``, so both filters see the same data.
    **filter_options
        Further keyword arguments of :class:`~rankedassign.tracking.lmb.LMBFilter` (``gate_prob``,
        ``theta_upper``, ``prune_track``, ``max_components``, ...) or of
        :class:`~rankedassign.tracking.glmb.GLMBFilter` (``h_upd``, ``h_max``, ...).

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
    if association is None:
        raise TypeError("run_scenario needs an association, e.g. ShortChainGibbs(400, 25, 5, 10)")
    check_choice(filter, "filter", FILTERS)
    if filter == "glmb" and (preset == "multi" or grouping):
        raise ValueError("filter='glmb' runs the single-sensor presets without grouping, got "
                         f"preset {preset!r}, grouping={grouping!r}")
    if grouping is not None:
        grouping = check_bool(grouping, "grouping")
    if preset == "multi":
        return run_multisensor_scenario(
            association, rng=rng, n_scans=n_scans,
            sensors=(0, 1, 2) if sensors is None else sensors,
            grouping=True if grouping is None else grouping,
            extraction=extraction or "hysteresis", **filter_options,
        )
    if sensors is not None:
        raise ValueError(f"sensors applies to the 'multi' preset only, got preset {preset!r}")
    grouping = False if grouping is None else grouping
    check_n_scans(n_scans)
    if extraction is None:
        extraction = PRESET_EXTRACTION.get(preset, "hysteresis")  # unknown presets fail below
    parent = spawning_generator(rng)
    meas_rng, filter_rng = parent.spawn(2)
    scenario = make_scenario(preset, rng=meas_rng, n_scans=n_scans)
    if filter == "glmb":
        filt = GLMBFilter(scenario.model, association, extraction=extraction, **filter_options)
    else:
        filt = LMBFilter(scenario.model, association, grouping=grouping, extraction=extraction,
                         **filter_options)
    K = scenario.truth.n_scans
    labelled, existence, counts, times = [], [], [], []
    scan_rngs = filter_rng.spawn(K)
    for k, scan in enumerate(scenario.scans):
        rec = filt.step(scan.z, rng=scan_rngs[k])
        # labels as tuples of Python ints, existence as Python floats
        labelled.append(dict(zip(map(tuple, rec.labels.tolist()), rec.states, strict=True)))
        existence.append(dict(zip(map(tuple, rec.track_labels.tolist()),
                                  rec.track_existence.tolist(), strict=True)))
        counts.append([getattr(rec, name) for name in COUNTER_KEYS] + [rec.labels.shape[0]])
        times.append([rec.timings[name] for name in TIMING_KEYS])
    counts = np.array(counts, dtype=np.int64).reshape(K, len(COUNTER_KEYS) + 1)
    counters = {name: counts[:, i].copy() for i, name in enumerate(COUNTER_KEYS)}
    counters["n_estimated"] = counts[:, -1].copy()
    times = np.array(times, dtype=np.float64).reshape(K, len(TIMING_KEYS))
    timings = {name: times[:, i].copy() for i, name in enumerate(TIMING_KEYS)}
    est, labels = tracks_to_array(labelled, dims=(0, 2), return_labels=True)
    if est.shape[2] == 0:  # nothing was ever reported
        est = np.full((K, 0, 2), np.nan)
    return ScenarioRun(
        scenario=scenario,
        association=repr(association),
        extraction=extraction,
        truth=scenario.truth.positions,
        estimates=est,
        estimate_labels=labels,
        labelled_estimates=labelled,
        existence=existence,
        timings=timings,
        **counters,
    )
