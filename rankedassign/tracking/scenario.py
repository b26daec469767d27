"""The 12-target scenario of the tracking study (spec §8) and its measurement generator."""

from __future__ import annotations

import dataclasses
import math
import numbers
from dataclasses import dataclass

import numpy as np

from ..engine.rng import check_rng
from ..validation import MAX_WORK_BYTES, check_int, check_type
from .models import Model, PoissonClutter, make_model

__all__ = ["MAX_SCANS", "TARGETS", "Truth", "Scan", "paper_truth", "generate_measurements",
           "Scenario", "make_scenario", "check_n_scans", "check_n_targets", "large_model",
           "large_truth", "LARGE_CELL", "LARGE_SPEED", "LARGE_BYTES"]

# Spec §8 (Vo's public gen_truth.m): x_start [p_x, v_x, p_y, v_y], t_birth, t_death (1-based,
# inclusive; t_death = 101 means the target survives to the end of the run).
TARGETS = (
    ((0.0, 0.0, 0.0, -10.0), 1, 70),
    ((400.0, -10.0, -600.0, 5.0), 1, 101),
    ((-800.0, 20.0, -200.0, -5.0), 1, 70),
    ((400.0, -7.0, -600.0, -4.0), 20, 101),
    ((400.0, -2.5, -600.0, 10.0), 20, 101),
    ((0.0, 7.5, 0.0, -5.0), 20, 101),
    ((-800.0, 12.0, -200.0, 7.0), 40, 101),
    ((-200.0, 15.0, 800.0, -10.0), 40, 101),
    ((-800.0, 3.0, -200.0, 15.0), 60, 101),
    ((-200.0, -3.0, 800.0, -15.0), 60, 101),
    ((0.0, -20.0, 0.0, -15.0), 80, 101),
    ((-200.0, 15.0, 800.0, -5.0), 80, 101),
)


#: Largest number of scans of a simulated run: the truth alone takes 384 bytes a scan (12
#: targets x 4 states x float64) and the measurements and per-scan records several kilobytes
#: more; a million scans is hours of filtering, far beyond the studies' 100.
MAX_SCANS = 10**6


def _size(n_bytes: float) -> str:
    """``n_bytes`` in binary units, e.g. ``'349.2 TiB'``."""
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if n_bytes < 1024 or unit == "PiB":
            return f"{n_bytes:.1f} {unit}" if unit != "B" else f"{int(n_bytes)} B"
        n_bytes /= 1024
    raise AssertionError  # pragma: no cover


def check_n_scans(n_scans) -> int:
    """``n_scans`` as an int in ``[1, MAX_SCANS]``; above the bound the message says the memory.

    Parameters
    ----------
    n_scans : int
        Number of scans of a simulated run (a Python or numpy integer, not ``bool``).

    Returns
    -------
    int
        ``n_scans`` as a Python int, in ``[1, MAX_SCANS]``.

    Raises
    ------
    TypeError
        If ``n_scans`` is not an int (``bool`` included).
    ValueError
        If it is below 1 or above :data:`MAX_SCANS`.

    Examples
    --------
    >>> from rankedassign.tracking.scenario import check_n_scans
    >>> check_n_scans(100)
    100
    >>> check_n_scans(10**12)
    Traceback (most recent call last):
    ...
    ValueError: n_scans must be an int <= 1000000 (MAX_SCANS), got 1000000000000: the truth of
    that many scans alone would need 349.2 TiB (384 bytes a scan)
    """
    if (isinstance(n_scans, numbers.Integral) and not isinstance(n_scans, bool)
            and n_scans > MAX_SCANS):
        per_scan = len(TARGETS) * 4 * 8
        raise ValueError(
            f"n_scans must be an int <= {MAX_SCANS} (MAX_SCANS), got {int(n_scans)}: the truth "
            f"of that many scans alone would need {_size(int(n_scans) * per_scan)} "
            f"({per_scan} bytes a scan)"
        )
    return check_int(n_scans, "n_scans", minimum=1, maximum=MAX_SCANS)


