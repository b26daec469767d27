"""The ``rankedassign`` command line: demo, reproduce, and its error handling."""

import dataclasses
import json
import os
import signal
import subprocess
import sys
import time

import pytest
from hypothesis import given
from hypothesis import strategies as st

from rankedassign import __version__
from rankedassign import cli as cli_module
from rankedassign.cli import main
from rankedassign.experiments import ReproduceError, study_names


def test_version(capsys):
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"rankedassign {__version__}"


def test_no_command_prints_help(capsys):
    assert main([]) == 0
    assert "reproduce" in capsys.readouterr().out


def test_demo(capsys):
    assert main(["demo", "--seed", "3"]) == 0
    out = capsys.readouterr().out
    assert "uniform" in out and "76,848" in out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["reproduce", "tabel1"], "unknown study 'tabel1'; choose from table1, sweep, tracking"),
        (["reproduce", "--mc", "0"], "argument --mc: must be a positive integer, got '0'"),
        (["reproduce", "--mc", "-3"], "argument --mc: must be a positive integer, got '-3'"),
        (["reproduce", "--workers", "two"], "argument --workers: must be a positive integer"),
        (["reproduce", "--seed", "-1"], "argument --seed: must be a non-negative integer"),
        (["reproduce", "--quick", "--full"], "not allowed with argument"),
    ],
)
def test_reproduce_bad_input_exit_2(argv, message, capsys, tmp_path):
    # every message is one line on stderr
    assert main([*argv, "--out", str(tmp_path / "r")]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "r").exists()


def test_reproduce_existing_out_needs_force(tmp_path, capsys):
    out = tmp_path / "report"
    out.mkdir()
    assert main(["reproduce", "table1", "--out", str(out), "--quiet"]) == 2
    assert f"output directory '{out}' exists; use --force to replace it" in capsys.readouterr().err


@pytest.mark.parametrize("force", [[], ["--force"]])
def test_reproduce_out_is_a_file(tmp_path, capsys, force):
    # --force cannot help with a file: the message says what is wrong instead
    out = tmp_path / "notes.txt"
    out.write_text("precious")
    assert main(["reproduce", "table1", "--out", str(out), "--quiet", *force]) == 2
    err = capsys.readouterr().err
    assert err == (f"rankedassign reproduce: error: output path '{out}' is a file, not a "
                   "directory; --force replaces only an earlier report directory: choose "
                   "another --out\n")
    assert out.read_text() == "precious"


def _never_run(monkeypatch):
    """Make every study fail loudly if it starts: the checks must come first."""

    def ran(*args, **kwargs):
        raise AssertionError("a study ran")

    for name in study_names():
        _replace_study(monkeypatch, name, task=ran)


