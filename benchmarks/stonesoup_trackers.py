"""Our LMB and δ-GLMB trackers with births from the measurements against Stone Soup's JPDA tracker.

Run with::

    python benchmarks/stonesoup_trackers.py            # 3 seeds, 100 scans (the README's)
    python benchmarks/stonesoup_trackers.py --seeds 5 --scans 50

The scenario is a Stone Soup simulation whose targets are born anywhere in the region: a
``MultiTargetGroundTruthSimulator`` (constant velocity, ``q = 0.05``, one-second steps) whose
targets start from ``N(0, diag(400², 4², 400², 4²))`` (5 at the start, 0.1 births and a death
probability of 0.01 per scan), seen by a ``SimpleDetectionSimulator`` (position sensor,
``R = 5² I``, ``P_D = 0.9``, 10 clutter detections per scan uniform on ±1500 m). Every tracker
sees the same detections of a seed.

* **JPDA**: Stone Soup's ``MultiTargetMixtureTracker`` with ``JPDAwithEHM2`` (a
  ``PDAHypothesiser``), a ``MultiMeasurementInitiator`` (GNN over a ``DistanceHypothesiser``,
  Mahalanobis, missed distance 3, the initiator's prior velocity variance 4²) and a
  ``CovarianceBasedDeleter``; the initiator's ``min_points`` and the deleter's
  ``covar_trace_thresh`` are tuned over a grid, and the best cell (lowest mean OSPA over the
  seeds, tuned on the very seeds it is scored on, which favours it) is reported.
* **LMB** and **GLMB**: ``LMBTracker`` / ``GLMBTracker`` built from the same
  ``KalmanPredictor`` and ``KalmanUpdater``, ``birth_components=None`` (births from the
  measurements, ``velocity_cov = 4²`` as the initiator's prior, other options at their
  defaults), default associations (short-chain Gibbs), not tuned.

Printed: mean OSPA (c = 10 m, p = 1, positions, every scan) and wall time per scan of each
tracker per seed, and their means. Numbers and the command are in ``benchmarks/README.md``.
"""

from __future__ import annotations

import argparse
import datetime
import itertools
import time

import numpy as np

T0 = datetime.datetime(2025, 1, 1)
#: The JPDA tracker's grid: initiator min_points x deleter covar_trace_thresh.
GRID = {"min_points": (2, 3, 4), "covar_trace_thresh": (25.0, 100.0, 400.0)}
CLUTTER_RATE = 10.0
P_D = 0.9
VELOCITY_SD = 4.0
#: The bearing–range sensor (``--sensor bearing-range``): position, noise, clutter region.
SENSOR = (0.0, -2500.0)
BEARING_SD = np.radians(0.1)
RANGE_SD = 5.0
BEARINGS = (np.pi / 6, 5 * np.pi / 6)
RANGES = (1000.0, 4500.0)


