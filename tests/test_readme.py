"""The README's example and quickstart stay true."""

import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def _blocks(lang):
    return re.findall(rf"```{lang}\n(.*?)```", README.read_text(), flags=re.S)


def test_readme_python_examples_run(capsys):
    blocks = _blocks("python")
    assert blocks, "README has no python example"
    for code in blocks:
        exec(compile(code, str(README), "exec"), {})
    out = capsys.readouterr().out
    assert "(4, 24) 76848" in out
    assert "[1 2] 6.0" in out
    assert "(4, 2) True" in out  # the multi-sensor example


def test_readme_has_two_quickstart_commands_and_ci_runs_the_test_one():
    bash = [b.strip() for b in _blocks("bash")]
    assert len(bash) >= 2
    install_and_run, install_and_test = bash[0], bash[1]
    assert install_and_run.startswith("python -m pip install") and "rankedassign" in install_and_run
    assert "pytest" in install_and_test
    ci = (README.parent / ".ci" / "run").read_text()
    assert "<!-- test-command -->" in ci  # CI extracts and runs exactly this block
