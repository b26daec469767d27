"""Tests of the multi-sensor LMB filter, its associations and the ``"multi"`` scenario."""

import re

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

import oracle
from rankedassign import AssignmentProblem
from rankedassign.engine.rng import base_key
from rankedassign.metrics import ospa2
from rankedassign.multisensor import MultiSensorProblem
from rankedassign.tracking import (
    LBP,
    Association,
    Exact,
    LMBFilter,
    MultiSensorGLMBFilter,
    MultiSensorLMBFilter,
    MultiSensorModel,
    Murty,
    OriginalGibbs,
    ShortChainGibbs,
    make_model,
    make_multisensor_model,
    make_multisensor_scenario,
    make_scenario,
    run_multisensor_scenario,
    run_scenario,
)
from rankedassign.tracking.multisensor.association import (
    MultiSensorAssociationResult,
    multisensor_marginals_from_hypotheses,
)


def small_problem():
    """P = 3 rows, V = 2 sensors, M = (2, 1), one forbidden tuple; |Γ| small."""
    rng = np.random.default_rng(5)
    eta = rng.uniform(0.1, 2.0, size=(3, 3, 2))
    eta[1, 2, 1] = 0.0
    return MultiSensorProblem.from_factors(
        [0.3, 0.5, 0.2], [0.7, 0.5, 0.8],
        [rng.uniform(0.1, 2.0, (3, 3)), rng.uniform(0.1, 2.0, (3, 2))], coupling=eta,
    )


class _SingleOnly(Association):
    """An association of one's own for one sensor's problems (``sensors`` as the base's)."""

    def __call__(self, problem, rng):  # pragma: no cover (refused before it is called)
        raise AssertionError


def two_sensor_model(base="vo"):
    m = make_model(base)
    return MultiSensorModel(m.motion, (m.sensor, m.sensor), (m.clutter, m.clutter), m.birth,
                            m.survival)


# ------------------------------------------------------------------ V = 1 equals LMBFilter
def test_one_sensor_reproduces_single_sensor_filter():
    sc = make_scenario("vo", rng=3, n_scans=8)
    single = LMBFilter(sc.model, Exact(), grouping=True)
    multi = MultiSensorLMBFilter(sc.model, Exact(), grouping=True)
    for k, scan in enumerate(sc.scans):
        a = single.step(scan.z, rng=k)
        b = multi.step([scan.z], rng=k)
        assert_array_equal(a.track_labels, b.track_labels)
        assert_array_equal(a.labels, b.labels)
        assert_allclose(b.track_existence, a.track_existence, rtol=1e-10, atol=1e-14)
        assert_allclose(b.states, a.states, rtol=1e-10, atol=1e-9)
        assert (a.n_groups, a.n_meas, a.n_meas_gated) == (b.n_groups, b.n_meas, b.n_meas_gated)
    assert_array_equal(single.offsets, multi.offsets)
    assert_allclose(multi.w, single.w, rtol=1e-9, atol=1e-15)
    assert_allclose(multi.P, single.P, rtol=1e-9, atol=1e-9)


def test_one_sensor_problem_is_the_single_sensor_problem():
    sc = make_scenario("vo", rng=4, n_scans=3)
    single = LMBFilter(sc.model, Exact())
    seen = []

    def capture(problem, rng):
        seen.append(problem)
        return Exact()(problem, rng)

    multi = MultiSensorLMBFilter(sc.model, capture, grouping=False)
    for k, scan in enumerate(sc.scans):
        single.step(scan.z, rng=k)
        multi.step([scan.z], rng=k)
    # rebuild the last single-sensor problem from the filter's own phases
    single_p = MultiSensorProblem.from_assignment_problem(
        _last_single_problem(sc, n=3)).log_eta_alive
    assert_allclose(seen[-1].log_eta_alive, single_p, rtol=1e-12)
    assert seen[-1].log_s is not None and len(seen[-1].log_theta) == 1


