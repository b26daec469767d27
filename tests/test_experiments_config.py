"""Study settings: paper values, quick mode, validation messages."""

import dataclasses

import pytest

from rankedassign.experiments import (
    STUDIES,
    AblationConfig,
    Config,
    ReproduceError,
    SweepConfig,
    Table1Config,
    TrackingConfig,
    config_from_dict,
)


def test_full_is_the_papers_settings():
    c = Config.full()
    assert c.mode == "full"
    t = c.table1
    assert (t.n_mc, t.original_obs, t.n_chains, t.chain_length, t.tau_stall, t.tau_stale) == (
        100, 250_000, 10_000, 25, 5, 25)
    # the paper's three families and the random family under the other reading of Pbar_D
    assert t.families == ("diagonal", "uniform", "random", "random-r_pd")
    k = c.tracking
    assert (k.n_mc, k.original_obs, k.n_chains, k.chain_length, k.tau_stall, k.tau_stale) == (
        100, 10_000, 400, 25, 5, 10)
    assert (k.ospa_c, k.ospa_p, k.ospa_window, k.preset, k.n_scans) == (200.0, 1.0, 5, "paper", 100)
    assert (k.grouping, k.sample_empty_groups) == (False, False)
    # the second tracking study: the same per-run settings, the paper-var reading, per group
    v = c.tracking_var
    assert (v.preset, v.grouping, v.sample_empty_groups) == ("paper-var", True, True)
    assert dataclasses.replace(v, preset="paper", grouping=False, sample_empty_groups=False) == k
    assert c.sweep.chain_lengths == (5, 10, 25, 50, 100)
    assert len(c.ablation.stall_readings) * len(c.ablation.stale_readings) == 12


def test_quick_keeps_per_run_settings():
    q, f = Config.quick(), Config.full()
    assert q.mode == "quick"
    for s in STUDIES:
        qs, fs = getattr(q, s), getattr(f, s)
        assert qs.n_mc < fs.n_mc
        for name in ("original_obs", "n_chains", "chain_length", "tau_stall", "tau_stale"):
            if hasattr(fs, name):
                assert getattr(qs, name) == getattr(fs, name), (s, name)
    assert set(q.sweep.obs_grid) <= set(f.sweep.obs_grid)
    assert max(q.sweep.obs_grid) == max(f.sweep.obs_grid) == 250_000


def test_with_mc_and_overrides():
    c = Config.quick().with_mc(7)
    assert all(getattr(c, s).n_mc == 7 for s in STUDIES)
    c2 = config_from_dict(c, {"table1": {"families": ["uniform"], "n_chains": 3}})
    assert c2.table1.families == ("uniform",) and c2.table1.n_chains == 3
    assert c2.sweep == c.sweep


@pytest.mark.parametrize(
    ("overrides", "match"),
    [
        ({"tables": {}}, "unknown study 'tables'"),
        ({"table1": {"n_chain": 3}}, r"unknown setting\(s\) \['n_chain'\] for study 'table1'"),
        ({"table1": {"n_mc": 0}}, "config for 'table1': n_mc must be a positive integer, got 0"),
        ([1], "config overrides must be a mapping"),
    ],
)
def test_config_from_dict_errors(overrides, match):
    with pytest.raises(ReproduceError, match=match):
        config_from_dict(Config.quick(), overrides)


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: Table1Config(n_mc=0), "n_mc must be a positive integer, got 0"),
        (lambda: Table1Config(tau_stall=-1), "tau_stall must be a positive integer, got -1"),
        (lambda: Table1Config(families=("square",)), "unknown family 'square'"),
        (lambda: Table1Config(families=()), "must name at least one family"),
        (lambda: Table1Config(pbar_d="x"), "pbar_d must be 'r_pd' or 'pd'"),
        (lambda: Table1Config(diagonal_pbar_d="x"), "diagonal_pbar_d must be 'r_pd' or 'pd'"),
        (lambda: Table1Config(granularity="x"), "granularity must be 'row' or 'matrix'"),
        (lambda: AblationConfig(stall_readings=("S9",)), "stall_readings must be a non-empty"),
        (lambda: SweepConfig(obs_grid=(10, 5)), "obs_grid must be strictly increasing"),
        (lambda: SweepConfig(chain_lengths=(0,)), "chain_lengths entry must be a positive"),
        (lambda: TrackingConfig(n_scans=0), "n_scans must be a positive integer"),
        (lambda: TrackingConfig(preset="papr"),
         r"preset must be one of \['paper', 'paper-var', 'vo'\], got 'papr'"),
        (lambda: TrackingConfig(marginals="exact"), r"marginals must be one of \('truncated', 'rao-blackwell'\), got 'exact'"),
        (lambda: Config.quick().with_mc(0), "n_mc must be a positive integer, got 0"),
    ],
)
def test_config_validation(make, match):
    with pytest.raises(ValueError, match=match):
        make()


