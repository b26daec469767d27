"""The study registry: what ``rankedassign reproduce``, :func:`run_study` and the report read.

A study is described once, by a :class:`Study`: its settings type, how its settings split into
independent tasks, the task itself (one Monte Carlo run, a module-level function), how the
per-run records are summarised into typed records, and how the summary is rendered (a markdown
section) and plotted. Adding a study is adding one module that builds a :class:`Study` and
passes it to :func:`register_study`, and importing that module in
``rankedassign/experiments/__init__.py``; the command line, the runner, the report, the
settings (:class:`Config`) and :func:`config_from_dict` pick it up from the registry.
"""

from __future__ import annotations

import dataclasses
import time
import warnings
from collections.abc import Callable, Hashable, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from . import _interrupts
from ._executor import run_tasks
from .config import rename_settings

__all__ = [
    "Study",
    "register_study",
    "get_study",
    "study_names",
    "default_study_names",
    "run_study",
    "warm_study",
    "warm_plan",
    "run_warm_item",
    "Config",
    "config_from_dict",
    "ReproduceError",
]


class ReproduceError(ValueError):
    """Bad input to a study or to ``reproduce`` (unknown study, bad count, unusable output)."""


@dataclass(frozen=True)
class Study:
    """Everything the runner, the command line and the report need to know about one study.

    Built with one keyword per field below; frozen.

    Attributes
    ----------
    name : str
        Identifier on the command line, in :class:`Config` and in the report's file names.
    title : str
        One line describing the study (command-line help, progress bar).
    config_type : type
        Frozen dataclass of the study's settings, with an ``n_mc`` field.
    full, quick : callable
        ``() -> config``: the paper's settings and the quick ones.
    tasks : callable
        ``(config, seed) -> list of tuple``: arguments of every call of ``task``.
    task : callable
        Module-level (picklable) function run once per task, returning the run's record (a
        frozen dataclass of the study's module, written to JSON field by field).
    summarise : callable
        ``(runs, config) -> summary`` (typed records).
    render : callable
        ``(summary, config) -> str``: the markdown section of the report.
    plot : callable, optional
        ``(summary, directory) -> list of file names`` written there.
    csv_rows : callable, optional
        ``summary -> list of dict`` for ``<name>.csv`` (default: the summary's records).
    paper : str
        Where the paper shows the same study ("Table I", "§V-B", or "" for none).
    order : float
        Place in the run order (the built-in studies use 10, 20, ..., 70).
    warm : callable, optional
        ``config -> config``: the same settings made tiny (one run, a few observations), so
        that every task of them runs in about a second once compiled, yet takes the code
        paths the real settings take. Before a study's tasks go out, ``reproduce`` runs the
        tiny tasks (:func:`warm_study`): numba compiles the study's kernels once, into its
        on-disk cache, and the tasks load them instead of compiling them while the progress
        bar stands still; the study's time in the report then excludes compiling. None:
        nothing runs ahead.
    warm_group : callable, optional
        ``task arguments -> hashable``: tiny tasks of one group compile the same kernels
        (e.g. the problem kind they run on). With worker processes, :func:`warm_study` runs
        the first task of every group at once, each compiling its own kernels on its own
        core; every other task waits for its group's first and then loads the kernels from
        the cache; so no two workers compile the same kernels side by side. A group's key is
        the study's own (two studies' keys never meet). None: the tiny tasks are one group;
        the first compiles the study's kernels and the rest wait for it.
    warm_after : str, optional
        The name of a study whose first tiny task compiles the kernels this study's tiny tasks
        need (``sweep``, ``ablation``, ``optimum`` and ``random_readings`` after ``table1``:
        the same samplers). When both warm up together (``rankedassign precompile``, a run of
        several studies with worker processes), this study's tiny tasks wait for that one
        instead of compiling the same kernels beside it. None: no such study.
    run_from_dict : callable, optional
        One item of ``<study>_runs.json`` read back into what ``task`` returned: a record
        (e.g. ``Table1Run.from_dict``), or the list of a task's records
        (``nonlinear_tracking``). None: not provided.
    warm_units : callable, optional
        ``config -> list of tuple``: every kernel of the tiny tasks of ``config`` (the tiny
        settings), cut finer than the tasks, for a study whose one task compiles much (the
        tempering study's task compiles every sampler of a problem kind). Each tuple is
        ``(function, *args)``, a module-level function that compiles one part (e.g. one
        sampler on one kind), longest first. With worker processes, :func:`warm_study` and
        :func:`~rankedassign.experiments.precompile.precompile` run the units before the tiny
        tasks, spread over the workers, so that one long task does not compile on one core
        while the others wait; the tiny tasks then load the kernels from the cache. None:
        the tiny tasks are the finest units.

    default_run : bool
        Run by ``rankedassign reproduce`` (and :func:`~rankedassign.experiments.reproduce`)
        when no study is named: True for the paper's own studies, False for the studies of
        the methods that came after it (the δ-GLMB filter, non-linear models, large scenes,
        multi-sensor problems, herding and tempering), which run when named or with
        ``--all``.

    Examples
    --------
    >>> from rankedassign.experiments import get_study
    >>> s = get_study("table1")
    >>> s.name, s.config_type.__name__, s.paper
    ('table1', 'Table1Config', 'Table I')
    """

    name: str
    title: str
    config_type: type
    full: Callable[[], Any]
    quick: Callable[[], Any]
    tasks: Callable[[Any, int], list[tuple]]
    task: Callable[..., Any]
    summarise: Callable[[list, Any], Any]
    render: Callable[[Any, Any], str]
    plot: Callable[[Any, Path], list[str]] | None = None
    csv_rows: Callable[[Any], list[dict]] | None = None
    paper: str = ""
    order: float = 100.0
    warm: Callable[[Any], Any] | None = None
    warm_group: Callable[[tuple], Hashable] | None = None
    warm_after: str | None = None
    run_from_dict: Callable[[dict], Any] | None = None
    warm_units: Callable[[Any], list[tuple]] | None = None
    default_run: bool = True


