"""A signal ends a long library call within about a second, and slicing changes no draw.

Two halves:

* **Latency.** A child process runs one huge call after another (the original sampler for
  ``2^40`` sweeps, ``10^6 x 10^6`` short chains on one and two workers, the multi-sensor and
  adaptive-birth samplers, the exact single- and multi-sensor marginals, a million best
  assignments by Murty; the last three take a few seconds each and run in a loop, so that no
  case can finish before the signal on a fast machine); for each, it prints ``start``,
  the parent waits 2 s so that the compiled kernel is surely running, sends SIGINT (SIGTERM for
  one case, whose handler raises its own exception as the CLI's does) and the child reports
  the exception it caught and when. The bound asserted is 10 s, generous for a loaded 2-core
  machine; the measured latencies are printed (``-s``) and are typically well under 0.1 s.
* **Bits.** The chain driver runs in slices (:mod:`rankedassign.engine._kernels`, "Slices"); with a
  budget of a few sweeps per slice every field of every result equals the unsliced run, on
  all three problem kinds, both samplers, stall and stale readings, one and two workers.
"""

from __future__ import annotations

import ast
import functools
import importlib
import os
import signal
import subprocess
import sys
import textwrap
import time
import weakref
from pathlib import Path

import numpy as np
import pytest
from ms_standin import random_problem
from numba.core import types
from numba.core.registry import CPUDispatcher
from numpy.testing import assert_array_equal

import oracle
import rankedassign
from rankedassign import sample_original, sample_short_chains, samplers
from rankedassign.adaptive_birth.problem import AdaptiveBirthProblem
from rankedassign.kinds import KINDS
from rankedassign.multisensor import MultiSensorProblem
from rankedassign.numba_options import interruptible, signal_exception
from rankedassign.single import synthetic
from rankedassign.validation import STALE_READINGS, STALL_READINGS

# Seconds from the signal to the exception in the child, asserted (the measured ones print).
BOUND = 10.0
# Seconds the parent waits after the child's "start" before signalling. The child prints
# "start" just before the call, whose Python preamble takes milliseconds, so the signal lands
# inside the kernel; every case runs for far longer than this (a "finished" line fails).
WAIT = 1.0

