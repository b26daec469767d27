"""run_filter: the one scan loop (≡ the scenario runners), its duck-typed filter interface and
its errors; the preset's extraction carried by the model."""

import dataclasses
import re
import sys
from typing import NamedTuple

import numpy as np
import pytest
from numpy.testing import assert_array_equal

from rankedassign.metrics import ospa, ospa2
from rankedassign.tracking import (
    PRESET_EXTRACTION,
    AdaptiveBirth,
    Exact,
    FilterRun,
    LMBFilter,
    Model,
    MultiSensorLMBFilter,
    MultiSensorModel,
    ScenarioRun,
    ShortChainGibbs,
    make_model,
    make_multisensor_model,
    make_multisensor_scenario,
    make_scenario,
    run_filter,
    run_multisensor_scenario,
    run_scenario,
)
from rankedassign.tracking.models import PRESETS
from rankedassign.tracking.runner import OSPA2_WINDOW, OSPA_C, OSPA_P, TIMING_KEYS

#: Fields of both records whose values depend on the run, timings (wall clock) aside.
SHARED = [f.name for f in dataclasses.fields(ScenarioRun)
          if f.name not in ("scenario", "truth", "timings")]


def assert_same_run(a, b, names=SHARED):
    for name in names:
        x, y = getattr(a, name), getattr(b, name)
        if isinstance(x, np.ndarray):
            assert_array_equal(x, y, err_msg=name)
            assert x.dtype == y.dtype, name
        elif name in ("labelled_estimates",):
            assert [list(d) for d in x] == [list(d) for d in y], name
            for dx, dy in zip(x, y, strict=True):
                for lab in dx:
                    assert_array_equal(dx[lab], dy[lab], err_msg=name)
        else:
            assert x == y, name


def scenario_rngs(seed):
    """The two child streams run_scenario spawns: measurements, then the filter."""
    return np.random.default_rng(seed).spawn(2)


# ------------------------------------------------------------------ run_filter ≡ the runners
@pytest.mark.parametrize(("preset", "assoc", "options"), [
    ("vo", Exact(), {"grouping": True}),
    ("paper", ShortChainGibbs(60, 10, tau_stall=5, tau_stale=10), {}),
    ("paper", Exact(), {"extraction": "map", "grouping": True}),
])
def test_run_filter_is_run_scenario(preset, assoc, options):
    seed, n = 4, 12
    ref = run_scenario(preset, assoc, rng=seed, n_scans=n, **options)
    meas_rng, filter_rng = scenario_rngs(seed)
    sc = make_scenario(preset, rng=meas_rng, n_scans=n)
    run = run_filter(LMBFilter(make_model(preset), assoc, **options), [s.z for s in sc.scans],
                     rng=filter_rng, truth=sc.truth)
    assert isinstance(run, FilterRun) and run.n_scans == n
    assert_same_run(run, ref)
    assert run.extraction == options.get("extraction", PRESET_EXTRACTION[preset])
    assert_array_equal(run.truth, ref.truth)
    assert list(run.timings) == list(ref.timings) == list(TIMING_KEYS)
    assert run.n_births is None  # the single-sensor filter does not report its births


@pytest.mark.parametrize("birth", ["paper", "adaptive"])
def test_run_filter_is_run_multisensor_scenario(birth):
    seed, n, sensors = 2, 6, (0, 2)
    assoc = ShortChainGibbs(40, 10, tau_stall=5, tau_stale=10, method="exact")
    ref = run_multisensor_scenario(assoc, rng=seed, n_scans=n, sensors=sensors, birth=birth)
    meas_rng, filter_rng = scenario_rngs(seed)
    sc = make_multisensor_scenario(rng=meas_rng, n_scans=n, sensors=sensors, birth=birth)
    filt = MultiSensorLMBFilter(make_multisensor_model(sensors, birth=birth), assoc,
                                birth=ref_birth(birth))
    scans = [tuple(s.z for s in per_sensor) for per_sensor in sc.scans]
    run = run_filter(filt, scans, rng=filter_rng)
    assert_same_run(run, ref, SHARED + ["n_births"])
    assert run.truth is None and run.ospa is None and run.ospa2 is None
    assert list(ref.timings) == [*TIMING_KEYS, "birth"]
    assert list(run.timings) == list(ref.timings if birth == "adaptive" else TIMING_KEYS)


def ref_birth(birth):
    return AdaptiveBirth() if birth == "adaptive" else None


