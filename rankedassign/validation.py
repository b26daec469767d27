"""Argument checks shared by every public boundary of :mod:`rankedassign` and :mod:`oracle`.

One rule for every argument check in the library:

* the wrong *kind* of value (a float or a bool where an int is expected, a non-string where a
  name is expected) raises :class:`TypeError`;
* a value of the right kind outside its range (a negative count, an unknown name, a NaN)
  raises :class:`ValueError`.

Every message names the argument and the value it got, so tests can pin it. This module sits
at the bottom of the import graph: it imports nothing from the package (only numpy).
"""

from __future__ import annotations

import dataclasses
import math
import numbers

import numpy as np
from numpy import bool_ as np_bool

__all__ = [
    "float_array",
    "MAX_COUNT",
    "MAX_WORK_BYTES",
    "STALL_READINGS",
    "STALE_READINGS",
    "check_beta",
    "check_bool",
    "check_fields",
    "check_choice",
    "check_int",
    "check_optional_int",
    "check_real",
    "check_type",
    "format_bytes",
]

# Largest count any kernel accepts: counters are int64 and some are summed or doubled, so stay
# well below 2**63. Larger values are refused in Python with a message instead of surfacing as
# a numba typing or overflow error.
MAX_COUNT = 2**62

# Largest amount of memory an exact computation of the oracle sets out to use for the arrays
# that grow with its answer (an enumeration's output and the sort's keys, the records Murty's
# search keeps per reported assignment): 4 GiB. Beyond it a request is refused with the bytes it
# would take, instead of growing until MemoryError or reaching numpy's "array is too big".
MAX_WORK_BYTES = 2**32

#: Most Monte Carlo runs one study accepts: every run's record is kept in memory (and in the
#: report's ``<study>_runs.json``), and the paper uses 100.
MAX_MC = 100_000

# Readings of the stall and stale rules (spec §3.2) and the integer codes the kernels use for
# them; 0 switches a rule off.
STALL_OFF, STALL_GLOBAL_CONSECUTIVE, STALL_GLOBAL_CUMULATIVE, STALL_CHAIN_LOCAL = 0, 1, 2, 3
STALE_OFF, STALE_CONSECUTIVE, STALE_CUMULATIVE, STALE_LITERAL_SET, STALE_LITERAL_MULTISET = (
    0, 1, 2, 3, 4,
)
#: Public names of the stall readings and their kernel codes.
STALL_READINGS = {
    "global-consecutive": STALL_GLOBAL_CONSECUTIVE,
    "global-cumulative": STALL_GLOBAL_CUMULATIVE,
    "chain-local": STALL_CHAIN_LOCAL,
}
#: Public names of the stale readings and their kernel codes.
STALE_READINGS = {
    "consecutive": STALE_CONSECUTIVE,
    "cumulative": STALE_CUMULATIVE,
    "literal-set": STALE_LITERAL_SET,
    "literal-multiset": STALE_LITERAL_MULTISET,
}


def check_int(value, name: str, *, minimum: int = 0, maximum: int = MAX_COUNT) -> int:
    """Return ``value`` as a Python int after checking it is an integer in ``[minimum, maximum]``.

    Parameters
    ----------
    value : object
        The argument to check. Python and numpy integers are accepted; ``bool`` is not.
    name : str
        Its name, used in the message.
    minimum, maximum : int
        Inclusive bounds.

    Returns
    -------
    int
        ``value`` converted to a Python int (a numpy integer becomes an ``int``).

    Raises
    ------
    TypeError
        If ``value`` is not an integer (``bool`` and floats included, even ``3.0``).
    ValueError
        If it is outside ``[minimum, maximum]``.

    Examples
    --------
    >>> check_int(3, "n_obs")
    3
    >>> check_int(0, "workers", minimum=1)
    Traceback (most recent call last):
    ...
    ValueError: workers must be an int >= 1, got 0
    >>> check_int(2.0, "n_obs")
    Traceback (most recent call last):
    ...
    TypeError: n_obs must be an int, got float 2.0
    """
    if type(value) is not int and (  # fast path for a plain int
            isinstance(value, bool) or not isinstance(value, numbers.Integral)):
        raise TypeError(f"{name} must be an int, got {type(value).__name__} {value!r}")
    v = int(value)
    if v < minimum:
        raise ValueError(f"{name} must be an int >= {minimum}, got {v}")
    if v > maximum:
        power = maximum.bit_length() - 1
        note = f" (2**{power})" if maximum > 1 and maximum == 2**power else ""
        raise ValueError(f"{name} must be an int <= {maximum}{note}, got {v}")
    return v