_REGISTRY: dict[str, Study] = {}


def _a(noun: str) -> str:
    """``noun`` with its indefinite article, for messages."""
    return ("an " if noun[:1].lower() in "aeiou" else "a ") + noun


def register_study(study: Study) -> Study:
    """Add ``study`` to the registry (run order: ``study.order``, then registration); returns it.

    Parameters
    ----------
    study : Study
        The study to register under ``study.name``. Registering the same object again does
        nothing.

    Returns
    -------
    Study
        ``study`` itself, so a module can write ``TABLE1 = register_study(Study(...))``.

    Raises
    ------
    TypeError
        If ``study`` is not a :class:`Study`.
    ReproduceError
        If a different study of the same name is registered already.

    Examples
    --------
    >>> from rankedassign.experiments import get_study, register_study
    >>> register_study(get_study("sweep")) is get_study("sweep")  # idempotent
    True
    """
    if not isinstance(study, Study):
        raise TypeError(f"study must be a Study, got {type(study).__name__}")
    known = _REGISTRY.get(study.name)
    if known is not None and known is not study:
        raise ReproduceError(f"a different study named {study.name!r} is registered already")
    _REGISTRY[study.name] = study
    return study


def study_names() -> tuple[str, ...]:
    """Names of the registered studies, in run order.

    Returns
    -------
    tuple of str
        The names, sorted by ``Study.order`` (ties in registration order).

    Examples
    --------
    >>> from rankedassign.experiments import study_names
    >>> study_names()[:2]
    ('table1', 'sweep')
    """
    return tuple(sorted(_REGISTRY, key=lambda n: _REGISTRY[n].order))


def default_study_names() -> tuple[str, ...]:
    """Names of the studies a run without named studies runs, in run order.

    These are the studies whose ``default_run`` is True: the paper's own. The studies of the
    later methods (``default_run=False``) run when named, or with ``--all``
    (``studies="all"``).

    Returns
    -------
    tuple of str
        A subsequence of :func:`study_names`.

    Examples
    --------
    >>> from rankedassign.experiments import default_study_names
    >>> default_study_names()
    ('table1', 'sweep', 'tracking', 'tracking_var', 'ablation', 'optimum', 'random_readings')
    """
    return tuple(n for n in study_names() if _REGISTRY[n].default_run)