_CHILD = textwrap.dedent("""
    import faulthandler, signal, sys, time
    faulthandler.enable()
    import numpy as np
    sys.path.insert(0, {tests!r})
    from ms_standin import random_problem
    import oracle
    from rankedassign import sample_original, sample_short_chains, synthetic
    from rankedassign.multisensor import MultiSensorProblem
    from rankedassign.adaptive_birth.problem import AdaptiveBirthProblem

    class Terminated(BaseException):
        pass

    # A signal handler's exception raised inside a finaliser is "unraisable" and dropped by
    # Python; say so on stderr, so that a lost signal is told from a slice that never ends.
    _hook = sys.unraisablehook
    def on_unraisable(u):
        print("unraisable", type(u.exc_value).__name__, "in", repr(u.object)[:200],
              file=sys.stderr, flush=True)
        _hook(u)
    sys.unraisablehook = on_unraisable

    def on_sigterm(signum, frame):
        raise Terminated

    # The child must not inherit the test runner's signal state: an ignored SIGINT (Python
    # then installs no handler of its own) or a blocked one would pass unseen through every
    # kernel. Say on stderr what was inherited, then take the defaults.
    print("inherited: SIGINT", signal.getsignal(signal.SIGINT), "blocked",
          sorted(int(s) for s in signal.pthread_sigmask(signal.SIG_BLOCK, [])),
          file=sys.stderr, flush=True)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {{signal.SIGINT, signal.SIGTERM}})
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, on_sigterm)
    p = synthetic.random(rng=0)
    def real(s):
        return MultiSensorProblem(s.log_eta_dead, s.log_eta_alive, s.log_s, s.log_theta)

    ms = real(random_problem(4, (4, 4), 0, "coupled"))
    ab = AdaptiveBirthProblem.from_log_weights(
        np.random.default_rng(0).normal(size=(6, 6, 6)), n_min=1)
    big = real(random_problem(11, (10, 10), 1, "coupled"))  # 2^20 measurement sets: ~3.5 s
    dense = synthetic.random(R=20, M=40, rng=0)  # subset DP over 2^20 row sets: ~2.3 s
    ranked = synthetic.random(R=20, M=50, rng=0)  # 10^6 best: about 4 s
    def repeated(call, times=60):
        # A finite exact call (a few seconds each) repeated, so that it cannot finish before
        # the parent's signal however fast the machine: a "finished" line is a lost signal.
        return lambda: [call() for _ in range(times)]

    CASES = {{
        "original": lambda: sample_original(p, 2**40, rng=1),
        "short": lambda: sample_short_chains(p, 10**6, 10**6, rng=1),
        "short-2-workers": lambda: sample_short_chains(p, 10**6, 10**6, rng=1, workers=2),
        "short-stall": lambda: sample_short_chains(p, 10**9, 25, tau_stall=10**6, rng=1,
                                                   workers=2),
        "multisensor-original": lambda: sample_original(ms, 2**40, rng=1),
        "multisensor-short": lambda: sample_short_chains(ms, 10**6, 10**6, rng=1, workers=2,
                                                         method="exact"),
        "adaptive-birth": lambda: sample_short_chains(ab, 10**6, 10**6, rng=1),
        "sigterm": lambda: sample_original(p, 2**40, rng=1),
        "multisensor-marginals": repeated(lambda: oracle.marginals(big)),
        "dp-marginals": repeated(lambda: oracle.marginals(dense)),
        "murty": repeated(lambda: oracle.murty(ranked, 10**6)),
    }}
    # compile or load every kernel before timing anything
    sample_original(p, 2, rng=1)
    sample_short_chains(p, 3, 2, rng=1, workers=2)
    sample_original(ms, 2, rng=1)
    sample_short_chains(ms, 3, 2, rng=1, workers=2, method="exact")
    sample_short_chains(ab, 3, 2, rng=1)
    oracle.marginals(real(random_problem(3, (2, 2), 0, "coupled")))
    oracle.marginals(synthetic.random(R=3, M=4, rng=0))
    oracle.murty(ranked, 10)
    for name in sys.argv[1:]:
        print("start", name, flush=True)
        try:
            CASES[name]()
            print("finished", name, flush=True)
        except BaseException as exc:
            print("caught", name, type(exc).__name__, time.monotonic(), flush=True)
""")

CASES = {
    "original": signal.SIGINT,
    "short": signal.SIGINT,
    "short-2-workers": signal.SIGINT,
    "short-stall": signal.SIGINT,
    "multisensor-original": signal.SIGINT,
    "multisensor-short": signal.SIGINT,
    "adaptive-birth": signal.SIGINT,
    "sigterm": signal.SIGTERM,
    "multisensor-marginals": signal.SIGINT,
    "dp-marginals": signal.SIGINT,
    "murty": signal.SIGINT,
}
EXPECTED = {signal.SIGINT: "KeyboardInterrupt", signal.SIGTERM: "Terminated"}


# Seconds the parent waits for any one line of the child before killing it: a signal that is
# lost (or a slice that never ends) fails the fixture with the child's stderr instead of
# stalling the run.
DEADLINE = 120.0


def _lines(child):
    """A queue of the child's stdout lines, filled by a reader thread (None at the end)."""
    import queue
    import threading

    q = queue.Queue()

    def read():
        for line in child.stdout:
            q.put(line)
        q.put(None)

    threading.Thread(target=read, daemon=True).start()
    return q


