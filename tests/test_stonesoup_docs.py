"""The example of ``docs/stonesoup.md`` runs, and says what it measures.

The page's ``python`` blocks (marked ``skip-test`` for ``tests/test_docs.py``, which would run
them at full length) run here in page order, in one namespace: on 12 scans in the default
suite (a few seconds), and on the page's 60 scans in the slow tier, where the numbers of the
page's table are checked.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("stonesoup")

PAGE = Path(__file__).resolve().parents[1] / "docs" / "stonesoup.md"
STEPS = "n_steps = 60"


def _code() -> str:
    text = PAGE.read_text()
    return "\n".join(re.findall(r"^```python\n(.*?)^```$", text, flags=re.S | re.M))


def _run(tmp_path, monkeypatch, n_steps: int) -> dict:
    import matplotlib

    matplotlib.use("Agg")
    code = _code()
    assert STEPS in code, f"the page's example no longer sets {STEPS!r}"
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "docs_stonesoup"}
    exec(compile(code.replace(STEPS, f"n_steps = {n_steps}"), str(PAGE), "exec"), namespace)
    assert (tmp_path / "stonesoup_ospa.png").stat().st_size > 0
    return namespace


def _means(ns) -> dict:
    return {key: (ns["mean"](f"OSPA {key}", "OSPA distances"),
                  ns["mean"](f"OSPA(2) {key}", "OSPA(2) distances")) for key in ("LMB", "JPDA")}


def test_the_example_runs_on_fewer_scans(tmp_path, monkeypatch):
    ns = _run(tmp_path, monkeypatch, 12)
    assert len(ns["scans"]) == 12
    assert ns["lmb_tracks"] and ns["jpda_tracks"]
    assert all(t.id.count(":") == 1 and "existence" in t.metadata for t in ns["lmb_tracks"])
    for ospa, ospa2 in _means(ns).values():
        assert 0 <= ospa <= 10 and 0 <= ospa2 <= 10  # both bounded by the cut-off c = 10 m


@pytest.mark.slow
def test_the_example_gives_the_pages_numbers(tmp_path, monkeypatch):
    """The table of "What it measured": mean OSPA and OSPA(2) of both trackers (about 10 s)."""
    ns = _run(tmp_path, monkeypatch, 60)
    means = _means(ns)
    np.testing.assert_allclose(means["LMB"], (1.81, 3.10), atol=0.005)
    # the GOSPA block's means (distance, localisation, missed, false), as the page says
    from stonesoup.plugins.rankedassign import GOSPAMetric

    gospa = {key: [np.mean([float(m.value) for m in ns["gospa_metrics"][f"GOSPA {key}"][t].value])
                   for t in GOSPAMetric.TITLES] for key in ("LMB", "JPDA")}
    np.testing.assert_allclose(gospa["LMB"], (9.28, 6.11, 2.83, 0.33), atol=0.005)
    np.testing.assert_allclose(gospa["JPDA"], (23.26, 7.26, 0.33, 15.67), atol=0.005)
    np.testing.assert_allclose(means["JPDA"], (3.57, 4.68), atol=0.005)
    assert (len(ns["truths"]), len(ns["lmb_tracks"]), len(ns["jpda_tracks"])) == (12, 11, 31)
    assert sum(len(d) for _, d in ns["scans"]) == 653
    table = PAGE.read_text()
    assert "**1.81 m** | **3.10 m**" in table and "| 3.57 m | 4.68 m |" in table