def get_study(name: str) -> Study:
    """The registered study called ``name``.

    Parameters
    ----------
    name : str
        A registered name (:func:`study_names`), e.g. ``"table1"``.

    Returns
    -------
    Study
        The registered record.

    Raises
    ------
    ReproduceError
        For an unknown name; the message lists the known ones.

    Examples
    --------
    >>> from rankedassign.experiments import get_study
    >>> get_study("optimum").title
    'sampled error against the best error for as many distinct solutions'
    """
    try:
        return _REGISTRY[name]
    except (KeyError, TypeError):
        raise ReproduceError(
            f"unknown study {name!r}; choose from {', '.join(study_names())}"
        ) from None


def study_config(config, study: Study):
    """Settings of ``study`` from ``config`` (its own settings, a :class:`Config` or None)."""
    if config is None:
        return study.full()
    if isinstance(config, Config):
        return config[study.name]
    if not isinstance(config, study.config_type):
        raise TypeError(
            f"config must be {_a(study.config_type.__name__)} or Config, "
            f"got {type(config).__name__}"
        )
    return config


def run_study(
    study: str | Study,
    config=None,
    *,
    seed: int = 0,
    executor: Executor | None = None,
    progress: bool = True,
    return_runs: bool = False,
    desc: str | None = None,
):
    """Run one study: its tasks through ``executor``, then its summary.

    Parameters
    ----------
    study : str or Study
        A registered name (``"table1"``, ``"sweep"``, ...) or a :class:`Study`.
    config : optional
        The study's settings, or a :class:`Config` (its field of that name); default the
        paper's settings.
    seed : int, optional
        Study seed; Monte Carlo run ``r`` draws only from
        ``np.random.SeedSequence(seed).spawn(n)[r]``.
    executor : concurrent.futures.Executor, optional
        Where to run the tasks (default: in this process).
    progress : bool, optional
        Show a progress bar on stderr.
    return_runs : bool, optional
        Also return the per-run records.
    desc : str, optional
        Label of the progress bar (default: the study's name).

    Returns
    -------
    summary
        The study's typed summary (e.g. a list of :class:`~rankedassign.experiments.Table1Row`).
    runs : list
        Per-run records, only if ``return_runs``.

    Examples
    --------
    >>> from rankedassign.experiments import Table1Config, run_study
    >>> cfg = Table1Config(n_mc=1, families=("diagonal",), original_obs=500, n_chains=40)
    >>> rows = run_study("table1", cfg, seed=1, progress=False)
    >>> [(r.family, r.criterion) for r in rows]
    [('diagonal', 'stall'), ('diagonal', 'stale'), ('diagonal', 'full')]
    """
    st = study if isinstance(study, Study) else get_study(study)
    cfg = study_config(config, st)
    runs = run_tasks(st.task, st.tasks(cfg, seed), executor=executor, progress=progress,
                     desc=desc or st.name)
    summary = st.summarise(runs, cfg)
    return (summary, runs) if return_runs else summary


def run_warm_unit(function: Callable[..., Any], *args) -> None:
    """Run one :attr:`Study.warm_units` unit, ``function(*args)`` (picklable for a worker).

    Parameters
    ----------
    function : callable
        A module-level function of the study.
    *args
        Its arguments.
    """
    function(*args)


def warm_study(study: str | Study, config=None, *, executor: Executor | None = None) -> float:
    """Run ``study``'s tasks at its tiny settings; returns the seconds taken.

    This compiles the study's numba kernels (or loads them from numba's on-disk cache), so
    that the study's own tasks find them in the cache.

    Parameters
    ----------
    study : str or Study
        A registered name or a :class:`Study`.
    config : optional
        The settings the study will run with (its own, a :class:`Config` or None for the
        paper's); their tiny form (:attr:`Study.warm`) runs. A study without ``warm`` runs
        nothing.
    executor : concurrent.futures.Executor, optional
        Where to run the tiny tasks (default: one after the other in this process). With
        several workers, the study's :attr:`Study.warm_units` run first, then the first task
        of each :attr:`Study.warm_group`, side by side, so that the workers compile disjoint
        sets of kernels at once; then the rest.

    Returns
    -------
    float
        Wall time in seconds (0.0 for a study without ``warm``).

    Examples
    --------
    >>> from rankedassign.experiments import Config, warm_study
    >>> warm_study("table1", Config.quick()) >= 0.0
    True
    """
    st = study if isinstance(study, Study) else get_study(study)
    if st.warm is None:
        return 0.0
    t0 = time.perf_counter()
    if executor is None:
        for args in st.tasks(st.warm(study_config(config, st)), 0):
            _interrupts.check()  # a safe point between two tiny tasks
            st.task(*args)
        return time.perf_counter() - t0
    items, after = warm_plan([st], config)
    calls = [(run_warm_unit if unit else st.task, args) for _, args, unit in items]
    run_tasks(_call, calls, executor=executor, progress=False, after=after)
    return time.perf_counter() - t0


