"""The ``rankedassign`` command line: demo, reproduce, and its error handling."""

import json
import subprocess
import sys

import pytest

from rankedassign import __version__
from rankedassign.cli import main


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
    assert main([*argv, "--out", str(tmp_path / "r")]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "r").exists()


def test_reproduce_existing_out_needs_force(tmp_path, capsys):
    out = tmp_path / "report"
    out.mkdir()
    assert main(["reproduce", "table1", "--out", str(out), "--quiet"]) == 2
    assert f"output directory '{out}' exists; use --force to replace it" in capsys.readouterr().err


def test_reproduce_force_refuses_unrelated_directory(tmp_path, capsys):
    out = tmp_path / "home"
    out.mkdir()
    (out / "thesis.tex").write_text("precious")
    assert main(["reproduce", "table1", "--out", str(out), "--force", "--quiet"]) == 2
    assert "it is not empty and holds no manifest.json" in capsys.readouterr().err
    assert (out / "thesis.tex").read_text() == "precious"


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


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("{not json", "cannot read --config"),
        (json.dumps({"table1": {"nmc": 1}}), "unknown setting(s) ['nmc'] for study 'table1'"),
    ],
)
def test_reproduce_bad_config_file(tmp_path, capsys, content, message):
    cfg = tmp_path / "c.json"
    cfg.write_text(content)
    assert main(["reproduce", "--config", str(cfg), "--out", str(tmp_path / "r")]) == 2
    assert message in capsys.readouterr().err


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
}
PNGS = ["table1.png", "sweep.png", "tracking_ospa2.png", "tracking_observations.png",
        "tracking_var_ospa2.png", "tracking_var_observations.png", "optimum.png"]


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


def test_reproduce_writes_complete_report(tmp_path, tiny_config, capsys):
    import csv

    out = tmp_path / "report"
    assert main(["reproduce", "--config", str(tiny_config), "--out", str(out),
                 "--workers", "1", "--seed", "4"]) == 0
    err = capsys.readouterr().err
    assert "table1" in err and f"report written to {out / 'report.md'}" in err  # progress
    for study in ("table1", "sweep", "tracking", "tracking_var", "ablation", "optimum"):
        data = _strict_json(out / f"{study}.json")
        assert data, study
        assert isinstance(_strict_json(out / f"{study}_runs.json"), list)
        rows = list(csv.DictReader((out / f"{study}.csv").read_text().splitlines()))
        assert rows, study
    for png in PNGS:
        assert (out / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", png
    t1 = _strict_json(out / "table1.json")
    assert len(t1) == 9 and t1[0]["n_mc"] == 2 and t1[0]["family"] == "diagonal"
    tr = _strict_json(out / "tracking.json")
    assert {"obs_original", "obs_proposed", "reduction_pct", "row_updates_original",
            "row_updates_proposed", "reduction_row_updates_pct", "ospa2_mean_original",
            "ospa2_mean_proposed", "curves"} <= set(tr)
    ab = _strict_json(out / "ablation.json")
    assert len(ab) == 12 * 4 * 3 and {"stall", "stale", "delta_obs_pct"} <= set(ab[0])
    report = (out / "report.md").read_text()
    for title in ("## Table I", "## Sweep", "## Tracking — LMB", "## Tracking — the paper's",
                  "## Ablation", "## Optimum"):
        assert title in report
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


def test_interrupted_run_leaves_no_report(tmp_path, tiny_config, capsys, monkeypatch):
    from rankedassign.experiments import runner as rep

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setitem(rep._RUNNERS, "sweep", interrupted)
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