def test_config_is_read_from_the_registry():
    from rankedassign.experiments import get_study, study_names

    c = Config.quick()
    assert set(c.studies) == set(study_names())
    assert all(c[s] == get_study(s).quick() for s in study_names())
    assert Config.full()["tracking_var"] == TrackingConfig.paper_var()
    assert c.to_dict()["mode"] == "quick" and c.to_dict()["table1"]["n_mc"] == c.table1.n_mc
    assert c.replace(table1=Table1Config(n_mc=3)).table1.n_mc == 3


@pytest.mark.parametrize(
    ("make", "error", "match"),
    [
        (lambda: Config("medium"), ReproduceError, "mode must be 'quick' or 'full', got 'medium'"),
        (lambda: Config("full", tabel1=Table1Config()), ReproduceError,
         "unknown study 'tabel1'; choose from table1, sweep"),
        (lambda: Config("full", sweep=Table1Config()), TypeError,
         "sweep settings must be a SweepConfig, got Table1Config"),
        (lambda: Config.full().tabel1, AttributeError, "Config has no study 'tabel1'"),
        (lambda: Config.full()["tabel1"], ReproduceError, "unknown study 'tabel1'"),
    ],
)
def test_config_errors(make, error, match):
    with pytest.raises(error, match=match):
        make()


# ------------------------------------------------------------------ every numeric field
def _numeric_fields():
    """``(study, field, kind)`` of every int and float setting of every registered study."""
    from rankedassign.experiments import get_study, study_names

    out = []
    for name in study_names():
        for f in dataclasses.fields(get_study(name).config_type):
            kind = f.type if isinstance(f.type, str) else f.type.__name__
            if kind in ("int", "float"):
                out.append((name, f.name, kind))
    return out


NUMERIC = _numeric_fields()
# Counts that may be zero (a part of a study switched off) or are not counts (a seed).
MAY_BE_ZERO = {("glmb_tracking", "murty_runs"), ("glmb_tracking", "glmb_exact_runs"),
               ("glmb_tracking", "tradeoff_runs"),
               ("tempering_herding", "tracking_mc"), ("multisensor_tracking", "seed")}
BAD_INT = [-1, 1.5, 2.0, True, "3", None, 2**70]
BAD_FLOAT = [float("nan"), float("inf"), -float("inf"), -1.0, 0.0, True, "1", None]


def test_the_table_covers_every_study():
    from rankedassign.experiments import study_names

    assert {s for s, _, _ in NUMERIC} == set(study_names())
    assert ("glmb_tracking", "ospa_c", "float") in NUMERIC
    assert ("tempering_herding", "ospa_p", "float") in NUMERIC


@pytest.mark.parametrize(("study", "name", "kind"), NUMERIC,
                         ids=[f"{s}.{f}" for s, f, _ in NUMERIC])
def test_every_numeric_setting_of_every_study_is_checked(study, name, kind):
    # issue: a bad ospa_c of glmb_tracking (not checked) or ospa_p of tempering_herding
    # (checked p > 0, not p >= 1) was found only when that study ran, after the earlier ones
    bad = list(BAD_INT if kind == "int" else BAD_FLOAT)
    if kind == "int" and (study, name) not in MAY_BE_ZERO:
        bad.append(0)
    if name == "ospa_p":
        bad += [0.5, 0.999]
    if name == "zr_beta":
        bad.append(1.5)
    for value in bad:
        with pytest.raises(ReproduceError, match=rf"^config for '{study}': .*{name}") as info:
            config_from_dict(Config.quick(), {study: {name: value}})
        # the value is named too (floats as Python prints them; ints beyond the range exactly)
        text = str(info.value)
        assert (repr(value) in text or str(value) in text
                or (isinstance(value, float) and str(float(value)) in text)), (value, text)


@pytest.mark.parametrize(("study", "name", "kind"), NUMERIC,
                         ids=[f"{s}.{f}" for s, f, _ in NUMERIC])