def test_run_filter_metrics_are_ospa_and_ospa2():
    meas_rng, filter_rng = scenario_rngs(0)
    sc = make_scenario("vo", rng=meas_rng, n_scans=10)
    run = run_filter(LMBFilter(make_model("vo"), Exact(), grouping=True),
                     [s.z for s in sc.scans], rng=filter_rng, truth=sc.truth.positions)
    assert (OSPA_C, OSPA_P, OSPA2_WINDOW) == (200.0, 1.0, 5)
    want = ospa2(sc.truth.positions, run.estimates, c=200, p=1, window=5)
    for got, exp in zip(run.ospa2, want, strict=True):
        assert_array_equal(got, exp)
    for k in range(10):
        x = sc.truth.positions[k][~np.isnan(sc.truth.positions[k, :, 0])]
        y = run.estimates[k][~np.isnan(run.estimates[k, :, 0])]
        np.testing.assert_allclose(run.ospa.value[k], ospa(x, y, 200, 1).value, rtol=1e-12)


def test_run_filter_resets_and_is_reproducible():
    scans = [s.z for s in make_scenario("vo", rng=1, n_scans=6).scans]
    filt = LMBFilter(make_model("vo"), ShortChainGibbs(40, 10, tau_stall=5, tau_stale=10))
    a = run_filter(filt, scans, rng=7)
    b = run_filter(filt, scans, rng=7)  # the same filter object, used again: reset first
    assert_same_run(a, b)
    c = run_filter(filt, iter(scans), rng=np.random.default_rng(7))  # any iterable of scans
    assert_same_run(a, c)
    # scan k runs on child k of rng
    filt.reset()
    children = np.random.default_rng(7).spawn(6)
    for k, z in enumerate(scans):
        rec = filt.step(z, rng=children[k])
    assert sorted(map(tuple, rec.labels.tolist())) == sorted(a.labelled_estimates[-1])


def test_run_filter_without_any_estimate():
    run = run_filter(LMBFilter(make_model("paper"), Exact()), [[], np.empty((0, 2))], rng=0)
    assert run.estimates.shape == (2, 0, 2) and run.estimate_labels == []
    assert_array_equal(run.n_estimated, [0, 0])
    assert_array_equal(run.n_meas, [0, 0])


# ------------------------------------------------------------------ the duck-typed interface
class _Record(NamedTuple):
    labels: np.ndarray
    states: np.ndarray
    track_labels: np.ndarray
    track_existence: np.ndarray
    timings: dict
    invocations: int = 1
    sweeps: int = 0
    row_updates: int = 0
    n_unique: int = 1
    n_tracks: int = 1
    n_meas: int = 0
    n_meas_gated: int = 0
    n_groups: int = 1


class _OneTrack:
    """A stand-in for a future filter (a δ-GLMB): reset() and step(z, rng), nothing else."""

    def reset(self):
        self.k = 0

    def step(self, z, rng=None):
        self.k += 1
        x = float(np.random.default_rng(rng).random())
        lab = np.array([[1, 1]])
        timings = {"prediction": 0.0, "update": 0.5, "hypotheses": 0.25}
        return _Record(lab, np.array([[x, 0.0, self.k, 0.0]]), lab, np.array([0.5]), timings,
                       n_meas=len(z))


def test_run_filter_takes_any_filter_with_step_and_reset():
    run = run_filter(_OneTrack(), [[[0.0, 0.0]], [], [[1.0, 1.0], [2.0, 2.0]]], rng=3)
    assert run.association is None and run.extraction is None and run.n_births is None
    assert run.estimate_labels == [(1, 1)]
    children = np.random.default_rng(3).spawn(3)
    assert_array_equal(run.estimates[:, 0, 0], [np.random.default_rng(c).random()
                                                for c in children])
    assert_array_equal(run.estimates[:, 0, 1], [1.0, 2.0, 3.0])  # state components 0 and 2
    assert_array_equal(run.n_meas, [1, 0, 2])
    assert run.existence == [{(1, 1): 0.5}] * 3
    # every phase timed, the standard four first (0 where a filter does not time one)
    assert list(run.timings) == [*TIMING_KEYS, "hypotheses"]
    assert_array_equal(run.timings["cost"], [0.0] * 3)
    assert_array_equal(run.timings["hypotheses"], [0.25] * 3)