def _readline(child, lines, deadline=DEADLINE):
    """The child's next stdout line, split; kill it and fail if none comes within ``deadline``."""
    import queue

    try:
        line = lines.get(timeout=deadline)
    except queue.Empty:
        # SIGABRT first: the child's faulthandler writes every thread's Python stack to stderr,
        # so a hang says where it is (a kernel's Python caller, a lock, the compiler).
        child.send_signal(signal.SIGABRT)
        try:
            child.wait(timeout=30)
        except subprocess.TimeoutExpired:
            child.kill()
        pytest.fail(f"the child printed nothing for {deadline:.0f} s; its stacks (SIGABRT) "
                    f"and stderr:\n{child.stderr.read()}")
    return [] if line is None else line.split()


@pytest.fixture(scope="module")
def latencies():
    """Run every case in one child; ``{name: (exception name, seconds)}``."""
    root = Path(rankedassign.__file__).resolve().parent.parent
    env = dict(os.environ, PYTHONPATH=str(root))
    code = _CHILD.format(tests=str(Path(__file__).resolve().parent))
    out = {}
    with subprocess.Popen([sys.executable, "-c", code, *CASES], cwd=root, env=env,
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) as child:
        lines = _lines(child)
        try:
            for name, signum in CASES.items():
                line = _readline(child, lines, 600.0)  # the first one waits for the warm-ups
                assert line == ["start", name], (line, "" if line else child.stderr.read())
                time.sleep(WAIT)
                sent = time.monotonic()
                child.send_signal(signum)
                line = _readline(child, lines)
                if line[:2] != ["caught", name]:
                    child.kill()
                    pytest.fail(f"{line} after a {signum.name} (expected 'caught {name}'); "
                                f"stderr:\n{child.stderr.read()}")
                out[name] = (line[2], float(line[3]) - sent)
            assert child.wait(timeout=60) == 0, child.stderr.read()
        finally:
            if child.poll() is None:
                child.kill()
    for name, (exc, seconds) in out.items():
        print(f"interrupt latency {name}: {exc} after {seconds * 1e3:.1f} ms")
    return out


@pytest.mark.e2e
@pytest.mark.parametrize("name", sorted(CASES))
def test_a_signal_ends_a_huge_call_promptly(latencies, name):
    exc, seconds = latencies[name]
    assert exc == EXPECTED[CASES[name]]
    assert seconds < BOUND


@pytest.mark.e2e
def test_a_signal_during_the_multisensor_tracking_study_ends_it_like_any_other(tmp_path):
    """The issue's item 5: SIGINT during ``multisensor_tracking`` (most of its time is spent
    in kernels that return arrays) ended in ``SystemError: CPUDispatcher(...) returned a
    result with an exception set`` and exit 1; now it is the CLI's interrupt, exit 130."""
    root = Path(rankedassign.__file__).resolve().parent.parent
    env = dict(os.environ, PYTHONPATH=str(root))
    cmd = [sys.executable, "-m", "rankedassign", "reproduce", "multisensor_tracking", "--mc",
           "1", "--workers", "1", "--out", str(tmp_path / "report")]
    with subprocess.Popen(cmd, cwd=tmp_path, env=env, stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True) as child:
        try:
            for line in child.stderr:
                if "kernels ready" in line:
                    break
            time.sleep(3.0)  # the study's tracking runs are under way
            sent = time.monotonic()
            child.send_signal(signal.SIGINT)
            _, err = child.communicate(timeout=60)
            seconds = time.monotonic() - sent
        finally:
            if child.poll() is None:
                child.kill()
    print(f"interrupt latency multisensor_tracking study: exit {child.returncode} after "
          f"{seconds * 1e3:.0f} ms")
    assert child.returncode == 130, err
    assert "Traceback" not in err and "SystemError" not in err, err
    assert seconds < BOUND


