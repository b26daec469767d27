"""Writers of the reproduction report: markdown (each study renders its own section from the
registry), JSON and CSV. The plots are drawn by each study's ``plot``."""

from __future__ import annotations

import csv
import dataclasses
import json
import math
from pathlib import Path

import numpy as np

from . import _format as fmt
from .registry import get_study, study_names

__all__ = ["write_json", "write_csv", "render_report", "SPEC_PAGE"]

#: Where the report's "spec §n" references point: the specification page of the documentation.
SPEC_PAGE = "docs/specification.md"


def _clean(obj):
    """JSON-safe copy: NaN/inf -> None, numpy scalars/arrays -> Python, tuples -> lists,
    records (dataclasses, named tuples) -> dicts."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return _clean(dataclasses.asdict(obj))
    if isinstance(obj, tuple) and hasattr(obj, "_asdict"):
        return _clean(obj._asdict())
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _clean(obj.tolist())
    if isinstance(obj, np.generic):
        return _clean(obj.item())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def write_json(path, obj) -> None:
    """Write ``obj`` as strict JSON (no NaN: non-finite numbers become ``null``).

    Parameters
    ----------
    path : str or os.PathLike
        File to write (replaced if it exists); the text ends with a newline.
    obj : object
        Plain data (dicts, lists, numbers, strings, ``None``) or what converts to it: records
        (dataclasses, named tuples) become objects, tuples and numpy arrays lists, numpy
        scalars Python numbers, and keys strings.

    Examples
    --------
    >>> import json, math, tempfile, pathlib
    >>> from rankedassign.experiments.report import write_json
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "x.json"
    >>> write_json(p, {"a": [1.5, math.nan]})
    >>> json.loads(p.read_text())
    {'a': [1.5, None]}
    """
    Path(path).write_text(json.dumps(_clean(obj), indent=1, allow_nan=False) + "\n")


def write_csv(path, rows: list[dict]) -> None:
    """Write a list of flat dicts as CSV (columns: union of keys in first-seen order).

    Parameters
    ----------
    path : str or os.PathLike
        File to write (replaced if it exists).
    rows : list of dict
        One dict per line, keys the column names, values scalars; a key missing from a row,
        a ``None`` and a non-finite float are written as empty cells.

    Examples
    --------
    >>> import csv, tempfile, pathlib
    >>> from rankedassign.experiments.report import write_csv
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "x.csv"
    >>> write_csv(p, [{"a": 1, "b": None}, {"a": 2, "c": 0.5}])
    >>> list(csv.DictReader(p.read_text().splitlines()))[1]
    {'a': '2', 'b': '', 'c': '0.5'}
    """
    cols: dict[str, None] = {}
    for r in rows:
        cols.update(dict.fromkeys(r))
    with Path(path).open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(cols), restval="")
        w.writeheader()
        for r in rows:
            w.writerow({k: "" if v is None else v for k, v in _clean(r).items()})


def render_report(results: dict, config, meta: dict) -> str:
    """The markdown report for the studies in ``results``.

    Parameters
    ----------
    results : dict
        ``{study: summary}`` as returned by :func:`~rankedassign.experiments.run_study`.
    config : Config
        The settings used.
    meta : dict
        ``command``, ``version``, ``mode``, ``seed``, ``executor``, ``seconds`` (per study) ...

    Returns
    -------
    str
    """
    parts = [
        "# Reproduction: On Gibbs Sampling Architecture for Labeled RFS Multi-Object Tracking",
        "",
        "Trezza, Bucci & Varshney (2023, arXiv:2306.15135), reproduced with "
        f"rankedassign {meta.get('version', '?')}. \"spec §n\" refers to the specification "
        f"page of the rankedassign documentation (`{SPEC_PAGE}`, *Algorithm specification*); "
        "the paper's published numbers are printed beside ours wherever the paper has them.",
        "",
        fmt.table(
            ["setting", "value"],
            [
                ["command", f"`{meta.get('command', '')}`"],
                ["mode", str(meta.get("mode"))],
                ["seed", str(meta.get("seed"))],
                ["executor", str(meta.get("executor"))],
                ["started (UTC)", str(meta.get("started"))],
                ["wall time (s)", ", ".join(
                    f"{k} {v:.1f}" for k, v in meta.get("seconds", {}).items())],
            ],
        ),
        "",
    ]
    left = [n for n in study_names() if n not in results]
    if left:
        parts += [
            "Studies not in this run: " + ", ".join(f"`{n}`" for n in left) + ". "
            "`rankedassign reproduce` without study names runs the paper's studies; "
            "`rankedassign reproduce --all` runs every study, and "
            f"`rankedassign reproduce {left[0]}` runs one.",
            "",
        ]
    for name, summary in results.items():
        parts.append(get_study(name).render(summary, config[name]))
    parts.append(
        "## Files\n\nEvery study writes `<study>.json` (summary records), `<study>.csv` and "
        "`<study>_runs.json` (per-run records); `config.json` holds the settings and "
        "`manifest.json` the run information.\n"
    )
    return "\n".join(parts)