def simulate(seed: int, n_scans: int, sensor: str = "position"):
    """``(scans, truths, density, transition_model, measurement_model)`` of one seed.

    ``scans`` is a list of ``(time, set of Detection)``, ``truths`` the true positions
    ``(n, 2)`` at every scan. ``sensor``: ``"position"`` or ``"bearing-range"``.
    """
    from stonesoup.models.measurement.linear import LinearGaussian
    from stonesoup.models.measurement.nonlinear import CartesianToBearingRange
    from stonesoup.models.transition.linear import (
        CombinedLinearGaussianTransitionModel,
        ConstantVelocity,
    )
    from stonesoup.simulator.simple import (
        MultiTargetGroundTruthSimulator,
        SimpleDetectionSimulator,
    )
    from stonesoup.types.state import GaussianState

    cv = CombinedLinearGaussianTransitionModel([ConstantVelocity(0.05)] * 2)
    mm = LinearGaussian(ndim_state=4, mapping=(0, 2), noise_covar=np.diag([25.0, 25.0]))
    prior = GaussianState([[0], [0], [0], [0]],
                          np.diag([400.0 ** 2, VELOCITY_SD ** 2, 400.0 ** 2,
                                   VELOCITY_SD ** 2]), timestamp=T0)
    gt = MultiTargetGroundTruthSimulator(
        cv, prior, timestep=datetime.timedelta(seconds=1), number_steps=n_scans,
        birth_rate=0.1, death_probability=0.01, initial_number_targets=5, seed=seed)
    meas_range = np.array([[-1500.0, 1500.0], [-1500.0, 1500.0]])
    if sensor == "bearing-range":
        mm = CartesianToBearingRange(
            4, (0, 2), np.diag([BEARING_SD ** 2, RANGE_SD ** 2]),
            translation_offset=np.array([[SENSOR[0]], [SENSOR[1]]]))
        meas_range = np.array([BEARINGS, RANGES])
    sim = SimpleDetectionSimulator(
        gt, mm, meas_range=meas_range,
        detection_probability=P_D, clutter_rate=CLUTTER_RATE, seed=seed + 1000)
    scans, truths = [], []
    for t, dets in sim:
        scans.append((t, set(dets)))
        X = [np.asarray(p.state_vector, float).ravel()[[0, 2]]
             for p in gt.groundtruth_paths if p.state.timestamp == t]
        truths.append(np.array(X).reshape(-1, 2))
    return scans, truths, sim.clutter_spatial_density, cv, mm


def mean_ospa(tracker, scans, truths) -> tuple[float, float]:
    """Mean OSPA (c = 10, p = 1) over the scans and the wall time per scan of ``tracker``."""
    from rankedassign.metrics import ospa

    values = []
    t0 = time.perf_counter()
    estimates = []
    for t, tracks in tracker:
        estimates.append(np.array([np.asarray(tr.state_vector, float).ravel()[[0, 2]]
                                   for tr in tracks if tr.state.timestamp == t]).reshape(-1, 2))
    seconds = (time.perf_counter() - t0) / len(scans)
    for X, Y in zip(truths, estimates, strict=True):
        values.append(ospa(X, Y, 10.0, 1.0).value)
    return float(np.mean(values)), seconds


def _kalman_family(mm):
    """Stone Soup's predictor and updater classes for ``mm``: the EKF for a non-linear one."""
    from stonesoup.models.base import LinearModel
    from stonesoup.predictor.kalman import ExtendedKalmanPredictor, KalmanPredictor
    from stonesoup.updater.kalman import ExtendedKalmanUpdater, KalmanUpdater

    if isinstance(mm, LinearModel):
        return KalmanPredictor, KalmanUpdater
    return ExtendedKalmanPredictor, ExtendedKalmanUpdater


def jpda_tracker(scans, density, cv, mm, min_points, covar_trace_thresh):
    """Stone Soup's JPDA tracker with the initiator and deleter of one grid cell."""
    from stonesoup.dataassociator.neighbour import GNNWith2DAssignment
    from stonesoup.dataassociator.probability import JPDAwithEHM2
    from stonesoup.deleter.error import CovarianceBasedDeleter
    from stonesoup.hypothesiser.distance import DistanceHypothesiser
    from stonesoup.hypothesiser.probability import PDAHypothesiser
    from stonesoup.initiator.simple import MultiMeasurementInitiator
    from stonesoup.measures import Mahalanobis
    from stonesoup.tracker.simple import MultiTargetMixtureTracker
    from stonesoup.types.state import GaussianState

    predictor_cls, updater_cls = _kalman_family(mm)
    predictor, updater = predictor_cls(cv), updater_cls(mm)
    deleter = CovarianceBasedDeleter(covar_trace_thresh=covar_trace_thresh)
    initiator = MultiMeasurementInitiator(
        prior_state=GaussianState([[0], [0], [0], [0]],
                                  np.diag([0.0, VELOCITY_SD ** 2, 0.0, VELOCITY_SD ** 2])),
        measurement_model=mm, deleter=deleter, updater=updater, min_points=min_points,
        data_associator=GNNWith2DAssignment(
            DistanceHypothesiser(predictor, updater, Mahalanobis(), missed_distance=3)))
    return MultiTargetMixtureTracker(
        initiator=initiator, deleter=deleter, detector=scans, updater=updater,
        data_associator=JPDAwithEHM2(PDAHypothesiser(
            predictor, updater, clutter_spatial_density=density, prob_detect=P_D)))