# ------------------------------------------------------------------------------ the guard
def test_signal_exception_unwraps_numba_return_path_errors():
    root = KeyboardInterrupt()
    mid = SystemError("<function _numba_unpickle> returned a result with an exception set")
    mid.__cause__ = root
    top = SystemError("CPUDispatcher(<k>) returned a result with an exception set")
    top.__cause__ = mid
    assert signal_exception(top) is root
    assert signal_exception(SystemError("something else")) is None
    lone = SystemError("CPUDispatcher(<k>) returned a result with an exception set")
    assert signal_exception(lone) is None
    with pytest.raises(KeyboardInterrupt):
        with interruptible:
            raise top
    with pytest.raises(SystemError, match="something else"):
        with interruptible:
            raise SystemError("something else")


# Plain functions that are compiled as templates (rankedassign.engine._kernels and the tempered
# loop of rankedassign.engine._tempered_kernels), not called by Python.
_TEMPLATES = {("rankedassign.engine._kernels", n) for n in
              ("_speculate", "_speculate_chain", "_advance", "_new_run", "_run_slice", "_start",
               "_pack", "_unpack", "_grow_run", "_as_record", "no_chain_done", "_run_problem")} | {
              ("rankedassign.engine._tempered_kernels", n) for n in ("_start", "_steps")} | {
              ("rankedassign.tracking.single._glmb_kernels", n) for n in ("_ranked", "_sample")}


@functools.cache
def _python_calls_of_kernels():
    """``(module, function, line, guarded, kernel)`` of every call of a compiled function
    from Python code in ``rankedassign`` and ``oracle`` (``guarded``: inside
    ``with interruptible:``); read once per process, for the two tests below."""
    root = Path(rankedassign.__file__).resolve().parent.parent
    found = []
    for path in sorted([*(root / "rankedassign").rglob("*.py"), *(root / "oracle").rglob("*.py")]):
        name = ".".join(path.relative_to(root).with_suffix("").parts).removesuffix(".__init__")
        if name.endswith("__main__"):
            continue
        module = importlib.import_module(name)

        def resolve(node, module=module):
            if isinstance(node, ast.Name):
                return vars(module).get(node.id)
            if isinstance(node, ast.Attribute):
                return getattr(resolve(node.value), node.attr, None)
            return None

        tree = ast.parse(path.read_text())
        parent = {c: n for n in ast.walk(tree) for c in ast.iter_child_nodes(n)}
        for node in ast.walk(tree):
            kernel = resolve(node.func) if isinstance(node, ast.Call) else None
            if not isinstance(kernel, CPUDispatcher):
                continue
            guarded, func, p = False, None, parent.get(node)
            while p is not None:
                if isinstance(p, ast.With) and any(
                        ast.unparse(i.context_expr) == "interruptible" for i in p.items):
                    guarded = True
                if isinstance(p, ast.FunctionDef) and func is None:
                    func = p
                p = parent.get(p)
            if func is not None and (any("jit" in ast.unparse(d) for d in func.decorator_list)
                                     or (name, func.name) in _TEMPLATES):
                continue  # compiled code calling compiled code
            found.append((name, func.name if func else "<module>", node.lineno, guarded, kernel))
    return tuple(found)


def test_every_kernel_call_from_python_is_interruptible():
    """A kernel returning arrays, called from Python, must run inside ``with interruptible:``
    (or a signal during it ends in a SystemError); the rule is kept for every kernel."""
    calls = _python_calls_of_kernels()
    assert len(calls) > 20  # the scan sees the call sites
    assert [c[:3] for c in calls if not c[3]] == []


def _named(t):
    if isinstance(t, types.BaseNamedTuple):
        return True
    if isinstance(t, types.Optional):
        return _named(t.type)
    if isinstance(t, types.BaseTuple):
        return any(_named(x) for x in t.types)
    return False