@dataclass(frozen=True, eq=False)
class Truth:
    """Ground truth of a run.

    Attributes
    ----------
    states : ndarray, shape (n_scans, n_targets, 4)
        State of target ``t`` at scan ``k`` (0-based ``k``), all-NaN where it does not exist.
    birth, death : ndarray of int, shape (n_targets,)
        1-based first and last scan at which each target exists (clipped to ``n_scans``).
    """

    states: np.ndarray
    birth: np.ndarray
    death: np.ndarray

    @property
    def n_scans(self) -> int:
        """Number of scans."""
        return int(self.states.shape[0])

    @property
    def positions(self) -> np.ndarray:
        """Positions ``(p_x, p_y)``, shape (n_scans, n_targets, 2), NaN where absent."""
        return self.states[:, :, [0, 2]]

    @property
    def exists(self) -> np.ndarray:
        """Existence mask, shape (n_scans, n_targets)."""
        return ~np.isnan(self.states[:, :, 0])

    @property
    def n_targets(self) -> np.ndarray:
        """Number of targets per scan, shape (n_scans,)."""
        return self.exists.sum(axis=1)

    def at(self, k: int) -> tuple[np.ndarray, np.ndarray]:
        """``(labels (n,), states (n, 4))`` of the targets at 0-based scan ``k``.

        Parameters
        ----------
        k : int
            0-based scan index, ``0 <= k < n_scans`` (numpy indexing: a negative ``k`` counts
            from the end).

        Returns
        -------
        labels : ndarray of int64, shape (n,)
            Indices (into the target axis of :attr:`states`, increasing) of the ``n`` targets
            that exist at scan ``k``.
        states : ndarray of float64, shape (n, 4)
            Their states ``[p_x, v_x, p_y, v_y]`` at scan ``k``.
        """
        idx = np.flatnonzero(self.exists[k])
        return idx, self.states[k, idx]


def paper_truth(n_scans: int = 100, F=None) -> Truth:
    """The 12-target truth of spec §8.

    Parameters
    ----------
    n_scans : int
        Number of scans ``K`` (the paper: 100; at most :data:`MAX_SCANS`). Targets with
        ``t_death = 101`` survive to the end whatever ``K`` is.
    F : array_like, shape (4, 4), optional
        Transition matrix (default: constant velocity with ``Δ = 1``).

    Returns
    -------
    Truth

    Notes
    -----
    Recording convention of Vo's ``gen_truth.m``: for ``k = t_birth .. min(t_death, K)``,
    ``x ← F x`` *then* record ``x``; the state at the birth scan is ``F x_start``. Noiseless.

    Examples
    --------
    >>> from rankedassign.tracking.scenario import paper_truth
    >>> t = paper_truth()
    >>> t.states[0, 0].tolist()
    [0.0, 0.0, -10.0, -10.0]
    >>> t.n_targets[[0, 19, 39, 59, 70, 79]].tolist()
    [3, 6, 8, 10, 8, 10]
    """
    K = check_n_scans(n_scans)
    if F is None:
        F = np.kron(np.eye(2), [[1.0, 1.0], [0.0, 1.0]])
    F = np.asarray(F, dtype=np.float64)
    n = len(TARGETS)
    states = np.full((K, n, 4), np.nan)
    birth = np.empty(n, dtype=np.int64)
    death = np.empty(n, dtype=np.int64)
    for t, (x0, tb, td) in enumerate(TARGETS):
        td = K if td > 100 else min(td, K)  # 101 = survives to the end
        birth[t], death[t] = tb, td
        x = np.array(x0)
        for k in range(tb, td + 1):
            x = F @ x  # x <- F x, then record (gen_truth.m)
            states[k - 1, t] = x
    return Truth(states, birth, death)


@dataclass(frozen=True, eq=False)
class Scan:
    """The measurements of one scan.

    Attributes
    ----------
    z : ndarray, shape (M, 2)
        Positions; target detections first (in target order), then clutter.
    origin : ndarray of int, shape (M,)
        Index of the target that generated each measurement, ``-1`` for clutter.
    """

    z: np.ndarray
    origin: np.ndarray


