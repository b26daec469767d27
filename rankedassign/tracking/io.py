"""Measurement files: read and write the scans a filter runs on, as CSV.

The layout users have: one row per measurement with columns ``scan, x, y`` and, for several
sensors, ``sensor``::

    scan,x,y
    1,-12.5,3.25
    1,402.0,-598.5
    3,-14.0,-7.0

Scan ``s`` of the file is entry ``s - first_scan`` of the list
:func:`read_measurements` returns, which :func:`~rankedassign.tracking.runner.run_filter`
takes; scans without measurements in between (scan 2 above) are kept as empty scans. A row
whose ``x`` and ``y`` are both empty (``2,,``) declares a scan (or, with ``sensor``, a sensor's
scan) without measurements, so that a file can also hold empty scans at its start or end;
:func:`write_measurements` writes such a row for every empty scan, so that reading gives back
exactly the scans written.
"""

from __future__ import annotations

import csv
import math
import os
from collections.abc import Sequence

import numpy as np

from ..validation import check_int
from .common import check_measurements as _check_measurements

__all__ = ["COLUMNS", "SENSOR_COLUMN", "read_measurements", "write_measurements"]

#: Columns of a measurement file: required, then optional (the sensor index, 0-based).
COLUMNS = ("scan", "x", "y")
SENSOR_COLUMN = "sensor"


def _where(path, line: int) -> str:
    return f"{os.fspath(path)}, line {line}"


def _index(text: str, what: str, where: str) -> int:
    """A scan number or sensor index: a non-negative integer (``3`` or ``3.0``)."""
    if text == "":
        raise ValueError(f"{where}: {what} is missing")
    try:
        value = int(text)
    except ValueError:
        try:
            f = float(text)
        except ValueError:
            raise ValueError(f"{where}: {what} must be a non-negative integer, got "
                             f"{text!r}") from None
        if not (math.isfinite(f) and f == int(f)):
            raise ValueError(f"{where}: {what} must be a non-negative integer, got "
                             f"{text!r}") from None
        value = int(f)
    if value < 0:
        raise ValueError(f"{where}: {what} must be a non-negative integer, got {text!r}")
    return value


def _coordinate(text: str, what: str, where: str) -> float:
    """A finite real number."""
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"{where}: {what} must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise ValueError(f"{where}: {what} must be a finite number, got {text!r}")
    return value


