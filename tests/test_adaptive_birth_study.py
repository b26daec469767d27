"""The adaptive-birth study's computation: task, summary, table, verdict, curve and plot."""

import math

import numpy as np
import pytest

from rankedassign.experiments.studies import adaptive_birth as S

TINY = S.AdaptiveBirthStudyConfig(n_mc=2, sensors=(2,), original_obs=60, n_chains=6, chain_length=10,
                     tau_stall=3, tau_stale=2, curve_obs=(20, 60))


@pytest.fixture(scope="module")
def runs():
    return [S.run_task(TINY, 3, r, f, 2) for f in S.FAMILIES for r in range(TINY.n_mc)]


def test_run_task_records(runs):
    for out in runs:
        assert set(out.to_dict()) == {"kind", "run", "family", "V", "original", *S.CRITERIA}
        assert out.kind == "run" and out.original.n_obs == TINY.original_obs
        for crit in S.CRITERIA:
            rec = getattr(out, crit)
            assert 0 < rec.n_obs <= TINY.n_chains * TINY.chain_length
            assert 0.0 <= rec.error <= 1.0
            assert rec.stop_reason in ("budget", "stale")
        assert out.stall.n_chains == TINY.n_chains or out.stall.stop_reason == "stale"
    # same seed, same records (the streams depend only on seed, run, family and V)
    again = S.run_task(TINY, 3, 1, "random", 2)
    assert again == next(r for r in runs if r.family == "random" and r.run == 1)


def test_summarise_rows_and_definitions(runs):
    rows = S.summarise(runs)
    assert [(r["family"], r["criterion"]) for r in rows] == [
        (f, c) for f in S.FAMILIES for c in S.CRITERIA]
    for row in rows:
        rs = [r for r in runs if r.family == row["family"]]
        no = np.mean([r.original.n_obs for r in rs])
        ns = np.mean([getattr(r, row["criterion"]).n_obs for r in rs])
        eo = np.mean([r.original.error for r in rs])
        es = np.mean([getattr(r, row["criterion"]).error for r in rs])
        assert row["delta_obs_pct"] == pytest.approx(100 * (no - ns) / no)
        assert row["delta_error_pp"] == pytest.approx(100 * abs(eo - es))
        assert row["n_mc"] == 2 and row["V"] == 2
    table = S.format_table(rows)
    assert len(table.splitlines()) == 2 + len(rows)
    assert "| random | 2 | full |" in table


def test_single_run_has_no_standard_error():
    rec = S.ABCall(n_obs=10, n_unique=1, n_chains=1, stop_reason="budget", error=0.5)
    runs = [S.AdaptiveBirthRun(kind="run", run=0, family="uniform", V=4, original=rec,
                               stall=rec, stale=rec, full=rec)]
    rows = S.summarise(runs)
    assert math.isnan(rows[0]["delta_error_se_pp"])
    # every cell of a one-run row says so, instead of a "± nan"
    assert "| 1 | 0.00 (1 run) | 0.00 (1 run) | 50.00 (1 run) | 50.00 (1 run) |" in (
        S.format_table(rows))


def _row(fam, V, saved, eo, es):
    return {"family": fam, "V": V, "criterion": "full", "delta_obs_pct": saved,
            "error_original": eo, "error_short": es}


def test_verdict_branches():
    assert S.verdict([_row("uniform", 4, 0.0, 0.9, 0.9)]).startswith(
        "uniform: no saving and no loss")
    assert S.verdict([_row("random", 4, 50.0, 0.01, 0.05)]).startswith(
        "random: savings cost accuracy (50.0 % fewer observations")
    v = S.verdict([_row("diagonal", 4, 70.0, 0.5, 0.001), _row("diagonal", 6, 80.0, 0.4, 0.002)])
    assert v.startswith("diagonal: savings carry over (70.0-80.0 % fewer observations")


def test_curve_and_plot(tmp_path):
    pts = S.curve(TINY, 0, "diagonal", 2)
    assert [p.n_obs for p in pts] == [20, 60]
    assert all(0 <= p.error_original <= 1 and 0 <= p.error_short <= 1 for p in pts)
    out = tmp_path / "ab.png"
    S.plot({("diagonal", 2): pts, ("uniform", 2): S.curve(TINY, 0, "uniform", 2)}, out)
    assert out.stat().st_size > 0


def test_quick_configuration_covers_the_spec_sizes():
    assert S.QUICK.sensors == (4, 6, 8) and S.QUICK.families == S.FAMILIES
    assert [S.SIZES[V] for V in S.QUICK.sensors] == [10, 6, 4]
    assert S.FULL.n_mc >= 20


def test_the_tasks_round_trip_through_json(runs, tmp_path):
    import json

    from rankedassign.experiments.report import write_json

    tasks = [*runs, S.adaptive_birth_task("curve", TINY, 3, 0, "uniform", 2)]
    write_json(tmp_path / "runs.json", tasks)
    back = [S.task_from_dict(d) for d in json.loads((tmp_path / "runs.json").read_text())]
    assert back == tasks and isinstance(back[-1].points[0], S.CurvePoint)
    assert S.summarise_adaptive_birth(back, TINY) == S.summarise_adaptive_birth(tasks, TINY)
    with pytest.raises(ValueError, match=r"^an adaptive_birth task has kind 'run' or 'curve', "
                                         r"got None$"):
        S.task_from_dict({"run": 0})