def generate_measurements(truth: Truth, model: Model, *, rng=None) -> list[Scan]:
    """Simulate the measurements of every scan (spec §8).

    Parameters
    ----------
    truth : Truth
    model : Model
    rng : None, int, SeedSequence, Generator or RandomState, optional
        Randomness (anything :func:`numpy.random.default_rng` accepts; a Generator or a
        RandomState is drawn from directly).

    Returns
    -------
    list of Scan
        One per scan.

    Notes
    -----
    Each target present is detected independently with ``P_D``; a detection is
    ``z = H x + v``, ``v ~ N(0, R)`` (not clipped to the region). Clutter: ``Poisson(λ_c)``
    points uniform on the region.

    Examples
    --------
    >>> from rankedassign.tracking.models import make_model
    >>> from rankedassign.tracking.scenario import generate_measurements, paper_truth
    >>> scans = generate_measurements(paper_truth(5), make_model("paper"), rng=1)
    >>> len(scans), scans[0].z.shape[1]
    (5, 2)
    """
    check_type(truth, "truth", Truth, "build one with paper_truth(n_scans)")
    check_type(model, "model", Model, "build one with make_model(preset) or Model(...)")
    gen = check_rng(rng)
    H, R, p_d = model.sensor.H, model.sensor.R, model.sensor.p_d
    Lr = np.linalg.cholesky(R)
    out = []
    for k in range(truth.n_scans):
        labels, X = truth.at(k)
        detected = gen.random(labels.size) < p_d
        Xd = X[detected]
        zt = Xd @ H.T + gen.standard_normal((Xd.shape[0], 2)) @ Lr.T
        zc = model.clutter.sample(gen)
        z = np.vstack([zt, zc]) if zc.size else zt.reshape(-1, 2)
        origin = np.concatenate([labels[detected], np.full(zc.shape[0], -1)]).astype(np.int64)
        z = np.ascontiguousarray(z, dtype=np.float64)
        z.setflags(write=False)
        out.append(Scan(z, origin))
    return out


@dataclass(frozen=True, eq=False)
class Scenario:
    """A model, its truth and one realisation of the measurements.

    Attributes
    ----------
    preset : str
        Name of the preset: ``"paper"``, ``"paper-var"`` or ``"vo"``
        (:data:`~rankedassign.tracking.models.PRESETS`), or ``"large"``.
    model : Model
        The preset's model, which drew the measurements.
    truth : Truth
        Ground truth of the run (:func:`paper_truth` with the model's ``F``).
    scans : list of Scan
        The measurements of every scan, ``len(scans) == truth.n_scans``
        (:func:`generate_measurements`).
    """

    preset: str
    model: Model
    truth: Truth
    scans: list


#: Side of the square each target of the ``"large"`` scenario has to itself: one target per
#: 200 m x 200 m.
LARGE_CELL = 200.0
#: Standard deviation (m/s) of each velocity component of a ``"large"`` scenario's targets.
LARGE_SPEED = 3.0
#: Bytes a ``"large"`` scenario holds per target and scan: its truth (4 float64) and about 1.3
#: measurements (a detection and 0.3 clutter points, position, origin and their share of the
#: arrays), rounded up.
LARGE_BYTES = 64


def check_n_targets(n_targets, n_scans: int) -> int:
    """``n_targets`` of the ``"large"`` scenario as an int ``>= 0`` that fits in memory.

    Parameters
    ----------
    n_targets : int
        Number of targets (a Python or numpy integer, not ``bool``).
    n_scans : int
        Number of scans (already checked).

    Returns
    -------
    int

    Raises
    ------
    TypeError
        If ``n_targets`` is not an int.
    ValueError
        If it is negative, or if the scenario would need more than
        :data:`~rankedassign.validation.MAX_WORK_BYTES` (the message says how much).

    Examples
    --------
    >>> from rankedassign.tracking.scenario import check_n_targets
    >>> check_n_targets(1000, 100)
    1000
    >>> check_n_targets(10**7, 100)
    Traceback (most recent call last):
    ...
    ValueError: n_targets = 10000000 with n_scans = 100 would need 59.6 GiB (64 bytes a target
    and scan), above MAX_WORK_BYTES = 4.0 GiB; use fewer targets or scans
    """
    if isinstance(n_targets, bool) or not isinstance(n_targets, numbers.Integral):
        raise TypeError(f"n_targets must be an int, got {type(n_targets).__name__} "
                        f"{n_targets!r}")
    n_targets = int(n_targets)
    if n_targets < 0:
        raise ValueError(f"n_targets must be >= 0, got {n_targets}")
    need = n_targets * n_scans * LARGE_BYTES
    if need > MAX_WORK_BYTES:
        raise ValueError(
            f"n_targets = {n_targets} with n_scans = {n_scans} would need {_size(need)} "
            f"({LARGE_BYTES} bytes a target and scan), above MAX_WORK_BYTES = "
            f"{_size(MAX_WORK_BYTES)}; use fewer targets or scans")
    return n_targets


