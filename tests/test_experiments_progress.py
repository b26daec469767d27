"""The compile-wait line of ``reproduce`` (:mod:`rankedassign.experiments._progress`)."""

import io

from rankedassign.experiments import Config, get_study, study_names
from rankedassign.experiments._progress import compile_wait, warm_description


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_on_a_terminal_the_line_names_the_kernels_ticks_and_is_erased():
    out = _Terminal()
    with compile_wait("[3/12] tracking", "kernels of the LMB filter", stream=out,
                      interval=0.01):
        pass
    text = out.getvalue()
    # the thread writes its first update at once, whatever the block's length
    assert text.startswith("\r[3/12] tracking: compiling or loading kernels of the LMB filter |")
    assert " 0 s\x1b[K" in text
    assert text.endswith("\r\x1b[K")  # the runner's "kernels ready in" line comes next


def test_elsewhere_one_plain_line_and_nothing_when_quiet():
    out = io.StringIO()
    with compile_wait("[1/1] table1", "kernels of Table I", stream=out, interval=0.001):
        pass
    assert out.getvalue().count("\n") == 1 and "\r" not in out.getvalue()
    quiet = _Terminal()
    with compile_wait("[1/1] table1", "kernels of Table I", stream=quiet, enabled=False):
        pass
    assert quiet.getvalue() == ""


def test_every_study_says_what_its_warm_up_compiles():
    quick = Config.quick()
    for name in study_names():
        what = warm_description(get_study(name), quick[name])
        assert what.startswith(f"kernels of {get_study(name).title}"), name
    th = warm_description(get_study("tempering_herding"), quick["tempering_herding"])
    assert "single, multisensor, adaptive_birth" in th
