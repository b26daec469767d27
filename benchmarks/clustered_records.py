"""Records of the clustered δ-GLMB filter on the ``"large"`` scenario, to hold two trees equal.

A change that only removes Python work from the clustered filter's scan must give the same
records, bit for bit. Dump them with each tree's package first on the path, then compare::

    PYTHONPATH=/path/to/before python benchmarks/clustered_records.py dump /tmp/before.pkl
    PYTHONPATH=/path/to/after python benchmarks/clustered_records.py dump /tmp/after.pkl
    python benchmarks/clustered_records.py compare /tmp/before.pkl /tmp/after.pkl

Five scans of four runs: N = 1 000 with the short chains, N = 300 with the retained mass on,
with Murty's truncation, and with the bearing–range sensor (the EKF path), every field of
every record but ``timings``.
"""

from __future__ import annotations

import argparse
import pickle

import numpy as np

from rankedassign.tracking import ClusteredGLMBFilter, Murty, ShortChainGibbs, make_scenario

RUNS = [("pos1000", 1000, "position", "short-chains", False),
        ("pos300mass", 300, "position", "short-chains", True),
        ("pos300murty", 300, "position", "murty", False),
        ("br300", 300, "bearing-range", "short-chains", False)]


def dump(path: str) -> None:
    """Run :data:`RUNS` and pickle their records (without timings) to ``path``."""
    out = {}
    for name, n, sensor, assoc, mass in RUNS:
        sc = make_scenario("large", n_targets=n, n_scans=5, rng=3, sensor=sensor)
        F = sc.model.motion.F
        means = np.linalg.solve(F, sc.truth.states[0].T).T
        labels = np.column_stack([np.zeros(n, np.int64), np.arange(1, n + 1)])
        covs = np.tile(np.diag([100.0, 25.0, 100.0, 25.0]), (n, 1, 1))
        a = (ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10) if assoc == "short-chains"
             else Murty(20))
        f = ClusteredGLMBFilter(sc.model, a, retained_mass=mass)
        f.set_prior(labels, means, covs)
        recs = []
        for k, s in enumerate(sc.scans):
            rec = f.step(s.z, rng=k)
            recs.append({key: v for key, v in rec._asdict().items() if key != "timings"})
        out[name] = recs
    with open(path, "wb") as fh:
        pickle.dump(out, fh)


def _same(x, y) -> bool:
    if isinstance(x, np.ndarray):
        return (x.shape == y.shape and x.dtype == y.dtype
                and np.array_equal(x, y, equal_nan=x.dtype.kind == "f"))
    if isinstance(x, float):
        return x == y or (np.isnan(x) and np.isnan(y))
    return x == y


def compare(a_path: str, b_path: str) -> int:
    """Print every field that differs; returns their number."""
    with open(a_path, "rb") as fa, open(b_path, "rb") as fb:
        a, b = pickle.load(fa), pickle.load(fb)
    bad = 0
    for name in a:
        for k, (ra, rb) in enumerate(zip(a[name], b[name], strict=True)):
            for field in ra:
                if not _same(ra[field], rb[field]):
                    bad += 1
                    print(f"differs: {name} scan {k} {field}")
    print(f"{sum(len(v) for v in a.values())} records compared, {bad} fields differ")
    return bad


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    sub.add_parser("dump").add_argument("path")
    cmp_ = sub.add_parser("compare")
    cmp_.add_argument("a")
    cmp_.add_argument("b")
    args = ap.parse_args(argv)
    if args.cmd == "dump":
        dump(args.path)
    else:
        raise SystemExit(1 if compare(args.a, args.b) else 0)


if __name__ == "__main__":
    main()
