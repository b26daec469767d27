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


def test_reproduce_unreachable_scheduler(tmp_path, capsys):
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
