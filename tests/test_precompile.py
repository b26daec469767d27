"""The on-disk kernel cache and ``rankedassign precompile``.

A cache miss in a second process is a defect: a user's second run (or CI's later tiers) would
compile again. The session's warm-up (``tests/conftest.py``) has filled numba's cache for the
samplers; a fresh process that calls the same entry points must load every kernel from it.
"""

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from rankedassign.cli import main
from rankedassign.experiments.precompile import _queue
from rankedassign.experiments.registry import Config, get_study, study_names

ROOT = Path(__file__).resolve().parents[1]

_LISTEN = textwrap.dedent("""
    import json
    from numba.core import event

    compiled = []

    class Listener(event.Listener):
        def on_start(self, ev):
            compiled.append(str(ev.data["dispatcher"].py_func.__qualname__))

        def on_end(self, ev):
            pass

    event.register("numba:compile", Listener())
""")


def _compiles_in_a_new_process(body: str) -> list[str]:
    code = _LISTEN + body + "\nprint(json.dumps(compiled))\n"
    proc = subprocess.run([sys.executable, "-c", code],
                          cwd=ROOT, capture_output=True, text=True, check=True)
    return json.loads(proc.stdout.strip().splitlines()[-1])


@pytest.mark.e2e
def test_a_second_process_compiles_no_sampler_kernel():
    # the session fixture ran warmup() in this process: every kernel it needs is cached
    assert _compiles_in_a_new_process("from rankedassign import warmup; warmup()") == []


# The first steps that docs/reproduction.md times (section "Compile cost of a first step"):
# the δ-GLMB filter with Murty and with short chains, the LMB filter with short chains.
_FIRST_STEPS = textwrap.dedent("""
    import numpy as np
    from rankedassign.tracking import GLMBFilter, LMBFilter, Murty, ShortChainGibbs, make_model

    z = np.array([[0.0, 0.0], [100.0, -50.0], [-300.0, 200.0]])
    for f in (GLMBFilter(make_model("vo"), Murty(100)),
              GLMBFilter(make_model("vo"), ShortChainGibbs(10, 25, tau_stall=5, tau_stale=10)),
              LMBFilter(make_model("vo"), ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10))):
        f.step(z, rng=0)
        f.step(z + 1, rng=1)
""")


@pytest.mark.e2e
def test_a_second_process_compiles_nothing_for_a_filters_first_step():
    # the first process loads what the suite has compiled and compiles what is missing (about a
    # minute with an empty cache); the second must load every kernel of the three first steps
    subprocess.run([sys.executable, "-c", _FIRST_STEPS], cwd=ROOT, check=True)
    assert _compiles_in_a_new_process(_FIRST_STEPS) == []


def test_the_queue_starts_with_the_longest_study_and_holds_every_warm_task():
    cfg = Config.quick()
    queue, after = _queue(study_names(), cfg)
    assert len(after) == len(queue)
    assert queue[0][0] == "tempering_herding"
    assert queue[1] == (None, (), False)  # the samplers' warm-up right after it
    for name in study_names():
        st = get_study(name)
        if st.warm is None:
            continue
        n = len(list(st.tasks(st.warm(cfg[name]), 0)))
        assert sum(1 for s, _, unit in queue if s == name and not unit) == n, name


def test_the_queue_runs_a_studys_warm_units_first_and_its_tiny_tasks_last():
    # the tempering study's one task per kind compiled every sampler of the kind on one core
    # (206 s of a 207 s precompile); its units go out first, one per sampler and kind, and
    # its tiny tasks after them, when they load from the cache
    cfg = Config.quick()
    queue, after = _queue(study_names(), cfg)
    st = get_study("tempering_herding")
    units = st.warm_units(st.warm(cfg["tempering_herding"]))
    is_unit = [unit for *_, unit in queue]
    assert sum(is_unit) == len(units) >= 9
    first = is_unit.index(False, 2)  # after the units (the samplers' warm-up is second)
    assert not any(is_unit[first:])
    assert [args for s, args, unit in queue if unit] == units
    tiny = [i for i, (s, _, unit) in enumerate(queue) if s == "tempering_herding" and not unit]
    assert len(tiny) == len(list(st.tasks(st.warm(cfg["tempering_herding"]), 0)))
    # each of them waits for every unit: it would compile what a running unit compiles
    assert all(after[i] == tuple(i for i, u in enumerate(is_unit) if u) for i in tiny)


def test_no_two_tasks_of_one_kernel_group_compile_side_by_side():
    # Measured from an empty cache, one task after another: the first tiny task of table1,
    # sweep, tracking, multisensor, adaptive_birth, optimum or random_readings compiled
    # 16.7-25.0 s of kernels, every later one of the same study 0.0-1.0 s; run side by side
    # the later ones compiled the same kernels again on the other core.
    cfg = Config.quick()
    queue, after = _queue(study_names(), cfg)
    first = {}
    for i, (study, args, _) in enumerate(queue):
        st = get_study(study) if study else None
        if st is None or st.warm_units is not None:  # the test above
            continue
        key = (study, st.warm_group(args) if st.warm_group else None)
        if key in first:
            assert after[i] == first[key], (i, key)  # waits for its group's first task
        first.setdefault(key, i)
    for i, a in enumerate(after):  # nothing waits for itself or a later item
        assert a is None or all(j < i for j in (a if isinstance(a, tuple) else (a,)))
    by_index = {i: s for i, (s, _, _) in enumerate(queue)}
    t1 = first[("table1", None)]
    for study in ("sweep", "ablation", "optimum", "random_readings"):  # Table I's samplers
        assert after[first[(study, None)]] == t1, study
    assert after[first[("tracking_var", None)]] == first[("tracking", None)]
    assert by_index[t1] == "table1"
    ms = {k[1]: i for k, i in first.items() if k[0] == "multisensor_tracking"}
    assert set(ms) == {"static", "adaptive", "glmb"}
    assert all(after[i] is None for i in ms.values())  # three kernel sets, side by side