def our_tracker(kind, scans, density, cv, mm, seed):
    """``LMBTracker`` or ``GLMBTracker`` from the same predictor and updater, births from
    the measurements."""
    from rankedassign.stonesoup import GLMBTracker, LMBTracker

    cls = LMBTracker if kind == "LMB" else GLMBTracker
    predictor_cls, updater_cls = _kalman_family(mm)
    return cls(scans, predictor=predictor_cls(cv), updater=updater_cls(mm),
               prob_detection=P_D, clutter_rate=CLUTTER_RATE, clutter_spatial_density=density,
               birth_options={"velocity_cov": VELOCITY_SD ** 2}, seed=seed)


def main(argv=None) -> dict:
    """Run the comparison and print it; returns ``{tracker: (per-seed OSPA, seconds)}``."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--scans", type=int, default=100)
    parser.add_argument("--sensor", choices=("position", "bearing-range"), default="position")
    args = parser.parse_args(argv)
    data = [simulate(s, args.scans, args.sensor) for s in range(args.seeds)]
    print(f"{args.sensor} sensor ({'EKF' if args.sensor != 'position' else 'Kalman'}); "
          f"{args.seeds} seeds x {args.scans} scans; targets per scan (seed 0): "
          f"{[len(x) for x in data[0][1]][::10]} (every 10th); detections per scan (mean): "
          f"{np.mean([len(d) for sc in data for _, d in sc[0]]):.1f}", flush=True)
    results = {}
    for kind in ("LMB", "GLMB"):
        # warm-up: the compiled kernels are loaded (or compiled) on the first scans; not timed
        sc, tr, dens, cv, mm = data[0]
        mean_ospa(our_tracker(kind, sc[:5], dens, cv, mm, 0), sc[:5], tr[:5])
        runs = [mean_ospa(our_tracker(kind, sc, dens, cv, mm, seed), sc, tr)
                for seed, (sc, tr, dens, cv, mm) in enumerate(data)]
        results[kind] = runs
        print(f"{kind:>5}: OSPA {[round(o, 2) for o, _ in runs]} mean "
              f"{np.mean([o for o, _ in runs]):.2f} m; "
              f"{1e3 * np.mean([s for _, s in runs]):.1f} ms per scan", flush=True)
    best = None
    for mp, thr in itertools.product(GRID["min_points"], GRID["covar_trace_thresh"]):
        runs = [mean_ospa(jpda_tracker(sc, dens, cv, mm, mp, thr), sc, tr)
                for sc, tr, dens, cv, mm in data]
        m = float(np.mean([o for o, _ in runs]))
        print(f" JPDA min_points={mp} covar_trace_thresh={thr:g}: OSPA "
              f"{[round(o, 2) for o, _ in runs]} mean {m:.2f} m; "
              f"{1e3 * np.mean([s for _, s in runs]):.1f} ms per scan", flush=True)
        if best is None or m < best[0]:
            best = (m, mp, thr, runs)
    results["JPDA"] = best[3]
    print(f"best JPDA cell: min_points={best[1]} covar_trace_thresh={best[2]:g}, mean OSPA "
          f"{best[0]:.2f} m")
    for kind in ("LMB", "GLMB"):
        diff = [o - j for (o, _), (j, _) in zip(results[kind], best[3], strict=True)]
        print(f"{kind} - best JPDA per seed: {[round(d, 2) for d in diff]} m")
    return results


if __name__ == "__main__":
    main()
