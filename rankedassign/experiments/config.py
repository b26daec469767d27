"""The settings vocabulary the studies share: the synthetic families, the readings of the
stall/stale rules and of the random family, Table I's criteria, the common settings of the
synthetic-matrix studies (:class:`SyntheticConfig`) and the checks of integer and family
settings. Each study's own settings type is defined in its module
(:mod:`rankedassign.experiments.studies`); :class:`~rankedassign.experiments.Config` gathers
them.

``quick`` keeps every per-run setting of the paper (chain lengths, observation budgets,
thresholds) and only lowers the number of Monte Carlo runs and of sweep points, so each number
it prints estimates the same quantity as the paper's, with a larger standard error.
"""

from __future__ import annotations

import functools
import warnings
from dataclasses import dataclass

from ..validation import MAX_COUNT, check_fields, check_real

__all__ = [
    "FAMILIES",
    "ALL_FAMILIES",
    "STALL_READINGS",
    "STALE_READINGS",
    "CRITERIA",
    "DEFAULT_PBAR_D",
    "DEFAULT_DIAGONAL_PBAR_D",
    "DEFAULT_GRANULARITY",
    "OTHER_RANDOM",
    "PBAR_D_READINGS",
    "SyntheticConfig",
    "check_positive",
    "check_families",
    "check_ospa",
    "renamed_settings",
    "rename_settings",
]

#: The paper's synthetic matrix families (spec §1.6), in report order.
FAMILIES = ("diagonal", "uniform", "random")
#: Every family a synthetic study accepts: ``"random-pd"`` and ``"random-r_pd"`` are the random
#: family with ``Pbar_D = P_d`` and with the paper's literal ``r P_d`` (spec A2) whatever the
#: setting ``pbar_d`` says, drawn from the same uniforms as ``"random"`` in the same run, so they
#: are paired with it.
ALL_FAMILIES = (*FAMILIES, "random-pd", "random-r_pd")
#: Default reading of ``Pbar_D`` in the random family and in the diagonal family, and of the
#: granularity of the random family's ``P_s, P_d`` (spec A2, A5): chosen by the
#: ``random_readings`` study, see the documentation's ambiguity list.
DEFAULT_PBAR_D, DEFAULT_DIAGONAL_PBAR_D, DEFAULT_GRANULARITY = "pd", "r_pd", "matrix"
#: The random family under the other reading of ``Pbar_D``, shown beside the default one.
OTHER_RANDOM = "random-r_pd" if DEFAULT_PBAR_D == "pd" else "random-pd"
PBAR_D_READINGS = ("r_pd", "pd")
#: Readings of the stall rule (spec §3.2), the recommended one (S3) first.
STALL_READINGS = ("global-consecutive", "global-cumulative", "chain-local")
#: Readings of the stale rule (spec §3.2), the recommended one (T3) first.
STALE_READINGS = ("consecutive", "cumulative", "literal-set", "literal-multiset")
#: Table I columns: which termination rules are active.
CRITERIA = ("stall", "stale", "full")


def check_positive(name: str, value) -> None:
    """Raise ``ValueError`` unless ``value`` is a positive ``int`` (not a bool), at most 2**62.

    Parameters
    ----------
    name : str
        The setting's name, for the message.
    value : object
        Its value.

    Examples
    --------
    >>> check_positive("n_mc", 0)
    Traceback (most recent call last):
    ...
    ValueError: n_mc must be a positive integer, got 0
    """
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ValueError(f"{name} must be a positive integer, got {value!r}")
    if value > MAX_COUNT:  # the kernels' counters are int64 (validation.MAX_COUNT)
        raise ValueError(f"{name} must be a positive integer <= 2**62, got {value!r}")


def check_families(name: str, fams, allowed=ALL_FAMILIES) -> None:
    """Raise ``ValueError`` unless ``fams`` names at least one family, each in ``allowed``.

    Parameters
    ----------
    name : str
        The setting's name, for the message.
    fams : sequence of str
        The families named.
    allowed : tuple of str, optional
        The families accepted (default :data:`ALL_FAMILIES`).

    Examples
    --------
    >>> check_families("families", ("square",))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: families: unknown family 'square'; choose from ('diagonal', ...)
    """
    if not fams:
        raise ValueError(f"{name} must name at least one family")
    for f in fams:
        if f not in allowed:
            raise ValueError(f"{name}: unknown family {f!r}; choose from {allowed}")


def check_ospa(c, p) -> None:
    """Raise unless ``c`` and ``p`` are a valid OSPA cut-off and order of a study's settings.

    The same bounds as :func:`rankedassign.metrics.ospa2` (``c > 0``, ``p >= 1``, both finite
    real numbers), checked when the settings are made, so that a bad value is refused before
    any study runs instead of when the study computes its first metric.

    Parameters
    ----------
    c, p : float
        The settings ``ospa_c`` and ``ospa_p``.

    Raises
    ------
    TypeError
        If either is not a real number.
    ValueError
        If either is NaN or infinite, ``c <= 0`` or ``p < 1``.

    Examples
    --------
    >>> check_ospa(200.0, 0.5)
    Traceback (most recent call last):
    ...
    ValueError: ospa_p must be >= 1.0, got 0.5
    """
    check_real(c, "ospa_c", minimum=0.0, strict_minimum=True)
    check_real(p, "ospa_p", minimum=1.0)


