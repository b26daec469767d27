"""Tests of the tracking models, the spec §8 truth and the measurement generator."""

import re

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from rankedassign.tracking import (
    BirthComponent,
    ConstantSurvival,
    ConstantVelocity,
    LMBBirth,
    Model,
    PoissonClutter,
    PositionSensor,
    generate_measurements,
    make_model,
    make_scenario,
    paper_truth,
)


# --------------------------------------------------------------------------- models
def test_constant_velocity_matrices():
    cv = ConstantVelocity(dt=2.0, sigma_w=5.0)
    F = np.array([[1, 2, 0, 0], [0, 1, 0, 0], [0, 0, 1, 2], [0, 0, 0, 1]], dtype=float)
    assert_array_equal(cv.F, F)
    block = 25.0 * np.array([[4.0, 4.0], [4.0, 4.0]])  # σ² [[Δ⁴/4, Δ³/2], [Δ³/2, Δ²]]
    assert_allclose(cv.Q[:2, :2], block, rtol=1e-15)
    assert_allclose(cv.Q[2:, 2:], block, rtol=1e-15)
    assert_array_equal(cv.Q[:2, 2:], 0.0)
    # paper values (A14)
    assert_allclose(ConstantVelocity().Q[:2, :2], [[6.25, 12.5], [12.5, 25.0]], rtol=1e-15)
    with pytest.raises(ValueError):
        cv.F[0, 0] = 3.0  # read-only


def test_sensor_and_clutter():
    s = PositionSensor()
    assert_array_equal(s.H, [[1, 0, 0, 0], [0, 0, 1, 0]])
    assert_array_equal(s.R, 100.0 * np.eye(2))
    assert s.sigma_v == 10.0 and s == PositionSensor(0.98, 10.0)
    # a general noise covariance: a matrix, or a vector for its diagonal; compared by value
    g = PositionSensor(noise_cov=[[25.0, 30.0], [30.0, 400.0]])
    assert_array_equal(g.R, [[25.0, 30.0], [30.0, 400.0]])
    assert g.sigma_v is None and hash(g) == hash(PositionSensor(noise_cov=g.R))
    assert_array_equal(PositionSensor(noise_cov=[25.0, 400.0]).R, np.diag([25.0, 400.0]))
    with pytest.raises(ValueError):
        g.R[0, 0] = 1.0  # read-only
    cl = PoissonClutter(50.0)
    assert_allclose(cl.intensity, 1.25e-5, rtol=1e-15)  # spec A16
    pts = cl.sample(np.random.default_rng(0))
    assert pts.ndim == 2 and pts.shape[1] == 2
    assert np.all(np.abs(pts) <= 1000.0)


def test_clutter_count_is_poisson():
    # Mean of 2000 Poisson(50) counts: SE = sqrt(50 / 2000) = 0.158; a 5-SE band fails with
    # probability < 1e-6 under the model.
    cl = PoissonClutter(50.0)
    rng = np.random.default_rng(1)
    counts = np.array([cl.sample(rng).shape[0] for _ in range(2000)])
    assert abs(counts.mean() - 50.0) < 5 * np.sqrt(50.0 / 2000)


def test_presets():
    paper = make_model("paper")
    assert paper.clutter.rate == 50.0
    assert_allclose(paper.birth.covs[0], np.diag([300.0**2, 10.0**2, 300.0**2, 10.0**2]))
    assert_allclose(paper.birth.r, 0.03)
    assert_array_equal(
        paper.birth.means,
        [[0, 0, 0, 0], [400, 0, -600, 0], [-800, 0, -200, 0], [-200, 0, 800, 0]],
    )
    assert (paper.sensor.p_d, paper.survival.p_s, paper.sensor.sigma_v) == (0.98, 0.99, 10.0)
    vo = make_model("vo")
    assert vo.clutter.rate == 30.0
    assert_allclose(vo.birth.covs, np.broadcast_to(100.0 * np.eye(4), (4, 4, 4)))
    # the paper's birth numbers read as variances; everything else as "paper"
    var = make_model("paper-var")
    assert_allclose(var.birth.covs, np.broadcast_to(np.diag([300.0, 10.0, 300.0, 10.0]),
                                                    (4, 4, 4)), rtol=1e-12)
    assert_array_equal(var.birth.means, paper.birth.means)
    assert_allclose(var.birth.r, paper.birth.r)
    assert (var.motion, var.sensor, var.clutter, var.survival) == (
        paper.motion, paper.sensor, paper.clutter, paper.survival)