def large_model(n_targets: int) -> Model:
    """The model of the ``"large"`` scenario with ``n_targets`` targets.

    Vo's model (``make_model("vo")``: constant velocity, position sensor with
    ``σ_v = 10`` m, ``P_D = 0.98``, ``P_S = 0.99``, the four birth places) with the clutter
    density of Vo's example, ``κ = 30 / 2000² = 7.5·10⁻⁶`` m⁻², over the scenario's square of
    side ``LARGE_CELL √max(n_targets, 1)`` centred on the origin (so ``0.3 n_targets`` clutter
    points a scan on average).

    Parameters
    ----------
    n_targets : int
        Number of targets (checked by the caller).

    Returns
    -------
    Model

    Examples
    --------
    >>> from rankedassign.tracking.scenario import large_model
    >>> large_model(100).clutter.region, large_model(100).clutter.rate
    (((-1000.0, 1000.0), (-1000.0, 1000.0)), 30.0)
    """
    base = make_model("vo")
    half = 0.5 * LARGE_CELL * math.sqrt(max(n_targets, 1))
    rate = base.clutter.intensity * (2 * half) ** 2
    return dataclasses.replace(base, clutter=PoissonClutter(rate, ((-half, half), (-half, half))))


def large_truth(n_targets: int, n_scans: int, F: np.ndarray, rng=None) -> Truth:
    """``n_targets`` targets at constant density that live through every scan.

    Positions uniform over the square of :func:`large_model` at scan 1, velocities
    ``N(0, LARGE_SPEED²)`` per axis, then ``x ← F x`` without process noise (as
    :func:`paper_truth`); no target is born or dies during the run, so the density stays one
    target per ``LARGE_CELL²`` (targets near the edge may drift out of the square).

    Parameters
    ----------
    n_targets, n_scans : int
        Checked by the caller.
    F : ndarray, shape (4, 4)
        Transition matrix.
    rng : optional
        Randomness (anything :func:`numpy.random.default_rng` accepts).

    Returns
    -------
    Truth

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.scenario import large_truth
    >>> t = large_truth(3, 2, np.eye(4), rng=0)
    >>> t.states.shape, t.birth.tolist(), t.death.tolist()
    ((2, 3, 4), [1, 1, 1], [2, 2, 2])
    """
    gen = check_rng(rng)
    half = 0.5 * LARGE_CELL * math.sqrt(max(n_targets, 1))
    x = np.empty((n_targets, 4))
    x[:, [0, 2]] = gen.uniform(-half, half, (n_targets, 2))
    x[:, [1, 3]] = gen.normal(0.0, LARGE_SPEED, (n_targets, 2))
    states = np.empty((n_scans, n_targets, 4))
    states[0] = x
    for k in range(1, n_scans):
        states[k] = states[k - 1] @ F.T  # x <- F x
    return Truth(states, np.ones(n_targets, dtype=np.int64),
                 np.full(n_targets, n_scans, dtype=np.int64))


