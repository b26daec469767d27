"""What the test suite compiles after ``rankedassign precompile``: compile CPU per test and kernel.

A pytest plugin (``-p suite_compile``) and its summary. Every process of the run (each xdist
worker) listens to numba's ``numba:compile`` events and writes one JSON line per compile into
``$SUITE_COMPILE_DIR``: the test that was running, the kernel (module and ``__qualname__``,
without the cache-key digest), its signature, the compile CPU with the kernels it compiled
inside it (``incl``) and without them (``excl``), and whether it was a top-level compile (one
that no other compile of the process contained). A compile event is a cache miss: a kernel
loaded from numba's cache sends none. Compiles in a subprocess that a test starts are not
seen. Run it in a copy of the checkout with an empty cache::

    export NUMBA_CACHE_DIR=$(mktemp -d) SUITE_COMPILE_DIR=$(mktemp -d)
    python -m rankedassign precompile
    PYTHONPATH=.:benchmarks python -m pytest -W error -n 2 --dist loadfile -p suite_compile
    python benchmarks/suite_compile.py $SUITE_COMPILE_DIR

The summary prints the top-level compile CPU per test module, the exclusive compile CPU per
kernel and the tests that compiled most, as Markdown tables. The listener is registered when
pytest loads the plugin, not on import (the suite's doctest collection imports this file).
"""

import glob
import json
import os
import sys
import time
from collections import defaultdict

_current = ["<collection>"]
_stack: list = []
_rows: list = []


def _listener():
    from numba.core import event

    class Listener(event.Listener):
        def on_start(self, ev):
            _stack.append([time.process_time(), 0.0])

        def on_end(self, ev):
            start, inner = _stack.pop()
            d = time.process_time() - start
            f = ev.data["dispatcher"].py_func
            _rows.append({"test": _current[0],
                          "kernel": f"{f.__module__}.{f.__qualname__.split('__')[0]}",
                          "sig": str(ev.data.get("args")), "incl": d, "excl": d - inner,
                          "top": not _stack})
            if _stack:
                _stack[-1][1] += d

    return Listener()


def pytest_configure(config):
    from numba.core import event

    event.register("numba:compile", _listener())


def pytest_runtest_logstart(nodeid, location):
    _current[0] = nodeid


def pytest_sessionfinish(session):
    out = os.environ.get("SUITE_COMPILE_DIR")
    if not out:
        return
    worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
    with open(os.path.join(out, f"compile_{worker}_{os.getpid()}.jsonl"), "w") as fh:
        fh.writelines(json.dumps(r) + "\n" for r in _rows)


def summarize(folder: str, n_tests: int = 20) -> str:
    """The Markdown tables of the JSON lines in ``folder``."""
    rows = [json.loads(line) for f in sorted(glob.glob(os.path.join(folder, "compile_*.jsonl")))
            for line in open(f)]
    module = defaultdict(lambda: [0.0, 0])
    kernel = defaultdict(lambda: [0.0, 0])
    test = defaultdict(float)
    for r in rows:
        if r["top"]:
            m = module[r["test"].split("::")[0]]
            m[0] += r["incl"]
            m[1] += 1
            test[r["test"]] += r["incl"]
        if not r["kernel"].startswith("numba."):  # numba's own overloads: in their callers
            k = kernel[r["kernel"]]
            k[0] += r["excl"]
            k[1] += 1
    total = sum(v[0] for v in module.values())
    out = [f"compile CPU {total:.1f} s in {sum(v[1] for v in module.values())} top-level "
           f"compiles ({len(rows)} compiles in all)", "",
           "| test module | compile CPU (s) | top-level compiles |", "|---|---:|---:|"]
    out += [f"| `{m}` | {v[0]:.1f} | {v[1]} |"
            for m, v in sorted(module.items(), key=lambda kv: -kv[1][0])]
    out += ["", "| kernel | compile CPU, excl. (s) | signatures |", "|---|---:|---:|"]
    out += [f"| `{k}` | {v[0]:.1f} | {v[1]} |"
            for k, v in sorted(kernel.items(), key=lambda kv: -kv[1][0]) if v[0] >= 0.05]
    out += ["", "| test | compile CPU (s) |", "|---|---:|"]
    out += [f"| `{t}` | {v:.1f} |"
            for t, v in sorted(test.items(), key=lambda kv: -kv[1])[:n_tests]]
    return "\n".join(out)


if __name__ == "__main__":
    print(summarize(sys.argv[1]))
