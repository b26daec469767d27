"""Settings types of the reproduction studies (each study's ``full`` and ``quick`` are in its
module; :class:`~rankedassign.experiments.Config` gathers them).

``quick`` keeps every per-run setting of the paper (chain lengths, observation budgets,
thresholds) and only lowers the number of Monte Carlo runs and of sweep points, so each number
it prints estimates the same quantity as the paper's, with a larger standard error.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..tracking.models import PRESETS
from ..tracking.single.association import MARGINALS
from ..tracking.single.lmb import EXTRACTIONS
from ..validation import check_choice, check_fields, check_real

__all__ = [
    "FAMILIES",
    "ALL_FAMILIES",
    "STALL_READINGS",
    "STALE_READINGS",
    "CRITERIA",
    "Table1Config",
    "SweepConfig",
    "TrackingConfig",
    "AblationConfig",
    "OptimumConfig",
    "ReadingsConfig",
    "TemperingHerdingConfig",
    "TH_FAMILIES",
    "TH_METHODS",
    "TH_TRACKING_METHODS",
    "RANDOM_READINGS",
    "DEFAULT_PBAR_D",
    "DEFAULT_DIAGONAL_PBAR_D",
    "DEFAULT_GRANULARITY",
    "OTHER_RANDOM",
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
_PBAR_D = ("r_pd", "pd")
#: Readings of the stall rule (spec §3.2), the recommended one (S3) first.
STALL_READINGS = ("global-consecutive", "global-cumulative", "chain-local")
#: Readings of the stale rule (spec §3.2), the recommended one (T3) first.
STALE_READINGS = ("consecutive", "cumulative", "literal-set", "literal-multiset")
#: Table I columns: which termination rules are active.
CRITERIA = ("stall", "stale", "full")


def _positive(name: str, value) -> None:
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ValueError(f"{name} must be a positive integer, got {value!r}")


def _families(name: str, fams, allowed=ALL_FAMILIES) -> None:
    if not fams:
        raise ValueError(f"{name} must name at least one family")
    for f in fams:
        if f not in allowed:
            raise ValueError(f"{name}: unknown family {f!r}; choose from {allowed}")


@dataclass(frozen=True)
class _Synthetic:
    """Common settings of the synthetic-matrix studies (paper §V-A, spec §3.4)."""

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
            _positive(name, getattr(self, name))
        _families("families", self.families)
        for name in ("pbar_d", "diagonal_pbar_d"):
            if getattr(self, name) not in _PBAR_D:
                raise ValueError(f"{name} must be 'r_pd' or 'pd', got {getattr(self, name)!r}")
        if self.granularity not in ("row", "matrix"):
            raise ValueError(f"granularity must be 'row' or 'matrix', got {self.granularity!r}")


@dataclass(frozen=True)
class Table1Config(_Synthetic):
    """Table I: original vs short-chain sampler with stall only, stale only and both.

    By default the random family is also run under the other reading of ``Pbar_D``
    (:data:`OTHER_RANDOM`), so the report shows both readings beside the paper's row.

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

    Examples
    --------
    >>> from rankedassign.experiments import Table1Config
    >>> Table1Config(n_mc=2).n_chains
    10000
    """

    families: tuple[str, ...] = (*FAMILIES, OTHER_RANDOM)


@dataclass(frozen=True)
class AblationConfig(_Synthetic):
    """Table I under every pair of stall x stale readings (spec §3.2).

    By default it adds the random family under the other reading of ``Pbar_D``
    (:data:`OTHER_RANDOM`, spec A2) to the paper's three, so that reading is ablated too.

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
    stall_readings : tuple of str
        Readings of the stall rule to run (a non-empty subset of :data:`STALL_READINGS`).
    stale_readings : tuple of str
        Readings of the stale rule to run (a non-empty subset of :data:`STALE_READINGS`);
        every stall reading is paired with every stale reading.

    Examples
    --------
    >>> from rankedassign.experiments import AblationConfig
    >>> len(AblationConfig().stall_readings) * len(AblationConfig().stale_readings)
    12
    """

    families: tuple[str, ...] = (*FAMILIES, OTHER_RANDOM)
    stall_readings: tuple[str, ...] = STALL_READINGS
    stale_readings: tuple[str, ...] = STALE_READINGS

    def __post_init__(self):
        super().__post_init__()
        for name, given, allowed in (
            ("stall_readings", self.stall_readings, STALL_READINGS),
            ("stale_readings", self.stale_readings, STALE_READINGS),
        ):
            if not given or any(r not in allowed for r in given):
                raise ValueError(f"{name} must be a non-empty subset of {allowed}, got {given!r}")


@dataclass(frozen=True)
class OptimumConfig(_Synthetic):
    """Sampled truncation error next to the best error with as many distinct solutions.

    The short-chain sampler runs with both rules under the recommended readings (S3, T3).

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

    Examples
    --------
    >>> from rankedassign.experiments import OptimumConfig
    >>> OptimumConfig().tau_stale
    25
    """


@dataclass(frozen=True)
class SweepConfig:
    """Truncation error against the number of observations, no early stopping.

    Attributes
    ----------
    n_mc : int
        Monte Carlo runs per family.
    families : tuple of str
        Matrix families to run (:data:`ALL_FAMILIES`).
    obs_grid : tuple of int
        Observation budgets (sweeps), strictly increasing; at budget ``n`` the original
        sampler runs ``n`` sweeps and the short-chain sampler ``n // L`` chains of ``L``.
    chain_lengths : tuple of int
        Chain lengths ``L`` of the short-chain sampler (a length above the budget is skipped).
    pbar_d : {"r_pd", "pd"}
        ``Pbar_D`` of the random family, and of the diagonal family if it is run (spec A2).
    granularity : {"row", "matrix"}
        Whether the random family draws ``P_s, P_d`` per row or once per matrix (spec A5).

    Examples
    --------
    >>> from rankedassign.experiments import SweepConfig
    >>> SweepConfig().chain_lengths
    (5, 10, 25, 50, 100)
    """

    n_mc: int = 100
    families: tuple[str, ...] = ("uniform", "random")
    #: Observation budgets (sweeps); the short-chain sampler runs ``n // L`` chains of ``L``.
    obs_grid: tuple[int, ...] = (
        100, 200, 500, 1_000, 2_000, 5_000, 10_000, 20_000, 50_000, 100_000, 250_000,
    )
    chain_lengths: tuple[int, ...] = (5, 10, 25, 50, 100)
    pbar_d: str = DEFAULT_PBAR_D
    granularity: str = DEFAULT_GRANULARITY

    def __post_init__(self):
        check_fields(self)
        _positive("n_mc", self.n_mc)
        _families("families", self.families)
        if not self.obs_grid or not self.chain_lengths:
            raise ValueError("obs_grid and chain_lengths must not be empty")
        for n in self.obs_grid:
            _positive("obs_grid entry", n)
        for n in self.chain_lengths:
            _positive("chain_lengths entry", n)
        if tuple(sorted(set(self.obs_grid))) != tuple(self.obs_grid):
            raise ValueError(f"obs_grid must be strictly increasing, got {self.obs_grid}")


@dataclass(frozen=True)
class TrackingConfig:
    """The paper's tracking study (paper §V-B, spec §6.6).

    Attributes
    ----------
    n_mc : int
        Monte Carlo runs (scenarios), each filtered once with each sampler.
    preset : str
        Scenario and model preset (a key of :data:`rankedassign.tracking.models.PRESETS`).
    n_scans : int
        Scans per run.
    original_obs : int
        Sweeps of the original sampler per call.
    n_chains, chain_length : int
        ``N_S`` chains of ``N_C`` sweeps of the short-chain sampler per call.
    tau_stall, tau_stale : int
        Thresholds of its stall and stale rules (readings S3, T3).
    grouping : bool
        One sampler call per group of tracks sharing gated measurements (spec §6.5a) instead
        of one per scan.
    sample_empty_groups : bool
        Also hand groups without gated measurements to the samplers (``LMBFilter``'s
        ``sample_empty_groups``): the accounting the paper's observation totals fit.
    extraction : str or None
        State extraction rule of the filter; ``None`` takes the preset's own rule (hysteresis
        for "paper", MAP cardinality for "vo").
    marginals : str
        Association marginals of both samplers: ``"truncated"`` (the paper's construction)
        or ``"rao-blackwell"`` (:func:`rankedassign.tracking.marginals_from_hypotheses`).
    ospa_c : float
        OSPA(2) cut-off, in metres (spec §7).
    ospa_p : float
        OSPA(2) order, ``>= 1``.
    ospa_window : int
        OSPA(2) window length, in scans.

    Examples
    --------
    >>> from rankedassign.experiments import TrackingConfig
    >>> c = TrackingConfig()
    >>> c.original_obs, (c.n_chains, c.chain_length, c.tau_stall, c.tau_stale)
    (10000, (400, 25, 5, 10))
    """

    n_mc: int = 100
    preset: str = "paper"
    n_scans: int = 100
    original_obs: int = 10_000
    n_chains: int = 400
    chain_length: int = 25
    tau_stall: int = 5
    tau_stale: int = 10
    grouping: bool = False
    #: Also hand groups without gated measurements to the samplers (``LMBFilter``'s
    #: ``sample_empty_groups``): the accounting the paper's observation totals fit.
    sample_empty_groups: bool = False
    #: State extraction; ``None`` takes the preset's own rule (hysteresis for "paper", as the
    #: paper uses; MAP cardinality for "vo", as Vo's code does).
    extraction: str | None = None
    #: Association marginals of both samplers: "truncated" (the paper's construction) or
    #: "rao-blackwell" (:func:`rankedassign.tracking.marginals_from_hypotheses`).
    marginals: str = "truncated"
    #: OSPA(2) parameters (spec §7): cut-off (m), order, window length (scans).
    ospa_c: float = 200.0
    ospa_p: float = 1.0
    ospa_window: int = 5

    @classmethod
    def paper_var(cls, **changes) -> TrackingConfig:
        """The ``tracking_var`` study: preset ``"paper-var"`` (the paper's birth numbers read as
        variances) with one sampler call per group of tracks, empty groups included.

        Parameters
        ----------
        **changes
            Further field values (e.g. ``n_mc=3``); they override the three above too.

        Returns
        -------
        TrackingConfig
            The settings, validated as any :class:`TrackingConfig`.

        Examples
        --------
        >>> from rankedassign.experiments import TrackingConfig
        >>> c = TrackingConfig.paper_var(n_mc=3)
        >>> c.preset, c.grouping, c.sample_empty_groups, c.n_mc
        ('paper-var', True, True, 3)
        """
        return cls(**{"preset": "paper-var", "grouping": True, "sample_empty_groups": True,
                      **changes})

    def __post_init__(self):
        check_fields(self)
        for name in (
            "n_mc", "n_scans", "original_obs", "n_chains", "chain_length", "tau_stall",
            "tau_stale", "ospa_window",
        ):
            _positive(name, getattr(self, name))
        if self.extraction is not None:
            check_choice(self.extraction, "extraction", EXTRACTIONS)
        check_real(self.ospa_c, "ospa_c", minimum=0.0, strict_minimum=True)
        check_real(self.ospa_p, "ospa_p", minimum=1.0)
        if self.preset not in PRESETS:
            raise ValueError(f"preset must be one of {sorted(PRESETS)}, got {self.preset!r}")
        if self.marginals not in MARGINALS:
            raise ValueError(
                f"marginals must be one of {MARGINALS}, got {self.marginals!r}"
            )


#: Readings of the random family the paper's text admits (spec A2, A5): ``(pbar_d,
#: granularity)`` with ``Pbar_D`` = ``r P_d`` or ``P_d`` and ``P_s, P_d`` drawn per row or once
#: per matrix (``q`` is per entry in every reading).
RANDOM_READINGS = (("r_pd", "row"), ("pd", "row"), ("r_pd", "matrix"), ("pd", "matrix"))


@dataclass(frozen=True)
class ReadingsConfig:
    """Table I (all nine cells) under each reading of the random family (spec A2, A5).

    ``Pbar_D`` also enters the diagonal family: every random reading is combined with each
    reading of the diagonal family's ``Pbar_D`` in ``diagonal_readings``, so each combination
    is a complete Table I; the uniform family depends on neither choice and is run once.

    Attributes
    ----------
    n_mc : int
        Monte Carlo runs per family and reading.
    readings : tuple of (str, str)
        ``(pbar_d, granularity)`` readings of the random family, a non-empty subset of
        :data:`RANDOM_READINGS` (lists are turned into tuples).
    diagonal_readings : tuple of str
        ``Pbar_D`` readings of the diagonal family, a non-empty subset of
        ``("r_pd", "pd")``.
    original_obs : int
        Sweeps of the original sampler's single chain.
    n_chains, chain_length : int
        ``N_S`` chains of ``N_C`` sweeps of the short-chain sampler.
    tau_stall, tau_stale : int
        Thresholds of the stall and stale rules (readings S3, T3).

    Examples
    --------
    >>> from rankedassign.experiments.config import ReadingsConfig
    >>> ReadingsConfig().readings[:2]
    (('r_pd', 'row'), ('pd', 'row'))
    """

    n_mc: int = 100
    readings: tuple[tuple[str, str], ...] = RANDOM_READINGS
    diagonal_readings: tuple[str, ...] = _PBAR_D
    original_obs: int = 250_000
    n_chains: int = 10_000
    chain_length: int = 25
    tau_stall: int = 5
    tau_stale: int = 25

    def __post_init__(self):
        check_fields(self)
        for name in ("n_mc", "original_obs", "n_chains", "chain_length", "tau_stall", "tau_stale"):
            _positive(name, getattr(self, name))
        readings = tuple(tuple(r) for r in self.readings)
        if not readings or any(r not in RANDOM_READINGS for r in readings):
            raise ValueError(
                f"readings must be a non-empty subset of {RANDOM_READINGS}, got {self.readings!r}"
            )
        object.__setattr__(self, "readings", readings)
        if not self.diagonal_readings or any(r not in _PBAR_D for r in self.diagonal_readings):
            raise ValueError(f"diagonal_readings must be a non-empty subset of {_PBAR_D}, got "
                             f"{self.diagonal_readings!r}")


#: Problems of the ``tempering_herding`` study: the paper's three families, the multi-sensor
#: cases A/B/C (``"ms:<size>/<family>"``, :mod:`rankedassign.multisensor.synthetic`) and the
#: adaptive-birth families with four sensors (``"birth:<family>"``,
#: :func:`rankedassign.adaptive_birth.synthetic.make_family`).
TH_FAMILIES = (*FAMILIES, "ms:A/random_coupled", "ms:B/random", "ms:C/uniform",
               "birth:diagonal", "birth:uniform", "birth:random")
#: Methods of the ``tempering_herding`` study, in report order (``lbp``: marginals only).
TH_METHODS = ("gibbs", "short", "herded-shared", "herded-full", "herded-short-shared",
              "herded-short-full", "beta-0.5", "beta-0.7", "beta-0.9", "zanella-roberts", "lbp")
#: LMB associations of the study's tracking part, in report order.
TH_TRACKING_METHODS = ("exact", "gibbs", "short", "herded", "herded-short", "lbp")


@dataclass(frozen=True)
class TemperingHerdingConfig:
    """Herded, tempered and LBP association graded by the exact oracle (the paper's future work).

    Attributes
    ----------
    n_mc : int
        Monte Carlo runs per problem family (random families re-drawn every run).
    families : tuple of str
        Problem families (:data:`TH_FAMILIES`).
    methods : tuple of str
        Methods (:data:`TH_METHODS`); a method that does not apply to a family's problem kind
        (LBP is single-sensor only) is reported as not applicable.
    budgets : tuple of int
        Sweeps per call, strictly increasing. One chain runs the budget; short chains run
        ``budget // L`` chains of ``L = min(chain_length, budget)`` sweeps (the stall and
        stale rules may stop them earlier); Zanella–Roberts runs ``budget * P`` moves (``P``
        moves update as many rows as one sweep; ``P = V`` sensors for the adaptive-birth
        kind), on the exact posterior of every kind (``ms_method`` does not apply to it).
    chain_length, tau_stall, tau_stale : int
        The short chains' ``N_C``, ``τ_stall``, ``τ_stale`` (readings S3, T3), Gibbs and herded.
    zr_beta : float
        Inverse temperature of the Zanella–Roberts tempered conditionals, in ``(0, 1]``.
    ms_method : str
        Conditional of the multi-sensor samplers (``"exact"`` or ``"mm"``).
    pbar_d, granularity, diagonal_pbar_d : str
        Readings of the paper's families (as in :class:`Table1Config`).
    tracking_mc : int
        Monte Carlo runs of the tracking part per preset (0: no tracking part).
    presets : tuple of str
        Tracking presets (:data:`~rankedassign.tracking.models.PRESETS`).
    tracking_methods : tuple of str
        LMB associations (:data:`TH_TRACKING_METHODS`).
    n_scans : int
        Scans per tracking run.
    tracking_obs : int
        Sweeps per call of the one-chain associations (Gibbs, herded).
    tracking_chains : int
        Short chains per call of the short-chain associations (``chain_length`` sweeps each).
    ospa_c, ospa_p : float
        OSPA(2) cut-off (m) and order.
    ospa_window : int
        OSPA(2) window (scans).

    Examples
    --------
    >>> from rankedassign.experiments.config import TemperingHerdingConfig
    >>> TemperingHerdingConfig().budgets
    (100, 1000, 10000, 250000)
    >>> TemperingHerdingConfig(methods=("tempered",))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: unknown methods: method 'tempered'; expected one of (...)
    """

    n_mc: int = 20
    families: tuple = TH_FAMILIES
    methods: tuple = TH_METHODS
    budgets: tuple = (100, 1_000, 10_000, 250_000)
    chain_length: int = 25
    tau_stall: int = 5
    tau_stale: int = 25
    zr_beta: float = 0.5
    ms_method: str = "exact"
    pbar_d: str = DEFAULT_PBAR_D
    granularity: str = DEFAULT_GRANULARITY
    diagonal_pbar_d: str = DEFAULT_DIAGONAL_PBAR_D
    tracking_mc: int = 10
    presets: tuple = ("paper", "vo")
    tracking_methods: tuple = TH_TRACKING_METHODS
    n_scans: int = 100
    tracking_obs: int = 1_000
    tracking_chains: int = 40
    ospa_c: float = 200.0
    ospa_p: float = 1.0
    ospa_window: int = 5

    def __post_init__(self):
        for name in ("families", "methods", "budgets", "presets", "tracking_methods"):
            value = getattr(self, name)
            if isinstance(value, list):
                object.__setattr__(self, name, tuple(value))
        check_fields(self)
        for name in ("n_mc", "chain_length", "tau_stall", "tau_stale", "n_scans",
                     "tracking_obs", "tracking_chains", "ospa_window"):
            _positive(name, getattr(self, name))
        if isinstance(self.tracking_mc, bool) or not isinstance(self.tracking_mc, int) \
                or self.tracking_mc < 0:
            raise ValueError(f"tracking_mc must be a non-negative integer, got "
                             f"{self.tracking_mc!r}")
        for name, one, allowed in (("families", "family", TH_FAMILIES),
                                   ("methods", "method", TH_METHODS),
                                   ("presets", "preset", PRESETS),
                                   ("tracking_methods", "method", TH_TRACKING_METHODS)):
            values = getattr(self, name)
            if not isinstance(values, tuple) or (not values and name != "presets"):
                raise ValueError(f"{name} must be a non-empty tuple, got {values!r}")
            for v in values:
                check_choice(v, f"{name}: {one}", allowed)
        b = self.budgets
        if not isinstance(b, tuple) or not b or any(
                isinstance(n, bool) or not isinstance(n, int) or n < 1 for n in b) or any(
                x >= y for x, y in zip(b, b[1:], strict=False)):
            raise ValueError(f"budgets must be a non-empty, strictly increasing tuple of "
                             f"positive integers, got {b!r}")
        check_real(self.zr_beta, "zr_beta", minimum=0.0, maximum=1.0, strict_minimum=True)
        check_choice(self.ms_method, "ms_method", ("exact", "mm"))
        for name in ("pbar_d", "diagonal_pbar_d"):
            check_choice(getattr(self, name), name, _PBAR_D)
        check_choice(self.granularity, "granularity", ("row", "matrix"))
        for name in ("ospa_c", "ospa_p"):
            check_real(getattr(self, name), name, minimum=0.0, strict_minimum=True)
