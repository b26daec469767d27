"""The gallery page ``docs/stonesoup-bearing-range.md`` runs: a bearing–range simulation, our
four trackers (LMB and δ-GLMB, EKF and UKF, births from the detections) and Stone Soup's JPDA
tracker, OSPA and GOSPA in one manager, the figure.

The page's ``python`` blocks (marked ``skip-test`` for ``tests/test_docs.py``, which would run
them at full length) run here in page order, in one namespace, on 10 scans instead of 60.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

pytest.importorskip("stonesoup")

PAGE = Path(__file__).resolve().parents[1] / "docs" / "stonesoup-bearing-range.md"
STEPS = "n_steps = 60"


def test_the_gallery_page_runs_on_fewer_scans(tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    code = "\n".join(re.findall(r"^```python\n(.*?)^```$", PAGE.read_text(),
                                flags=re.S | re.M))
    assert STEPS in code, f"the page's example no longer sets {STEPS!r}"
    monkeypatch.chdir(tmp_path)
    ns = {"__name__": "docs_gallery"}
    exec(compile(code.replace(STEPS, "n_steps = 10"), str(PAGE), "exec"), ns)
    assert (tmp_path / "stonesoup_bearing_range.png").stat().st_size > 0
    assert len(ns["scans"]) == 10
    assert set(ns["summary"]) == {"LMB EKF", "LMB UKF", "GLMB EKF", "GLMB UKF", "JPDA EKF"}
    for key, (ospa, gospa) in ns["summary"].items():
        assert 0 <= ospa <= 10 and gospa >= 0, key
        assert ns["all_tracks"][key], key
    # our trackers found the targets: below the cut-off on average after their first scans
    for key in ("LMB EKF", "GLMB UKF"):
        assert ns["summary"][key][0] < 6.0, ns["summary"]
