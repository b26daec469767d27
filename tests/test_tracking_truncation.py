"""The truncation contract: one class per truncation for every filter and sensor count, the
refusals from one place, and the check of a truncation of one's own output, for every filter."""

from __future__ import annotations

import re

import numpy as np
import pytest
from numpy.testing import assert_array_equal

from rankedassign import AssignmentProblem
from rankedassign.multisensor import MultiSensorProblem
from rankedassign.tracking import (
    LBP,
    Exact,
    GLMBFilter,
    HerdedGibbs,
    Hypotheses,
    LMBFilter,
    MultiSensorGLMBFilter,
    MultiSensorLMBFilter,
    Murty,
    OriginalGibbs,
    ShortChainGibbs,
    TemperedGibbs,
    check_truncation,
    make_model,
    make_multisensor_model,
    truncate,
)
from rankedassign.tracking.association import BatchPlan, check_hypotheses

SINGLE = AssignmentProblem.from_eta([[3.0, 1.0], [0.5, 2.0]], [1.0, 0.5], [1.0, 1.0])
MULTI = MultiSensorProblem.from_eta([1.0, 0.5], np.ones((2, 3, 2)))
Z1 = [[0.0, 0.0], [400.0, -600.0]]
ZS = [Z1, Z1]


def _filters(assoc):
    """Every filter of the library with ``assoc`` (the same object for all of them)."""
    return {
        "lmb": lambda: LMBFilter(make_model("vo"), assoc),
        "glmb": lambda: GLMBFilter(make_model("vo"), assoc, h_upd=20, h_max=20),
        "ms-lmb": lambda: MultiSensorLMBFilter(make_multisensor_model((0, 1), birth="narrow"),
                                               assoc),
        "ms-glmb": lambda: MultiSensorGLMBFilter(make_multisensor_model((0, 1), birth="narrow"),
                                                 assoc, h_upd=20, h_max=20),
    }


#: Which filters each truncation serves (the rest refuse it with a TypeError).
SERVES = [
    (OriginalGibbs(20), {"lmb", "glmb", "ms-lmb", "ms-glmb"}),
    (ShortChainGibbs(10, 5, tau_stall=5, tau_stale=10), {"lmb", "glmb", "ms-lmb", "ms-glmb"}),
    (HerdedGibbs(20), {"lmb", "glmb", "ms-lmb", "ms-glmb"}),
    (Exact(), {"lmb", "glmb", "ms-lmb", "ms-glmb"}),
    (Murty(5), {"lmb", "glmb"}),
    (LBP(), {"lmb"}),
    (TemperedGibbs(20, beta=0.5), {"lmb", "glmb", "ms-lmb", "ms-glmb"}),
    (TemperedGibbs(20, beta=0.5, scheme="zanella-roberts"), {"lmb", "glmb", "ms-lmb", "ms-glmb"}),
]


@pytest.mark.parametrize("assoc, serves", SERVES, ids=lambda x: repr(sorted(x)) if isinstance(x, set) else repr(x))
def test_every_filter_runs_every_truncation_it_can_use(assoc, serves):
    for name, make in _filters(assoc).items():
        if name not in serves:
            with pytest.raises(TypeError, match=f"cannot use {type(assoc).__name__}: "):
                make()
            continue
        f = make()
        rec = f.step(ZS if name.startswith("ms") else Z1, rng=0)
        f.step(ZS if name.startswith("ms") else Z1, rng=1)
        assert rec.n_meas == (4 if name.startswith("ms") else 2)


def test_one_class_solves_both_kinds():
    # MULTI has no separable factors, so the chains use the Alg. 1 row conditional
    for assoc in (OriginalGibbs(50, method="exact"), ShortChainGibbs(5, 5, method="exact"),
                  HerdedGibbs(50, method="exact"), Exact()):
        single = truncate(assoc, SINGLE, 10, rng=0)
        multi = truncate(assoc, MULTI, 10, rng=0)
        assert single.assignments.shape[1:] == (2,)
        assert multi.assignments.shape[1:] == (2, 2)
        assert assoc(SINGLE, 0).beta.shape == (2, 4)
        assert assoc(MULTI, 0).tuples.shape == (2, 3, 2)