def read_measurements(path, *, first_scan: int | None = None,
                      n_sensors: int | None = None) -> list:
    """Read the scans of a measurement file (CSV with columns ``scan, x, y`` [, ``sensor``]).

    Parameters
    ----------
    path : str or path-like
        A CSV file with a header row naming the columns ``scan``, ``x``, ``y`` (in any order,
        case and surrounding spaces ignored) and optionally ``sensor``; other columns are
        ignored. One row per measurement; rows need not be sorted by scan, and within a scan
        (and sensor) the measurements keep their order in the file. A row with ``x`` and ``y``
        both empty declares a scan without measurements.
    first_scan : int, optional
        The scan number of the first entry of the result. Default: the smallest scan number
        in the file. ``first_scan=1`` for a file numbered from 1 whose first scans may be
        empty, so that entry ``k`` is always scan ``k + 1`` (and the labels ``(birth scan,
        index)`` of :class:`~rankedassign.tracking.single.lmb.LMBFilter`, which counts scans from 1,
        give the file's scan numbers).
    n_sensors : int, optional
        With a ``sensor`` column: the number of sensors ``V`` (sensors are indices
        ``0 .. V - 1``). Default: the largest index in the file plus one.

    Returns
    -------
    list
        One entry per scan from ``first_scan`` to the last scan of the file, empty scans in
        between included: an ``(M, 2)`` float64 array of positions per scan, or, with a
        ``sensor`` column, a tuple of one such array per sensor (the form
        :class:`~rankedassign.tracking.multisensor.MultiSensorLMBFilter` takes).

    Raises
    ------
    TypeError
        If ``first_scan`` or ``n_sensors`` is not an int.
    ValueError
        On a file without a header or with a required column missing, a row with the wrong
        number of fields, a scan number or sensor index that is missing, negative or not an
        integer, a coordinate that is missing, not a number, NaN or infinite, a scan number
        below ``first_scan``, a sensor index ``>= n_sensors``, or a file without any row.
        Every message names the file and the line.
    OSError
        If the file cannot be read.

    See Also
    --------
    write_measurements : the inverse.
    rankedassign.tracking.runner.run_filter : runs a filter on the scans.

    Examples
    --------
    >>> from pathlib import Path
    >>> import tempfile
    >>> from rankedassign.tracking import read_measurements
    >>> path = Path(tempfile.mkdtemp()) / "meas.csv"
    >>> _ = path.write_text("scan,x,y\\n1,-12.5,3.25\\n1,402.0,-598.5\\n3,-14.0,-7.0\\n")
    >>> scans = read_measurements(path)
    >>> [z.shape for z in scans]                  # scan 2 has no measurement
    [(2, 2), (0, 2), (1, 2)]
    >>> _ = path.write_text("scan,x,y\\n1,-12.5,nan\\n")
    >>> read_measurements(path)                   # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: ...meas.csv, line 2: y must be a finite number, got 'nan'
    """
    if first_scan is not None:
        first_scan = check_int(first_scan, "first_scan", minimum=0)
    if n_sensors is not None:
        n_sensors = check_int(n_sensors, "n_sensors", minimum=1)
    rows = []  # (line, scan, sensor, x, y); x is None for a row declaring an empty scan
    with open(path, newline="", encoding="utf-8-sig") as f:
        reader = csv.reader(f)
        header = next((r for r in reader if r), None)
        if header is None:
            raise ValueError(f"{_where(path, 1)}: the file is empty; a measurement file starts "
                             f"with a header row naming the columns {', '.join(COLUMNS)}")
        names = [h.strip().lower() for h in header]
        missing = [c for c in COLUMNS if c not in names]
        if missing:
            raise ValueError(
                f"{_where(path, reader.line_num)}: column{'s' if len(missing) > 1 else ''} "
                f"{', '.join(map(repr, missing))} missing from the header {header!r}; a "
                f"measurement file has the columns {', '.join(COLUMNS)} (and {SENSOR_COLUMN!r} "
                "for several sensors)"
            )
        for c in (*COLUMNS, SENSOR_COLUMN):
            if names.count(c) > 1:
                raise ValueError(f"{_where(path, reader.line_num)}: column {c!r} appears "
                                 f"{names.count(c)} times in the header {header!r}")
        col = {c: names.index(c) for c in (*COLUMNS, SENSOR_COLUMN) if c in names}
        multi = SENSOR_COLUMN in col
        for fields in reader:
            if not fields or all(not v.strip() for v in fields):
                continue  # a blank line
            where = _where(path, reader.line_num)
            if len(fields) != len(names):
                raise ValueError(f"{where}: {len(fields)} fields, the header has {len(names)}")
            v = {c: fields[i].strip() for c, i in col.items()}
            scan = _index(v["scan"], "scan", where)
            sensor = _index(v[SENSOR_COLUMN], "sensor", where) if multi else 0
            if n_sensors is not None and sensor >= n_sensors:
                raise ValueError(f"{where}: sensor {sensor} is not an index in "
                                 f"0..{n_sensors - 1} (n_sensors = {n_sensors})")
            if v["x"] == "" and v["y"] == "":
                rows.append((reader.line_num, scan, sensor, None, None))
                continue
            x = _coordinate(v["x"], "x", where) if v["x"] else None
            y = _coordinate(v["y"], "y", where) if v["y"] else None
            if x is None or y is None:
                raise ValueError(f"{where}: {'x' if x is None else 'y'} is missing (a row "
                                 "with both x and y empty declares a scan without "
                                 "measurements)")
            rows.append((reader.line_num, scan, sensor, x, y))
        last_line = reader.line_num
    if not rows:
        raise ValueError(f"{_where(path, last_line)}: no measurement rows after the header; "
                         "a scan without measurements is a row with x and y empty")
    lo = min(r[1] for r in rows)
    if first_scan is None:
        first_scan = lo
    elif lo < first_scan:
        line = next(r[0] for r in rows if r[1] == lo)
        raise ValueError(f"{_where(path, line)}: scan {lo} is before first_scan = {first_scan}")
    K = max(r[1] for r in rows) - first_scan + 1
    V = n_sensors if n_sensors is not None else max(r[2] for r in rows) + 1
    points = [[[] for _ in range(V)] for _ in range(K)]
    for _, scan, sensor, x, y in rows:
        if x is not None:
            points[scan - first_scan][sensor].append((x, y))
    out = []
    for per_sensor in points:
        arrays = tuple(np.array(p, dtype=np.float64).reshape(-1, 2) for p in per_sensor)
        out.append(arrays if multi else arrays[0])
    return out