@pytest.mark.parametrize(
    ("build", "match"),
    [
        (lambda: make_model("nope"), "unknown preset 'nope'"),
        (lambda: ConstantVelocity(dt=0.0), "dt must be a positive"),
        (lambda: ConstantVelocity(sigma_w=-1.0), "sigma_w must be"),
        (lambda: PositionSensor(p_d=0.0), r"p_d must be in \(0, 1\]"),
        (lambda: PositionSensor(sigma_v=0.0), "sigma_v must be"),
        (lambda: PositionSensor(sigma_v=5.0, noise_cov=[1.0, 1.0]),
         "give either sigma_v or noise_cov, not both"),
        (lambda: PositionSensor(noise_cov=np.eye(3)),
         r"noise_cov must be a symmetric positive definite 2x2 matrix, got shape \(3, 3\)"),
        (lambda: PositionSensor(noise_cov=[[1.0, 2.0], [2.0, 1.0]]),
         r"noise_cov must be a symmetric positive definite 2x2 matrix, got shape \(2, 2\) "
         r"with values \[\[1.0, 2.0\], \[2.0, 1.0\]\]"),
        (lambda: PositionSensor(noise_cov=[np.nan, 1.0]), "noise_cov must be a symmetric"),
        (lambda: PositionSensor(noise_cov=[1.0, 1.0, 1.0]),
         r"noise_cov must be a symmetric positive definite 2x2 matrix, got shape \(3,\)$"),
        (lambda: BirthComponent(0.5, np.zeros(4), np.eye(3)),
         r"birth covariance must be a symmetric positive definite 4x4 matrix, got shape \(3, 3\)"),
        (lambda: PoissonClutter(-1.0), "clutter rate must be"),
        (lambda: PoissonClutter(1.0, ((0, 0), (0, 1))), "region must be"),
        (lambda: ConstantSurvival(1.5), r"p_s must be in \(0, 1\]"),
        (lambda: BirthComponent(1.0, np.zeros(4), np.eye(4)), "birth existence probability"),
        (lambda: BirthComponent(0.1, np.zeros(3), np.eye(4)), "birth mean must be 4"),
        (lambda: BirthComponent(0.1, np.zeros(4), -np.eye(4)), "symmetric positive definite"),
    ],
)
def test_model_errors(build, match):
    with pytest.raises(ValueError, match=match):
        build()


def test_birth_type_error():
    with pytest.raises(TypeError, match="components must be BirthComponent"):
        LMBBirth(("x",))


@pytest.mark.parametrize(
    ("build", "match"),
    [
        # "0.5" < 1 raised "'<' not supported"; True passed as p_d = 1
        (lambda: PositionSensor("0.5"), "p_d must be a real number, got str '0.5'"),
        (lambda: PositionSensor(True), "p_d must be a real number, got bool True"),
        (lambda: PositionSensor(0.9, "10"), "sigma_v must be a real number, got str '10'"),
        (lambda: PositionSensor(noise_cov=[True, True]),
         re.escape("noise_cov must hold real numbers, got [True, True] (dtype bool)")),
        (lambda: PositionSensor(noise_cov=["25", "400"]), "noise_cov must hold real numbers"),
        (lambda: ConstantVelocity(dt=True), "dt must be a real number, got bool True"),
        (lambda: ConstantVelocity(sigma_w="5"), "sigma_w must be a real number, got str '5'"),
        (lambda: PoissonClutter(True), "rate must be a real number, got bool True"),
        (lambda: PoissonClutter(5.0, (("0", "1"), (0, 1))), "region must hold real numbers"),
        (lambda: ConstantSurvival("0.99"), "p_s must be a real number, got str '0.99'"),
        (lambda: BirthComponent(True, np.zeros(4), np.eye(4)),
         "r must be a real number, got bool True"),
        (lambda: BirthComponent(0.1, ["0", "0", "0", "0"], np.eye(4)),
         "birth mean must hold real numbers"),
        (lambda: Model(motion="cv"), "motion must be a ConstantVelocity or LinearMotion, got str"),
        (lambda: Model(sensor=PoissonClutter()), "sensor must be a PositionSensor, got "
                                                  "PoissonClutter"),
        (lambda: Model(birth=(BirthComponent(0.1, np.zeros(4), np.eye(4)),)),
         "birth must be a LMBBirth, got tuple"),
    ],
)
def test_model_type_errors(build, match):
    with pytest.raises(TypeError, match=match):
        build()