def test_no_kernel_called_from_python_returns_a_named_tuple(monkeypatch):
    """numba boxes a named tuple by calling its class; a signal handler's exception raised
    there is a segmentation fault. Checked on every kernel called from Python, as compiled in
    this process, after running the sliced driver of every kind and the sliced Murty (whose
    states cross into Python)."""
    monkeypatch.setattr(samplers, "_SLICE_WORK", 1)
    for p in PROBLEMS.values():
        sample_short_chains(p, 5, 3, workers=2)
    monkeypatch.setattr(importlib.import_module("oracle.single.murty"), "_SLICE_WORK", 1)
    oracle.murty(synthetic.random(R=3, M=4, rng=0), 50)
    kernels = {c[4] for c in _python_calls_of_kernels()}
    drivers = [d for kind in KINDS for d in kind.drivers.values()]
    for driver in drivers:  # the driver's loop calls its kernels by closure
        kernels |= {c.cell_contents for c in driver.__closure__
                    if isinstance(c.cell_contents, CPUDispatcher)}
    checked = 0
    for kernel in kernels:
        for cres in kernel.overloads.values():
            checked += 1
            assert not _named(cres.signature.return_type), (kernel, cres.signature)
    assert checked > 10


# ------------------------------------------------------------------------------ bit for bit
FIELDS = ("assignments", "costs", "counts", "n_observations", "n_chains_run", "stop_reason",
          "n_speculative_discarded")


def _same(a, b):
    for f in FIELDS:
        x, y = getattr(a, f), getattr(b, f)
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype, f
            assert_array_equal(x, y, err_msg=f)
        else:
            assert x == y, f


def _sliced(monkeypatch, work, fn, *args, **kwargs):
    with monkeypatch.context() as m:
        m.setattr(samplers, "_SLICE_WORK", work)
        return fn(*args, **kwargs)


def _real(s):
    return MultiSensorProblem(s.log_eta_dead, s.log_eta_alive, s.log_s, s.log_theta)


def _problems():
    ab = AdaptiveBirthProblem.from_log_weights(
        np.random.default_rng(3).normal(size=(3, 4, 3)), n_min=1)
    return {
        "single": synthetic.random(R=3, M=5, rng=2),
        "single-prefix": synthetic.random(R=2, M=40, rng=2),
        "multisensor": _real(random_problem(3, (2, 3), 5, "coupled")),
        "adaptive-birth": ab,
    }


PROBLEMS = _problems()
# Problems on which 4 000 observations find more than the unique set's initial 1 024 places.
GROWING = {
    "single": synthetic.random(R=5, M=8, rng=2),
    "single-prefix": synthetic.random(R=2, M=40, rng=2),
    "multisensor": _real(random_problem(5, (3, 4), 5, "separable")),
    "adaptive-birth": AdaptiveBirthProblem.from_log_weights(
        np.random.default_rng(3).normal(scale=0.3, size=(6, 6, 6, 6)), n_min=1),
}


@pytest.mark.parametrize("kind", sorted(PROBLEMS))
def test_original_sampler_in_slices_is_bit_identical(monkeypatch, kind):
    p = PROBLEMS[kind]
    ref = sample_original(p, 3000, rng=4)
    # a whole number of sweeps per slice, one sweep, and a slice ending mid-way
    for work in (1, 7 * 50, 10**4):
        _same(ref, _sliced(monkeypatch, work, sample_original, p, 3000, rng=4))


@pytest.mark.parametrize("workers", [1, 2])
@pytest.mark.parametrize("kind", sorted(PROBLEMS))
def test_short_chains_in_slices_are_bit_identical(monkeypatch, kind, workers):
    p = PROBLEMS[kind]
    readings = [(stall, stale) for stall in sorted(STALL_READINGS)
                for stale in sorted(STALE_READINGS)]
    for i, (stall, stale) in enumerate(readings):
        kw = dict(tau_stall=2 + i % 3, tau_stale=4 + i % 5, stall=stall, stale=stale,
                  rng=10 + i, workers=workers)
        ref = sample_short_chains(p, 300, 6, **kw)
        for work in (1, 100, 3000):
            _same(ref, _sliced(monkeypatch, work, sample_short_chains, p, 300, 6, **kw))
    # no rules: every chain runs to N_C, the speculation batches fill, and U grows past its
    # initial capacity in the middle of a run in slices
    p = GROWING[kind]
    ref = sample_short_chains(p, 400, 10, rng=3, workers=workers)
    assert len(ref) > 1024
    for work in (1, 997 * 7):
        _same(ref, _sliced(monkeypatch, work, sample_short_chains, p, 400, 10, rng=3,
                           workers=workers))