def _call(function: Callable[..., Any], args: tuple) -> None:
    function(*args)


def run_warm_item(study: str | Study, args: tuple, unit: bool = False) -> None:
    """Run one item of :func:`warm_plan`: a tiny task of ``study``, or with ``unit`` one of its
    :attr:`Study.warm_units` (picklable for a worker).

    Parameters
    ----------
    study : str or Study
        A registered name or a :class:`Study`.
    args : tuple
        The tiny task's arguments, or the unit ``(function, *args)``.
    unit : bool, optional
        ``args`` is a warm unit.
    """
    st = study if isinstance(study, Study) else get_study(study)
    if unit:
        run_warm_unit(*args)
    else:
        st.task(*args)


def warm_plan(studies: Sequence[str | Study], config=None, *, groups_first: Sequence = ()
              ) -> tuple[list[tuple[str, tuple, bool]], list[int | tuple[int, ...] | None]]:
    """The warm-up of ``studies`` as one queue, and what each item of it waits for.

    Items are ``(study, args, unit)`` for :func:`run_warm_item`, in this order: every warm
    unit (:attr:`Study.warm_units`); the first tiny task of every kernel group
    (:attr:`Study.warm_group`), those whose group key is in ``groups_first`` first; then the
    others. Each of the others waits (the ``after`` of :func:`run_tasks`) for the first task
    of its group, for its study's units, or for the first task of its
    :attr:`Study.warm_after` study, so that no two workers compile the same kernels at once.

    Parameters
    ----------
    studies : sequence of str or Study
        The studies, in the order their groups should go out.
    config : optional
        Their settings (as for :func:`warm_study`); their tiny form runs.
    groups_first : sequence, optional
        Group keys (:attr:`Study.warm_group` values) whose first tasks go before the others'.

    Returns
    -------
    items : list of tuple
        ``(study name, args, unit)``.
    after : list
        For each item, None or the index (a tuple of indices) of the items it waits for.

    Examples
    --------
    >>> from rankedassign.experiments import Config, warm_plan
    >>> items, after = warm_plan(["table1", "sweep"], Config.quick())
    >>> [(study, args[-1]) for study, args, _ in items]  # doctest: +NORMALIZE_WHITESPACE
    [('table1', 'diagonal'), ('table1', 'uniform'), ('table1', 'random'),
     ('table1', 'random-r_pd'), ('sweep', 'uniform'), ('sweep', 'random')]
    >>> after  # table1's first task compiles; the rest load its kernels after it
    [None, 0, 0, 0, 0, 4]
    """
    sts = [s if isinstance(s, Study) else get_study(s) for s in studies]
    names = {st.name for st in sts}
    units: list = []
    leaders: list = []
    followers: list = []  # (item, what it waits for, the group it is the first of or None)
    for st in sts:
        if st.warm is None:
            continue
        tiny = st.warm(study_config(config, st))
        tasks = list(st.tasks(tiny, 0))
        if st.warm_units is not None:
            units += [(st.name, tuple(u), True) for u in st.warm_units(tiny)]
            followers += [((st.name, args, False), ("units", st.name), None) for args in tasks]
            continue
        group = st.warm_group or (lambda args: None)
        after_other = st.warm_after if st.warm_after in names - {st.name} else None
        seen: set = set()
        for args in tasks:
            key = group(args)
            item = (st.name, args, False)
            if key in seen:
                followers.append((item, ("group", st.name, key), None))
            elif after_other is not None:
                followers.append((item, ("first", after_other), ("group", st.name, key)))
            else:
                rank = list(groups_first).index(key) if key in groups_first else len(groups_first)
                leaders.append((rank, len(leaders), item, ("group", st.name, key)))
            seen.add(key)
    leaders.sort(key=lambda t: t[:2])
    items = units + [item for _, _, item, _ in leaders] + [item for item, _, _ in followers]
    index: dict = {}  # ("group", study, key) and ("first", study) -> the index of its first item
    unit_index: dict = {}
    for i, (name, _args, unit) in enumerate(items):
        if unit:
            unit_index.setdefault(name, []).append(i)
        index.setdefault(("first", name), i)
    for j, (_, _, _item, key) in enumerate(leaders):
        index[key] = len(units) + j
    after: list = [None] * len(items)
    for j, (_item, wait, first_of) in enumerate(followers):
        i = len(units) + len(leaders) + j
        after[i] = tuple(unit_index[wait[1]]) if wait[0] == "units" else index[wait]
        if first_of is not None:  # its group's first task, itself waiting for another study
            index[first_of] = i
    return items, after


