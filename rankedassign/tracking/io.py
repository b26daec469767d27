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
import re
from collections.abc import Sequence

import numpy as np

from ..validation import check_int, format_bytes
from .common import check_measurements as _check_measurements
from .multisensor.scenario import MULTI_SENSORS
from .scenario import MAX_SCANS

__all__ = ["COLUMNS", "MAX_MEASUREMENT_SETS", "SENSOR_COLUMN", "read_measurements",
           "write_measurements"]

#: Columns of a measurement file: required, then optional (the sensor index, 0-based).
COLUMNS = ("scan", "x", "y")
SENSOR_COLUMN = "sensor"


#: Most measurement sets (one per scan and sensor) :func:`read_measurements` builds: the
#: largest simulated run, :data:`~rankedassign.tracking.scenario.MAX_SCANS` scans of the four
#: sensors of the ``"multi"`` preset. The scans alone are bounded by ``MAX_SCANS``, as
#: ``n_scans`` of the scenario runners.
MAX_MEASUREMENT_SETS = MAX_SCANS * len(MULTI_SENSORS)
# Bytes one empty measurement set takes in the result: an empty (0, 2) float64 array (128
# bytes on CPython 3.11 / numpy 2) and its slot in the list or tuple (8).
_SET_BYTES = 136
# A scan number or sensor index as written by a person or a program: decimal digits,
# optionally an integral float ("5.0"). Python's int() also takes "1_000", "+3", " 3" and
# non-ASCII digits, which no measurement file means.
_PLAIN_INDEX = re.compile(r"[0-9]+(\.0*)?")
# A coordinate: a decimal number with an optional exponent (float() also takes "1_0.5" and
# non-ASCII digits).
_PLAIN_NUMBER = re.compile(r"[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?")


def _check_path(path, who: str):
    """``path`` if it names a file: a str, bytes or os.PathLike (an int would be a descriptor)."""
    if isinstance(path, bool) or not isinstance(path, (str, bytes, os.PathLike)):
        raise TypeError(f"{who}: path must be a str or path-like (os.PathLike) naming a file, "
                        f"got {type(path).__name__} {path!r}"
                        + ("; an int is a file descriptor, which is not accepted"
                           if isinstance(path, int) else ""))
    return path


def _where(path, line: int) -> str:
    return f"{os.fsdecode(path)}, line {line}"


def _index(text: str, what: str, where: str) -> int:
    """A scan number or sensor index: a non-negative plain decimal integer (``3`` or ``3.0``)."""
    if text == "":
        raise ValueError(f"{where}: {what} is missing")
    if not _PLAIN_INDEX.fullmatch(text):
        raise ValueError(f"{where}: {what} must be a non-negative integer, got {text!r} "
                         "(decimal digits, as 3 or 3.0)")
    digits = text.split(".")[0]
    if len(digits) > 18:  # beyond any bound below, and int() refuses 4300 digits itself
        raise ValueError(f"{where}: {what} {digits[:18]}... ({len(digits)} digits) is too "
                         f"large; at most {MAX_MEASUREMENT_SETS} scans and sensors are read")
    return int(digits)


def _coordinate(text: str, what: str, where: str) -> float:
    """A finite real number, written as a plain decimal number."""
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"{where}: {what} must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise ValueError(f"{where}: {what} must be a finite number, got {text!r}")
    if not _PLAIN_NUMBER.fullmatch(text):
        raise ValueError(f"{where}: {what} must be a plain decimal number (digits, a point, "
                         f"an exponent), got {text!r}")
    return value


def _undecodable_line(path) -> tuple[int, str]:
    """Line (1-based) and description of the first bytes of ``path`` that are not UTF-8."""
    with open(path, "rb") as f:
        for n, raw in enumerate(f, start=1):
            try:
                raw.decode("utf-8-sig" if n == 1 else "utf-8")
            except UnicodeDecodeError as err:
                bad = raw[err.start:err.end]
                return n, f"byte{'s' if len(bad) > 1 else ''} {bad.hex(' ')} at column " \
                    f"{err.start + 1}"
    return 1, "a byte sequence"  # pragma: no cover - the text reader failed, so some line does


def _size_check(path, rows, K: int, V: int, first_scan: int, n_sensors) -> None:
    """Refuse a file whose scan numbers or sensor indices span more sets than we build."""
    if K > MAX_SCANS:
        last = max(rows, key=lambda r: r[1])
        raise ValueError(
            f"{_where(path, last[0])}: scan {last[1]} makes {K} scans from first_scan = "
            f"{first_scan}, above MAX_SCANS = {MAX_SCANS} (the bound of n_scans): the empty "
            f"scans alone would need {format_bytes(K * V * _SET_BYTES)}, {_SET_BYTES} bytes a "
            "scan and sensor"
        )
    if K * V > MAX_MEASUREMENT_SETS:
        if n_sensors is None:
            line, what = max(rows, key=lambda r: r[2])[0], f"sensor {V - 1} makes {V} sensors"
        else:
            line, what = 1, f"n_sensors = {V}"
        raise ValueError(
            f"{_where(path, line)}: {what} of {K} scan{'s' if K > 1 else ''}, {K * V} "
            f"measurement sets, above MAX_MEASUREMENT_SETS = {MAX_MEASUREMENT_SETS} (MAX_SCANS "
            f"scans of {len(MULTI_SENSORS)} sensors): the empty sets alone would need "
            f"{format_bytes(K * V * _SET_BYTES)}, {_SET_BYTES} bytes a set"
        )