def test_reproduce_out_under_a_file(tmp_path, capsys, monkeypatch):
    _never_run(monkeypatch)
    parent = tmp_path / "notes.txt"
    parent.write_text("x")
    for out in (parent / "sub", parent / "a" / "b"):
        assert main(["reproduce", "table1", "--out", str(out), "--quiet"]) == 2
        assert capsys.readouterr().err == (
            f"rankedassign reproduce: error: cannot write the report to '{out}': a parent, "
            f"'{parent}', is a file, not a directory\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="Linux /proc and /sys paths")
@pytest.mark.parametrize(("out", "reason"), [
    ("/proc/rankedassign-test/report", "No such file or directory"),  # cannot be created
    ("/sys/rankedassign-test/report", "Operation not permitted"),  # read-only, even for root
])
def test_reproduce_out_under_system_path(out, reason, capsys, monkeypatch):
    _never_run(monkeypatch)
    assert main(["reproduce", "table1", "--out", out, "--quiet"]) == 2
    assert capsys.readouterr().err == (
        f"rankedassign reproduce: error: cannot write the report to '{out}': {reason}\n")


@pytest.mark.skipif(os.geteuid() == 0, reason="root ignores directory permissions")
def test_reproduce_read_only_parent(tmp_path, capsys, monkeypatch):
    _never_run(monkeypatch)
    parent = tmp_path / "ro"
    parent.mkdir(mode=0o555)
    try:
        assert main(["reproduce", "table1", "--out", str(parent / "r"), "--quiet"]) == 2
        assert "cannot write the report to" in capsys.readouterr().err
        assert list(parent.iterdir()) == []
    finally:
        parent.chmod(0o755)


def _earlier_report(tmp_path, tiny_config):
    out = tmp_path / "report"
    assert main(["reproduce", "optimum", "--config", str(tiny_config), "--out", str(out),
                 "--workers", "1", "--quiet"]) == 0
    return out, {p.name: p.read_bytes() for p in out.iterdir()}


def test_force_checks_that_out_can_be_replaced_first(tmp_path, tiny_config, capsys,
                                                     monkeypatch):
    # a directory that cannot be moved away (a mount point): found before the studies run
    out, before = _earlier_report(tmp_path, tiny_config)
    real = os.path.ismount
    monkeypatch.setattr(os.path, "ismount", lambda p: os.fspath(p) == os.fspath(out) or real(p))
    _never_run(monkeypatch)
    assert main(["reproduce", "table1", "--config", str(tiny_config), "--out", str(out),
                 "--workers", "1", "--quiet", "--force"]) == 2
    assert capsys.readouterr().err == (
        f"rankedassign reproduce: error: cannot replace '{out}': it is a mount point and cannot "
        "be moved\n")
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert _no_leftovers(tmp_path)


def test_failed_final_move_keeps_the_finished_report(tmp_path, tiny_config, capsys,
                                                     monkeypatch):
    out, before = _earlier_report(tmp_path, tiny_config)
    from rankedassign.experiments import _outdir

    real = _outdir.renameat2

    def no_final_move(src, dst, flags):
        if ".partial-" in os.fspath(src) and os.fspath(dst) == os.fspath(out):
            raise OSError(28, "No space left on device")
        return real(src, dst, flags)

    monkeypatch.setattr(_outdir, "renameat2", no_final_move)
    assert main(["reproduce", "table1", "--config", str(tiny_config), "--out", str(out),
                 "--workers", "1", "--quiet", "--force"]) == 2
    err = capsys.readouterr().err
    kept = [p for p in tmp_path.iterdir() if p.name.startswith("report.new-")]
    assert len(kept) == 1 and (kept[0] / "manifest.json").exists()
    assert (kept[0] / "table1.json").exists()
    assert err == (f"rankedassign reproduce: error: could not move the finished report into "
                   f"'{out}' (No space left on device); the finished report is kept in '{kept[0]}'\n")
    # the earlier report is back in place; no hidden directory is left behind
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert _no_leftovers(tmp_path)


def test_workers_capped_at_the_cpus(tmp_path, capsys, monkeypatch):
    calls = []
    monkeypatch.setattr("rankedassign.cli.available_cpus", lambda: 2)
    monkeypatch.setattr("rankedassign.experiments.reproduce",
                        lambda *a, **kw: calls.append(kw))
    assert main(["reproduce", "--workers", "16", "--out", str(tmp_path / "r")]) == 0
    assert capsys.readouterr().err == (
        "rankedassign reproduce: note: --workers 16 is more than the 2 CPUs available; "
        "using 2\n")
    assert calls[-1]["workers"] == 2
    assert main(["reproduce", "--workers", "2", "--out", str(tmp_path / "r")]) == 0
    assert calls[-1]["workers"] == 2 and capsys.readouterr().err == ""


def test_reproduce_runs_the_papers_studies_unless_told_otherwise(tmp_path, capsys, monkeypatch):
    from rankedassign.experiments import default_study_names, runner

    paper = ("table1", "sweep", "tracking", "tracking_var", "ablation", "optimum",
             "random_readings")
    assert default_study_names() == paper
    assert runner._study_list(None) == list(paper) and runner._study_list([]) == list(paper)
    assert runner._study_list("paper") == list(paper)
    assert runner._study_list("all") == list(study_names())
    assert runner._study_list(["scaling", "table1"]) == ["table1", "scaling"]
    with pytest.raises(ReproduceError, match="studies must be 'paper', 'all' or a sequence of "
                                             "study names, got 'table1'"):
        runner._study_list("table1")
    calls = []
    monkeypatch.setattr("rankedassign.experiments.reproduce", lambda *a, **kw: calls.append(a))
    out = str(tmp_path / "r")
    assert main(["reproduce", "--out", out]) == 0 and calls[-1][0] == "paper"
    assert main(["reproduce", "--all", "--out", out]) == 0 and calls[-1][0] == "all"
    assert main(["reproduce", "scaling", "--out", out]) == 0 and calls[-1][0] == ["scaling"]
    capsys.readouterr()
    assert main(["reproduce", "--all", "scaling", "--out", out]) == 2
    assert capsys.readouterr().err == (
        "rankedassign reproduce: error: --all runs every study; name studies or give --all, "
        "not both\n")
    assert len(calls) == 3


def test_reproduce_without_studies_warns_that_its_default_changed(tmp_path, monkeypatch):
    from rankedassign import experiments

    _never_run(monkeypatch)
    # the warning comes first; the run then stops at the output check (out is a file)
    out = tmp_path / "a-file"
    out.write_text("x")
    with pytest.warns(FutureWarning, match="reproduce\\(\\) without studies now runs the "
                                           "paper's seven studies, no longer every study: "
                                           "pass studies='paper'"):
        with pytest.raises(ReproduceError):
            experiments.reproduce(out=out, progress=False)


def test_the_report_names_the_studies_it_left_out():
    from rankedassign.experiments import Config
    from rankedassign.experiments.report import render_report

    text = render_report({}, Config.quick(), {"version": "x"})
    line = next(s for s in text.splitlines() if s.startswith("Studies not in this run"))
    for name in study_names():
        assert f"`{name}`" in line
    assert "`rankedassign reproduce --all` runs every study" in line


@pytest.mark.e2e
def test_sigterm_is_handled_as_an_interrupt(tmp_path):
    # a run long enough to be inside a study when the signal arrives
    cfg = tmp_path / "long.json"
    cfg.write_text(json.dumps({"table1": {"n_mc": 400, "original_obs": 20_000}}))
    out = tmp_path / "r"
    err_path = tmp_path / "stderr.txt"
    with err_path.open("w") as err:
        proc = subprocess.Popen(
            [sys.executable, "-m", "rankedassign", "reproduce", "table1", "--config", str(cfg),
             "--out", str(out), "--workers", "2"],
            stderr=err, stdout=subprocess.DEVNULL, text=True,
        )
        try:
            deadline = time.monotonic() + 600
            # inside the study proper: its kernels are ready and its tasks run on the workers
            while "[1/1] table1: kernels ready" not in err_path.read_text():
                assert proc.poll() is None, err_path.read_text()
                assert time.monotonic() < deadline, "the study never started"
                time.sleep(0.2)
            proc.send_signal(signal.SIGTERM)
            code = proc.wait(timeout=300)
        finally:
            if proc.poll() is None:
                proc.kill()
    text = err_path.read_text()
    assert code == 128 + signal.SIGTERM, text
    assert "terminated (SIGTERM); no report written" in text
    assert "leaked semaphore" not in text and "Traceback" not in text
    assert sorted(p.name for p in tmp_path.iterdir()) == ["long.json", "stderr.txt"]


@pytest.mark.e2e
def test_a_second_sigterm_ends_a_run_with_workers_at_once(tmp_path):
    # the hard exit kills the workers and removes the lock and the partial report; the pool's
    # semaphores are unlinked first, so the resource tracker reports none as leaked
    cfg = tmp_path / "long.json"
    cfg.write_text(json.dumps({"table1": {"n_mc": 400, "original_obs": 20_000}}))
    out = tmp_path / "r"
    err_path = tmp_path / "stderr.txt"
    with err_path.open("w") as err:
        proc = subprocess.Popen(
            [sys.executable, "-m", "rankedassign", "reproduce", "table1", "--config", str(cfg),
             "--out", str(out), "--workers", "2"],
            stderr=err, stdout=subprocess.DEVNULL, text=True,
        )
        try:
            deadline = time.monotonic() + 600
            # inside the study proper: its kernels are ready and its tasks run on the workers
            while "[1/1] table1: kernels ready" not in err_path.read_text():
                assert proc.poll() is None, err_path.read_text()
                assert time.monotonic() < deadline, "the study never started"
                time.sleep(0.2)
            # Two signals that arrive before Python runs the handler count as one (Python
            # coalesces them), so SIGTERM is sent every 20 ms until the process ends: the first
            # one handled starts the cleanup (ending the workers takes longer than that), a
            # later one ends the process at once
            sent = 0
            while proc.poll() is None and sent < 500:
                proc.send_signal(signal.SIGTERM)
                sent += 1
                time.sleep(0.02)
            code = proc.wait(timeout=300)
        finally:
            if proc.poll() is None:
                proc.kill()
    time.sleep(1.0)  # the resource tracker (a separate process) has had its say
    text = err_path.read_text()
    assert code == 128 + signal.SIGTERM, text
    assert ("SIGTERM again: stopped at once; the lock and the partial report were removed, no "
            "report written\n") in text
    assert "leaked semaphore" not in text and "Traceback" not in text, text
    assert sorted(p.name for p in tmp_path.iterdir()) == ["long.json", "stderr.txt"]


TOKENS = ["reproduce", "demo", "table1", "sweep", "nosuch", "--full", "--quick", "--mc",
          "--seed", "--out", "--workers", "--dask-scheduler", "--config", "--force", "--quiet",
          "--help", "--version", "-h", "0", "1", "-1", "2", "x", "", "--", "=", "--mc=3",
          "/nonexistent/c.json"]


@given(st.lists(st.one_of(st.sampled_from(TOKENS), st.text(max_size=8)), max_size=6))
def test_fuzz_argument_handling(argv):
    # arbitrary argument lists: exit 0 or 2 with a message, never a traceback. The studies
    # themselves are replaced by a stub (the parsing and the checks are under test).
    import contextlib
    import io
    from unittest import mock

    calls = []
    out, err = io.StringIO(), io.StringIO()
    with mock.patch("rankedassign.experiments.reproduce", lambda *a, **kw: calls.append(kw)), \
            contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    assert code in (0, 2), (argv, code)
    if code == 2:
        assert err.getvalue().strip(), argv
    assert "Traceback" not in err.getvalue()


def test_reproduce_force_refuses_unrelated_directory(tmp_path, capsys):
    out = tmp_path / "home"
    out.mkdir()
    (out / "thesis.tex").write_text("precious")
    assert main(["reproduce", "table1", "--out", str(out), "--force", "--quiet"]) == 2
    assert "it is not empty and holds no manifest.json" in capsys.readouterr().err
    assert (out / "thesis.tex").read_text() == "precious"


@pytest.mark.e2e
def test_reproduce_unreachable_scheduler(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr("rankedassign.experiments._executor.DASK_CONNECT_TIMEOUT", 1.0)
    out = tmp_path / "r"
    code = main(["reproduce", "table1", "--out", str(out), "--quiet",
                 "--dask-scheduler", "tcp://127.0.0.1:9"])
    assert code == 2
    assert "could not connect to the Dask scheduler at 'tcp://127.0.0.1:9'" in (
        capsys.readouterr().err)
    assert not out.exists()
    assert list(tmp_path.iterdir()) == []


def test_reproduce_config_naming_a_removed_setting_warns_and_runs_without_it(tmp_path,
                                                                             monkeypatch):
    # the deprecated alias reaches the user who wrote the file, and the run goes on without it
    seen = {}

    def reproduce(studies, mode, out, *, config, **kwargs):
        seen["config"] = config

    monkeypatch.setattr(cli_module.experiments, "reproduce", reproduce)
    cfg = tmp_path / "c.json"
    cfg.write_text(json.dumps({"glmb_tracking": {"glmb_extraction": "map", "n_mc": 3}}))
    with pytest.warns(DeprecationWarning, match="'glmb_extraction' is deprecated and ignored"):
        code = main(["reproduce", "glmb_tracking", "--config", str(cfg), "--out",
                     str(tmp_path / "r"), "--quiet"])
    assert code == 0
    assert seen["config"].glmb_tracking.n_mc == 3


def test_reproduce_config_naming_a_renamed_setting_warns_and_reads_it(tmp_path, monkeypatch):
    # a --config file written before the studies' settings were renamed ("methods" holding
    # truncations) still runs the same settings, the warning naming the new key
    seen = {}

    def reproduce(studies, mode, out, *, config, **kwargs):
        seen["config"] = config

    monkeypatch.setattr(cli_module.experiments, "reproduce", reproduce)
    cfg = tmp_path / "c.json"
    cfg.write_text(json.dumps({"glmb_tracking": {"methods": [["lmb", "murty"]],
                                                 "tradeoff_methods": ["original"]}}))
    with pytest.warns(DeprecationWarning) as got:
        code = main(["reproduce", "glmb_tracking", "--config", str(cfg), "--out",
                     str(tmp_path / "r"), "--quiet"])
    assert code == 0
    assert [str(w.message) for w in got] == [
        "config for 'glmb_tracking': 'methods' is deprecated; write 'filter_truncations'",
        "config for 'glmb_tracking': 'tradeoff_methods' is deprecated; write "
        "'tradeoff_truncations'"]
    assert seen["config"].glmb_tracking.filter_truncations == (("lmb", "murty"),)
    assert seen["config"].glmb_tracking.tradeoff_truncations == ("original",)


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("{not json", "cannot read --config"),
        (json.dumps({"table1": {"nmc": 1}}), "unknown setting(s) ['nmc'] for study 'table1'"),
        # issue: a deeply nested file ended in a RecursionError traceback
        ("[" * 100_000, "config file '{cfg}' is nested too deeply (more than 16 levels); a "
                        'settings file is a JSON object of studies, e.g. {{"table1": {{"n_mc": 5}}}}'),
        ("{" + '"a": {' * 5_000 + "}" * 5_001, "config file '{cfg}' is nested too deeply"),
        ("[" * 17 + "]" * 17, "config file '{cfg}' is nested too deeply"),
        (json.dumps({"table1": {"families": [[[[[[[[[[[[[[[["x"]]]]]]]]]]]]]]]]}}),
         "config file '{cfg}' is nested too deeply"),
        # valid JSON of the wrong shape
        ("[]", "config file '{cfg}' must hold a JSON object of studies, e.g. "
               '{{"table1": {{"n_mc": 5}}}}, not an array'),
        ("5", "must hold a JSON object of studies, e.g. {{\"table1\": {{\"n_mc\": 5}}}}, not a number"),
        ("null", "not null"),
        ('"table1"', "not a string"),
        ("true", "not a boolean"),
        ('{"table1": 5}', "config for 'table1' must be a mapping of its settings (e.g. "
                          '{{"n_mc": 5}}), got int 5'),
        ('{"table1": [' + "1, " * 100 + "1]}",
         "config for 'table1' must be a mapping of its settings (e.g. {{\"n_mc\": 5}}), got "
         "list [1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1,...\n"),
        ('{"table1": {"n_mc": NaN}}', "config for 'table1': n_mc must be an int, got float nan"),
        ('{"glmb_tracking": {"ospa_c": -1}}',
         "config for 'glmb_tracking': ospa_c must be > 0.0, got -1.0"),
        ('{"tempering_herding": {"ospa_p": 0.5}}',
         "config for 'tempering_herding': ospa_p must be >= 1.0, got 0.5"),
        ('{"table1": {"n_mc": 1' + "0" * 5000 + "}}", "cannot read --config '{cfg}': Exceeds"),
        (b'{"t": "\xff"}', "cannot read --config '{cfg}': 'utf-8' codec can't decode"),
    ],
)
def test_reproduce_bad_config_file(tmp_path, capsys, monkeypatch, content, message):
    _never_run(monkeypatch)
    cfg = tmp_path / "c.json"
    if isinstance(content, bytes):
        cfg.write_bytes(content)
    else:
        cfg.write_text(content)
    assert main(["reproduce", "--config", str(cfg), "--out", str(tmp_path / "r")]) == 2
    err = capsys.readouterr().err
    assert message.format(cfg=cfg) in err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.json"]