def _last_single_problem(sc, n):
    captured = []

    class Capture(Exact):
        def __call__(self, problem, rng):
            captured.append(problem)
            return super().__call__(problem, rng)

    f = LMBFilter(sc.model, Capture())
    for k, scan in enumerate(sc.scans[:n]):
        f.step(scan.z, rng=k)
    return captured[-1]


# ------------------------------------------------------------------ filter behaviour
def test_two_sensors_confirm_a_target_faster_than_one():
    one = MultiSensorLMBFilter(make_model("vo"), Exact())
    two = MultiSensorLMBFilter(two_sensor_model(), Exact())
    z = [[400.0, -600.0]]
    r1 = one.step([z], rng=0).track_existence.max()
    r2 = two.step([z, z], rng=0).track_existence.max()
    assert r2 > r1


def test_scan_without_measurements_is_closed_form():
    f = MultiSensorLMBFilter(two_sensor_model(), Exact())
    rec = f.step([[], np.empty((0, 2))], rng=0)
    # births: r = r_B (1 - P_D)^2 / (1 - r_B + r_B (1 - P_D)^2)
    q = 0.03 * 0.02**2
    assert_allclose(rec.track_existence, q / (0.97 + q), rtol=1e-12)
    assert rec.n_groups == 0 and rec.invocations == 0


def test_step_needs_one_array_per_sensor():
    f = MultiSensorLMBFilter(two_sensor_model(), Exact())
    with pytest.raises(ValueError, match=r"one measurement array per sensor \(V = 2\), got 1"):
        f.step([[[0.0, 0.0]]])
    with pytest.raises(ValueError, match="got an array"):
        f.step(np.zeros((2, 1, 2)))


def test_association_returning_wrong_shapes_is_refused():
    def bad(problem, rng):
        return MultiSensorAssociationResult(np.zeros(1), np.zeros((1, 1)), 1, 0, 0, 0)

    f = MultiSensorLMBFilter(two_sensor_model(), bad)
    with pytest.raises(ValueError, match="association returned marginals of shapes"):
        f.step([[[400.0, -600.0]], [[400.0, -600.0]]])


def test_model_validation():
    m = make_model("vo")
    with pytest.raises(ValueError, match="at least one sensor"):
        MultiSensorModel(m.motion, (), (), m.birth, m.survival)
    with pytest.raises(ValueError, match=r"one entry per sensor \(2\), got 1"):
        MultiSensorModel(m.motion, (m.sensor, m.sensor), (m.clutter,), m.birth, m.survival)
    with pytest.raises(TypeError, match=r"sensors\[0\]"):
        MultiSensorModel(m.motion, ("x",), (m.clutter,), m.birth, m.survival)
    with pytest.raises(TypeError, match=r"clutters\[0\]"):
        MultiSensorModel(m.motion, (m.sensor,), (1.0,), m.birth, m.survival)
    with pytest.raises(ValueError, match=r"distinct indices in 0..1, got \[1, 1\]"):
        two_sensor_model().select([1, 1])
    with pytest.raises(TypeError, match="model"):
        MultiSensorLMBFilter("paper", Exact())
    with pytest.raises(TypeError, match="motion must be a ConstantVelocity, got str"):
        MultiSensorModel("cv", (m.sensor,), (m.clutter,), m.birth, m.survival)
    with pytest.raises(TypeError, match="survival must be a ConstantSurvival, got float"):
        MultiSensorModel(m.motion, (m.sensor,), (m.clutter,), m.birth, 0.99)
    with pytest.raises(TypeError, match="sensors must be a Sequence, got PositionSensor; one "
                                        "entry per sensor"):
        MultiSensorModel(m.motion, m.sensor, (m.clutter,), m.birth, m.survival)