def test_the_smallest_allowed_value_is_accepted(study, name, kind):
    if kind == "float":
        value = 1.0 if name in ("ospa_p", "zr_beta") else 1e-9
    else:
        value = 0 if (study, name) in MAY_BE_ZERO else 1
    assert getattr(config_from_dict(Config.quick(), {study: {name: value}})[study], name) == value


@pytest.mark.parametrize(("study", "name", "value", "message"), [
    ("glmb_tracking", "ospa_c", -1.0, "ospa_c must be > 0.0, got -1.0"),
    ("glmb_tracking", "ospa_p", 0.5, "ospa_p must be >= 1.0, got 0.5"),
    ("tempering_herding", "ospa_p", 0.5, "ospa_p must be >= 1.0, got 0.5"),
    ("tempering_herding", "ospa_c", float("inf"), "ospa_c must be a finite real number, got inf"),
    ("tracking_var", "ospa_c", 0.0, "ospa_c must be > 0.0, got 0.0"),
    ("glmb_tracking", "filter_truncations", [],
     r"filter_truncations must name at least one \(filter, truncation\) pair"),
])
def test_ospa_settings_messages(study, name, value, message):
    with pytest.raises(ReproduceError, match=rf"^config for '{study}': {message}$"):
        config_from_dict(Config.quick(), {study: {name: value}})


def test_reproduce_checks_every_studys_settings_before_any_runs(tmp_path):
    from rankedassign.experiments import reproduce
    from rankedassign.experiments.runner import check_settings

    cfg = Config.quick()
    check_settings(cfg)  # the defaults pass
    # a record changed after its checks (object.__setattr__ bypasses the frozen dataclass)
    object.__setattr__(cfg.tempering_herding, "ospa_p", 0.5)
    with pytest.raises(ReproduceError, match=r"^settings of study 'tempering_herding': ospa_p "
                                             r"must be >= 1.0, got 0.5$"):
        reproduce(["table1"], out=tmp_path / "r", config=cfg, workers=1, progress=False)
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(ReproduceError, match=r"^config must be a Config, got TrackingConfig$"):
        reproduce(["tracking"], out=tmp_path / "r", config=TrackingConfig(), progress=False)


@pytest.mark.parametrize(("study", "name", "message"), [
    ("sweep", "obs_grid", r"obs_grid entry must be a positive integer <= 2\*\*62, got "),
    ("sweep", "chain_lengths",
     r"chain_lengths entry must be a positive integer <= 2\*\*62, got "),
    ("tempering_herding", "budgets", "budgets must be a non-empty, strictly increasing tuple of "
                                     r"positive integers \(at most 2\*\*62\), got \("),
])
def test_count_lists_are_bounded_like_the_counts(study, name, message):
    # an entry past the kernels' int64 counters was accepted and failed when the study ran
    with pytest.raises(ReproduceError, match=rf"^config for '{study}': {message}"
                                             rf"{2**70}"):
        config_from_dict(Config.quick(), {study: {name: [2**70]}})
    assert getattr(config_from_dict(Config.quick(), {study: {name: [2**62]}})[study],
                   name) == (2**62,)


def _string_fields():
    """``(study, field)`` of every string setting of every registered study."""
    from rankedassign.experiments import get_study, study_names

    return [(name, f.name) for name in study_names()
            for f in dataclasses.fields(get_study(name).config_type)
            if (f.type if isinstance(f.type, str) else f.type.__name__) in ("str", "str | None")]


STRINGS = _string_fields()


@pytest.mark.parametrize(("study", "name"), STRINGS, ids=[f"{s}.{f}" for s, f in STRINGS])
def test_every_string_setting_of_every_study_is_checked(study, name):
    # issue found on re-probing: sweep accepted any pbar_d and granularity
    assert ("sweep", "pbar_d") in STRINGS and ("sweep", "granularity") in STRINGS
    for value in ("", "nosuch", 5, True, ["x"]):
        with pytest.raises(ReproduceError, match=rf"^config for '{study}': .*{name}"):
            config_from_dict(Config.quick(), {study: {name: value}})


@pytest.mark.parametrize("value", ["map", "hysteresis", "trajectory", None])
def test_removed_glmb_extraction_is_a_deprecated_alias_that_is_ignored(value):
    # glmb_tracking's glmb_extraction was removed (every filter now extracts by MAP, each
    # filter's other estimator scored beside it); an old --config naming it still loads
    base = Config.quick()
    with pytest.warns(DeprecationWarning,
                      match=r"config for 'glmb_tracking': 'glmb_extraction' is deprecated and "
                            r"ignored; every filter of the study extracts by MAP"):
        c = config_from_dict(base, {"glmb_tracking": {"glmb_extraction": value, "n_mc": 3}})
    assert c.glmb_tracking == dataclasses.replace(base.glmb_tracking, n_mc=3)
    assert "glmb_extraction" not in {f.name for f in dataclasses.fields(c.glmb_tracking)}