@dataclass(frozen=True, init=False)
class Config:
    """Settings of every registered study, by name: ``config.table1``, ``config["sweep"]``.

    Parameters
    ----------
    mode : {"full", "quick"}
        Whose settings fill the studies not given.
    **studies
        Settings of single studies, by name.

    Attributes
    ----------
    mode : {"full", "quick"}
        Whose settings filled the studies not given.
    studies : dict of str to settings
        The settings of every registered study, by name (each an instance of the study's
        ``config_type``); also reachable as ``config.<name>`` and ``config["<name>"]``.

    Raises
    ------
    ReproduceError
        For an unknown mode or study name.
    TypeError
        If a study's settings are not of its ``config_type``.

    Examples
    --------
    >>> from rankedassign.experiments import Config
    >>> Config.full().table1.n_mc, Config.quick().table1.n_chains
    (100, 10000)
    >>> Config.quick().with_mc(3).sweep.n_mc
    3
    """

    mode: str
    studies: dict = field(default_factory=dict)

    def __init__(self, mode: str = "full", **studies):
        if mode not in ("quick", "full"):
            raise ReproduceError(f"mode must be 'quick' or 'full', got {mode!r}")
        settings = {}
        for name in study_names():
            st = get_study(name)
            given = studies.pop(name, None)
            if given is None:
                given = st.full() if mode == "full" else st.quick()
            elif not isinstance(given, st.config_type):
                raise TypeError(f"{name} settings must be {_a(st.config_type.__name__)}, "
                                f"got {type(given).__name__}")
            settings[name] = given
        if studies:
            raise ReproduceError(
                f"unknown study {next(iter(studies))!r}; choose from {', '.join(study_names())}"
            )
        object.__setattr__(self, "mode", mode)
        object.__setattr__(self, "studies", settings)

    def __getattr__(self, name: str):
        studies = self.__dict__.get("studies", {})
        if name in studies:
            return studies[name]
        raise AttributeError(f"Config has no study {name!r}")

    def __getitem__(self, name: str):
        get_study(name)
        return self.studies[name]

    @classmethod
    def full(cls) -> Config:
        """The paper's settings: 100 Monte Carlo runs everywhere."""
        return cls("full")

    @classmethod
    def quick(cls) -> Config:
        """The paper's per-run settings with fewer Monte Carlo runs and sweep points."""
        return cls("quick")

    def replace(self, **studies) -> Config:
        """The same settings with some studies' settings replaced.

        Parameters
        ----------
        **studies
            New settings of single studies, by name (instances of each study's
            ``config_type``).

        Returns
        -------
        Config
            A new object with the same ``mode``; the studies not named keep their settings.
        """
        return Config(self.mode, **{**self.studies, **studies})

    def with_mc(self, n_mc: int) -> Config:
        """The same settings with ``n_mc`` Monte Carlo runs in every study.

        Parameters
        ----------
        n_mc : int
            Monte Carlo runs, ``>= 1``.

        Returns
        -------
        Config
            A new object in which every study's ``n_mc`` is ``n_mc`` (other settings kept).

        Raises
        ------
        ValueError
            If ``n_mc`` is not a positive integer.
        """
        if isinstance(n_mc, bool) or not isinstance(n_mc, int) or n_mc < 1:
            raise ValueError(f"n_mc must be a positive integer, got {n_mc!r}")
        return self.replace(
            **{s: dataclasses.replace(c, n_mc=n_mc) for s, c in self.studies.items()}
        )

    def to_dict(self) -> dict:
        """Plain-data view (for the report's ``config.json``).

        Returns
        -------
        dict
            ``{"mode": mode, <study>: {field: value}, ...}``, each study's settings as
            :func:`dataclasses.asdict` gives them.
        """
        return {"mode": self.mode,
                **{s: dataclasses.asdict(c) for s, c in self.studies.items()}}