# ------------------------------------------------------------------ errors
def test_run_filter_errors():
    filt = LMBFilter(make_model("vo"), Exact())
    scans = [[[0.0, 0.0]]]
    with pytest.raises(TypeError, match=re.escape(
            "run_filter needs a filter with methods step(z, rng) and reset(), such as "
            "LMBFilter or MultiSensorLMBFilter; got Exact without step() and reset()")):
        run_filter(Exact(), scans)
    with pytest.raises(TypeError, match=re.escape(
            "scans must be a sequence with one entry per scan (an (M, 2) array, or a tuple of "
            "one array per sensor), got str")):
        run_filter(filt, "scans.csv")
    with pytest.raises(TypeError, match="one array per sensor\\), got int"):
        run_filter(filt, 5)
    with pytest.raises(ValueError, match=re.escape(
            "got one array of shape (3, 2); a single scan is [z]")):
        run_filter(filt, np.zeros((3, 2)))
    with pytest.raises(ValueError, match="scans is empty: run_filter needs at least one scan"):
        run_filter(filt, [])
    with pytest.raises(ValueError, match=re.escape(
            "truth must have shape (n_scans, n_targets, 2) = (1, n_targets, 2), one row of "
            "positions per scan, got shape (2, 3, 2)")):
        run_filter(filt, scans, truth=np.zeros((2, 3, 2)))
    with pytest.raises(ValueError, match=re.escape("got shape (1, 3, 4)")):
        run_filter(filt, scans, truth=np.zeros((1, 3, 4)))
    with pytest.raises(TypeError, match="truth must hold real numbers .* got dtype <U1"):
        run_filter(filt, scans, truth=[[["a", "b"]]])
    with pytest.raises(ValueError, match="truth must be .* got a ragged sequence"):
        run_filter(filt, scans, truth=[[[0.0, 1.0]], [[0.0]]])
    with pytest.raises(TypeError, match="rng must be None"):
        run_filter(filt, scans, rng=1.5)


def test_a_bad_scan_is_named():
    filt = LMBFilter(make_model("vo"), Exact())
    with pytest.raises(ValueError, match=re.escape(
            "measurements must have shape (M, 2), got shape (3,)")) as info:
        run_filter(filt, [[[0.0, 0.0]], [], [1.0, 2.0, 3.0]])
    if sys.version_info >= (3, 11):
        assert info.value.__notes__ == ["in scan 2 (scans[2]) of the 3 given to run_filter"]
    ms = MultiSensorLMBFilter(make_multisensor_model((0, 1)), ShortChainGibbs(5, 5, tau_stall=5, tau_stale=5, method="exact"))
    with pytest.raises(ValueError, match=re.escape(
            "step needs one measurement array per sensor (V = 2), got 1 arrays")):
        run_filter(ms, [([[0.0, 0.0]],)])


# ------------------------------------------------------------------ extraction travels
def test_preset_extraction_travels_with_the_model():
    for preset, rule in PRESET_EXTRACTION.items():
        model = make_model(preset)
        assert model.extraction == rule
        assert LMBFilter(model, Exact()).extraction == rule
        assert MultiSensorModel.from_model(model).extraction == rule
        assert MultiSensorLMBFilter(model, ShortChainGibbs(5, 5, tau_stall=5, tau_stale=5, method="exact")).extraction == rule
        for other in ("hysteresis", "map"):  # an explicit argument wins
            assert LMBFilter(model, Exact(), extraction=other).extraction == other
    assert Model().extraction == "hysteresis"  # a model built by hand: the paper's rule
    assert make_multisensor_model().extraction == "hysteresis"
    ms = MultiSensorModel.from_model(make_model("vo"))
    assert ms.select([0]).extraction == ms.single(0).extraction == "map"
    # the preset's parts are unchanged
    m, raw = make_model("vo"), PRESETS["vo"]()
    assert raw.extraction == "hysteresis"
    assert (m.motion, m.sensor, m.clutter, m.survival) == (raw.motion, raw.sensor, raw.clutter,
                                                           raw.survival)
    assert_array_equal(m.birth.covs, raw.birth.covs)


def test_filter_on_the_vo_model_is_run_scenario_on_vo():
    # the 1.6 m of issue 30: LMBFilter(make_model("vo")) used hysteresis, run_scenario("vo") MAP
    meas_rng, filter_rng = scenario_rngs(3)
    sc = make_scenario("vo", rng=meas_rng, n_scans=15)
    run = run_filter(LMBFilter(make_model("vo"), Exact(), grouping=True), [s.z for s in sc.scans],
                     rng=filter_rng)
    assert_same_run(run, run_scenario("vo", Exact(), rng=3, n_scans=15, grouping=True))