@pytest.mark.parametrize(("study", "name", "old", "new"), [
    ("multisensor_tracking", "associations", ["long", "short-mm"],
     (("original", "exact"), ("short-chain", "mm"))),
    ("multisensor_tracking", "glmb_adaptive_associations", ["short-mm-fixed"],
     (("short-chain", "mm-fixed"),)),
    ("glmb_tracking", "filter_truncations", ["lmb-long", "glmb-murty-matched"],
     (("lmb", "original"), ("glmb", "murty-matched"))),
    ("glmb_tracking", "tradeoff_truncations", ["glmb-short"], ("short-chain",)),
])
def test_a_config_file_with_the_old_method_strings_still_loads_deprecated(study, name, old, new):
    # the studies' old one-string spellings read as the vocabulary's pairs and names; a
    # --config file that writes the new ones (two-element lists) loads silently
    base = Config.quick()
    with pytest.warns(DeprecationWarning) as got:
        c = config_from_dict(base, {study: {name: old}})
    assert [str(w.message).split(";")[0] for w in got] == [
        f"{name}: {v!r} is deprecated" for v in old]
    assert getattr(c[study], name) == new
    pairs = [list(v) if isinstance(v, tuple) else v for v in new]
    assert getattr(config_from_dict(base, {study: {name: pairs}})[study], name) == new


#: The settings renamed so that ``method`` means only the multi-sensor row conditional:
#: ``(study, old name, new name, a value)``.
RENAMED = [
    ("tempering_herding", "methods", "truncations", [["herded", "keys=full"], "lbp"]),
    ("tempering_herding", "tracking_methods", "tracking_truncations", [["exact", ""]]),
    ("multisensor_tracking", "methods", "associations", [["short-chain", "mm"]]),
    ("multisensor_tracking", "adaptive_methods", "adaptive_associations", []),
    ("multisensor_tracking", "glmb_methods", "glmb_associations", [["original", "exact"]]),
    ("multisensor_tracking", "glmb_adaptive_methods", "glmb_adaptive_associations",
     [["short-chain", "exact"]]),
    ("glmb_tracking", "methods", "filter_truncations", [["lmb", "short-chain"]]),
    ("glmb_tracking", "tradeoff_methods", "tradeoff_truncations", ["original"]),
]


@pytest.mark.parametrize(("study", "old", "new", "value"), RENAMED,
                         ids=[f"{s}.{o}" for s, o, _, _ in RENAMED])
def test_a_renamed_setting_still_reads_by_its_old_name_deprecated(study, old, new, value):
    # a --config file (or a dict) written before the rename loads, with a warning naming the
    # new key, to the same settings as the new key gives
    from rankedassign.experiments import get_study

    base = Config.quick()
    want = config_from_dict(base, {study: {new: value, "n_mc": 1}})[study]
    with pytest.warns(DeprecationWarning,
                      match=rf"^config for '{study}': '{old}' is deprecated; write '{new}'$"):
        got = config_from_dict(base, {study: {old: value, "n_mc": 1}})[study]
    assert got == want
    with pytest.raises(ReproduceError, match=rf"^config for '{study}': give '{new}' alone, "
                                             rf"not also its deprecated name '{old}'$"):
        config_from_dict(base, {study: {old: value, new: value}})
    # the settings type: the old keyword and the old attribute, each with the same warning
    cls = get_study(study).config_type
    assert {old: new}.items() <= cls.RENAMED_SETTINGS.items()
    assert old not in {f.name for f in dataclasses.fields(cls)}
    pairs = tuple(tuple(v) if isinstance(v, list) else v for v in value)
    with pytest.warns(DeprecationWarning,
                      match=rf"^{cls.__name__}: '{old}' is deprecated; write '{new}'$"):
        made = cls(**{old: pairs})
    assert made == cls(**{new: pairs})
    with pytest.warns(DeprecationWarning,
                      match=rf"^{cls.__name__}: '{old}' is deprecated; write '{new}'$"):
        assert getattr(made, old) == getattr(made, new)
    with pytest.raises(TypeError, match=rf"^{cls.__name__}: give '{new}' alone, not also its "
                                        rf"deprecated name '{old}'$"):
        cls(**{old: pairs, new: pairs})
