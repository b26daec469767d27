"""The 12-target scenario of the tracking study (spec §8) and its measurement generator."""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np

from ..engine.rng import check_rng
from ..validation import check_int, check_type
from .models import Model, make_model

__all__ = ["MAX_SCANS", "TARGETS", "Truth", "Scan", "paper_truth", "generate_measurements",
           "Scenario", "make_scenario", "check_n_scans"]

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
        Name of the model's preset (``"paper"``, ``"paper-var"`` or ``"vo"``,
        :data:`~rankedassign.tracking.models.PRESETS`).
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


def make_scenario(preset: str = "paper", *, rng=None, n_scans: int = 100) -> Scenario:
    """Build a preset's model, the truth of spec §8 and simulated measurements.

    Parameters
    ----------
    preset : {"paper", "paper-var", "vo"}
    rng : optional
        Randomness of the measurements.
    n_scans : int
        Number of scans (default 100, at most :data:`MAX_SCANS`).

    Returns
    -------
    Scenario

    Examples
    --------
    >>> from rankedassign.tracking.scenario import make_scenario
    >>> sc = make_scenario("vo", rng=0, n_scans=3)
    >>> sc.model.clutter.rate, len(sc.scans)
    (30.0, 3)
    """
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