def test_the_multisensor_method_has_one_default_and_is_ignored_on_one_sensor():
    a, b = OriginalGibbs(30), OriginalGibbs(30, method="exact")
    assert a.method == "mm" and b.method == "exact"
    assert_array_equal(a.hypotheses(SINGLE, 20, 0).assignments,
                       b.hypotheses(SINGLE, 20, 0).assignments)


def test_batch_plans_say_what_the_glmb_filters_may_batch():
    assert ShortChainGibbs(4, 5, tau_stall=5).batch_plan("single-sensor") == BatchPlan(
        chains=True, tau_stall=5, start_alone=True, marginal_chains=(4, 5))
    # a marginals call of the chains is batched only for the truncated marginals
    assert OriginalGibbs(9).batch_plan("single-sensor").marginal_chains == (1, 9)
    assert ShortChainGibbs(4, 5, marginals="rao-blackwell").batch_plan(
        "single-sensor") == BatchPlan(chains=True, start_alone=True)
    assert ShortChainGibbs(4, 5, backend="python").batch_plan("single-sensor") == BatchPlan(
        start_alone=True)
    # several sensors: the compiled path for the row conditionals it reproduces bit for bit
    assert OriginalGibbs(4).batch_plan("multi-sensor") == BatchPlan(
        chains=True, start_alone=True, method="mm")
    assert ShortChainGibbs(4, 5, tau_stale=3, method="exact", scan="random").batch_plan(
        "multi-sensor") == BatchPlan(chains=True, random_scan=True, tau_stale=3,
                                     start_alone=True, method="exact")
    assert ShortChainGibbs(4, 5, method="mm-fixed").batch_plan("multi-sensor") == BatchPlan(
        start_alone=True)
    assert OriginalGibbs(4, survival_power="V").batch_plan("multi-sensor") == BatchPlan(
        start_alone=True)
    assert Murty(7).batch_plan("single-sensor") == BatchPlan(ranked=True, k=7)
    assert Murty(7, backend="scipy").batch_plan("single-sensor") is None
    assert Exact().batch_plan("single-sensor") == BatchPlan(ranked=True, k=0)
    assert Exact().batch_plan("multi-sensor") is None
    assert HerdedGibbs(4).batch_plan("single-sensor") is None


@pytest.mark.parametrize("sensors, need, exc, match", [
    ("multi-sensor", "marginals", TypeError, "X cannot use Murty: Murty's ranked search"),
    ("single-sensor", "hypotheses", TypeError, "X cannot use LBP: it returns association "
                                               "marginals only"),
    ("multi-sensor", "marginals", TypeError, "X cannot use LBP: loopy belief propagation is "
                                             "written for one sensor's problem"),
])
def test_refusals_come_from_one_place(sensors, need, exc, match):
    assoc = Murty(3) if "Murty" in match else LBP()
    with pytest.raises(exc, match=match):
        check_truncation(assoc, "X", sensors, need)


def test_a_function_gives_marginals_not_hypotheses():
    def mine(problem, rng):  # pragma: no cover (refused before it is called)
        raise AssertionError

    check_truncation(mine, "X", "single-sensor", "marginals")
    with pytest.raises(TypeError, match=re.escape("X cannot use test_a_function_gives_marginals"
                                                  "_not_hypotheses.<locals>.mine: it returns "
                                                  "association marginals only")):
        check_truncation(mine, "X", "single-sensor", "hypotheses")


# ------------------------------------------------------------------ a truncation's output
class _Returns:
    """A truncation of one's own that returns ``out(problem)``."""

    def __init__(self, out):
        self.out = out

    def hypotheses(self, problem, budget, rng):
        return self.out(problem)


def _best(problem):
    return truncate(Exact(), problem, 0)


def _first(problem):
    h = _best(problem)
    return Hypotheses(h.assignments[:1], h.costs[:1])


