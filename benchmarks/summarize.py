"""Summarise a pytest-benchmark JSON file into the tables of ``benchmarks/README.md``.

Usage::

    python -m pytest benchmarks --benchmark-enable --benchmark-json=bench.json
    python benchmarks/summarize.py bench.json

Prints, per benchmark group, every benchmark's min and median time and its ratio to the
fastest one of the group (side by side, from the same run; per sweep where the benchmark records
its sweeps in ``extra_info["sweeps"]``, since calls of different sizes are compared), the time
per sweep, and for the LMB filter the per-scan time split.
"""

from __future__ import annotations

import json
import sys
from collections import defaultdict


def _fmt(seconds: float) -> str:
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6), ("ns", 1e-9)):
        if seconds >= scale or unit == "ns":
            return f"{seconds / scale:.3g} {unit}"
    raise AssertionError  # pragma: no cover


def _sweeps(b: dict) -> int:
    return b.get("extra_info", {}).get("sweeps") or 0


def summarize(data: dict) -> str:
    """Markdown tables of a pytest-benchmark result (``--benchmark-json`` contents).

    Examples
    --------
    >>> data = {"benchmarks": [
    ...     {"group": "g", "name": "a", "stats": {"min": 2e-3, "median": 2.5e-3},
    ...      "extra_info": {"sweeps": 1000}},
    ...     {"group": "g", "name": "b", "stats": {"min": 1e-3, "median": 1.2e-3},
    ...      "extra_info": {}}]}
    >>> print(summarize(data))  # doctest: +NORMALIZE_WHITESPACE
    ### g
    <BLANKLINE>
    | benchmark | min | median | ratio to fastest (min) | per sweep (min) |
    |---|---|---|---|---|
    | b | 1 ms | 1.2 ms | 1.00 | |
    | a | 2 ms | 2.5 ms | 2.00 | |
    """
    groups = defaultdict(list)
    for b in data["benchmarks"]:
        groups[b.get("group") or "ungrouped"].append(b)
    out = []
    for group in sorted(groups):
        # compare per sweep when every member records its sweeps (calls of different sizes),
        # else per call
        per_sweep = all(_sweeps(b) for b in groups[group])

        def _key(b, per_sweep=per_sweep):
            return b["stats"]["min"] / (_sweeps(b) if per_sweep else 1)

        rows = sorted(groups[group], key=_key)
        fastest = _key(rows[0])
        out += [f"### {group}", "",
                "| benchmark | min | median | ratio to fastest (min) | per sweep (min) |",
                "|---|---|---|---|---|"]
        for b in rows:
            st, info = b["stats"], b.get("extra_info", {})
            per = _fmt(st["min"] / _sweeps(b)) if per_sweep else ""
            out.append(f"| {b['name']} | {_fmt(st['min'])} | {_fmt(st['median'])} | "
                       f"{_key(b) / fastest:.2f} | {per} |")
            split = {k[len("per_scan_"):-2]: v for k, v in info.items()
                     if k.startswith("per_scan_") and k.endswith("_s")}
            if split:
                parts = ", ".join(f"{k} {_fmt(v)}" for k, v in split.items())
                out.append(f"| ↳ per scan: {parts} | | | | |")
        out.append("")
    return "\n".join(out).rstrip()


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 1:
        print(__doc__, file=sys.stderr)
        return 2
    with open(argv[0]) as f:
        print(summarize(json.load(f)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