def test_reproduce_config_file_that_is_not_a_file(tmp_path, capsys, monkeypatch):
    _never_run(monkeypatch)
    for path, message in ((tmp_path, "Is a directory"),
                          (tmp_path / "nosuch.json", "No such file or directory")):
        assert main(["reproduce", "--config", str(path), "--out", str(tmp_path / "r")]) == 2
        err = capsys.readouterr().err
        assert err.startswith(f"rankedassign reproduce: error: cannot read --config '{path}': ")
        assert message in err
    big = tmp_path / "big.json"
    with big.open("wb") as f:
        f.truncate((1 << 24) + 1)  # sparse: 16 MiB and one byte of zeros
    assert main(["reproduce", "--config", str(big), "--out", str(tmp_path / "r")]) == 2
    assert capsys.readouterr().err == (
        f"rankedassign reproduce: error: config file '{big}' is larger than 16 MiB; a settings "
        "file is a JSON object of a few studies' settings\n")


@pytest.mark.e2e
def test_console_entry_point_exit_code(tmp_path):
    # The real process: argparse errors and ours both end with status 2 and a stderr message.
    proc = subprocess.run(
        [sys.executable, "-m", "rankedassign", "reproduce", "nosuch", "--out",
         str(tmp_path / "r")],
        capture_output=True, text=True, timeout=120,
    )
    assert proc.returncode == 2
    assert "unknown study 'nosuch'" in proc.stderr