def check_optional_int(value, name: str, *, minimum: int = 1, maximum: int = MAX_COUNT,
                       none_means: str = "off"):
    """``None`` passes through (a rule switched off); anything else as :func:`check_int`.

    ``none_means`` says in the messages what ``None`` stands for (default ``"off"``).

    Parameters
    ----------
    value : object
        The argument to check: ``None``, or a Python or numpy integer (``bool`` is refused).
    name : str
        Its name, used in the messages.
    minimum, maximum : int, optional
        Inclusive bounds on an integer ``value`` (default ``1`` and :data:`MAX_COUNT`).
    none_means : str, optional
        What ``None`` stands for, written in brackets in the range message
        (``"tau_stall must be None (off) or an int >= 1"``).

    Returns
    -------
    int or None
        ``None`` if ``value`` is ``None``, else ``value`` as a Python int.

    Raises
    ------
    TypeError
        If ``value`` is neither ``None`` nor an integer.
    ValueError
        If it is an integer outside ``[minimum, maximum]``.

    Examples
    --------
    >>> check_optional_int(None, "tau_stall") is None
    True
    >>> check_optional_int(5, "tau_stall")
    5
    >>> check_optional_int(0, "tau_stall")
    Traceback (most recent call last):
    ...
    ValueError: tau_stall must be None (off) or an int >= 1, got 0
    """
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be None or an int, got {type(value).__name__} {value!r}")
    if value < minimum:
        raise ValueError(f"{name} must be None ({none_means}) or an int >= {minimum}, "
                         f"got {value}")
    return check_int(value, name, minimum=minimum, maximum=maximum)


def check_bool(value, name: str) -> bool:
    """Return ``value`` as a bool if it is one: Python's ``True``/``False`` or a numpy bool.

    Strings, numbers and ``None`` are refused: ``bool("false")`` is true, so a switch parsed by
    truthiness would turn on when a user means off.

    Parameters
    ----------
    value : object
        The argument to check.
    name : str
        Its name, used in the message.

    Returns
    -------
    bool
        ``value`` as a Python bool (a ``numpy.bool_`` is converted).

    Raises
    ------
    TypeError
        If ``value`` is not a bool, with its type and value in the message.

    Examples
    --------
    >>> check_bool(False, "grouping")
    False
    >>> check_bool("false", "grouping")
    Traceback (most recent call last):
    ...
    TypeError: grouping must be True or False, got str 'false'
    """
    if isinstance(value, (bool, np_bool)):
        return bool(value)
    raise TypeError(f"{name} must be True or False, got {type(value).__name__} {value!r}")


def check_choice(value, name: str, choices) -> str:
    """Return ``value`` if it is one of the strings ``choices``.

    Parameters
    ----------
    value : object
        The argument to check; only a ``str`` equal to one of ``choices`` passes.
    name : str
        What ``value`` names (``"scan"``, ``"backend"``), used in the message.
    choices : iterable of str
        The allowed values, listed in the message in this order.

    Returns
    -------
    str
        ``value`` itself, unchanged.

    Raises
    ------
    ValueError
        If it is not (whatever its type), with the allowed values in the message.

    Examples
    --------
    >>> check_choice("random", "scan", ("systematic", "random"))
    'random'
    >>> check_choice("rand", "scan", ("systematic", "random"))
    Traceback (most recent call last):
    ...
    ValueError: unknown scan 'rand'; expected one of ('systematic', 'random')
    """
    if not isinstance(value, str) or value not in choices:
        raise ValueError(f"unknown {name} {value!r}; expected one of {tuple(choices)}")
    return value


def check_beta(beta) -> float:
    """Return the inverse temperature ``beta`` as a float after checking it is in ``(0, 1]``.

    Parameters
    ----------
    beta : object
        A Python or numpy real number (``bool`` is refused).

    Returns
    -------
    float

    Raises
    ------
    ValueError
        If ``beta`` is not a real number, is NaN, or lies outside ``(0, 1]``; the message names
        ``beta``.

    Examples
    --------
    >>> check_beta(0.5)
    0.5
    >>> check_beta(0)
    Traceback (most recent call last):
    ...
    ValueError: beta must be a real number in (0, 1] (the conditionals are raised to beta), got 0
    """
    ok = isinstance(beta, numbers.Real) and not isinstance(beta, bool | np.bool_)
    if not ok or not (0.0 < float(beta) <= 1.0):  # NaN fails the comparison
        raise ValueError(f"beta must be a real number in (0, 1] (the conditionals are raised "
                         f"to beta), got {beta!r}")
    return float(beta)


