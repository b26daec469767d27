"""What a first call compiles: CPU of the process and numba's compile time per kernel.

Run it in a fresh process with an empty numba cache, one call per process::

    NUMBA_CACHE_DIR=$(mktemp -d) python benchmarks/first_call_compile.py glmb-murty

``CALL`` is one of ``glmb-murty``, ``glmb-short``, ``lmb-short`` (the first two ``step`` calls of
``GLMBFilter(make_model("vo"), Murty(100))``, of ``GLMBFilter(..., ShortChainGibbs(10, 25,
...))`` and of ``LMBFilter(..., ShortChainGibbs(400, 25, ...))`` on three measurements) or
``ssc-single``, ``ssc-multisensor``, ``ssc-adaptive_birth`` (the first
``sample_short_chains(problem, 100, 20, tau_stall=5, tau_stale=10)`` on a small problem of
that kind) or ``oracle-murty`` (``oracle.murty(synthetic.random(R=4, M=6, rng=0), 10)``,
then ``k = 20``) or ``herded-multisensor`` (``sample_herded(problem, 100)`` on the small
multi-sensor problem, the largest inlined sweep). It prints the CPU seconds of the process
(import included) and, from numba's
``numba:compile`` events, per kernel (its ``__qualname__``; two kernels of one name in
different modules are summed): the compile CPU with the kernels it compiled inside it
(``incl``), without them (``excl``), and the number of compiles (``n``, one per signature).
Run it from the checkout (``PYTHONPATH=.``) to time the checkout's kernels rather than an
installed copy's.
"""

import resource
import sys
import time
from collections import defaultdict

from numba.core import event

incl = defaultdict(float)
excl = defaultdict(float)
count = defaultdict(int)
_stack = []


class _Listener(event.Listener):
    def on_start(self, ev):
        _stack.append([time.process_time(), 0.0])

    def on_end(self, ev):
        start, inner = _stack.pop()
        d = time.process_time() - start
        name = ev.data["dispatcher"].py_func.__qualname__.split("__")[0]
        incl[name] += d
        excl[name] += d - inner
        count[name] += 1
        if _stack:
            _stack[-1][1] += d


event.register("numba:compile", _Listener())

import numpy as np  # noqa: E402

CALLS = ("glmb-murty", "glmb-short", "lmb-short", "ssc-single", "ssc-multisensor",
         "ssc-adaptive_birth", "oracle-murty", "herded-multisensor")


def _filter_steps(call):
    from rankedassign.tracking import GLMBFilter, LMBFilter, Murty, ShortChainGibbs, make_model

    f = {"glmb-murty": lambda: GLMBFilter(make_model("vo"), Murty(100)),
         "glmb-short": lambda: GLMBFilter(make_model("vo"),
                                          ShortChainGibbs(10, 25, tau_stall=5, tau_stale=10)),
         "lmb-short": lambda: LMBFilter(make_model("vo"),
                                        ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10)),
         }[call]()
    z = np.array([[0.0, 0.0], [100.0, -50.0], [-300.0, 200.0]])
    t = time.perf_counter()
    f.step(z, rng=0)
    t1 = time.perf_counter()
    f.step(z + 1, rng=1)
    return t1 - t, time.perf_counter() - t1


def _first_sample(call):
    from rankedassign import sample_short_chains, synthetic

    kind = call[4:]
    if kind == "single":
        p = synthetic.random(R=4, M=6, rng=0)
    elif kind == "multisensor":
        from rankedassign.multisensor import synthetic as ms_synthetic

        p = ms_synthetic.random(P=4, M=(4, 4), rng=0)
    else:
        from rankedassign.adaptive_birth import AdaptiveBirthProblem

        z = [np.array([[0.0], [50.0]]), np.array([[1.0]])]
        p = AdaptiveBirthProblem.from_measurements(
            z, [[0.99, 0.95], [0.95]], H=[[1.0]], R=[[1.0]], P_D=0.9, clutter_intensity=0.01,
            mu0=[0.0], P0=[[100.0]])
    t = time.perf_counter()
    sample_short_chains(p, 100, 20, tau_stall=5, tau_stale=10, rng=0)
    t1 = time.perf_counter()
    sample_short_chains(p, 100, 20, tau_stall=5, tau_stale=10, rng=1)
    return t1 - t, time.perf_counter() - t1


def _herded_multisensor(call):
    from rankedassign import sample_herded
    from rankedassign.multisensor import synthetic as ms_synthetic

    p = ms_synthetic.random(P=4, M=(4, 4), rng=0)
    t = time.perf_counter()
    sample_herded(p, 100, rng=0)
    t1 = time.perf_counter()
    sample_herded(p, 100, rng=1)
    return t1 - t, time.perf_counter() - t1


def _oracle_murty(call):
    import oracle
    from rankedassign import synthetic

    p = synthetic.random(R=4, M=6, rng=0)
    t = time.perf_counter()
    oracle.murty(p, 10)
    t1 = time.perf_counter()
    oracle.murty(p, 20)
    return t1 - t, time.perf_counter() - t1


def main(call, top=15):
    if call not in CALLS:
        raise SystemExit(f"first_call_compile.py: unknown call {call!r}; choose from "
                         + ", ".join(CALLS))
    run = (_first_sample if call.startswith("ssc-") else
           _oracle_murty if call == "oracle-murty" else
           _herded_multisensor if call == "herded-multisensor" else _filter_steps)
    first, second = run(call)
    ru = resource.getrusage(resource.RUSAGE_SELF)
    print(f"{call}: first call {first:.1f} s wall, second {second * 1e3:.1f} ms, "
          f"CPU of the process {ru.ru_utime + ru.ru_stime:.1f} s, "
          f"{sum(count.values())} compiles")
    for name, v in sorted(incl.items(), key=lambda kv: -kv[1])[:top]:
        print(f"  incl {v:6.1f} s  excl {excl[name]:6.1f} s  n={count[name]:2d}  {name}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "glmb-murty")