TINY_CONFIG = {
    "table1": {"n_mc": 2, "original_obs": 1_000, "n_chains": 40},
    "sweep": {"n_mc": 2, "obs_grid": [10, 100, 1_000], "chain_lengths": [5, 25]},
    "tracking": {"n_mc": 1, "n_scans": 6, "original_obs": 100, "n_chains": 10},
    "tracking_var": {"n_mc": 1, "n_scans": 6, "original_obs": 100, "n_chains": 10},
    "ablation": {"n_mc": 1, "original_obs": 1_000, "n_chains": 40},
    "optimum": {"n_mc": 2, "original_obs": 1_000, "n_chains": 40},
    "random_readings": {"n_mc": 2, "original_obs": 1_000, "n_chains": 40},
    "multisensor": {"n_mc": 2, "cases": ["A/diagonal"], "methods": ["exact", "mm"],
                    "original_obs": 200, "n_chains": 8},
    "adaptive_birth": {"n_mc": 2, "sensors": [2], "original_obs": 60, "n_chains": 6,
                       "chain_length": 10, "curve_obs": [20, 60]},
    "glmb_tracking": {"n_mc": 1, "n_scans": 4,
                      "filter_truncations": [["lmb", "short-chain"], ["glmb", "short-chain"],
                                             ["glmb", "murty"]],
                      "murty_runs": 1, "h_upd": 50, "h_max": 20, "n_chains": 10, "murty_k": 10},
    "multisensor_tracking": {"n_mc": 1, "n_scans": 3, "sensor_sets": [[0], [0, 1]],
                             "associations": [["original", "exact"], ["short-chain", "exact"]],
                             "long_obs": 30, "n_chains": 10,
                             "chain_length": 4},
    "nonlinear_tracking": {"n_mc": 1, "n_scans": 3, "lmb_budget": 20, "glmb_budget": 20,
                           "chain_length": 5},
    "scaling": {"n_mc": 1, "sizes": [5, 20], "n_scans": 2, "n_chains": 10, "mass_max_n": 5},
    "tempering_herding": {"n_mc": 1, "families": ["random", "ms:A/random_coupled"],
                          "budgets": [20, 100], "tracking_mc": 1, "presets": ["vo"],
                          "n_scans": 3, "tracking_obs": 20, "tracking_chains": 2},
}
PNGS = ["table1.png", "sweep.png", "tracking_ospa2.png", "tracking_observations.png",
        "tracking_var_ospa2.png", "tracking_var_observations.png", "optimum.png",
        "multisensor.png", "adaptive_birth.png", "multisensor_tracking.png", "glmb_tracking.png",
        "glmb_tradeoff.png", "nonlinear_tracking.png", "scaling.png",
        "tempering_herding_obs.png", "tempering_herding_time.png",
        "tempering_herding_marginals.png"]


