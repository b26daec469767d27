"""Importance-weighted marginals of Zanella-Roberts tempered Gibbs against the oracle, per kind.

Run as ``python benchmarks/tempered_kinds_accuracy.py``; prints a Markdown table, for the
multi-sensor and adaptive-birth families below, of the error of ``sample_tempered``'s
marginals against :func:`oracle.marginals` after 10^3 .. 10^6 moves at beta = 1 and 0.5: the
mean over rows of the L1 distance (multi-sensor: over dead and every tuple; adaptive birth:
over each sensor's entry) and the largest absolute error, each the mean over 5 problems of the
family (``rng = 0..4``, one run each with ``rng = 100 + problem``), and the time per move of
the 10^6-move runs. The documentation's herding page quotes it.
"""

import time

import numpy as np

import oracle
from rankedassign import sample_tempered
from rankedassign.adaptive_birth import AdaptiveBirthProblem
from rankedassign.adaptive_birth import synthetic as ab_synthetic
from rankedassign.multisensor import synthetic as ms_synthetic

FAMILIES = [
    ("multi-sensor A random (P = 4, M = (4, 4))",
     lambda s: ms_synthetic.random(P=4, M=(4, 4), rng=s)),
    ("multi-sensor A random-coupled", lambda s: ms_synthetic.random_coupled(P=4, M=(4, 4), rng=s)),
    ("multi-sensor C random-coupled (P = 3, M = (4, 4, 4))",
     lambda s: ms_synthetic.random_coupled(P=3, M=(4, 4, 4), rng=s)),
    ("adaptive birth, Gaussian random family (V = 4, M = 10)",
     lambda s: ab_synthetic.make_family("random", 4, rng=s)),
    ("adaptive birth, random tensor (V = 3, M = (3, 4, 5), N(0, 2^2) log-weights)",
     lambda s: AdaptiveBirthProblem.from_log_weights(
         np.random.default_rng(s).normal(0, 2, (4, 5, 6)))),
]
STEPS = (1_000, 10_000, 100_000, 1_000_000)
BETAS = (1.0, 0.5)


def errors(problem, exact, res):
    """``(mean row L1, max abs)`` of the result's marginals against the exact ones."""
    if hasattr(exact, "tuples"):
        P = problem.n_rows
        d = np.concatenate([(res.marginals.dead - exact.dead)[:, None],
                            (res.marginals.tuples - exact.tuples).reshape(P, -1)], axis=1)
        return float(np.abs(d).sum() / P), float(np.abs(d).max())
    d = [m - e for m, e in zip(res.marginals, exact, strict=True)]
    return (float(np.mean([np.abs(x).sum() for x in d])),
            float(max(np.abs(x).max() for x in d)))


def main():
    sample_tempered(FAMILIES[0][1](0), 10, beta=0.5, rng=0)  # compile outside the timing
    sample_tempered(FAMILIES[3][1](0), 10, beta=0.5, rng=0)
    print("| family | β | " + " | ".join(f"{n:,} moves" for n in STEPS) + " | µs / move |")
    print("|---|---|" + "---|" * (len(STEPS) + 1))
    for name, make in FAMILIES:
        problems = [make(s) for s in range(5)]
        exact = [oracle.marginals(p) for p in problems]
        for beta in BETAS:
            cells, per_move = [], []
            for n in STEPS:
                l1, mx = [], []
                for s, (p, e) in enumerate(zip(problems, exact, strict=True)):
                    t0 = time.perf_counter()
                    res = sample_tempered(p, n, beta=beta, rng=100 + s)
                    if n == STEPS[-1]:
                        per_move.append((time.perf_counter() - t0) / n * 1e6)
                    a, b = errors(p, e, res)
                    l1.append(a)
                    mx.append(b)
                cells.append(f"{np.mean(l1):.3f} / {np.mean(mx):.3f}")
            print(f"| {name} | {beta:g} | " + " | ".join(cells)
                  + f" | {np.mean(per_move):.2f} |")


if __name__ == "__main__":
    main()