BAD = [
    (lambda p: (_first(p).assignments, _first(p).costs), TypeError,
     "association _Returns returned a tuple from hypotheses"),
    (lambda p: Hypotheses(_first(p).assignments.astype(float), _first(p).costs), TypeError,
     "association _Returns returned assignments of dtype float64, expected integer column "
     "indices"),
    (lambda p: Hypotheses(_first(p).assignments, np.array(["a"])), TypeError,
     "association _Returns returned costs of dtype <U1, expected real numbers"),
    (lambda p: Hypotheses(_first(p).assignments[0], _first(p).costs), ValueError,
     r"association _Returns returned assignments of shape \(\d+,( \d+)?\), expected "
     r"\(n >= 1, 2(, 2)?\)"),
    (lambda p: Hypotheses(_first(p).assignments, np.zeros(3)), ValueError,
     r"association _Returns returned costs of shape \(3,\), expected \(1,\), one per "
     "assignment"),
    (lambda p: Hypotheses(_first(p).assignments, np.full(1, np.nan)), ValueError,
     r"association _Returns returned a NaN cost \(costs\[0\]\)"),
    (lambda p: Hypotheses(_first(p).assignments + 99, _first(p).costs), ValueError,
     r"association _Returns returned an entry out of range: assignments\[0, 0(, 0)?\] = \d+ "
     r"\(row 0(, sensor 0)?\), expected"),
    (lambda p: Hypotheses(np.repeat(_first(p).assignments, 2, axis=0),
                          np.repeat(_first(p).costs, 2)), ValueError,
     "association _Returns returned duplicate assignments"),
    (lambda p: Hypotheses(_first(p).assignments, _first(p).costs + 1.0), ValueError,
     "association _Returns returned costs that are not those of its assignments"),
]


@pytest.mark.parametrize("out, exc, match", BAD)
@pytest.mark.parametrize("problem", [SINGLE, MULTI], ids=["single", "multi"])
def test_a_truncations_bad_output_is_refused_naming_it_and_the_field(problem, out, exc, match):
    with pytest.raises(exc, match=match):
        truncate(_Returns(out), problem, 5)


def test_an_infeasible_assignment_is_refused():
    p = AssignmentProblem.from_eta([[3.0, 0.0]], [1.0], [1.0])  # measurement 1 not gated
    with pytest.raises(ValueError, match=re.escape(
            "association str returned an infeasible assignment (assignments[0]")):
        check_hypotheses("x", p, Hypotheses([[1]], [0.0]))


@pytest.mark.parametrize("make", ["glmb", "ms-glmb"])
def test_every_glmb_filter_checks_a_truncations_output_in_the_same_place(make):
    f = _filters(_Returns(BAD[1][0]))[make]()
    with pytest.raises(TypeError, match=BAD[1][2]):
        f.step(ZS if make.startswith("ms") else Z1, rng=0)


# ------------------------------------------------------------------ the filter protocol
def test_the_runners_take_a_filter_name_class_or_object():
    from rankedassign.tracking import Filter, make_filter, run_multisensor_scenario, run_scenario

    by_name = run_scenario("vo", Exact(), filter="glmb", rng=0, n_scans=2)
    by_class = run_scenario("vo", Exact(), filter=GLMBFilter, rng=0, n_scans=2)
    obj = LMBFilter(make_model("vo"), Exact())
    assert isinstance(obj, Filter)
    by_object = run_scenario("vo", filter=obj, rng=0, n_scans=2)
    lmb = run_scenario("vo", Exact(), rng=0, n_scans=2)
    assert_array_equal(by_name.estimates, by_class.estimates)
    assert_array_equal(by_object.estimates, lmb.estimates)
    chains = ShortChainGibbs(5, 3, method="exact")
    # GLMBFilter stands for its row of the table: the multi-sensor δ-GLMB filter here
    ms = run_multisensor_scenario(chains, filter=GLMBFilter, rng=0, n_scans=1, sensors=(0, 1))
    ref = run_multisensor_scenario(chains, filter="glmb", rng=0, n_scans=1, sensors=(0, 1))
    assert_array_equal(ms.estimates, ref.estimates)
    with pytest.raises(ValueError, match=re.escape(
            "unknown filter 'phd'; expected one of ('lmb', 'glmb'), a filter class or a filter "
            "object")):
        make_filter("phd", make_model("vo"), Exact(), multi=False)
    with pytest.raises(TypeError, match="filter must be one of .*got int"):
        make_filter(3, make_model("vo"), Exact(), multi=False)
    with pytest.raises(TypeError, match="a filter object runs as it is"):
        run_scenario("vo", Exact(), filter=obj, n_scans=1)