def _strict_json(path):
    def no_nan(name):
        raise ValueError(f"{path.name} contains {name}")

    return json.loads(path.read_text(), parse_constant=no_nan)


@pytest.fixture
def tiny_config(tmp_path):
    path = tmp_path / "tiny.json"
    path.write_text(json.dumps(TINY_CONFIG))
    return path


def _no_leftovers(parent):
    return [p.name for p in parent.iterdir() if p.name.startswith(".")] == []


@pytest.mark.e2e
def test_several_studies_on_two_workers_warm_up_together_and_match_one_worker(
        tmp_path, tiny_config, capsys):
    # two workers prepare the kernels of every study of the run at once (the later studies'
    # tiny tasks wait for table1's first one instead of compiling its samplers beside it);
    # the numbers do not depend on it
    runs = {}
    for workers in ("1", "2"):
        out = tmp_path / f"w{workers}"
        assert main(["reproduce", "table1", "sweep", "optimum", "--config", str(tiny_config),
                     "--out", str(out), "--workers", workers, "--seed", "3"]) == 0
        err = capsys.readouterr().err
        assert ("all studies: kernels ready in" in err) == (workers == "2"), err
        assert "[1/3] table1: kernels ready" in err and "[3/3] optimum: kernels ready" in err
        # on two workers the studies' tiny tasks ran together, once, before the first study
        assert ("[1/3] table1: kernels ready (prepared with the other studies)" in err) == (
            workers == "2"), err
        runs[workers] = {s: _strict_json(out / f"{s}_runs.json")
                         for s in ("table1", "sweep", "optimum")}
    assert runs["1"] == runs["2"]


@pytest.mark.e2e
def test_reproduce_writes_complete_report(tmp_path, tiny_config, capsys):
    import csv

    out = tmp_path / "report"
    assert main(["reproduce", "--all", "--config", str(tiny_config), "--out", str(out),
                 "--workers", "1", "--seed", "4"]) == 0
    err = capsys.readouterr().err
    assert "[1/14] table1" in err and "[14/14] tempering_herding" in err  # study i of n
    assert "preparing each study's compiled kernels" in err
    assert "[1/14] table1: kernels ready in" in err
    assert f"report written to {out / 'report.md'}" in err
    for study in ("table1", "sweep", "tracking", "tracking_var", "ablation", "optimum",
                  "random_readings", "glmb_tracking", "multisensor", "adaptive_birth",
                  "multisensor_tracking", "nonlinear_tracking", "scaling", "tempering_herding"):
        data = _strict_json(out / f"{study}.json")
        assert data, study
        assert isinstance(_strict_json(out / f"{study}_runs.json"), list)
        rows = list(csv.DictReader((out / f"{study}.csv").read_text().splitlines()))
        assert rows, study
    for png in PNGS:
        assert (out / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", png
    t1 = _strict_json(out / "table1.json")
    assert len(t1) == 12 and t1[0]["n_mc"] == 2 and t1[0]["family"] == "diagonal"
    tr = _strict_json(out / "tracking.json")
    assert {"obs_original", "obs_proposed", "reduction_pct", "row_updates_original",
            "row_updates_proposed", "reduction_row_updates_pct", "ospa2_mean_original",
            "ospa2_mean_proposed", "curves"} <= set(tr)
    ab = _strict_json(out / "ablation.json")
    assert len(ab) == 12 * 4 * 3 and {"stall", "stale", "delta_obs_pct"} <= set(ab[0])
    report = (out / "report.md").read_text()
    for title in ("## Table I", "## Sweep", "## Tracking — LMB", "## Tracking (variance",
                  "## Ablation", "## Optimum", "## Readings of the random family",
                  "## Multi-sensor Table I", "## Adaptive birth",
                  "## Tempering, herding and belief propagation"):
        assert title in report
    assert "algorithms.md" not in report and "docs/specification.md" in report
    assert "Studies not in this run" not in report
    assert "1 Monte Carlo runs" not in report and "Grouping: False" not in report
    assert "1 Monte Carlo run" in report and "one sampler call per scan" in report
    assert t1[0]["paper_delta_obs_pct"] == 79.95 and t1[0]["paper_delta_error_pp"] == 0.04
    for png in PNGS:
        assert f"({png})" in report
    manifest = _strict_json(out / "manifest.json")
    assert manifest["seed"] == 4 and manifest["studies"][0] == "table1"
    assert "--seed 4" in manifest["command"]
    assert _strict_json(out / "config.json")["table1"]["n_chains"] == 40
    assert _no_leftovers(tmp_path)

    # --force replaces the earlier report as a whole.
    assert main(["reproduce", "table1", "--config", str(tiny_config), "--out", str(out),
                 "--workers", "1", "--quiet", "--force"]) == 0
    assert capsys.readouterr().err == ""
    assert (out / "table1.json").exists() and not (out / "sweep.json").exists()
    assert "## Sweep" not in (out / "report.md").read_text()
    assert _no_leftovers(tmp_path)


def _replace_study(monkeypatch, name, **changes):
    from rankedassign.experiments import get_study, registry

    monkeypatch.setitem(registry._REGISTRY, name,
                        dataclasses.replace(get_study(name), **changes))


def test_interrupted_run_leaves_no_report(tmp_path, tiny_config, capsys, monkeypatch):
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    _replace_study(monkeypatch, "sweep", task=interrupted)
    out = tmp_path / "report"
    code = main(["reproduce", "table1", "sweep", "--config", str(tiny_config), "--out",
                 str(out), "--workers", "1", "--quiet"])
    assert code == 130
    assert "interrupted; no report written" in capsys.readouterr().err
    assert not out.exists()
    assert list(tmp_path.iterdir()) == [tiny_config]


def test_failed_run_keeps_earlier_report(tmp_path, tiny_config, monkeypatch):
    from rankedassign.experiments import runner as rep

    out = tmp_path / "report"
    assert main(["reproduce", "optimum", "--config", str(tiny_config), "--out", str(out),
                 "--workers", "1", "--quiet"]) == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}

    def broken(*args, **kwargs):
        raise RuntimeError("plotting failed")

    monkeypatch.setattr(rep, "render_report", broken)
    with pytest.raises(RuntimeError, match="plotting failed"):
        main(["reproduce", "table1", "--config", str(tiny_config), "--out", str(out),
              "--workers", "1", "--quiet", "--force"])
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert _no_leftovers(tmp_path)


