"""Tests of the multi-sensor LMB filter, its associations and the ``"multi"`` scenario."""

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

import oracle
from rankedassign.metrics import ospa2
from rankedassign.multisensor import MultiSensorProblem
from rankedassign.tracking import (
    Exact,
    LMBFilter,
    MultiSensorExact,
    MultiSensorGibbs,
    MultiSensorLMBFilter,
    MultiSensorModel,
    MultiSensorShortChains,
    make_model,
    make_multisensor_scenario,
    make_scenario,
    run_multisensor_scenario,
    run_scenario,
)
from rankedassign.tracking.multisensor_association import (
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


def two_sensor_model(base="vo"):
    m = make_model(base)
    return MultiSensorModel(m.motion, (m.sensor, m.sensor), (m.clutter, m.clutter), m.birth,
                            m.survival)


# ------------------------------------------------------------------ V = 1 equals LMBFilter
def test_one_sensor_reproduces_single_sensor_filter():
    sc = make_scenario("vo", rng=3, n_scans=8)
    single = LMBFilter(sc.model, Exact(), grouping=True)
    multi = MultiSensorLMBFilter(sc.model, MultiSensorExact(), grouping=True)
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
        return MultiSensorExact()(problem, rng)

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
    one = MultiSensorLMBFilter(make_model("vo"), MultiSensorExact())
    two = MultiSensorLMBFilter(two_sensor_model(), MultiSensorExact())
    z = [[400.0, -600.0]]
    r1 = one.step([z], rng=0).track_existence.max()
    r2 = two.step([z, z], rng=0).track_existence.max()
    assert r2 > r1


def test_scan_without_measurements_is_closed_form():
    f = MultiSensorLMBFilter(two_sensor_model(), MultiSensorExact())
    rec = f.step([[], np.empty((0, 2))], rng=0)
    # births: r = r_B (1 - P_D)^2 / (1 - r_B + r_B (1 - P_D)^2)
    q = 0.03 * 0.02**2
    assert_allclose(rec.track_existence, q / (0.97 + q), rtol=1e-12)
    assert rec.n_groups == 0 and rec.invocations == 0


def test_step_needs_one_array_per_sensor():
    f = MultiSensorLMBFilter(two_sensor_model(), MultiSensorExact())
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
        MultiSensorLMBFilter("paper", MultiSensorExact())


# ------------------------------------------------------------------ associations
@pytest.mark.parametrize("method", ["truncated", "rao-blackwell"])
def test_marginals_from_every_hypothesis_are_exact(method):
    p = small_problem()
    every = oracle.enumerate_assignments(p)
    dead, tup = multisensor_marginals_from_hypotheses(p, every.assignments, method=method)
    ex = oracle.marginals(p)
    assert_allclose(dead, ex.dead, rtol=1e-12)
    assert_allclose(tup, ex.tuples, rtol=1e-12, atol=1e-15)


def test_rao_blackwell_rows_sum_to_one_on_a_truncated_set():
    p = small_problem()
    some = oracle.enumerate_assignments(p).assignments[:3]
    dead, tup = multisensor_marginals_from_hypotheses(p, some, method="rao-blackwell")
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
    with pytest.raises(ValueError, match="unknown method 'other'"):
        multisensor_marginals_from_hypotheses(p, np.zeros((1, 3, 2)), method="other")


@pytest.mark.parametrize("method", ["exact", "mm", "mm-fixed", "componentwise"])
@pytest.mark.parametrize("kind", ["gibbs", "short"])
def test_samplers_that_find_every_hypothesis_give_the_exact_marginals(method, kind):
    # |Γ| = 18 (9 collapsed); 2000 sweeps (or 40 chains of 50) visit every assignment with
    # this seed; the marginals of the full set are exact whatever the kernel's own target.
    p = MultiSensorProblem.from_factors([0.3, 0.5], [0.7, 0.5], [[[0.5, 2.0], [0.3, 1.0]],
                                        [[0.4, 1.5], [0.2, 0.9]]], coupling=np.full((2, 2, 2), 1.3))
    assoc = (MultiSensorGibbs(2000, method=method) if kind == "gibbs"
             else MultiSensorShortChains(40, 50, method=method))
    res = assoc(p, np.random.default_rng(11))
    assert res.n_unique == (9 if method == "componentwise" else 18) and res.invocations == 1
    ex = oracle.marginals(p)
    assert_allclose(res.dead, ex.dead, rtol=1e-10)
    assert_allclose(res.tuples, ex.tuples, rtol=1e-10, atol=1e-15)


def test_association_reprs_and_checks():
    assert repr(MultiSensorGibbs(10, method="mm")) == "MultiSensorGibbs(10, method='mm')"
    assert repr(MultiSensorShortChains(4, 5)) == (
        "MultiSensorShortChains(4, 5, tau_stall=None, tau_stale=None)")
    assert "fallback=MultiSensorGibbs(5)" in repr(MultiSensorExact(MultiSensorGibbs(5)))
    with pytest.raises(ValueError, match="unknown method 'fast'"):
        MultiSensorGibbs(10, method="fast")
    with pytest.raises(ValueError, match="n_obs"):
        MultiSensorGibbs(0)
    with pytest.raises(TypeError, match="fallback must be an association or None, got int"):
        MultiSensorExact(3)


def test_exact_refuses_a_problem_beyond_the_dp_and_falls_back_when_asked():
    p = MultiSensorProblem.from_eta(np.full(3, 0.5), np.ones((3, 13, 13)))  # 24 bits, 3.1e6
    with pytest.raises(ValueError, match=r"MultiSensorExact: a group of P = 3 tracks with "
                                         r"M = \(12, 12\) gated measurements is beyond"):
        MultiSensorExact()(p, None)
    ex = MultiSensorExact(fallback=MultiSensorShortChains(2, 2))
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
    run = run_scenario("multi", MultiSensorShortChains(30, 5, 5, 10), rng=2, n_scans=4,
                       sensors=(0, 2))
    assert run.scenario.sensors == (0, 2) and run.truth.shape == (4, 12, 2)
    assert run.estimates.shape[:2] == (4, run.estimates.shape[1])[:2]
    assert (run.invocations >= 1).all() and (run.sweeps > 0).all()
    curve = ospa2(run.truth, run.estimates, c=200, p=1, window=5).value
    assert curve.shape == (4,) and np.isfinite(curve).all()
    again = run_multisensor_scenario(MultiSensorShortChains(30, 5, 5, 10), rng=2, n_scans=4,
                                     sensors=(0, 2))
    assert_array_equal(np.nan_to_num(again.estimates), np.nan_to_num(run.estimates))


def test_run_scenario_errors():
    with pytest.raises(ValueError, match="sensors applies to the 'multi' preset only"):
        run_scenario("vo", Exact(), n_scans=1, sensors=(0,))
    with pytest.raises(TypeError, match="run_multisensor_scenario needs an association"):
        run_multisensor_scenario(None, n_scans=1)
    with pytest.raises(ValueError, match="n_scans"):
        make_multisensor_scenario(n_scans=0)


@pytest.mark.parametrize("method", ["exact", "mm", "componentwise"])
def test_filter_runs_with_rao_blackwellised_marginals(method):
    run = run_multisensor_scenario(
        MultiSensorShortChains(20, 5, 5, 10, method=method, marginals="rao-blackwell"),
        rng=3, n_scans=3, sensors=(0, 1), birth="narrow")
    assert all(0 <= r <= 1 for scan in run.existence for r in scan.values())
    assert (run.sweeps > 0).any()