@pytest.mark.parametrize("family", ["coupled", "extreme"])  # linear and log-space DPs
def test_multisensor_row_dps_in_slices_are_bit_identical(monkeypatch, family):
    from oracle.multisensor import dp as msdp

    p = _real(random_problem(5, (3, 2), 8, family))
    want = (oracle.marginals(p), oracle.log_normalizer(p), msdp.surrogate_log_normalizer(p))
    for work in (1, 29):
        with monkeypatch.context() as m:
            m.setattr(msdp, "_SLICE_WORK", work)
            got = (oracle.marginals(p), oracle.log_normalizer(p),
                   msdp.surrogate_log_normalizer(p))
        assert_array_equal(got[0].dead, want[0].dead)
        assert_array_equal(got[0].tuples, want[0].tuples)
        assert got[1:] == want[1:]


@pytest.mark.parametrize("method", ["dense", "frontier"])
def test_single_sensor_dps_in_slices_are_bit_identical(monkeypatch, method):
    from oracle.single import dp

    rng = np.random.default_rng(4)
    C = rng.normal(size=(7, 9)) * 2
    C[rng.random(C.shape) < 0.5] = np.inf  # sparse: a frontier order exists
    D = np.full((7, 9 + 14), np.inf)
    D[:, :9] = C
    D[np.arange(7), 9 + np.arange(7)] = 0.5
    D[np.arange(7), 16 + np.arange(7)] = 1.0
    p = rankedassign.AssignmentProblem.from_cost(D)
    want = dp._log_normalizer(p, method), dp._marginals(p, method)
    with monkeypatch.context() as m:
        m.setattr(dp, "_SLICE_WORK", 1)  # one step per slice
        got = dp._log_normalizer(p, method), dp._marginals(p, method)
    assert got[0] == want[0]
    assert_array_equal(got[1], want[1])


def test_murty_in_slices_is_bit_identical(monkeypatch):
    murty_module = importlib.import_module("oracle.single.murty")
    problems = [synthetic.random(R=6, M=9, rng=1), synthetic.uniform()]  # ties in the second
    want = [murty_module.murty(p, 3000) for p in problems]
    with monkeypatch.context() as m:
        m.setattr(murty_module, "_SLICE_WORK", 1)  # one iteration per slice
        got = [murty_module.murty(p, 3000) for p in problems]
    for a, b in zip(got, want, strict=True):
        assert_array_equal(a.assignments, b.assignments)
        assert_array_equal(a.costs, b.costs)


def test_enumeration_and_counting_in_slices_are_bit_identical(monkeypatch):
    enumerate_module = importlib.import_module("oracle.single.enumerate")
    msen = importlib.import_module("oracle.multisensor.enumerate")
    cc = np.ascontiguousarray(synthetic.random(R=4, M=6, rng=3).compact_cost)
    ms = _real(random_problem(3, (2, 3), 2, "forbidden"))
    n = ms.n_feasible()
    want = (enumerate_module._count_by_search(cc, 10**9),
            enumerate_module._count_by_search(cc, 100),
            msen._enumerate(*msen._kernel_args(ms), n, False),
            msen._enumerate(*msen._kernel_args(ms), 10**9, True))
    with monkeypatch.context() as m:
        m.setattr(enumerate_module, "_SLICE_WORK", 1)  # one option tried per slice
        m.setattr(msen, "_SLICE_WORK", 1)
        got = (enumerate_module._count_by_search(cc, 10**9),
               enumerate_module._count_by_search(cc, 100),
               msen._enumerate(*msen._kernel_args(ms), n, False),
               msen._enumerate(*msen._kernel_args(ms), 10**9, True))
    assert got[0] == want[0] > 100 and got[1] == want[1] == 101
    assert_array_equal(got[2][0], want[2][0])
    assert got[2][1] == want[2][1] == n == got[3][1] == want[3][1]


