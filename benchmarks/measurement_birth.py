"""Measurement-driven birth against the presets' static births, where these are right and not.

Run with::

    python benchmarks/measurement_birth.py                 # "vo" and "paper", 3 seeds
    python benchmarks/measurement_birth.py --presets vo --seeds 5
    python benchmarks/measurement_birth.py --presets vo-ekf   # bearing-range, EKF

For each preset and seed, the 12-target truth of spec §8 (``paper_truth``; for ``"vo-ekf"``
Vo's ten coordinated-turn targets, ``vo_truth``) and the same truth with every target moved by
up to ±600 m in x and y (uniform, drawn from the seed), so that no target is born at a static
birth's place; the measurements of the preset's sensor and clutter are drawn once per seed and
truth. On ``"vo-ekf"`` the births are placed through the bearing–range sensor's inverse. The LMB and δ-GLMB filters (short-chain Gibbs,
``ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)``) run with the preset's static birth
and with ``MeasurementBirth()`` at its defaults. Printed: mean OSPA (c = 100 m, p = 1,
positions, every scan) per filter, birth, truth and seed, and the means over the seeds. The
numbers are in ``benchmarks/README.md`` and the Stone Soup page of the documentation.
"""

from __future__ import annotations

import argparse

import numpy as np

#: The measurement birth's prior of the unmeasured components, per preset (default: the
#: defaults, N(0, 10² I) velocity). ``"vo-ekf"``: ``[v_x, v_y, ω]`` with the spread of Vo's
#: own birth terms (50 m/s, 6°/s), the turn rate unmeasured too.
PRIORS = {"vo-ekf": {"velocity_cov": [50.0 ** 2, 50.0 ** 2, (6.0 * np.pi / 180.0) ** 2]}}


def _truth(preset: str, n_scans: int):
    """The preset's truth where its static births are right: ``paper_truth``, or Vo's ten
    coordinated-turn targets (``vo_truth``) for ``"vo-ekf"``."""
    from rankedassign.tracking.nonlinear import make_nonlinear_model, vo_truth
    from rankedassign.tracking.scenario import paper_truth

    if preset == "vo-ekf":
        return vo_truth(make_nonlinear_model("vo-ekf"), n_scans)
    return paper_truth(n_scans)


def shifted_truth(seed: int, n_scans: int, preset: str = "vo"):
    """The preset's truth with each target moved by ``U(−600, 600)`` m in x and in y."""
    from rankedassign.tracking.scenario import Truth

    t = _truth(preset, n_scans)
    off = np.random.default_rng(seed).uniform(-600.0, 600.0, size=(t.states.shape[1], 2))
    st = t.states.copy()
    st[:, :, 0] += off[:, 0]
    st[:, :, 2] += off[:, 1]
    return Truth(st, t.birth, t.death)


def mean_ospa(filt, truth, scans) -> float:
    """Mean OSPA (c = 100, p = 1) of a filter's estimates over the scans."""
    from rankedassign.metrics import ospa

    out = []
    for k, sc in enumerate(scans):
        rec = filt.step(sc.z, rng=k)
        out.append(ospa(truth.positions[k][truth.exists[k]],
                        np.asarray(rec.states)[:, [0, 2]], 100.0, 1.0).value)
    return float(np.mean(out))


def main(argv=None) -> dict:
    """Run the comparison and print it; returns ``{(preset, filter, truth, birth): [OSPA]}``."""
    from rankedassign.tracking import (
        GLMBFilter,
        LMBFilter,
        MeasurementBirth,
        ShortChainGibbs,
        make_model,
    )
    from rankedassign.tracking.nonlinear import generate_nonlinear_measurements
    from rankedassign.tracking.scenario import generate_measurements

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--presets", nargs="+", default=["vo", "paper"])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--scans", type=int, default=100)
    args = parser.parse_args(argv)
    out = {}
    for preset in args.presets:
        model = make_model(preset)
        for name, cls in (("LMB", LMBFilter), ("GLMB", GLMBFilter)):
            for where in ("births right", "targets moved"):
                for birth in ("static", "measurement"):
                    vals = []
                    for seed in range(args.seeds):
                        truth = (_truth(preset, args.scans) if where == "births right"
                                 else shifted_truth(seed, args.scans, preset))
                        if preset == "vo-ekf":
                            scans = generate_nonlinear_measurements(truth, model,
                                                                    rng=100 + seed)
                        else:
                            scans = generate_measurements(truth, model, rng=100 + seed)
                        f = cls(model, ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10),
                                birth=None if birth == "static" else MeasurementBirth(
                                    **PRIORS.get(preset, {})))
                        vals.append(mean_ospa(f, truth, scans))
                    out[preset, name, where, birth] = vals
                    print(f"{preset:>6} {name:>4} {where:>13} {birth:>11}: OSPA "
                          f"{[round(v, 2) for v in vals]} mean {np.mean(vals):.2f} m",
                          flush=True)
    return out


if __name__ == "__main__":
    main()