@pytest.mark.parametrize(
    ("build", "match"),
    [
        # Python's float ** raised OverflowError here
        (lambda: ConstantVelocity(sigma_w=1e200),
         re.escape("sigma_w = 1e+200 is too large: sigma_w**2 overflows")),
        (lambda: ConstantVelocity(dt=1e200),
         re.escape("dt = 1e+200 is too large: the noise gain G = I_2 ⊗ [dt**2 / 2, dt]' "
                   "overflows")),
        # numpy put inf into Q with a RuntimeWarning
        (lambda: ConstantVelocity(dt=1e100),
         re.escape("dt = 1e+100 with sigma_w = 5.0 makes the process noise covariance "
                   "Q = sigma_w**2 G G' overflow")),
        (lambda: PositionSensor(0.9, 1e200),
         re.escape("sigma_v = 1e+200 is too large: the noise covariance R = sigma_v**2 I or "
                   "its determinant sigma_v**4 overflows")),
        (lambda: PositionSensor(0.9, 1e100), "sigma_v = 1e[+]100 is too large"),
        (lambda: PositionSensor(0.9, 1e-200),
         re.escape("sigma_v = 1e-200 is too small: the noise covariance R = sigma_v**2 I "
                   "underflows to 0")),
        (lambda: PositionSensor(noise_cov=[1e200, 1e200]),
         re.escape("noise_cov is too large: its determinant overflows")),
        (lambda: PositionSensor(noise_cov=[[1e308, -1e308], [1e308, 1e308]]),
         "noise_cov must be a symmetric positive definite 2x2 matrix"),
        (lambda: BirthComponent(0.1, np.zeros(4), np.full(4, 1e100)),
         "birth covariance is too large: its determinant overflows"),
        # ±1e200 gave "math domain error" (ln κ with κ = 0) in the filter
        (lambda: PoissonClutter(5.0, ((-1e200, 1e200), (-1e200, 1e200))),
         re.escape("region ((-1e+200, 1e+200), (-1e+200, 1e+200)) has area (x_max - x_min) * "
                   "(y_max - y_min) = inf, which is not a positive finite number")),
        (lambda: PoissonClutter(5.0, ((0.0, 1e-200), (0.0, 1e-200))), "has area .* = 0.0"),
        (lambda: PoissonClutter(5.0, ((-np.inf, 0.0), (0.0, 1.0))),
         "region must have finite bounds"),
        (lambda: PoissonClutter(1e-320),
         re.escape("clutter intensity rate / area = 1e-320 / 4000000.0 = 0.0 is not a positive "
                   "finite number")),
        (lambda: PoissonClutter(5.0, ((0, 1), (0, 1, 2))),
         "region must be a rectangular array of real numbers, got the ragged sequence"),
    ],
)
def test_model_values_that_would_overflow(build, match):
    with pytest.raises(ValueError, match=match):
        build()