def test_report_directory_has_usual_permissions(tmp_path, tiny_config):
    import os
    import stat

    out = tmp_path / "report"
    assert main(["reproduce", "optimum", "--config", str(tiny_config), "--out", str(out),
                 "--workers", "1", "--quiet"]) == 0
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(out.stat().st_mode) == 0o777 & ~umask


# --------------------------------------------------------------------------- data loss
def _tree(root):
    """``{relative path: bytes}`` of every file below ``root``."""
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*"))
            if p.is_file()}


def test_force_refuses_a_foreign_manifest(tmp_path, capsys, monkeypatch):
    # issue: --force deleted any folder holding a file *named* manifest.json
    w = tmp_path / "w"
    (w / "src").mkdir(parents=True)
    (w / "manifest.json").write_text('{"name": "my-pwa"}')
    (w / "src" / "app.js").write_text("x")
    before = _tree(w)
    _never_run(monkeypatch)
    assert main(["reproduce", "table1", "--out", str(w), "--force", "--quiet"]) == 2
    assert capsys.readouterr().err == (
        f"rankedassign reproduce: error: refusing to replace '{w}': its manifest.json is not "
        "the manifest of a rankedassign report\n")
    assert _tree(w) == before and _no_leftovers(tmp_path)


@pytest.mark.parametrize(("extra", "message"), [
    ("notes.txt", "it holds 'notes.txt', which is not part of the report its manifest.json "
                  "lists"),
    ("sub/", "it holds 'sub', which is not part of the report its manifest.json lists"),
    ("table1.json/", "'table1.json' in it is not a regular file"),
])
def test_force_refuses_a_report_with_anything_else_in_it(tmp_path, tiny_config, capsys,
                                                          monkeypatch, extra, message):
    out = tmp_path / "report"
    assert main(["reproduce", "table1", "--config", str(tiny_config), "--out", str(out),
                 "--workers", "1", "--quiet"]) == 0
    name = extra.rstrip("/")
    if name == "table1.json":
        (out / name).unlink()
    if extra.endswith("/"):
        (out / name).mkdir()
        (out / name / "keep.txt").write_text("mine")
    else:
        (out / name).write_text("mine")
    before = _tree(out)
    _never_run(monkeypatch)
    assert main(["reproduce", "table1", "--config", str(tiny_config), "--out", str(out),
                 "--workers", "1", "--quiet", "--force"]) == 2
    assert capsys.readouterr().err == (
        f"rankedassign reproduce: error: refusing to replace '{out}': {message}\n")
    assert _tree(out) == before


def test_force_replaces_an_earlier_report_and_a_legacy_one(tmp_path, tiny_config):
    out = tmp_path / "report"
    assert main(["reproduce", "optimum", "--config", str(tiny_config), "--out", str(out),
                 "--workers", "1", "--quiet"]) == 0
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["schema"] == "rankedassign-report/1"
    assert manifest["files"] == sorted(p.name for p in out.iterdir())
    # a report written before the manifest had a schema: the old key set, its files only
    legacy = {k: v for k, v in manifest.items() if k not in ("schema", "files")}
    (out / "manifest.json").write_text(json.dumps(legacy))
    assert main(["reproduce", "table1", "--config", str(tiny_config), "--out", str(out),
                 "--workers", "1", "--quiet", "--force"]) == 0
    assert json.loads((out / "manifest.json").read_text())["studies"] == ["table1"]
    assert not (out / "optimum.json").exists() and _no_leftovers(tmp_path)


def _study_that(monkeypatch, name, action):
    """Replace ``name``'s task by one that runs ``action()`` once, then the real task."""
    from rankedassign.experiments import get_study

    real = get_study(name).task
    done = []

    def task(*args):
        if not done:
            done.append(action())
        return real(*args)

    _replace_study(monkeypatch, name, task=task)


def test_a_folder_that_appears_during_the_run_is_left_alone(tmp_path, tiny_config, capsys,
                                                            monkeypatch):
    # issue: a folder made at --out while the run worked was deleted at the end (no --force)
    out = tmp_path / "r3"

    def appear():
        out.mkdir()
        (out / "t.tex").write_text("x")

    _study_that(monkeypatch, "table1", appear)
    assert main(["reproduce", "table1", "--config", str(tiny_config), "--out", str(out),
                 "--workers", "1", "--quiet"]) == 2
    kept = [p for p in tmp_path.iterdir() if p.name.startswith("r3.new-")]
    assert len(kept) == 1 and (kept[0] / "table1.json").exists()
    assert not (kept[0] / ".run").exists()
    assert capsys.readouterr().err == (
        f"rankedassign reproduce: error: '{out}' appeared while the run worked and was left as "
        f"it is; the finished report is kept in '{kept[0]}'\n")
    assert _tree(out) == {"t.tex": b"x"} and _no_leftovers(tmp_path)


def test_an_earlier_report_changed_during_the_run_is_left_alone(tmp_path, tiny_config, capsys,
                                                                monkeypatch):
    out, _ = _earlier_report(tmp_path, tiny_config)
    _study_that(monkeypatch, "table1", lambda: (out / "t.tex").write_text("x"))
    assert main(["reproduce", "table1", "--config", str(tiny_config), "--out", str(out),
                 "--workers", "1", "--quiet", "--force"]) == 2
    kept = [p for p in tmp_path.iterdir() if p.name.startswith("report.new-")]
    assert len(kept) == 1
    assert capsys.readouterr().err.endswith(
        f"'{out}' changed while the run worked and was left as it is; the finished report is "
        f"kept in '{kept[0]}'\n")
    assert (out / "t.tex").read_text() == "x" and (out / "optimum.json").exists()