def make_scenario(preset: str = "paper", *, rng=None, n_scans: int = 100,
                  n_targets: int | None = None) -> Scenario:
    """Build a preset's model, the truth of spec §8 and simulated measurements.

    Parameters
    ----------
    preset : {"paper", "paper-var", "vo", "large"}
        A model preset with the 12-target truth of spec §8, or ``"large"``: ``n_targets``
        targets at one per 200 m x 200 m, alive through the run (:func:`large_truth`), with
        Vo's model and clutter density over their square (:func:`large_model`).
    rng : optional
        Randomness of the measurements (and of the ``"large"`` truth: the truth draws first).
    n_scans : int
        Number of scans (default 100, at most :data:`MAX_SCANS`).
    n_targets : int, optional
        Targets of the ``"large"`` scenario (default 100); refused for the other presets.

    Returns
    -------
    Scenario

    Raises
    ------
    TypeError
        If ``n_targets`` is not an int.
    ValueError
        On an unknown preset, ``n_targets`` negative, given with another preset, or beyond
        memory (the message says the bytes it would need, :func:`check_n_targets`).

    Examples
    --------
    >>> from rankedassign.tracking.scenario import make_scenario
    >>> sc = make_scenario("vo", rng=0, n_scans=3)
    >>> sc.model.clutter.rate, len(sc.scans)
    (30.0, 3)
    >>> sc = make_scenario("large", n_targets=400, rng=0, n_scans=2)
    >>> sc.truth.states.shape, sc.model.clutter.rate
    ((2, 400, 4), 120.0)
    """
    if preset == "large":
        n_scans = check_n_scans(n_scans)
        n_targets = check_n_targets(100 if n_targets is None else n_targets, n_scans)
        model = large_model(n_targets)
        gen = check_rng(rng)
        truth = large_truth(n_targets, n_scans, model.motion.F, gen)
        return Scenario(preset, model, truth, generate_measurements(truth, model, rng=gen))
    if n_targets is not None:
        raise ValueError(f"n_targets is an option of the 'large' scenario only (preset "
                         f"{preset!r} has the 12 targets of spec §8)")
    model = make_model(preset)
    truth = paper_truth(n_scans, model.motion.F)
    return Scenario(preset, model, truth, generate_measurements(truth, model, rng=rng))


COUNTER_KEYS = ("invocations", "sweeps", "row_updates", "n_unique", "n_tracks", "n_meas",
                "n_meas_gated", "n_groups")


@dataclass(frozen=True, eq=False)
class ScenarioRun:
    """Result of :func:`run_scenario`.

    Attributes
    ----------
    scenario : Scenario
        Model, truth and the measurements the filter saw.
    association : str
        ``repr`` of the association used.
    extraction : str
        State extraction used (``"hysteresis"`` or ``"map"``).
    truth : ndarray, shape (n_scans, n_targets, 2)
        True positions, NaN where a target does not exist.
    estimates : ndarray, shape (n_scans, n_est_tracks, 2)
        Estimated positions, one column per reported label (order of first report), NaN where
        a label is not reported.
    estimate_labels : list of tuple
        Labels ``(birth scan, birth index)`` of the columns of ``estimates``.
    labelled_estimates : list of dict
        Per scan, ``{label: state (4,)}`` of the reported tracks.
    existence : list of dict
        Per scan, ``{label: r}`` of every track held after the update.
    invocations, sweeps, row_updates, n_unique : ndarray of int64, shape (n_scans,)
        Association accounting per scan (sampler calls, Markov-chain observations = full
        sweeps, single-row updates, unique hypotheses).
    n_tracks : ndarray of int64, shape (n_scans,)
        Predicted tracks per scan (rows of the association, births included).
    n_estimated : ndarray of int64, shape (n_scans,)
        Reported tracks per scan.
    n_meas, n_meas_gated, n_groups : ndarray of int64, shape (n_scans,)
        Measurements received, measurements inside some gate, problems solved.
    timings : dict of ndarray
        Per-scan seconds of ``prediction``, ``cost``, ``association``, ``update``.
    """

    scenario: Scenario
    association: str
    extraction: str
    truth: np.ndarray
    estimates: np.ndarray
    estimate_labels: list
    labelled_estimates: list
    existence: list
    invocations: np.ndarray
    sweeps: np.ndarray
    row_updates: np.ndarray
    n_unique: np.ndarray
    n_tracks: np.ndarray
    n_estimated: np.ndarray
    n_meas: np.ndarray
    n_meas_gated: np.ndarray
    n_groups: np.ndarray
    timings: dict

    @property
    def n_scans(self) -> int:
        """Number of scans."""
        return int(self.truth.shape[0])