def test_model_parameters_are_stored_as_floats_with_the_same_matrices():
    # ints (and numpy floats) are real numbers: the same matrices as the Python floats
    cv = ConstantVelocity(dt=2, sigma_w=np.float64(5.0))
    assert (cv.dt, cv.sigma_w) == (2.0, 5.0) and type(cv.dt) is float
    assert_array_equal(cv.Q, ConstantVelocity(2.0, 5.0).Q)
    s = PositionSensor(1, 10)
    assert s == PositionSensor(1.0, 10.0) and type(s.p_d) is float
    assert_array_equal(s.R, PositionSensor(1.0, 10.0).R)
    cl = PoissonClutter(50)
    assert cl.intensity == PoissonClutter(50.0).intensity == 1.25e-5
    # large but representable values are kept
    assert np.isfinite(ConstantVelocity(dt=1e10, sigma_w=1e10).Q).all()
    assert PositionSensor(0.9, 1e70).R[0, 0] == 1e140


# --------------------------------------------------------------------------- truth (spec §8)
def test_truth_counts_per_scan():
    t = paper_truth()
    expected = np.concatenate(
        [np.full(19, 3), np.full(20, 6), np.full(20, 8), np.full(11, 10), np.full(9, 8),
         np.full(21, 10)]
    )
    assert_array_equal(t.n_targets, expected)
    assert_allclose(t.n_targets.mean(), 7.29, rtol=1e-12)


def test_truth_first_recorded_states():
    t = paper_truth()
    assert_allclose(t.states[0, 0], [0, 0, -10, -10], rtol=1e-15)
    assert_allclose(t.states[0, 1], [390, -10, -595, 5], rtol=1e-15)
    assert_allclose(t.states[0, 2], [-780, 20, -205, -5], rtol=1e-15)
    # target 4 is born at scan 20: its first recorded state is F x_start
    assert np.isnan(t.states[18, 3]).all()
    assert_allclose(t.states[19, 3], [393, -7, -604, -4], rtol=1e-15)
    # targets 1 and 3 exist up to scan 70 inclusive
    assert not np.isnan(t.states[69, 0]).any() and np.isnan(t.states[70, 0]).all()


def test_truth_region_and_positions():
    t = paper_truth()
    pos = t.positions
    assert pos.shape == (100, 12, 2)
    assert np.nanmin(pos[..., 0]) >= -797 and np.nanmax(pos[..., 0]) <= 715
    assert np.nanmin(pos[..., 1]) >= -924 and np.nanmax(pos[..., 1]) <= 795
    labels, X = t.at(75)
    assert_array_equal(labels, [1, 3, 4, 5, 6, 7, 8, 9])
    assert_array_equal(X, t.states[75, labels])
    short = paper_truth(30)
    assert_array_equal(short.states, t.states[:30])
    with pytest.raises(ValueError, match="n_scans must be an int >= 1, got 0"):
        paper_truth(0)
    with pytest.raises(TypeError, match="n_scans must be an int, got bool True"):
        paper_truth(True)


def test_n_scans_bound_names_the_memory():
    # numpy's MemoryError "Unable to allocate 349. TiB" before
    with pytest.raises(ValueError, match=re.escape(
            "n_scans must be an int <= 1000000 (MAX_SCANS), got 1000000000000: the truth of that "
            "many scans alone would need 349.2 TiB (384 bytes a scan)")):
        paper_truth(10**12)
    with pytest.raises(ValueError, match=r"got 1000001: .* 366.2 MiB"):
        make_scenario("vo", n_scans=10**6 + 1)
    assert paper_truth(np.int64(3)).n_scans == 3


# --------------------------------------------------------------------------- measurements
def test_measurements_reproducible_and_shaped():
    model = make_model("paper")
    truth = paper_truth(10)
    a = generate_measurements(truth, model, rng=3)
    b = generate_measurements(truth, model, rng=3)
    assert len(a) == 10
    for sa, sb in zip(a, b, strict=True):
        assert_array_equal(sa.z, sb.z)
        assert_array_equal(sa.origin, sb.origin)
        assert sa.z.shape == (sa.origin.size, 2)
        # detections come first, in target order, then clutter
        det = sa.origin >= 0
        assert not np.any(det[1:] & ~det[:-1])