def read_measurements(path, *, first_scan: int | None = None,
                      n_sensors: int | None = None) -> list:
    """Read the scans of a measurement file (CSV with columns ``scan, x, y`` [, ``sensor``]).

    Parameters
    ----------
    path : str or path-like
        A CSV file (UTF-8, an optional BOM) with a header row naming the columns ``scan``,
        ``x``, ``y`` (in any order, case and surrounding spaces ignored) and optionally
        ``sensor``; other columns are ignored. One row per measurement; rows need not be
        sorted by scan, and within a scan (and sensor) the measurements keep their order in
        the file. A row with ``x`` and ``y`` both empty declares a scan without measurements.
        Scan numbers and sensor indices are written in decimal digits (``3``, or ``3.0``);
        coordinates as decimal numbers with an optional exponent (``-12.5``, ``1e3``). An
        int (a file descriptor) or an open file is refused.
    first_scan : int, optional
        The scan number of the first entry of the result. Default: the smallest scan number
        in the file. ``first_scan=1`` for a file numbered from 1 whose first scans may be
        empty, so that entry ``k`` is always scan ``k + 1`` (and the labels ``(birth scan,
        index)`` of :class:`~rankedassign.tracking.single.lmb.LMBFilter`, which counts scans from 1,
        give the file's scan numbers).
    n_sensors : int, optional
        With a ``sensor`` column: the number of sensors ``V`` (sensors are indices
        ``0 .. V - 1``). Default: the largest index in the file plus one. Given for a file
        without a ``sensor`` column it is refused (``ValueError``), not ignored: such a file
        holds one array per scan, whatever ``n_sensors`` says.

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
        If ``path`` is not a str or path-like (an int, an open file), or ``first_scan`` or
        ``n_sensors`` is not an int.
    ValueError
        On a file without a header or with a required column missing, a row with the wrong
        number of fields, a scan number or sensor index that is missing, negative or not a
        plain decimal integer (``1_000``, ``+3``), a coordinate that is missing, not a plain
        decimal number, NaN or infinite, a scan number below ``first_scan``, a sensor index
        ``>= n_sensors``, ``n_sensors`` for a file without a ``sensor`` column, a file
        without any row, more than :data:`~rankedassign.tracking.scenario.MAX_SCANS` scans or
        :data:`MAX_MEASUREMENT_SETS` sets of a scan and sensor (the message gives the memory
        they would need), bytes that are not UTF-8, or a row the csv module refuses (a field
        beyond its size limit). Every message names the file and the line.
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
    _check_path(path, "read_measurements")
    if first_scan is not None:
        first_scan = check_int(first_scan, "first_scan", minimum=0)
    if n_sensors is not None:
        n_sensors = check_int(n_sensors, "n_sensors", minimum=1)
    rows = []  # (line, scan, sensor, x, y); x is None for a row declaring an empty scan
    with open(path, newline="", encoding="utf-8-sig") as f:
        reader = csv.reader(f)
        try:
            multi, last_line = _read_rows(path, reader, rows, n_sensors)
        except UnicodeDecodeError as err:
            line, what = _undecodable_line(path)
            raise ValueError(f"{_where(path, line)}: the file is not UTF-8 text ({what}: "
                             f"{err.reason}); save it as UTF-8 (or ASCII)") from None
        except csv.Error as err:
            # the csv module's own errors (a field over csv.field_size_limit(), a NUL byte)
            raise ValueError(f"{_where(path, reader.line_num)}: not a CSV row the reader can "
                             f"take: {err}") from None
    if not rows:
        raise ValueError(f"{_where(path, last_line)}: no measurement rows after the header; "
                         "a scan without measurements is a row with x and y empty")
    if n_sensors is not None and not multi:
        raise ValueError(f"{_where(path, 1)}: n_sensors = {n_sensors} is for a file with a "
                         f"{SENSOR_COLUMN!r} column, and this one has none (its scans are one "
                         "array each); leave n_sensors out")
    lo = min(r[1] for r in rows)
    if first_scan is None:
        first_scan = lo
    elif lo < first_scan:
        line = next(r[0] for r in rows if r[1] == lo)
        raise ValueError(f"{_where(path, line)}: scan {lo} is before first_scan = {first_scan}")
    K = max(r[1] for r in rows) - first_scan + 1
    V = n_sensors if n_sensors is not None else max(r[2] for r in rows) + 1
    # bounded before anything of size K x V is built: two rows can name scan 10**12
    _size_check(path, rows, K, V, first_scan, n_sensors)
    points = [[[] for _ in range(V)] for _ in range(K)]
    for _, scan, sensor, x, y in rows:
        if x is not None:
            points[scan - first_scan][sensor].append((x, y))
    out = []
    for per_sensor in points:
        arrays = tuple(np.array(p, dtype=np.float64).reshape(-1, 2) for p in per_sensor)
        out.append(arrays if multi else arrays[0])
    return out


def _read_rows(path, reader, rows: list, n_sensors) -> tuple[bool, int]:
    """Check the header and append every row of ``reader`` to ``rows``.

    Returns whether the file has a sensor column and the number of its last line.
    """
    header = next((r for r in reader if r), None)
    if header is None:
        raise ValueError(f"{_where(path, 1)}: the file is empty; a measurement file starts "
                         f"with a header row naming the columns {', '.join(COLUMNS)}")
    if any("\x00" in h for h in header):
        # UTF-16 without a BOM decodes as UTF-8 text with a NUL before every ASCII character
        raise ValueError(f"{_where(path, reader.line_num)}: the header holds NUL characters: "
                         "the file is not UTF-8 text (UTF-16?); save it as UTF-8 (or ASCII)")
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
        if n_sensors is not None and multi and sensor >= n_sensors:
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
    return multi, reader.line_num


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
        If ``path`` is not a str or path-like (an int would be a file descriptor), ``scans``
        is not a sequence, mixes single- and multi-sensor scans, holds
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
    _check_path(path, "write_measurements")
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