# ------------------------------------------------------------------ the command line's handler
# The CLI records SIGINT/SIGTERM and acts on them at safe points (experiments._interrupts). A
# child process runs `rankedassign reproduce` with table1's tasks replaced by ones that
# receive the signal where an exception raised by a handler would be lost or harmful.
_CLI_CHILD = textwrap.dedent("""
    import dataclasses, os, signal, sys, threading, time, weakref
    from pathlib import Path
    from rankedassign import sample_original
    from rankedassign.cli import main
    from rankedassign.experiments import _interrupts, get_study, registry
    from rankedassign.single import synthetic

    mode, out, marks = sys.argv[1], sys.argv[2], Path(sys.argv[3])
    problem = synthetic.random(rng=0)
    sample_original(problem, 10, rng=0)  # compiled or loaded before the run

    class Thing:
        pass

    def in_finaliser():
        # the signal arrives, and its handler runs, inside a finaliser (as numba's disposal
        # callbacks are); an exception raised there is "ignored" by Python
        os.kill(os.getpid(), signal.SIGTERM)
        for _ in range(1000):
            pass

    def task(i):
        if not mode.startswith("second"):
            print("start", i, flush=True)
        if mode == "finaliser" and i == 0:
            t = Thing()
            weakref.finalize(t, in_finaliser)
            del t
            # a bounded amount of library work: the interrupt lands in it
            for k in range(400):
                sample_original(problem, 5000, rng=k)
        elif mode.startswith("second"):
            # a task that waits where the first signal cannot be acted on: in Thread.join
            main = threading.main_thread().ident

            def wait():
                # "start" once the main thread waits in threading's code
                while "threading" not in sys._current_frames()[main].f_code.co_filename:
                    time.sleep(0.001)
                print("start", i, flush=True)
                for _ in range(3000):
                    time.sleep(0.01)
                    if _interrupts.pending() is not None and not (marks / "seen").exists():
                        (marks / "seen").write_text("")
                        print("seen", flush=True)
            t = threading.Thread(target=wait)
            t.start()
            t.join()
        (marks / f"finished-{i}").write_text("")
        return i

    study = get_study("table1")
    registry._REGISTRY["table1"] = dataclasses.replace(
        study, task=task, warm=None, tasks=lambda cfg, seed: [(i,) for i in range(4)])
    sys.exit(main(["reproduce", "table1", "--out", out, "--workers", "1", "--quiet"]))
""")