def test_measurements_rng_and_argument_errors():
    model, truth = make_model("vo"), paper_truth(3)
    with pytest.raises(TypeError, match=r"rng must be None, a non-negative int .*; got 'seed'"):
        generate_measurements(truth, model, rng="seed")
    with pytest.raises(TypeError, match=r"rng must be .*; got 1.5"):
        generate_measurements(truth, model, rng=1.5)
    with pytest.raises(ValueError, match=r"rng must be .*; got -1 \(expected non-negative"):
        generate_measurements(truth, model, rng=-1)
    with pytest.raises(TypeError, match="truth must be a Truth, got int"):
        generate_measurements(3, model, rng=0)
    with pytest.raises(TypeError, match="model must be a Model, got str"):
        generate_measurements(truth, "vo", rng=0)
    # a RandomState is drawn from directly, as numpy's default_rng wraps it (no change)
    a = generate_measurements(truth, model, rng=np.random.RandomState(4))
    b = generate_measurements(truth, model, rng=np.random.default_rng(np.random.RandomState(4)))
    for sa, sb in zip(a, b, strict=True):
        assert_array_equal(sa.z, sb.z)
    sc = make_scenario("vo", rng=np.random.RandomState(4), n_scans=3)
    for sa, sb in zip(sc.scans, a, strict=True):
        assert_array_equal(sa.z, sb.z)


def test_measurement_statistics():
    # Over 100 scans of the paper scenario: 729 target-scans detected with P_D = 0.98.
    # Detected fraction SE = sqrt(.98 * .02 / 729) = 0.0052; the 5-SE band fails w.p. < 1e-6.
    # Noise: residual variance per axis 100 m²; 700 pairs -> the sample std has SE ≈ 0.27 m.
    sc = make_scenario("paper", rng=11)
    truth = sc.truth
    n_det = n_targets = 0
    res = []
    n_clutter = []
    for k, scan in enumerate(sc.scans):
        labels, X = truth.at(k)
        n_targets += labels.size
        det = scan.origin >= 0
        n_det += det.sum()
        res.append(scan.z[det] - X[np.searchsorted(labels, scan.origin[det])][:, [0, 2]])
        n_clutter.append((~det).sum())
    assert abs(n_det / n_targets - 0.98) < 5 * np.sqrt(0.98 * 0.02 / n_targets)
    res = np.vstack(res)
    assert_allclose(res.mean(axis=0), 0.0, atol=5 * 10 / np.sqrt(len(res)))
    assert_allclose(res.std(axis=0), 10.0, atol=5 * 0.27)
    # clutter mean 50, 100 scans: SE 0.71
    assert abs(np.mean(n_clutter) - 50.0) < 5 * np.sqrt(50.0 / 100)


def test_measurement_noise_with_a_general_covariance():
    # R = [[25, 30], [30, 400]] (5 m and 20 m, correlation 0.3) over the 100 scans of the paper
    # truth, p_D = 1: n = 729 residuals. Standard errors of the sample covariance entries:
    # sqrt(2 R_xx² / n) = 1.31, sqrt(2 R_yy² / n) = 21.0, sqrt((R_xx R_yy + R_xy²) / n) = 3.87;
    # each 5-SE band fails with probability < 1e-6.
    R = np.array([[25.0, 30.0], [30.0, 400.0]])
    model = Model(sensor=PositionSensor(1.0, noise_cov=R))
    truth = paper_truth()
    res = []
    for k, scan in enumerate(generate_measurements(truth, model, rng=5)):
        labels, X = truth.at(k)
        det = scan.origin >= 0
        assert det.sum() == labels.size  # p_D = 1
        res.append(scan.z[det] - X[np.searchsorted(labels, scan.origin[det])][:, [0, 2]])
    res = np.vstack(res)
    n = len(res)
    cov = np.cov(res.T)
    se = np.sqrt(np.array([[2 * R[0, 0] ** 2, R[0, 0] * R[1, 1] + R[0, 1] ** 2],
                           [R[0, 0] * R[1, 1] + R[0, 1] ** 2, 2 * R[1, 1] ** 2]]) / n)
    assert np.all(np.abs(cov - R) < 5 * se), (cov, se)