def test_model_extraction_errors():
    msg = "unknown extraction 'best'; expected one of ('hysteresis', 'map')"
    with pytest.raises(ValueError, match=re.escape(msg)):
        Model(extraction="best")
    base = make_model("vo")
    with pytest.raises(ValueError, match=re.escape(msg)):
        MultiSensorModel(base.motion, (base.sensor,), (base.clutter,), base.birth,
                         base.survival, "best")
    # the LMB filter also takes the MAP cardinality of every cluster
    with pytest.raises(ValueError, match=re.escape(msg[:-1] + ", 'cluster-map')")):
        LMBFilter(base, Exact(), extraction="best")


# ------------------------------------------------------------------ what a filter's step returns
class _Returns(_OneTrack):
    """A filter whose step returns ``change(a good record)`` at the second scan."""

    def __init__(self, change):
        self.change = change

    def step(self, z, rng=None):
        rec = super().step(z, rng)
        return self.change(rec) if self.k == 2 else rec


@pytest.mark.parametrize("change, exc, match", [
    (lambda r: None, TypeError, re.escape(
        "run_filter: _Returns.step returned NoneType at scan 1, without labels, states, "
        "track_labels, track_existence, timings, invocations, sweeps, row_updates, n_unique, "
        "n_tracks, n_meas, n_meas_gated, n_groups; step must return a record with the fields "
        "of ScanRecord (labels (n, 2), states (n, 4), track_labels (L, 2), track_existence "
        "(L,), timings and invocations")),
    (lambda r: (r.labels, r.states), TypeError, "_Returns.step returned tuple at scan 1, "
                                                "without labels"),
    (lambda r: r._asdict(), TypeError, "_Returns.step returned dict at scan 1"),
    (lambda r: r._replace(labels=r.labels + 0.5), TypeError, re.escape(
        "run_filter: _Returns.step returned labels of dtype float64 at scan 1, expected ints")),
    (lambda r: r._replace(labels=[[1, 1, 1]]), ValueError, re.escape(
        "_Returns.step returned labels of shape (1, 3) at scan 1, expected (n, 2)")),
    (lambda r: r._replace(labels=[[1, 1], [2]]), ValueError, re.escape(
        "_Returns.step returned a ragged labels at scan 1")),
    (lambda r: r._replace(states=np.zeros((2, 4))), ValueError, re.escape(
        "_Returns.step returned states of shape (2, 4) at scan 1, expected (1, d)")),
    (lambda r: r._replace(states=np.zeros((1, 2))), ValueError, re.escape(
        "_Returns.step returned states of shape (1, 2) at scan 1, expected (n, 4): the "
        "positions are columns 0 and 2")),
    (lambda r: r._replace(states=[["a"] * 4]), TypeError,
     "_Returns.step returned states of dtype <U1 at scan 1, expected real numbers"),
    (lambda r: r._replace(track_labels=np.zeros((1, 2))), TypeError,
     "_Returns.step returned track_labels of dtype float64 at scan 1, expected ints"),
    (lambda r: r._replace(track_existence=[0.5, 0.5]), ValueError, re.escape(
        "_Returns.step returned track_existence of shape (2,) at scan 1, expected (1,)")),
    (lambda r: r._replace(sweeps=1.5), TypeError, re.escape(
        "_Returns.step returned sweeps = 1.5 at scan 1, expected an int")),
    (lambda r: r._replace(n_meas=None), TypeError, "_Returns.step returned n_meas = None"),
    (lambda r: r._replace(timings=None), TypeError, re.escape(
        "_Returns.step returned timings = None at scan 1, expected a dict of phase names to "
        "seconds")),
    (lambda r: r._replace(timings={"update": "1 s"}), TypeError,
     "_Returns.step returned timings = .* expected a dict of phase names to seconds"),
])
def test_run_filter_checks_what_step_returns_naming_the_filter(change, exc, match):
    with pytest.raises(exc, match=match):
        run_filter(_Returns(change), [[], [], []], rng=0)
    # a record of numpy ints and lists is fine
    run = run_filter(_Returns(lambda r: r._replace(sweeps=np.int64(4), labels=r.labels.tolist())),
                     [[], [], []], rng=0)
    assert_array_equal(run.sweeps, [0, 4, 0])