# ------------------------------------------------------------------ argument checks
@pytest.mark.parametrize(
    ("association", "match"),
    [
        # a numba TypingError after half a minute before
        (Murty(5), re.escape(
            "MultiSensorLMBFilter cannot use Murty: Murty's ranked search solves one sensor's "
            "problem; there is no ranked multi-sensor search (use Exact or a sampler "
            "truncation)")),
        (LBP(), re.escape("MultiSensorLMBFilter cannot use LBP: loopy belief propagation is "
                          "written for one sensor's problem")),
        (_SingleOnly(), "MultiSensorLMBFilter cannot use _SingleOnly: it solves single-sensor "
                        "problems only"),
        (3, "association must be callable as association\\(problem, rng\\), got int"),
    ],
)
def test_filter_refuses_a_single_sensor_association(association, match):
    with pytest.raises(TypeError, match=match):
        MultiSensorLMBFilter(two_sensor_model(), association)
    with pytest.raises(TypeError, match=match):
        run_multisensor_scenario(association, n_scans=1)


def test_one_exact_class_serves_both_kinds_and_takes_any_fallback():
    ex = Exact(fallback=Exact())
    single = AssignmentProblem.from_eta([[3.0]], [1.0], [1.0])
    assert_allclose(ex(single, None).beta, [[0.6, 0.2, 0.2]], rtol=1e-12)
    multi = MultiSensorProblem.from_eta([1.0], [[[1.0, 2.0], [3.0, 0.0]]])
    assert_allclose(7 * ex(multi, None).dead, [1.0], rtol=1e-12)


@pytest.mark.parametrize(
    ("sensors", "exc", "match"),
    [
        # 0.5 ran as sensor 0, True as sensor 1, strings were converted by int()
        ((0.5,), TypeError, re.escape("sensors[0] must be an int (a sensor index), got float 0.5")),
        ((0, True), TypeError, re.escape("sensors[1] must be an int (a sensor index), got bool "
                                         "True")),
        (("1",), TypeError, re.escape("sensors[0] must be an int (a sensor index), got str '1'")),
        (np.array([0.0, 1.0]), TypeError, re.escape("sensors[0] must be an int (a sensor index)")),
        # "'int' object is not iterable" before
        (5, TypeError, "sensors must be a sequence of sensor indices \\(ints\\), got int 5"),
        ("01", TypeError, "sensors must be a sequence of sensor indices \\(ints\\), got str '01'"),
        ({0, 1}, TypeError, "sensors must be a sequence of sensor indices \\(ints\\), got set"),
        ((0, 0), ValueError, re.escape("sensors must be distinct indices in 0..3, got [0, 0]")),
        ((4,), ValueError, re.escape("sensors must be distinct indices in 0..3, got [4]")),
        ((-1,), ValueError, re.escape("sensors must be distinct indices in 0..3, got [-1]")),
        ((), ValueError, re.escape("sensors must be distinct indices in 0..3, got []")),
    ],
)
def test_sensor_selection_errors(sensors, exc, match):
    with pytest.raises(exc, match=match):
        make_multisensor_model(sensors)
    with pytest.raises(exc, match=match):
        make_multisensor_scenario(n_scans=1, sensors=sensors)
    with pytest.raises(exc, match=match):
        run_scenario("multi", Exact(), n_scans=1, sensors=sensors)


def test_sensor_selections_that_are_accepted():
    ref = make_multisensor_model((2, 0))
    for sensors in ([2, 0], np.array([2, 0]), (np.int64(2), 0)):
        m = make_multisensor_model(sensors)
        assert (m.sensors, m.clutters) == (ref.sensors, ref.clutters)
    assert make_multisensor_model(range(2)).sensors == make_multisensor_model((0, 1)).sensors
    sc = make_multisensor_scenario(rng=1, n_scans=2, sensors=np.array([2, 0]))
    assert sc.sensors == (2, 0) and all(type(v) is int for v in sc.sensors)


def test_single_refuses_what_is_not_a_sensor_index():
    m = two_sensor_model()
    assert m.single(np.int64(1)).sensor == m.sensors[1]
    # -1 returned the last sensor before
    with pytest.raises(ValueError, match="v must be an int >= 0, got -1"):
        m.single(-1)
    with pytest.raises(ValueError, match="v must be an int <= 1, got 2"):
        m.single(2)
    with pytest.raises(TypeError, match="v must be an int, got bool True"):
        m.single(True)
    with pytest.raises(TypeError, match="v must be an int, got float 1.0"):
        m.single(1.0)


