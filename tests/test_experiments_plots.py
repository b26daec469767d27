"""Every plot of the report reads at a glance, measured with matplotlib's own geometry.

Each study's plot is drawn from a tiny run of its quick settings (``Study.warm``: one run, a
few observations, the same code paths; ``tempering_herding`` from fabricated records of its
nine families, whose tiny run is too slow here) and checked by
:func:`rankedassign.experiments._plots.figure_problems`: no two tick labels overlap, no axes
is empty, at most six series per panel that stay distinct in greyscale, no data clipped, and
no legend over more than 2 % of a panel's plotted points. The checker itself is tested on
figures built to fail each rule.
"""

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from matplotlib.figure import Figure  # noqa: E402

from rankedassign.experiments import Config, get_study, run_study, study_names  # noqa: E402
from rankedassign.experiments._plots import (  # noqa: E402
    figure,
    figure_problems,
    legend_below,
    series_style,
)


def _tempering_herding_summary():
    """Fabricated records of every family, method and quick budget of ``tempering_herding``
    (its tiny run grades nine families against the oracle: too slow for this module)."""
    from rankedassign.experiments.studies import tempering_herding as th

    cfg = Config.quick()["tempering_herding"]
    rng = np.random.default_rng(0)
    rows = []
    for fam in cfg.families:
        kind = th.kind_name(fam)
        for m in cfg.truncations:
            if m == th.LBP:
                if kind == "single":
                    rows.append(th.THRow(fam, kind, *m, 0, 3, 0, None, None, None, 1e-3, 0.01,
                                         1e-3, 1e-3))
                continue
            base = rng.uniform(5, 99)
            for b in cfg.budgets:
                e = base * (100 / b) ** rng.uniform(0.05, 0.5)
                rows.append(th.THRow(fam, kind, *m, b, 3, b * rng.uniform(0.3, 1), e, e / 20,
                                     100.0, b * 1e-6 * rng.uniform(1, 3),
                                     None if kind == "adaptive_birth" else e / 100, 1e-3,
                                     b * 1e-6))
    tracking = [th.THTrackingRow(p, *m, 1, 35.0, None, 1e3, 1.0, 0.5)
                for p in cfg.presets for m in cfg.tracking_truncations]
    return th.THSummary(rows=rows, tracking=tracking)


#: Every plot the quick report writes, per study (17 files; the report's sections link them).
PLOTS = {
    "table1": ["table1.png"],
    "sweep": ["sweep.png"],
    "tracking": ["tracking_ospa2.png", "tracking_observations.png"],
    "tracking_var": ["tracking_var_ospa2.png", "tracking_var_observations.png"],
    "optimum": ["optimum.png"],
    "glmb_tracking": ["glmb_tracking.png", "glmb_tradeoff.png"],
    "nonlinear_tracking": ["nonlinear_tracking.png"],
    "scaling": ["scaling.png"],
    "multisensor": ["multisensor.png"],
    "adaptive_birth": ["adaptive_birth.png"],
    "multisensor_tracking": ["multisensor_tracking.png"],
    "tempering_herding": ["tempering_herding_obs.png", "tempering_herding_time.png",
                          "tempering_herding_marginals.png"],
}


def test_the_check_below_covers_every_plot_of_the_report():
    with_plot = [n for n in study_names() if get_study(n).plot is not None]
    assert sorted(with_plot) == sorted(PLOTS)
    assert sum(len(v) for v in PLOTS.values()) == 17


@pytest.mark.e2e
@pytest.mark.parametrize("name", [n for n in study_names() if get_study(n).plot is not None])
def test_every_plot_of_the_report_reads_at_a_glance(name, tmp_path, monkeypatch):
    st = get_study(name)
    if name == "tempering_herding":
        summary = _tempering_herding_summary()
        cfg = Config.quick()[name]
    else:
        cfg = st.warm(Config.quick()[name])
        summary = run_study(st, cfg, seed=0, progress=False)
    drawn = []
    save = Figure.savefig

    def spy(fig, *args, **kwargs):
        drawn.append(fig)
        return save(fig, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", spy)
    files = st.plot(summary, tmp_path)
    assert files == PLOTS[name]
    assert len(drawn) == len(files)
    section = st.render(summary, cfg)
    assert all(f"]({file})" in section for file in files)  # the report shows every plot
    for fig, file in zip(drawn, files, strict=True):
        assert figure_problems(fig) == [], file


def _lines(ax, n, points=20):
    x = np.arange(points)
    for i in range(n):
        ax.plot(x, x + 10 * i, label=f"series {i}", **series_style(i))


def test_a_figure_that_follows_the_rules_passes():
    fig, axes = figure(2)
    for ax in axes:
        _lines(ax, 6)
    legend_below(fig)
    assert figure_problems(fig) == []


def test_overlapping_tick_labels_are_found():
    fig, (ax,) = figure(width=3.0)
    ax.bar(range(8), np.ones(8))
    ax.set_xticks(range(8), [f"a long label {i}" for i in range(8)])
    assert any("x tick labels 'a long label 0' and 'a long label 1' overlap" in p
               for p in figure_problems(fig))


def test_an_empty_panel_is_found_even_with_a_note_in_it():
    fig, (full, empty) = figure(2)
    _lines(full, 1)
    empty.text(0.5, 0.5, "not computed on this preset", transform=empty.transAxes)
    assert figure_problems(fig) == ["axes 1: no data"]


def test_a_legend_on_the_data_is_found():
    fig, (ax,) = figure()
    x = np.linspace(0, 1, 50)
    for i in range(3):
        ax.plot(x, np.full_like(x, 0.9 + 0.01 * i), label=f"line {i}", **series_style(i))
    ax.set_ylim(0, 1)
    ax.legend(loc="upper center")
    assert any("the legend covers" in p for p in figure_problems(fig))


def test_too_many_series_merged_styles_and_clipped_data_are_found():
    fig, (ax,) = figure()
    _lines(ax, 7)
    ax.plot([0, 1], [5, 6], label="same look as series 0", **series_style(0))
    ax.set_ylim(0, 50)
    problems = figure_problems(fig)
    assert "axes 0: 8 series (at most 6)" in problems
    assert any("look the same in greyscale" in p for p in problems)
    assert any("data points outside the axes" in p for p in problems)