def test_precompile_one_study_in_process(capsys):
    assert main(["precompile", "table1", "--workers", "1", "--quiet"]) == 0
    assert capsys.readouterr().err.startswith("rankedassign precompile: kernels ready in ")


@pytest.mark.parametrize(("argv", "message"), [
    (["precompile", "nosuch"],
     "rankedassign precompile: error: unknown study 'nosuch'; choose from table1, "),
    (["precompile", "--workers", "0"], "argument --workers: must be a positive integer"),
])
def test_precompile_bad_arguments(argv, message, capsys):
    assert main(argv) == 2
    assert message in capsys.readouterr().err


@pytest.mark.slow
def test_after_precompile_a_new_process_compiles_no_kernel_of_any_study():
    # the first process fills the cache (the README's test command has already done it, so it
    # only loads); the second, running every study's tiny tasks, must load every kernel
    body = ("from rankedassign.experiments.precompile import precompile\n"
            "precompile(1, progress=False)")
    subprocess.run([sys.executable, "-c", body], cwd=ROOT, check=True)
    assert _compiles_in_a_new_process(body) == []


def test_the_samplers_warm_up_compiles_each_kinds_growth_kernel():
    # A run's unique set starts with room for 512 states and grows when it fills. The growth
    # kernel of the multi-sensor kind was compiled by no study's warm-up: the first
    # sample_short_chains on a 4 x (4, 4) problem after `rankedassign precompile` compiled
    # it, 2.8 s instead of 0.2 s.
    from rankedassign import warmup
    from rankedassign.adaptive_birth import _kernels as ab
    from rankedassign.multisensor import _kernels as ms
    from rankedassign.single import _kernels as single

    warmup()
    for driver in (single.run_chains, single.run_chains_prefix, ms.run_chains, ab.run_chains):
        assert driver.kernels["grow_run"].signatures, driver.__name__


_SIGNATURES = textwrap.dedent("""
    import gc
    import json

    from numba.core.registry import CPUDispatcher


    def signatures():
        out = {}
        for obj in gc.get_objects():
            if isinstance(obj, CPUDispatcher) and obj.signatures:
                f = obj.py_func
                if f.__module__.split(".")[0] in ("rankedassign", "oracle"):
                    name = f"{f.__module__}.{f.__qualname__}"
                    out.setdefault(name, []).extend(str(s) for s in obj.signatures)
        return out
""")

# A researcher's first calls (benchmarks/first_call_compile.py): the first two steps of the
# δ-GLMB filter with Murty and with short chains and of the LMB filter with short chains on
# "vo", and the first two sample_short_chains on a small problem of each kind.
_FIRST_CALLS = _FIRST_STEPS + textwrap.dedent("""
    from rankedassign import sample_short_chains, synthetic
    from rankedassign.adaptive_birth import AdaptiveBirthProblem
    from rankedassign.multisensor import synthetic as ms_synthetic

    zz = [np.array([[0.0], [50.0]]), np.array([[1.0]])]
    for p in (synthetic.random(R=4, M=6, rng=0), ms_synthetic.random(P=4, M=(4, 4), rng=0),
              AdaptiveBirthProblem.from_measurements(
                  zz, [[0.99, 0.95], [0.95]], H=[[1.0]], R=[[1.0]], P_D=0.9,
                  clutter_intensity=0.01, mu0=[0.0], P0=[[100.0]])):
        for seed in (0, 1):
            sample_short_chains(p, 100, 20, tau_stall=5, tau_stale=10, rng=seed)
""")

_PRECOMPILE_QUEUE = textwrap.dedent("""
    from rankedassign.experiments.precompile import _queue, _task
    from rankedassign.experiments.registry import Config, study_names

    queue, _ = _queue(study_names(), Config.quick())
    for study, args, unit in queue:
        _task(study, args, unit)
""")


def _signatures_in_a_new_process(body: str) -> dict[str, list[str]]:
    code = _SIGNATURES + body + "\nprint(json.dumps(signatures()))\n"
    proc = subprocess.run([sys.executable, "-c", code],
                          cwd=ROOT, capture_output=True, text=True, check=True)
    return json.loads(proc.stdout.strip().splitlines()[-1])


@pytest.mark.slow
def test_precompile_compiles_every_kernel_signature_of_a_researchers_first_calls():
    # After `rankedassign precompile` a first filter step or sampler call must load every
    # kernel (well under a second), not compile one that no study uses. Each side runs in a
    # process of its own and lists the signatures its kernels hold (loaded or compiled, so
    # the check does not depend on what the cache holds). Found by it: the LMB filter's
    # posterior components took a strided `nu` in the studies and a C-ordered one on "vo",
    # and no study grew a multi-sensor run's unique set.
    queue = _signatures_in_a_new_process(_PRECOMPILE_QUEUE)
    first = _signatures_in_a_new_process(_FIRST_CALLS)
    assert first
    missing = {name: sorted(set(sigs) - set(queue.get(name, ())))
               for name, sigs in first.items()}
    assert {name: sigs for name, sigs in missing.items() if sigs} == {}