def _cli_child(tmp_path, mode):
    root = Path(rankedassign.__file__).resolve().parent.parent
    env = dict(os.environ, PYTHONPATH=str(root))
    marks = tmp_path / "marks"
    marks.mkdir()
    work = tmp_path / "work"
    work.mkdir()
    child = subprocess.Popen([sys.executable, "-c", _CLI_CHILD, mode, str(work / "r"),
                              str(marks)], cwd=work, env=env, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    return child, work, marks


@pytest.mark.e2e
def test_a_sigterm_handled_inside_a_finaliser_still_stops_the_run(tmp_path):
    # issue: the handler raised in the finaliser, Python printed "Exception ignored in ..." and
    # the run went on (exit 0); a later SIGKILL left .<out>.lock and .<out>.partial-*
    child, work, marks = _cli_child(tmp_path, "finaliser")
    with child:
        try:
            _, err = child.communicate(timeout=600)  # a safety net; the work is bounded
        finally:
            if child.poll() is None:
                child.kill()
    assert child.returncode == 128 + signal.SIGTERM, err
    assert err == "rankedassign reproduce: terminated (SIGTERM); no report written\n"
    # it landed inside the first task's library work, not after it
    assert sorted(p.name for p in marks.iterdir()) == []
    assert list(work.iterdir()) == []  # no report, no lock, no partial report


@pytest.mark.e2e
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_second_signal_ends_a_run_whose_first_cannot_be_acted_on(tmp_path, signum):
    child, work, marks = _cli_child(tmp_path, "second")
    with child:
        try:
            lines = _lines(child)
            assert _readline(child, lines, 600.0) == ["start", "0"]
            child.send_signal(signum)
            assert _readline(child, lines) == ["seen"]  # recorded; the task goes on
            child.send_signal(signum)
            _, err = child.communicate(timeout=60)
        finally:
            if child.poll() is None:
                child.kill()
    assert child.returncode == 128 + signum, err
    assert err == (f"rankedassign reproduce: {signal.Signals(signum).name} again: stopped at "
                   "once; the lock and the partial report were removed, no report written\n")
    assert sorted(p.name for p in marks.iterdir()) == ["seen"]  # the task did not finish
    assert list(work.iterdir()) == []


@pytest.fixture
def tests_as_library(monkeypatch):
    """The handler's decisions, recorded; no second attempt during the test."""
    from rankedassign.experiments import _interrupts

    monkeypatch.setattr(_interrupts, "RETRY", 3600.0)  # no second attempt during the test
    seen = []
    handler = _interrupts._on_signal

    def spy(signum, frame):
        seen.append((Path(frame.f_code.co_filename).name, frame.f_code.co_name,
                     _interrupts._may_raise_in(frame)))
        return handler(signum, frame)

    monkeypatch.setattr(_interrupts, "_on_signal", spy)
    return seen


def _finalised_with(callback):
    class Thing:
        pass

    t = Thing()
    weakref.finalize(t, callback)
    del t


class _WithDel:
    def __del__(self):
        signal.raise_signal(signal.SIGINT)


@pytest.mark.parametrize("where", ["finalize", "__del__", "library"])
def test_the_handler_raises_only_where_it_is_safe(tests_as_library, where):
    from rankedassign.experiments import _interrupts

    unraisable = []
    hook = sys.unraisablehook
    sys.unraisablehook = unraisable.append
    try:
        with _interrupts.deferred_interrupts():
            if where == "library":  # an ordinary frame of library code: raised at once
                with pytest.raises(KeyboardInterrupt):
                    signal.raise_signal(signal.SIGINT)
            elif where == "finalize":
                _finalised_with(lambda: signal.raise_signal(signal.SIGINT))
            else:
                _WithDel()
            assert _interrupts.pending() == signal.SIGINT
            with pytest.raises(KeyboardInterrupt):
                _interrupts.check()  # the next safe point
        assert _interrupts.pending() is None  # cleared with the handlers
    finally:
        sys.unraisablehook = hook
    assert unraisable == []
    assert [s[2] for s in tests_as_library] == [where == "library"]


def test_the_handler_never_raises_in_threading_code(tests_as_library):
    # the "release unlocked lock" traceback: a handler's exception in CPython 3.11's
    # Thread.join releases the joined thread's lock, which fails when the thread ends in
    # between. The handler only records the signal there.
    import threading

    from rankedassign.experiments import _interrupts

    with _interrupts.deferred_interrupts():
        release = threading.Event()
        worker = threading.Thread(target=release.wait)
        worker.start()

        def signal_then_release():
            os.kill(os.getpid(), signal.SIGTERM)
            while _interrupts.pending() is None:
                time.sleep(0.001)
            release.set()

        threading.Thread(target=signal_then_release).start()
        worker.join()  # the handler runs in here
        assert _interrupts.pending() == signal.SIGTERM
        with pytest.raises(_interrupts.Terminated):
            _interrupts.check()
    # in Thread.start's or Thread.join's wait, whichever the signal finds the main thread in
    assert [(f, ok) for f, _, ok in tests_as_library] == [("threading.py", False)]