def test_filter_boolean_options():
    with pytest.raises(TypeError, match="grouping must be True or False, got str 'no'"):
        MultiSensorLMBFilter(two_sensor_model(), Exact(), grouping="no")
    with pytest.raises(TypeError, match="sample_empty_groups must be True or False, got str"):
        MultiSensorLMBFilter(two_sensor_model(), Exact(), sample_empty_groups="x")
    with pytest.raises(TypeError, match="grouping must be True or False, got int 0"):
        run_multisensor_scenario(Exact(), n_scans=1, grouping=0)
    with pytest.raises(TypeError, match="grouping must be True or False, got str 'no'"):
        run_scenario("multi", Exact(), n_scans=1, grouping="no")
    f = MultiSensorLMBFilter(two_sensor_model(), Exact(), grouping=np.False_,
                             sample_empty_groups=True)
    assert f.grouping is False


def test_n_scans_bound():
    match = re.escape("n_scans must be an int <= 1000000 (MAX_SCANS), got 1000000000000: the "
                      "truth of that many scans alone would need 349.2 TiB (384 bytes a scan)")
    with pytest.raises(ValueError, match=match):
        make_multisensor_scenario(n_scans=10**12)
    with pytest.raises(ValueError, match=match):
        run_multisensor_scenario(Exact(), n_scans=10**12)
    with pytest.raises(ValueError, match=match):
        run_scenario("multi", Exact(), n_scans=10**12)


@pytest.mark.parametrize(
    ("zs", "exc", "match"),
    [
        ([[[0.0, 0.0]], [["1.5", "2"]]], TypeError,
         re.escape("measurements of sensor 1 must be real numbers, got strings (dtype <U3) in a "
                   "scan of shape (1, 2)")),
        ([np.zeros((0, 3)), []], ValueError,
         re.escape("measurements of sensor 0 must have shape (M, 2), got shape (0, 3)")),
        ([[[0.0, 0.0], [1.0]], []], ValueError,
         "measurements of sensor 0 must be an \\(M, 2\\) array of real numbers, got a ragged"),
        ([[], [[np.nan, 0.0]]], ValueError,
         re.escape("measurements of sensor 1 must be finite, got nan at [0, 0] in a scan of "
                   "shape (1, 2)")),
        (5, TypeError, re.escape("step needs one measurement array per sensor (V = 2), got int")),
    ],
)
def test_step_measurement_errors(zs, exc, match):
    f = MultiSensorLMBFilter(two_sensor_model(), Exact())
    with pytest.raises(exc, match=match):
        f.step(zs)


def test_step_rng_errors_and_random_state():
    f = MultiSensorLMBFilter(two_sensor_model(), Exact())
    with pytest.raises(TypeError, match=r"rng must be None, .*; got 1.5"):
        f.step([[], []], rng=1.5)
    with pytest.raises(TypeError, match=r"rng must be None, .*; got 'seed'"):
        f.step([[], []], rng="seed")
    with pytest.raises(ValueError, match=r"rng must be None, .*; got -1"):
        f.step([[], []], rng=-1)
    # "does not implement spawning" before: the Generator seeded with one draw, as the
    # samplers take it
    z = [[[400.0, -600.0], [0.0, 0.0]], [[401.0, -602.0]]]
    rs, keys = np.random.RandomState(2), np.random.RandomState(2)
    g, h = (MultiSensorLMBFilter(two_sensor_model(), ShortChainGibbs(20, 5, tau_stall=5, tau_stale=10, method="exact"))
            for _ in range(2))
    for _ in range(2):
        a, b = g.step(z, rng=rs), h.step(z, rng=base_key(keys))
        assert_array_equal(a.track_existence, b.track_existence)
        assert a.sweeps == b.sweeps > 0
    a = make_multisensor_scenario(rng=np.random.RandomState(5), n_scans=2, sensors=(0,))
    b = make_multisensor_scenario(rng=base_key(np.random.RandomState(5)), n_scans=2,
                                  sensors=(0,))
    assert_array_equal(a.scans[1][0].z, b.scans[1][0].z)
    with pytest.raises(TypeError, match=r"rng must be None, .*; got 1.5"):
        make_multisensor_scenario(rng=1.5, n_scans=1)