def config_from_dict(base: Config, overrides: dict) -> Config:
    """``base`` with per-study fields replaced, e.g. ``{"table1": {"n_mc": 3}}``.

    Parameters
    ----------
    base : Config
        The settings to start from.
    overrides : dict
        ``{study: {field: value}}``; lists become tuples.

    Returns
    -------
    Config
        A new object: ``base`` with the named fields replaced (re-validated by each study's
        settings type).

    Raises
    ------
    ReproduceError
        Unknown study or setting, or a value the study's settings reject.

    Warns
    -----
    DeprecationWarning
        For a removed setting that its study still names in the class attribute
        ``DEPRECATED_SETTINGS`` (``{name: what replaced it}``); the setting is then ignored.
        For a renamed setting's old name (the class attribute ``RENAMED_SETTINGS``,
        ``{old: new}``, :func:`~rankedassign.experiments.config.renamed_settings`), naming the
        new one; its value is then the new setting's.

    Examples
    --------
    >>> from rankedassign.experiments import Config, config_from_dict
    >>> config_from_dict(Config.quick(), {"sweep": {"chain_lengths": [5]}}).sweep.chain_lengths
    (5,)
    """
    if not isinstance(overrides, dict):
        raise ReproduceError(f"config overrides must be a mapping of studies, got "
                             f"{_short(overrides)}")
    changes = {}
    for name, fields in overrides.items():
        if name not in study_names():
            raise ReproduceError(
                f"config: unknown study {name!r}; choose from {study_names()}"
            )
        if not isinstance(fields, dict):
            raise ReproduceError(f"config for {name!r} must be a mapping of its settings "
                                 f"(e.g. {{\"n_mc\": 5}}), got {_short(fields)}")
        sub = base[name]
        # a setting that was removed keeps a deprecated alias for a release (SciPy's
        # practice): its settings type names it in DEPRECATED_SETTINGS with what replaced it,
        # and it is ignored after a warning
        deprecated = getattr(type(sub), "DEPRECATED_SETTINGS", {})
        for old in sorted(set(fields) & set(deprecated)) if isinstance(fields, dict) else ():
            warnings.warn(f"config for {name!r}: {old!r} is deprecated and ignored; "
                          f"{deprecated[old]}", DeprecationWarning, stacklevel=2)
            fields = {k: v for k, v in fields.items() if k != old}
        # a renamed setting's old name reads for a release, with a warning naming the new one
        try:
            fields = rename_settings(fields, getattr(type(sub), "RENAMED_SETTINGS", {}),
                                     f"config for {name!r}: ")
        except TypeError as exc:
            raise ReproduceError(str(exc)) from None
        known = {f.name for f in dataclasses.fields(sub)}
        if not isinstance(fields, dict) or not set(fields) <= known:
            bad = sorted(set(fields) - known) if isinstance(fields, dict) else fields
            raise ReproduceError(f"config: unknown setting(s) {bad} for study {name!r}")
        vals = {k: tuple(v) if isinstance(v, list) else v for k, v in fields.items()}
        try:
            changes[name] = dataclasses.replace(sub, **vals)
        except (TypeError, ValueError) as exc:
            raise ReproduceError(f"config for {name!r}: {exc}") from None
    return base.replace(**changes)


def _short(value) -> str:
    """``value``'s type and a bounded repr, for messages about what a user's file holds."""
    try:
        text = repr(value)
    except RecursionError:  # pragma: no cover - a structure nested past Python's limit
        text = "..."
    if len(text) > 60:
        text = text[:57] + "..."
    return f"{type(value).__name__} {text}"


def per_family_tasks(cfg, seed: int) -> list[tuple]:
    """``(cfg, seed, run, family)`` for every family and Monte Carlo run (family-major)."""
    return [(cfg, seed, r, fam) for fam in cfg.families for r in range(cfg.n_mc)]


def as_rows(summary) -> list[dict]:
    """Records (dataclasses) as plain dicts, for CSV."""
    if isinstance(summary, Sequence):
        return [dataclasses.asdict(r) for r in summary]
    return [dataclasses.asdict(summary)]
