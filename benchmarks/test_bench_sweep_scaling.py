"""How the cost of a sweep grows with the number of measurements M and of rows P.

Run the timings and draw the figure of the docs with::

    python -m pytest benchmarks/test_bench_sweep_scaling.py --benchmark-enable \
        --benchmark-json=scaling.json
    python benchmarks/plot_sweep_scaling.py scaling.json docs/figures/sweep_scaling.png

A row update draws either by the direct sum over the row's ``M + 2`` candidates (``O(M)``) or,
when :func:`rankedassign.single.prepare.uses_prefix_sums` says so (``M > 32`` and ``M > 2 P``), from
per-row prefix sums corrected for the measurements the other rows hold (``O(P + log M)``).
Each size runs twice: ``rule="direct"`` forces the direct sum on every row (the sampler before
the prefix sums: *before*), ``rule="auto"`` is the sampler as shipped (*after*). Both rules
draw the same states (the prefix-sum draw differs from the direct one only where rounding puts
``target`` on a boundary), so only the time differs. ``extra_info["sweeps"]`` holds the sweeps
per call (one long chain, de-duplication included), so ``mean / sweeps`` is the time per sweep;
the problems are the paper's random family (``synthetic.random(R=P, M=M)``).
"""

import pytest

from rankedassign import kinds, sample_original, warmup
from rankedassign.single import prepare as single_prepare
from rankedassign.single import synthetic

#: Grids of the figure: M at P = 50, and P at M = 1000.
MS = (50, 100, 200, 500, 1_000, 2_000, 5_000, 10_000)
PS = (10, 20, 50, 100, 200)
RULES = ("direct", "auto")


def sweeps_per_call(P: int, M: int, rule: str) -> int:
    """Sweeps per benchmark call: about 20 ms of work at ~1 ns per candidate and row."""
    per_sweep = P * (M + 2) if rule == "direct" else P * (4 * P + 300)
    return int(min(20_000, max(20, 2e7 // per_sweep)))


@pytest.fixture(scope="module", autouse=True)
def _compiled():
    warmup()


@pytest.fixture
def rule(request, monkeypatch):
    if request.param == "direct":  # every row draws by the direct sum, whatever M
        monkeypatch.setattr(single_prepare, "uses_prefix_sums", lambda P, M: False)
    return request.param


def _run(benchmark, P, M, rule):
    problem = synthetic.random(R=P, M=M, rng=0)
    n = sweeps_per_call(P, M, rule)
    res = benchmark.pedantic(sample_original, args=(problem, n), kwargs=dict(rng=1), rounds=3,
                             warmup_rounds=1)
    assert res.n_observations == n
    benchmark.extra_info.update(sweeps=n, P=P, M=M, rule=rule)


@pytest.mark.parametrize("rule", RULES, indirect=True)
@pytest.mark.parametrize("M", MS)
def test_bench_sweep_against_M(benchmark, M, rule):
    benchmark.group = f"sweep cost against M (P = 50), M = {M}"
    _run(benchmark, 50, M, rule)


@pytest.mark.parametrize("rule", RULES, indirect=True)
@pytest.mark.parametrize("P", PS)
def test_bench_sweep_against_P(benchmark, P, rule):
    benchmark.group = f"sweep cost against P (M = 1000), P = {P}"
    _run(benchmark, P, 1_000, rule)


def test_direct_rule_is_forced(monkeypatch):
    """The ``direct`` fixture really switches the large problems to the direct draw."""
    p = synthetic.random(R=5, M=100, rng=0)
    assert kinds.prepare(p, "all_missed", "systematic", 0).driver == "prefix"
    monkeypatch.setattr(single_prepare, "uses_prefix_sums", lambda P, M: False)
    assert kinds.prepare(p, "all_missed", "systematic", 0).driver == "direct"