def _ms_result(dead_value, tuple_value=0.0, at=None):
    """An association giving every row ``dead_value`` and ``tuple_value`` on tuple ``at``."""

    def fixed(problem, rng):
        tup = np.zeros(problem.log_eta_alive.shape)
        if at is not None:
            tup[(slice(None), *at)] = tuple_value
        return MultiSensorAssociationResult(np.full(problem.n_rows, dead_value), tup, 1, 0, 0, 0)

    return fixed


@pytest.mark.parametrize(
    ("association", "match"),
    [
        (_ms_result(np.nan), re.escape("association _ms_result.<locals>.fixed returned a "
                                       "non-finite marginal: dead[0] = nan")),
        (_ms_result(1.0, -0.5, (1, 0)),
         re.escape("returned a negative marginal: tuples[0, 1, 0] = -0.5")),
        (_ms_result(0.5),
         re.escape("association _ms_result.<locals>.fixed returned marginals that are not a "
                   "distribution: dead[0] + tuples[0].sum() = 0.5, not 1 (tolerance 1e-09)")),
        (_ms_result(0.5, 0.5, (0, 0)), None),  # a distribution: accepted
    ],
)
def test_association_output_is_checked(association, match):
    f = MultiSensorLMBFilter(two_sensor_model(), association)
    z = [[[400.0, -600.0]], [[400.0, -600.0]]]
    if match is None:
        assert f.step(z, rng=0).n_groups >= 1
        return
    with pytest.raises(ValueError, match=match):
        f.step(z, rng=0)


# ------------------------------------------------------------------ associations
@pytest.mark.parametrize("method", ["truncated", "rao-blackwell"])
def test_marginals_from_every_hypothesis_are_exact(method):
    p = small_problem()
    every = oracle.enumerate_assignments(p)
    dead, tup = multisensor_marginals_from_hypotheses(p, every.assignments, marginals=method)
    ex = oracle.marginals(p)
    assert_allclose(dead, ex.dead, rtol=1e-12)
    assert_allclose(tup, ex.tuples, rtol=1e-12, atol=1e-15)


def test_rao_blackwell_rows_sum_to_one_on_a_truncated_set():
    p = small_problem()
    some = oracle.enumerate_assignments(p).assignments[:3]
    dead, tup = multisensor_marginals_from_hypotheses(p, some, marginals="rao-blackwell")
    assert_allclose(dead + tup.reshape(3, -1).sum(axis=1), 1.0, rtol=1e-12)
    assert (tup.reshape(3, -1)[:, p.log_eta_alive.reshape(3, -1)[0] == -np.inf] == 0).all()


def test_marginals_from_hypotheses_errors():
    p = small_problem()
    with pytest.raises(ValueError, match=r"shape \(H, P, V\) = \(H, 3, 2\)"):
        multisensor_marginals_from_hypotheses(p, np.zeros((1, 3)))
    with pytest.raises(ValueError, match="at least one hypothesis"):
        multisensor_marginals_from_hypotheses(p, np.zeros((0, 3, 2)))
    with pytest.raises(ValueError, match="every hypothesis must be feasible"):
        multisensor_marginals_from_hypotheses(p, [[[1, 0], [1, 0], [0, 0]]])
    with pytest.raises(ValueError, match=r"costs must have shape \(1,\)"):
        multisensor_marginals_from_hypotheses(p, np.zeros((1, 3, 2)), costs=[1.0, 2.0])
    with pytest.raises(ValueError, match="unknown marginals 'other'"):
        multisensor_marginals_from_hypotheses(p, np.zeros((1, 3, 2)), marginals="other")