# ------------------------------------------------------------------ tempered Gibbs
def test_tempered_gibbs_at_beta_one_is_the_original_chain():
    for problem in (SINGLE, MULTI):
        a = truncate(TemperedGibbs(30, beta=1.0, method="exact"), problem, 25, rng=3)
        b = truncate(OriginalGibbs(30, method="exact"), problem, 25, rng=3)
        assert_array_equal(a.assignments, b.assignments)
        assert_array_equal(a.costs, b.costs)
        assert a.sweeps == b.sweeps == 24


@pytest.mark.parametrize("problem", [SINGLE, MULTI], ids=["single", "multi"])
def test_zanella_roberts_marginals_are_the_exact_ones_in_the_limit(problem):
    import oracle

    zr = TemperedGibbs(4000, beta=0.5, scheme="zanella-roberts")
    out = zr(problem, np.random.default_rng(0))
    exact = oracle.marginals(problem)
    if problem is SINGLE:
        got, want = out.beta, exact
    else:
        got = np.concatenate([out.dead.ravel(), out.tuples.ravel()])
        want = np.concatenate([np.ravel(exact.dead), np.ravel(exact.tuples)])
    # 4000 sweeps' worth of moves on a 2-row problem: importance-weighted estimates to ~1e-2
    assert np.abs(got - want).max() < 0.03
    # the truncated construction from the same draw's unique states differs in general
    assert out.row_updates == 4000 * problem.n_rows


def test_tempered_gibbs_hypotheses_are_exact_and_unique():
    import oracle

    for scheme in TemperedGibbs.SCHEMES:
        hyp = truncate(TemperedGibbs(1000, beta=0.3, scheme=scheme), SINGLE, 1001, rng=1)
        assert_array_equal(hyp.costs, SINGLE.cost_of(hyp.assignments))
        assert len({tuple(r) for r in hyp.assignments}) == len(hyp.costs)
        # every assignment of this tiny problem is reached at a hot temperature
        assert len(hyp.costs) == len(oracle.enumerate_assignments(SINGLE).costs)


def test_tempered_gibbs_repr_and_refusals():
    assert repr(TemperedGibbs(200, beta=0.5)) == "TemperedGibbs(200, beta=0.5)"
    assert repr(TemperedGibbs(9, beta=1, scheme="zanella-roberts", marginals="truncated")) == (
        "TemperedGibbs(9, beta=1.0, scheme='zanella-roberts', marginals='truncated')")
    with pytest.raises(ValueError, match=re.escape("beta must be a number in (0, 1], got 0")):
        TemperedGibbs(10, beta=0)
    with pytest.raises(ValueError, match=re.escape("beta must be a number in (0, 1], got True")):
        TemperedGibbs(10, beta=True)
    with pytest.raises(ValueError, match=re.escape("unknown scheme 'parallel'; expected one of")):
        TemperedGibbs(10, beta=0.5, scheme="parallel")
    with pytest.raises(ValueError, match="marginals='importance' are the Zanella-Roberts "):
        TemperedGibbs(10, beta=0.5, marginals="importance")
    with pytest.raises(ValueError, match=re.escape(
            "method='mm' does not apply to the Zanella-Roberts scheme")):
        TemperedGibbs(10, beta=0.5, scheme="zanella-roberts", method="mm")


def test_the_multisensor_runner_moved_above_the_filters_with_deprecated_old_paths():
    import rankedassign.tracking.multisensor as ms
    import rankedassign.tracking.multisensor.scenario as old
    from rankedassign.tracking import run_multisensor_scenario
    from rankedassign.tracking.run import FILTERS

    for module, name, new in ((old, "run_multisensor_scenario", run_multisensor_scenario),
                              (ms, "run_multisensor_scenario", run_multisensor_scenario),
                              (old, "FILTERS", FILTERS)):
        with pytest.warns(DeprecationWarning, match=re.escape(
                f"rankedassign.tracking.multisensor.scenario.{name} moved to "
                f"rankedassign.tracking.run.{name}")):
            assert getattr(module, name) is new
    with pytest.raises(AttributeError, match="has no attribute 'nothing'"):
        ms.nothing  # noqa: B018