def check_real(value, name: str, *, minimum=None, maximum=None, strict_minimum=False,
               finite=True) -> float:
    """Return ``value`` as a float after checking it is a real number in range.

    Parameters
    ----------
    value : object
        The argument to check: a Python or numpy real number (``bool`` is refused).
    name : str
        Its name, used in the messages.
    minimum, maximum : float or None
        Bounds (``None``: unbounded); ``maximum`` is inclusive.
    strict_minimum : bool
        Require ``value > minimum`` instead of ``>=``.
    finite : bool
        Refuse ``inf`` (NaN is always refused).

    Returns
    -------
    float
        ``value`` as a Python float.

    Raises
    ------
    TypeError
        If ``value`` is not a real number (``bool``, strings, complex numbers, ``None``).
    ValueError
        If it is NaN, infinite while ``finite`` is true, or outside the bounds.

    Examples
    --------
    >>> check_real(0.5, "p", minimum=0.0, maximum=1.0)
    0.5
    >>> check_real(float("nan"), "c")
    Traceback (most recent call last):
    ...
    ValueError: c must be a finite real number, got nan
    >>> check_real(10**400, "p")
    Traceback (most recent call last):
    ...
    ValueError: p must be a finite real number, got inf
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__} {value!r}")
    try:
        v = float(value)
    except OverflowError:  # an int beyond the floats (10**400): infinite as a float
        v = math.inf if value > 0 else -math.inf
    if math.isnan(v) or (finite and math.isinf(v)):
        kind = "finite real number" if finite else "real number"
        raise ValueError(f"{name} must be a {kind}, got {v}")
    if minimum is not None and (v <= minimum if strict_minimum else v < minimum):
        op = ">" if strict_minimum else ">="
        raise ValueError(f"{name} must be {op} {minimum}, got {v}")
    if maximum is not None and v > maximum:
        raise ValueError(f"{name} must be <= {maximum}, got {v}")
    return v


def check_type(value, name: str, types, hint: str = ""):
    """Return ``value`` if it is an instance of ``types``, else raise :class:`TypeError`.

    Parameters
    ----------
    value : object
        The argument to check.
    name : str
        Its name, used in the message.
    types : type or tuple of type
        The accepted types, as for :func:`isinstance`; their names are joined by ``" or "`` in
        the message.
    hint : str, optional
        Advice appended to the message after a semicolon (e.g. how to build the right object);
        empty by default.

    Returns
    -------
    object
        ``value`` itself, unchanged.

    Raises
    ------
    TypeError
        If ``value`` is not an instance of ``types``.

    Examples
    --------
    >>> check_type(3, "x", int)
    3
    >>> check_type("a", "problem", (int, float), "build one with from_eta")
    Traceback (most recent call last):
    ...
    TypeError: problem must be an int or float, got str; build one with from_eta
    """
    if not isinstance(value, types):
        names = " or ".join(t.__name__ for t in (types if isinstance(types, tuple) else (types,)))
        article = "an" if names[:1].lower() in "aeiou" else "a"
        raise TypeError(f"{name} must be {article} {names}, got {type(value).__name__}"
                        + (f"; {hint}" if hint else ""))
    return value


def format_bytes(n: int) -> str:
    """``n`` bytes in binary units with the exact count, for messages.

    Parameters
    ----------
    n : int
        A number of bytes, non-negative (converted with :class:`int`).

    Returns
    -------
    str
        ``"<n> bytes"`` below 1 KiB; otherwise the size to one decimal in the largest binary
        unit (KiB to YiB) followed by the exact count in brackets; beyond the YiB range, ``n``
        in scientific notation.

    Examples
    --------
    >>> format_bytes(512)
    '512 bytes'
    >>> format_bytes(2**32)
    '4.0 GiB (4294967296 bytes)'
    >>> format_bytes(10**21)
    '867.4 EiB (1000000000000000000000 bytes)'
    >>> format_bytes(10**40)
    '1.0e+40 bytes'
    """
    n = int(n)
    if n < 1024:
        return f"{n} bytes"
    units = ("KiB", "MiB", "GiB", "TiB", "PiB", "EiB", "ZiB", "YiB")
    e = (n.bit_length() - 1) // 10
    if e > len(units):
        return f"{float(n):.1e} bytes"
    return f"{n / 1024**e:.1f} {units[e - 1]} ({n} bytes)"


def check_fields(obj, *, where: str = "") -> None:
    """Check every field of the dataclass ``obj`` against its annotation, by kind only.

    ``int`` fields take ints (no bools, no floats), ``float`` fields real numbers (no bools),
    ``bool`` fields real booleans (not the strings ``"false"``/``"true"``), ``str`` fields
    strings (``str | None`` also None); a field called ``n_mc`` is at most :data:`MAX_MC`.
    Sequences, ranges and allowed values stay the dataclass's own checks. Used by the
    study settings, so that a bad ``--config`` value is refused before any study runs.

    Parameters
    ----------
    obj : dataclass instance
        With ``from __future__ import annotations`` style (string) annotations or types.
    where : str, optional
        Prefix of the messages (e.g. the study's name).

    Raises
    ------
    TypeError, ValueError
        Naming the field and the value it got.

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> @dataclass
    ... class S:
    ...     grouping: bool = False
    ...     ospa_c: float = 200.0
    >>> check_fields(S(grouping="false"))
    Traceback (most recent call last):
    ...
    TypeError: grouping must be True or False, got str 'false'
    """
    for f in dataclasses.fields(obj):
        kind = f.type if isinstance(f.type, str) else getattr(f.type, "__name__", str(f.type))
        kind = kind.replace(" ", "")
        name = f"{where}{f.name}"
        value = getattr(obj, f.name)
        optional = kind.endswith("|None") or kind.startswith("None|")
        if optional:
            if value is None:
                continue
            kind = kind.replace("|None", "").replace("None|", "")
        if kind == "int":
            check_int(value, name, minimum=-MAX_COUNT,
                      maximum=MAX_MC if f.name == "n_mc" else MAX_COUNT)
        elif kind == "float":
            check_real(value, name, finite=False)
        elif kind == "bool":
            check_bool(value, name)
        elif kind == "str":
            if not isinstance(value, str):
                raise TypeError(f"{name} must be a string, got {type(value).__name__} {value!r}")


def float_array(x, name: str, *, ndim: int | None = None, allow_nan: bool = True) -> np.ndarray:
    """Validate numeric array-like input; return a float64 C-contiguous copy.

    The one float-array validator of the package: every public function that takes an array
    of reals (cost matrices, weights, measurements, states) goes through it.

    Parameters
    ----------
    x : array_like
        Real numbers (booleans count as 0 and 1); Python ints too large for int64 are
        converted one by one.
    name : str
        What ``x`` is, for the messages.
    ndim : int, optional
        Required number of dimensions.
    allow_nan : bool, optional
        ``False`` refuses NaN entries.

    Returns
    -------
    ndarray of float64
        A new C-contiguous array.

    Raises
    ------
    TypeError
        If ``x`` is not an array of real numbers (strings, ``None``, complex, dates, ragged
        lists).
    ValueError
        For a Python int too large for a float64, a wrong number of dimensions, or NaN when
        ``allow_nan`` is false.

    Examples
    --------
    >>> float_array([[1, 2]], "cost").tolist()
    [[1.0, 2.0]]
    >>> float_array(["a"], "cost")
    Traceback (most recent call last):
    ...
    TypeError: cost must be a numeric array, got dtype <U1
    >>> float_array([1.0, float("nan")], "z", ndim=1, allow_nan=False)
    Traceback (most recent call last):
    ...
    ValueError: z contains NaN
    """
    try:
        arr = np.asarray(x)
    except Exception as exc:  # ragged lists and the like
        raise TypeError(f"{name} must be a numeric array, could not convert: {exc}") from None
    if arr.dtype == object and arr.size and all(
        isinstance(v, numbers.Real) for v in arr.reshape(-1)
    ):
        # Python ints beyond int64 (e.g. 10**30) land in an object array; convert one by one
        flat = np.empty(arr.size)
        for k, v in enumerate(arr.reshape(-1)):
            try:
                flat[k] = float(v)
            except OverflowError:
                text = repr(v)
                text = text if len(text) <= 24 else f"{text[:12]}... ({len(text)} digits)"
                raise ValueError(f"{name} has an entry too large for a float64: {text}") from None
        arr = flat.reshape(arr.shape)
    if (
        arr.dtype == object
        or arr.dtype.kind in "mM"  # datetime64 / timedelta64 count as numbers to numpy
        or not (np.issubdtype(arr.dtype, np.number) or np.issubdtype(arr.dtype, np.bool_))
    ):
        raise TypeError(f"{name} must be a numeric array, got dtype {arr.dtype}")
    if np.issubdtype(arr.dtype, np.complexfloating):
        raise TypeError(f"{name} must be real, got dtype {arr.dtype}")
    if ndim is not None and arr.ndim != ndim:
        raise ValueError(f"{name} must be {ndim}-D, got shape {arr.shape}")
    out = np.array(arr, dtype=np.float64, order="C", copy=True)
    if not allow_nan and np.isnan(out).any():
        raise ValueError(f"{name} contains NaN")
    return out