def test_a_second_run_into_the_same_out_is_refused(tmp_path, tiny_config, capsys, monkeypatch):
    from rankedassign.experiments import _outdir

    out = tmp_path / "report"
    _never_run(monkeypatch)
    with _outdir.run_lock(out, "rankedassign reproduce --out report"):
        assert main(["reproduce", "table1", "--config", str(tiny_config), "--out", str(out),
                     "--workers", "1", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"rankedassign reproduce: error: another run is writing the report to "
                          f"'{out}' (pid {os.getpid()} on ")
    assert err.endswith(": rankedassign reproduce --out report); wait for it to finish or choose "
                        "another --out\n")
    assert not out.exists() and _no_leftovers(tmp_path)  # the lock file goes with its run


def test_stale_partial_reports_are_removed_under_the_lock(tmp_path, tiny_config, capsys):
    # a run killed by SIGKILL leaves its partial report; the next run into the same out removes
    # it (its lock proves that no run writes there) and says so. Foreign look-alikes stay.
    dead = tmp_path / ".report.partial-abc123"
    dead.mkdir()
    (dead / ".run").write_text(json.dumps({"pid": 4242, "host": "h", "command": "c"}))
    (dead / "table1.json").write_text("{}")
    foreign = tmp_path / ".report.partial-mine"
    foreign.mkdir()
    (foreign / "keep.txt").write_text("mine")
    other = tmp_path / ".other.partial-xyz"
    other.mkdir()
    (other / ".run").write_text("{}")
    out = tmp_path / "report"
    assert main(["reproduce", "optimum", "--config", str(tiny_config), "--out", str(out),
                 "--workers", "1", "--quiet"]) == 0
    assert capsys.readouterr().err == (
        f"rankedassign reproduce: note: removed '{dead}', the partial report of an earlier run "
        "into the same --out that was killed (pid 4242)\n")
    assert not dead.exists() and (foreign / "keep.txt").exists() and (other / ".run").exists()


def test_a_failed_study_keeps_the_finished_studies(tmp_path, tiny_config, capsys, monkeypatch):
    def broken(*args, **kwargs):
        raise RuntimeError("out of luck")

    _replace_study(monkeypatch, "optimum", task=broken)
    out = tmp_path / "report"
    assert main(["reproduce", "table1", "optimum", "--config", str(tiny_config), "--out",
                 str(out), "--workers", "1", "--quiet"]) == 1
    assert capsys.readouterr().err == (
        "rankedassign reproduce: error: study 'optimum' failed (RuntimeError: out of luck); the "
        f"report of the studies that finished before it (table1) was written to '{out}'\n")
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["studies"] == ["table1"]
    assert manifest["failed"] == {"study": "optimum", "error": "RuntimeError: out of luck",
                                  "not_run": []}
    # beside an earlier report, never over it
    before = _tree(out)
    assert main(["reproduce", "table1", "optimum", "--config", str(tiny_config), "--out",
                 str(out), "--workers", "1", "--quiet", "--force"]) == 1
    kept = [p for p in tmp_path.iterdir() if p.name.startswith("report.incomplete-")]
    assert len(kept) == 1 and (kept[0] / "table1.json").exists()
    assert capsys.readouterr().err.endswith(f"was written to '{kept[0]}'\n")
    assert _tree(out) == before and _no_leftovers(tmp_path)
    # the first study failing: nothing to keep, nothing written
    assert main(["reproduce", "optimum", "--config", str(tiny_config), "--out",
                 str(tmp_path / "r2"), "--workers", "1", "--quiet"]) == 1
    assert "no study finished, nothing was written" in capsys.readouterr().err
    assert not (tmp_path / "r2").exists() and _no_leftovers(tmp_path)


# --------------------------------------------------------------------------- the lock's place
def _lock_refusal(out, what):
    lock = out.parent / f".{out.name}.lock"
    return (f"rankedassign reproduce: error: cannot write the report to '{out}': '{lock}', "
            f"where its lock goes, {what}, not a lock of rankedassign reproduce; it was left as "
            "it is: move it away or choose another --out\n")


def _make_at_lock(kind, lock, target):
    """Put a user's ``kind`` of thing at the lock's place; returns what must stay unchanged."""
    if kind == "file":
        lock.write_text("notes\n")
    elif kind == "empty file":
        lock.write_text("")
    elif kind == "foreign json":
        lock.write_text(json.dumps({"pid": 1, "note": "mine"}))
    elif kind == "big file":
        lock.write_bytes(b"{" + b" " * (1 << 17) + b"}")
    elif kind == "symlink to a file":
        target.write_text("precious")
        lock.symlink_to(target)
    elif kind == "symlink to our lock record":
        target.write_text(json.dumps({"pid": 4242, "host": "h", "command": "c",
                                      "started": "s"}))
        lock.symlink_to(target)
    elif kind == "dangling symlink":
        lock.symlink_to(target)
    elif kind == "directory":
        lock.mkdir()
        (lock / "keep.txt").write_text("mine")
    elif kind == "fifo":
        os.mkfifo(lock)
    return {"lock": (os.lstat(lock).st_ino, os.path.islink(lock) and os.readlink(lock)),
            "target": target.read_bytes() if target.exists() else None,
            "tree": _tree(lock.parent)}


@pytest.mark.parametrize(("kind", "what"), [
    ("file", "is a file that is not a lock record"),
    ("empty file", "is a file that is not a lock record"),
    ("foreign json", "is a file that is not a lock record"),
    ("big file", "is a file that is not a lock record"),
    ("symlink to a file", "is a symbolic link"),
    ("symlink to our lock record", "is a symbolic link"),
    ("dangling symlink", "is a symbolic link"),
    ("directory", "is a directory"),
    ("fifo", "is not a regular file"),
])
def test_a_users_thing_at_the_locks_place_is_refused_and_left_alone(tmp_path, capsys,
                                                                     monkeypatch, kind, what):
    # issue: a file at .<out>.lock was truncated, overwritten with the lock's record and
    # deleted at the end (exit 0); a symbolic link there was written through
    _never_run(monkeypatch)
    home = tmp_path / "home"
    home.mkdir()
    out, lock, target = home / "r", home / ".r.lock", tmp_path / "target.txt"
    before = _make_at_lock(kind, lock, target)
    assert main(["reproduce", "table1", "--out", str(out), "--quiet"]) == 2
    assert capsys.readouterr().err == _lock_refusal(out, what)
    after = {"lock": (os.lstat(lock).st_ino, os.path.islink(lock) and os.readlink(lock)),
             "target": target.read_bytes() if target.exists() else None,
             "tree": _tree(lock.parent)}
    assert after == before
    assert sorted(p.name for p in home.iterdir()) == [".r.lock"]  # no report, no partial


def test_a_stale_lock_of_a_killed_run_is_replaced(tmp_path, tiny_config, capsys):
    from rankedassign.experiments import _outdir

    out = tmp_path / "report"
    lock = _outdir.lock_path(out)
    # the record of a run killed by SIGKILL (no process holds its flock): this version's and
    # the one written before the record had a schema
    for record in ({"schema": "rankedassign-lock/1", "pid": 4242, "host": "h", "command": "c",
                    "started": "s", "token": "t"},
                   {"pid": 4243, "host": "h", "command": "c", "started": "s"}):
        lock.write_text(json.dumps(record))
        assert main(["reproduce", "optimum", "--config", str(tiny_config), "--out", str(out),
                     "--workers", "1", "--quiet", "--force"]) == 0
        assert capsys.readouterr().err == (
            f"rankedassign reproduce: note: removed '{lock}', the lock of an earlier run into "
            f"the same --out that was killed (pid {record['pid']})\n")
        assert (out / "optimum.json").exists() and _no_leftovers(tmp_path)


def test_a_live_lock_with_a_record_being_written_is_a_live_run(tmp_path, capsys, monkeypatch):
    import fcntl

    from rankedassign.experiments import _outdir

    _never_run(monkeypatch)
    out = tmp_path / "report"
    lock = _outdir.lock_path(out)
    lock.write_text("")  # created, flocked, record not yet written
    with lock.open() as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        assert main(["reproduce", "table1", "--out", str(out), "--quiet"]) == 2
    assert capsys.readouterr().err == (
        f"rankedassign reproduce: error: another run is writing the report to '{out}' (a run "
        "whose details cannot be read); wait for it to finish or choose another --out\n")
    assert lock.read_text() == ""


@pytest.mark.parametrize("swap", ["file", "symlink"])
def test_a_lock_replaced_during_the_run_is_not_removed(tmp_path, swap):
    # the lock is removed at the end only if the file at its place is the one the run made
    from rankedassign.experiments import _outdir

    out = tmp_path / "report"
    target = tmp_path / "target.txt"
    target.write_text("precious")
    with _outdir.run_lock(out, "c") as held:
        record = json.loads(held.path.read_text())
        assert record["schema"] == "rankedassign-lock/1" and record["pid"] == os.getpid()
        assert len(record["token"]) == 32
        held.path.unlink()
        if swap == "file":
            held.path.write_text("mine")
        else:
            held.path.symlink_to(target)
    if swap == "file":
        assert held.path.read_text() == "mine"
    else:
        assert os.readlink(held.path) == str(target)
    assert target.read_text() == "precious"
    held.release()  # idempotent
    assert os.path.lexists(held.path)


def test_a_stale_lock_that_cannot_be_removed_is_refused(tmp_path, capsys, monkeypatch):
    from rankedassign.experiments import _outdir

    _never_run(monkeypatch)
    out = tmp_path / "report"
    lock = _outdir.lock_path(out)
    lock.write_text(json.dumps({"pid": 4242, "host": "h", "command": "c", "started": "s"}))
    real = os.unlink

    def unlink(path, *args, **kwargs):  # another user's file in a sticky directory
        if os.fspath(path) == os.fspath(lock):
            raise PermissionError(1, "Operation not permitted")
        return real(path, *args, **kwargs)

    monkeypatch.setattr(_outdir.os, "unlink", unlink)
    assert main(["reproduce", "table1", "--out", str(out), "--quiet"]) == 2
    assert capsys.readouterr().err == (
        f"rankedassign reproduce: error: cannot write the report to '{out}': its lock '{lock}' "
        "was left by a run that was killed (pid 4242), and it cannot be removed (Operation not "
        "permitted); remove it or choose another --out\n")
    assert lock.exists()


def test_a_file_system_without_flock_leaves_no_lock_file(tmp_path, capsys, monkeypatch):
    import errno

    from rankedassign.experiments import _outdir

    _never_run(monkeypatch)

    def no_locks(fd, op):
        raise OSError(errno.ENOLCK, "No locks available")

    monkeypatch.setattr(_outdir.fcntl, "flock", no_locks)
    out = tmp_path / "report"
    assert main(["reproduce", "table1", "--out", str(out), "--quiet"]) == 2
    assert capsys.readouterr().err == (
        f"rankedassign reproduce: error: cannot write the report to '{out}': cannot create its "
        f"lock file '{_outdir.lock_path(out)}' (No locks available)\n")
    assert list(tmp_path.iterdir()) == []


def test_a_signal_while_the_report_is_moved_into_place(tmp_path, tiny_config, capsys,
                                                       monkeypatch):
    # the move is not cut short; the run says the report is complete and exits as signalled
    import signal as sig

    from rankedassign.experiments import _outdir

    real = _outdir.renameat2
    out = tmp_path / "report"

    def renameat2(src, dst, flags):  # called by _outdir.place for the final move
        if os.fspath(dst) == os.fspath(out):
            sig.raise_signal(sig.SIGTERM)
        return real(src, dst, flags)

    monkeypatch.setattr(_outdir, "renameat2", renameat2)
    assert main(["reproduce", "table1", "--config", str(tiny_config), "--out", str(out),
                 "--workers", "1", "--quiet"]) == 128 + sig.SIGTERM
    assert capsys.readouterr().err == (
        f"rankedassign reproduce: SIGTERM received as the run was finishing; the report is "
        f"complete in '{out}'\n")
    assert (out / "manifest.json").exists() and _no_leftovers(tmp_path)