@pytest.mark.parametrize("method", ["exact", "mm", "mm-fixed", "componentwise"])
@pytest.mark.parametrize("kind", ["gibbs", "short"])
def test_samplers_that_find_every_hypothesis_give_the_exact_marginals(method, kind):
    # |Γ| = 18 (9 collapsed); 2000 sweeps (or 40 chains of 50) visit every assignment with
    # this seed; the marginals of the full set are exact whatever the kernel's own target.
    p = MultiSensorProblem.from_factors([0.3, 0.5], [0.7, 0.5], [[[0.5, 2.0], [0.3, 1.0]],
                                        [[0.4, 1.5], [0.2, 0.9]]], coupling=np.full((2, 2, 2), 1.3))
    assoc = (OriginalGibbs(2000, method=method) if kind == "gibbs"
             else ShortChainGibbs(40, 50, method=method))
    res = assoc(p, np.random.default_rng(11))
    assert res.n_unique == (9 if method == "componentwise" else 18) and res.invocations == 1
    ex = oracle.marginals(p)
    assert_allclose(res.dead, ex.dead, rtol=1e-10)
    assert_allclose(res.tuples, ex.tuples, rtol=1e-10, atol=1e-15)


def test_association_reprs_and_checks():
    assert repr(OriginalGibbs(10, method="mm")) == "OriginalGibbs(10)"
    assert repr(ShortChainGibbs(4, 5, method="exact")) == (
        "ShortChainGibbs(4, 5, tau_stall=None, tau_stale=None, method='exact')")
    assert "fallback=OriginalGibbs(5, method='exact')" in repr(
        Exact(OriginalGibbs(5, method="exact")))
    with pytest.raises(ValueError, match="unknown method 'fast'"):
        OriginalGibbs(10, method="fast")
    with pytest.raises(ValueError, match="n_obs"):
        OriginalGibbs(0, method="exact")
    with pytest.raises(TypeError, match="fallback must be an association or None, got int"):
        Exact(3)


@pytest.mark.parametrize(("old", "new", "args"), [
    ("MultiSensorOriginalGibbs", "OriginalGibbs", (10,)),
    ("MultiSensorShortChainGibbs", "ShortChainGibbs", (4, 5)),
    ("MultiSensorHerdedGibbs", "HerdedGibbs", (10,)),
    ("MultiSensorExact", "Exact", ()),
])
def test_the_old_multisensor_names_are_deprecated_aliases(old, new, args):
    import rankedassign.tracking as tracking
    from rankedassign.tracking.multisensor import association as old_module

    alias = getattr(tracking, old)
    assert getattr(old_module, old) is alias
    with pytest.warns(DeprecationWarning, match=f"{old} is deprecated .*; use {new} "):
        a = alias(*args)
    assert isinstance(a, getattr(tracking, new))
    assert repr(a).startswith(f"{old}(")   # the repr the runs recorded
    if new != "Exact":   # the old default row conditional, so that the numbers hold
        assert a.method == "exact" and getattr(tracking, new)(*args).method == "mm"


def test_exact_refuses_a_problem_beyond_the_dp_and_falls_back_when_asked():
    p = MultiSensorProblem.from_eta(np.full(3, 0.5), np.ones((3, 13, 13)))  # 24 bits, 3.1e6
    with pytest.raises(ValueError, match=r"Exact: a group of P = 3 tracks with "
                                         r"M = \(12, 12\) gated measurements is beyond"):
        Exact()(p, None)
    ex = Exact(fallback=ShortChainGibbs(2, 2, method="exact"))
    res = ex(p, np.random.default_rng(0))
    assert ex.n_fallback == 1 and res.sweeps > 0