def rename_settings(fields: dict, renamed: dict, where: str) -> dict:
    """``fields`` with each renamed setting under its new name, warning once per old name.

    Parameters
    ----------
    fields : dict
        Settings by name, as given (keyword arguments, or a ``--config`` file's mapping).
    renamed : dict
        ``{old name: new name}`` (a settings type's ``RENAMED_SETTINGS``).
    where : str
        Prefix of the messages (the settings type, or the study of a ``--config`` file).

    Returns
    -------
    dict
        A new mapping: every old name replaced by its new one, the other settings unchanged.

    Raises
    ------
    TypeError
        If both an old name and its new one are given.

    Warns
    -----
    DeprecationWarning
        ``"<where>'<old>' is deprecated; write '<new>'"``, for each old name given.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     new = rename_settings({"methods": ("lbp",), "n_mc": 2}, {"methods": "truncations"},
    ...                           "tempering_herding: ")
    >>> new
    {'truncations': ('lbp',), 'n_mc': 2}
    >>> print(w[0].message)
    tempering_herding: 'methods' is deprecated; write 'truncations'
    """
    out = {}
    for key, value in fields.items():
        new = renamed.get(key)
        if new is not None:
            if new in fields:
                raise TypeError(f"{where}give {new!r} alone, not also its deprecated name "
                                f"{key!r}")
            # stacklevel 3: the call of the settings type (or of config_from_dict)
            warnings.warn(f"{where}{key!r} is deprecated; write {new!r}", DeprecationWarning,
                          stacklevel=3)
            key = new
        out[key] = value
    return out


def renamed_settings(**renamed):
    """Class decorator: a study's settings type still takes its renamed settings' old names.

    For one release (SciPy's practice) the settings type accepts an old name as a keyword
    argument, and :func:`~rankedassign.experiments.config_from_dict` (a ``--config`` file)
    as a key, each with a :class:`DeprecationWarning` naming the new one
    (:func:`rename_settings`); reading ``settings.<old>`` warns the same way and gives the new
    field's value. The type lists them in ``RENAMED_SETTINGS``.

    Parameters
    ----------
    **renamed : str
        The new name of each old one (``methods="truncations"``).

    Returns
    -------
    callable
        The decorator: it returns the class it is given, changed in place.

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> @renamed_settings(methods="truncations")
    ... @dataclass(frozen=True)
    ... class S:
    ...     truncations: tuple = ()
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     s = S(methods=("lbp",))
    >>> s.truncations, str(w[0].message)
    (('lbp',), "S: 'methods' is deprecated; write 'truncations'")
    """
    def decorate(cls):
        init = cls.__init__

        @functools.wraps(init)
        def __init__(self, *args, **kwargs):
            init(self, *args, **rename_settings(kwargs, renamed, f"{cls.__name__}: "))

        def alias(old: str, new: str) -> property:
            def get(self):
                warnings.warn(f"{cls.__name__}: {old!r} is deprecated; write {new!r}",
                              DeprecationWarning, stacklevel=2)
                return getattr(self, new)
            return property(get, doc=f"Deprecated name of ``{new}``.")

        cls.__init__ = __init__
        cls.RENAMED_SETTINGS = dict(renamed)
        for old, new in renamed.items():
            setattr(cls, old, alias(old, new))
        return cls
    return decorate


@dataclass(frozen=True)
class SyntheticConfig:
    """Common settings of the synthetic-matrix studies (paper §V-A, spec §3.4): the base of
    :class:`~rankedassign.experiments.Table1Config`, ``AblationConfig`` and ``OptimumConfig``.

    Attributes
    ----------
    n_mc : int
        Monte Carlo runs per family; the random family's matrix is re-drawn every run.
    families : tuple of str
        Matrix families to run, in report order (:data:`ALL_FAMILIES`).
    original_obs : int
        Sweeps of the original sampler's single chain (``sample_original(problem, 250_000)``).
    n_chains, chain_length : int
        ``N_S`` chains of ``N_C`` sweeps of the short-chain sampler (spec §3.4).
    tau_stall, tau_stale : int
        Thresholds of the stall and stale rules (spec §3.2), where a rule is on.
    pbar_d : {"r_pd", "pd"}
        ``Pbar_D`` of the random family (spec A2): ``r P_d`` (the paper's text) or ``P_d``
        (Vo's code).
    granularity : {"row", "matrix"}
        Whether the random family draws ``P_s, P_d`` per row or once per matrix (spec A5).
    diagonal_pbar_d : {"r_pd", "pd"}
        ``Pbar_D`` of the diagonal family (spec A2).
    """

    n_mc: int = 100
    families: tuple[str, ...] = FAMILIES
    #: Sweeps of the original sampler's single chain (``sample_original(problem, 250_000)``).
    original_obs: int = 250_000
    n_chains: int = 10_000
    chain_length: int = 25
    tau_stall: int = 5
    tau_stale: int = 25
    #: ``Pbar_D`` of the random family (spec A2) and granularity of ``P_s, P_d`` (A5).
    pbar_d: str = DEFAULT_PBAR_D
    granularity: str = DEFAULT_GRANULARITY
    #: ``Pbar_D`` of the diagonal family (spec A2).
    diagonal_pbar_d: str = DEFAULT_DIAGONAL_PBAR_D

    def __post_init__(self):
        check_fields(self)
        for name in ("n_mc", "original_obs", "n_chains", "chain_length", "tau_stall", "tau_stale"):
            check_positive(name, getattr(self, name))
        check_families("families", self.families)
        for name in ("pbar_d", "diagonal_pbar_d"):
            if getattr(self, name) not in PBAR_D_READINGS:
                raise ValueError(f"{name} must be 'r_pd' or 'pd', got {getattr(self, name)!r}")
        if self.granularity not in ("row", "matrix"):
            raise ValueError(f"granularity must be 'row' or 'matrix', got {self.granularity!r}")