def _scan_kind(scan) -> bool:
    """True for a multi-sensor scan (a tuple of arrays), False for one array."""
    return isinstance(scan, tuple)


def write_measurements(path, scans, *, first_scan: int = 1) -> None:
    """Write scans to a measurement file that :func:`read_measurements` reads back exactly.

    Parameters
    ----------
    path : str or path-like
        The CSV file to write (overwritten).
    scans : sequence
        One entry per scan: an ``(M, 2)`` array of positions (``[]`` for none), or, for
        several sensors, a tuple of one such array per sensor (the same number of sensors in
        every scan); :func:`read_measurements` returns this form.
    first_scan : int, optional
        Scan number of ``scans[0]`` in the file (default 1, as Vo's MATLAB code and the
        filter's scan counter).

    Notes
    -----
    Columns ``scan,x,y`` or ``scan,sensor,x,y``; coordinates are written with Python's
    shortest round-trip representation, so reading gives back the same float64 values. A scan
    (or a sensor's scan) without measurements is written as one row with ``x`` and ``y``
    empty.

    Raises
    ------
    TypeError
        If ``scans`` is not a sequence, mixes single- and multi-sensor scans, holds
        measurements that are not real numbers, or ``first_scan`` is not an int.
    ValueError
        If a scan is not of shape ``(M, 2)`` or not finite (the message names the scan and
        sensor), or the scans do not all have the same number of sensors.

    Examples
    --------
    >>> from pathlib import Path
    >>> import tempfile
    >>> import numpy as np
    >>> from rankedassign.tracking import read_measurements, write_measurements
    >>> path = Path(tempfile.mkdtemp()) / "two_sensors.csv"
    >>> scans = [(np.array([[1.0, 2.0]]), np.empty((0, 2))), ([], [[0.1, -3.5], [7.0, 8.0]])]
    >>> write_measurements(path, scans)
    >>> print(path.read_text().strip())
    scan,sensor,x,y
    1,0,1.0,2.0
    1,1,,
    2,0,,
    2,1,0.1,-3.5
    2,1,7.0,8.0
    >>> [[z.tolist() for z in scan] for scan in read_measurements(path)]
    [[[[1.0, 2.0]], []], [[], [[0.1, -3.5], [7.0, 8.0]]]]
    """
    first_scan = check_int(first_scan, "first_scan", minimum=0)
    if isinstance(scans, (str, bytes)) or not isinstance(scans, (Sequence, np.ndarray)):
        raise TypeError(f"scans must be a sequence with one entry per scan, got "
                        f"{type(scans).__name__}")
    if len(scans) == 0:
        raise ValueError("scans is empty: nothing to write")
    multi = _scan_kind(scans[0])
    V = len(scans[0]) if multi else 1
    checked = []
    for k, scan in enumerate(scans):
        if _scan_kind(scan) != multi:
            raise TypeError(
                f"scans[{k}] is {'one array' if multi else 'a tuple'}, scans[0] "
                f"{'a tuple (one array per sensor)' if multi else 'one array'}: every scan "
                "must be of the same kind"
            )
        parts = scan if multi else (scan,)
        if len(parts) != V:
            raise ValueError(f"scans[{k}] has {len(parts)} sensors, scans[0] has {V}")
        checked.append([
            _check_measurements(z, f"measurements of scans[{k}]" + (f", sensor {v}" if multi
                                                                    else ""))
            for v, z in enumerate(parts)
        ])
    with open(path, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["scan", SENSOR_COLUMN, "x", "y"] if multi else list(COLUMNS))
        for k, parts in enumerate(checked):
            for v, z in enumerate(parts):
                lead = [first_scan + k, v] if multi else [first_scan + k]
                if z.shape[0] == 0:
                    w.writerow(lead + ["", ""])
                for x, y in z.tolist():
                    w.writerow(lead + [repr(x), repr(y)])