# ------------------------------------------------------------------ scenario
def test_sensor_measurements_do_not_depend_on_the_selection():
    a = make_multisensor_scenario(rng=7, n_scans=4, sensors=(0, 1, 2, 3))
    b = make_multisensor_scenario(rng=7, n_scans=4, sensors=(3, 1))
    for k in range(4):
        assert_array_equal(a.scans[k][3].z, b.scans[k][0].z)
        assert_array_equal(a.scans[k][1].origin, b.scans[k][1].origin)
    c = make_multisensor_scenario(rng=8, n_scans=4, sensors=(1,))
    assert not np.array_equal(np.vstack([s[0].z for s in c.scans]),
                              np.vstack([s[1].z for s in b.scans]))
    assert [s.p_d for s in b.model.sensors] == [0.7, 0.7]
    assert [s.sigma_v for s in a.model.sensors] == [10.0, 15.0, 20.0, 10.0]


def test_run_scenario_multi_feeds_ospa2():
    run = run_scenario("multi", ShortChainGibbs(30, 5, tau_stall=5, tau_stale=10, method="exact"), rng=2, n_scans=4,
                       sensors=(0, 2))
    assert run.scenario.sensors == (0, 2) and run.truth.shape == (4, 12, 2)
    assert run.estimates.shape[:2] == (4, run.estimates.shape[1])[:2]
    assert (run.invocations >= 1).all() and (run.sweeps > 0).all()
    curve = ospa2(run.truth, run.estimates, c=200, p=1, window=5).value
    assert curve.shape == (4,) and np.isfinite(curve).all()
    again = run_multisensor_scenario(ShortChainGibbs(30, 5, tau_stall=5, tau_stale=10, method="exact"), rng=2, n_scans=4,
                                     sensors=(0, 2))
    assert_array_equal(np.nan_to_num(again.estimates), np.nan_to_num(run.estimates))


def test_run_scenario_errors():
    with pytest.raises(ValueError, match=re.escape(
            "sensors applies to the multi-sensor presets ('multi', 'multi-bearing-range') "
            "only")):
        run_scenario("vo", Exact(), n_scans=1, sensors=(0,))
    with pytest.raises(TypeError, match="run_multisensor_scenario needs an association"):
        run_multisensor_scenario(None, n_scans=1)
    with pytest.raises(ValueError, match="n_scans"):
        make_multisensor_scenario(n_scans=0)


@pytest.mark.parametrize("method", ["exact", "mm", "componentwise"])
def test_filter_runs_with_rao_blackwellised_marginals(method):
    run = run_multisensor_scenario(
        ShortChainGibbs(20, 5, tau_stall=5, tau_stale=10, method=method, marginals="rao-blackwell"),
        rng=3, n_scans=3, sensors=(0, 1), birth="narrow")
    assert all(0 <= r <= 1 for scan in run.existence for r in scan.values())
    assert (run.sweeps > 0).any()


@pytest.mark.parametrize("cls", [MultiSensorLMBFilter, MultiSensorGLMBFilter])
def test_detection_probability_one_gives_no_nan(cls):
    """P_D = 1 (allowed by the sensor) makes log(1 - P_D) = -inf: the hypotheses that miss a
    sensor weigh 0, those that detect on every sensor stay finite; the result is the limit
    P_D -> 1 (compared with P_D = 1 - 1e-13), never NaN."""
    import dataclasses

    def model(p_d):
        m = make_model("vo")
        s = dataclasses.replace(m.sensor, p_d=p_d)
        return MultiSensorModel(m.motion, (s, s), (m.clutter, m.clutter), m.birth, m.survival)

    z = [[400.0, -600.0], [-200.0, 300.0]]
    scans = [[z, z], [z, np.array(z) + 5.0]]
    exact, near = cls(model(1.0), Exact()), cls(model(1.0 - 1e-13), Exact())
    for k, scan in enumerate(scans):
        a, b = exact.step(scan, rng=k), near.step(scan, rng=k)
        assert np.all(np.isfinite(a.track_existence))
        assert_allclose(a.track_existence, b.track_existence, rtol=1e-9, atol=1e-12)
