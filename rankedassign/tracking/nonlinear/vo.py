"""Vo's non-linear examples: the coordinated-turn, bearing–range presets ``"vo-ekf"``, ``"vo-ukf"``.

Every number is read from the four example folders ``jointglmb/ekf``, ``jointglmb/ukf``,
``jointlmb/ekf`` and ``jointlmb/ukf`` of Vo's public MATLAB toolbox (their ``gen_model.m``,
``gen_truth.m``, ``gen_meas.m`` and ``gen_newstate_fn.m`` are identical across the four; the
filters' settings are in each ``run_filter.m``). The table with the file of every number is on
the "Non-linear models" page of the documentation.

The state is Vo's ``[p_x, v_x, p_y, v_y, ω]`` and a measurement his ``[bearing, range]`` from a
sensor at the origin.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ...engine.rng import check_rng
from ...validation import check_choice, check_int
from ..scenario import Scan, Truth
from .filters import ExtendedKalmanFilter, UnscentedKalmanFilter
from .models import BearingRange, BearingRangeClutter, CoordinatedTurn, GaussianBirth, wrap_angle

__all__ = [
    "NONLINEAR_PRESETS",
    "VO_TARGETS",
    "VoFilterSettings",
    "NonlinearModel",
    "make_nonlinear_model",
    "vo_truth",
    "generate_nonlinear_measurements",
]

#: The presets of :func:`make_nonlinear_model`.
NONLINEAR_PRESETS = ("vo-ekf", "vo-ukf")

_TURN = 2.0 * math.pi / 180.0  # gen_truth.m: wturn

#: Vo's ten targets (``gen_truth.m``): initial state ``[p_x, v_x, p_y, v_y, ω]``, 1-based birth
#: and death scan (inclusive; 101 = to the end of the 100-scan run). The state recorded at the
#: birth scan is the initial state moved one scan on, as in his loop.
VO_TARGETS = (
    ((1000 + 3.8676, -10.0, 1500 - 11.7457, -10.0, _TURN / 8), 1, 101),
    ((-250 - 5.8857, 20.0, 1000 + 11.4102, 3.0, -_TURN / 3), 10, 101),
    ((-1500 - 7.3806, 11.0, 250 + 6.7993, 10.0, -_TURN / 2), 10, 101),
    ((-1500.0, 43.0, 250.0, 0.0, 0.0), 10, 66),
    ((250 - 3.8676, 11.0, 750 - 11.0747, 5.0, _TURN / 4), 20, 80),
    ((-250 + 7.3806, -12.0, 1000 - 6.7993, -12.0, _TURN / 2), 40, 101),
    ((1000.0, 0.0, 1500.0, -10.0, _TURN / 4), 40, 101),
    ((250.0, -50.0, 750.0, 0.0, -_TURN / 4), 40, 80),
    ((1000.0, -50.0, 1500.0, 0.0, -_TURN / 4), 60, 101),
    ((250.0, -40.0, 750.0, 25.0, _TURN / 4), 60, 101),
)


@dataclass(frozen=True)
class VoFilterSettings:
    """The settings of Vo's filters in his non-linear examples (each ``run_filter.m``).

    Attributes
    ----------
    glmb_h_upd : int
        δ-GLMB: requested number of updated hypotheses ``H_upd`` (3000).
    glmb_h_max : int
        δ-GLMB: cap on the posterior hypotheses ``H_max`` (3000).
    glmb_hyp_threshold : float
        δ-GLMB: pruning threshold of hypothesis weights (1e-15).
    lmb_t_max : int
        LMB: most tracks kept (100).
    lmb_track_threshold : float
        LMB: tracks with ``r`` at or below it are pruned (1e-3).
    lmb_h_upd : int
        LMB: requested number of hypotheses of its GLMB update (1000).
    lmb_l_max : int
        LMB: most Gaussians per track (10).
    elim_threshold : float
        LMB: Gaussians of a track with a weight at or below it are pruned (1e-5).
    merge_threshold : float
        LMB: Mahalanobis merging threshold of a track's Gaussians (4).
    gate_prob : float
        Gate probability ``P_G`` (0.9999999); the gate is ``χ²₂`` at it (:attr:`gate`).
    ukf_alpha, ukf_beta, ukf_kappa : float
        The UKF's ``α = 1``, ``β = 2``, ``κ = 2``.

    Examples
    --------
    >>> from rankedassign.tracking.nonlinear import VoFilterSettings
    >>> round(VoFilterSettings().gate, 3)
    32.236
    """

    glmb_h_upd: int = 3000
    glmb_h_max: int = 3000
    glmb_hyp_threshold: float = 1e-15
    lmb_t_max: int = 100
    lmb_track_threshold: float = 1e-3
    lmb_h_upd: int = 1000
    lmb_l_max: int = 10
    elim_threshold: float = 1e-5
    merge_threshold: float = 4.0
    gate_prob: float = 0.9999999
    ukf_alpha: float = 1.0
    ukf_beta: float = 2.0
    ukf_kappa: float = 2.0

    @property
    def gate(self) -> float:
        """``chi2inv(P_G, 2)``: the gate on the squared Mahalanobis distance."""
        from scipy.stats import chi2  # here: scipy.stats takes 0.3 s to import

        return float(chi2.ppf(self.gate_prob, 2))

    def filter_options(self, kind: str) -> dict:
        """These settings as keyword arguments of the LMB or the δ-GLMB filter.

        The requested hypotheses of the LMB's update (``lmb_h_upd``) belong to its
        association (e.g. ``ShortChainGibbs(1000, ...)``), not to the filter.

        Parameters
        ----------
        kind : {"lmb", "glmb"}
            :class:`~rankedassign.tracking.LMBFilter` or
            :class:`~rankedassign.tracking.GLMBFilter`.

        Returns
        -------
        dict
            ``gate_prob`` and, for the LMB, ``max_tracks``, ``prune_track``,
            ``max_components``, ``prune_component``, ``merge_threshold`` and
            ``merge_rule="heaviest"`` (Vo's ``gaus_merge`` measures the distance in the
            heaviest component's covariance); for the δ-GLMB ``h_upd``, ``h_max``,
            ``prune_hypothesis``.

        Raises
        ------
        ValueError
            On another ``kind``.

        Examples
        --------
        >>> from rankedassign.tracking.nonlinear import VoFilterSettings
        >>> VoFilterSettings().filter_options("glmb")["h_upd"]
        3000
        """
        kind = check_choice(kind, "kind", ("lmb", "glmb"))
        if kind == "glmb":
            return {"gate_prob": self.gate_prob, "h_upd": self.glmb_h_upd,
                    "h_max": self.glmb_h_max, "prune_hypothesis": self.glmb_hyp_threshold}
        return {"gate_prob": self.gate_prob, "max_tracks": self.lmb_t_max,
                "prune_track": self.lmb_track_threshold, "max_components": self.lmb_l_max,
                "prune_component": self.elim_threshold, "merge_threshold": self.merge_threshold,
                "merge_rule": "heaviest"}


def _vo_birth() -> tuple:
    # gen_model.m: four single-Gaussian terms, std diag([50 50 50 50 6π/180]), P = B B'
    cov = np.diag([50.0, 50.0, 50.0, 50.0, 6.0 * math.pi / 180.0]) ** 2
    terms = (((-1500.0, 0.0, 250.0, 0.0, 0.0), 0.02), ((-250.0, 0.0, 1000.0, 0.0, 0.0), 0.02),
             ((250.0, 0.0, 750.0, 0.0, 0.0), 0.03), ((1000.0, 0.0, 1500.0, 0.0, 0.0), 0.03))
    return tuple(GaussianBirth(r, np.array(m), cov) for m, r in terms)


@dataclass(frozen=True)
class NonlinearModel:
    """A non-linear multi-object model: motion, sensor, clutter, birth, survival, filter.

    Attributes
    ----------
    motion : CoordinatedTurn
        Motion model (any object of the motion interface).
    sensor : BearingRange
        Measurement model with its ``p_d`` (any object of the measurement interface).
    clutter : BearingRangeClutter
        Poisson clutter uniform in measurement space.
    birth : tuple of GaussianBirth
        The LMB birth terms, labels ``(k, 1..B)``.
    p_s : float
        Survival probability.
    filter : ExtendedKalmanFilter or UnscentedKalmanFilter
        The single-object filter the preset prescribes.
    settings : VoFilterSettings
        The multi-object filters' settings.
    extraction : str
        ``"map"``: Vo's MAP-cardinality state extraction.
    n_scans : int
        Length of the preset's run (100).

    Examples
    --------
    >>> from rankedassign.tracking.nonlinear import make_nonlinear_model
    >>> m = make_nonlinear_model("vo-ukf")
    >>> m.clutter.rate, m.sensor.p_d, m.p_s, [b.r for b in m.birth]
    (15.0, 0.98, 0.99, [0.02, 0.02, 0.03, 0.03])
    """

    motion: CoordinatedTurn = field(default_factory=CoordinatedTurn)
    sensor: BearingRange = field(default_factory=BearingRange)
    clutter: BearingRangeClutter = field(default_factory=BearingRangeClutter)
    birth: tuple = field(default_factory=_vo_birth)
    p_s: float = 0.99
    filter: object = field(default_factory=ExtendedKalmanFilter)
    settings: VoFilterSettings = field(default_factory=VoFilterSettings)
    extraction: str = "map"
    n_scans: int = 100

    @property
    def position_indices(self) -> tuple:
        """State components of the position, named by the sensor model."""
        return self.sensor.position_indices


def make_nonlinear_model(preset: str = "vo-ekf") -> NonlinearModel:
    """The model of a non-linear preset.

    Parameters
    ----------
    preset : {"vo-ekf", "vo-ukf"}
        Vo's CT / bearing–range example with his EKF, or with his UKF (``α = 1``, ``β = 2``,
        ``κ = 2``, sigma points of the noise too, as his ``ut.m`` is used).

    Returns
    -------
    NonlinearModel

    Raises
    ------
    ValueError
        On an unknown preset.

    Examples
    --------
    >>> from rankedassign.tracking.nonlinear import make_nonlinear_model
    >>> make_nonlinear_model("vo-ekf").filter
    ExtendedKalmanFilter()
    """
    preset = check_choice(preset, "preset", NONLINEAR_PRESETS)
    settings = VoFilterSettings()
    if preset == "vo-ekf":
        filt = ExtendedKalmanFilter()
    else:
        filt = UnscentedKalmanFilter(settings.ukf_alpha, settings.ukf_beta, settings.ukf_kappa,
                                     augmented=True)
    return NonlinearModel(filter=filt, settings=settings)


def vo_truth(model: NonlinearModel | None = None, n_scans: int = 100) -> Truth:
    """Vo's ten noiseless CT trajectories (``gen_truth.m``).

    Parameters
    ----------
    model : NonlinearModel, optional
        Its motion moves the targets (default: the preset's ``CoordinatedTurn``).
    n_scans : int, optional
        Number of scans (default 100; deaths are clipped to it).

    Returns
    -------
    Truth
        States ``(n_scans, 10, 5)``, NaN where a target does not exist.

    Examples
    --------
    >>> from rankedassign.tracking.nonlinear import vo_truth
    >>> truth = vo_truth()
    >>> truth.states.shape, truth.n_targets[[0, 9, 65, 66, 99]].tolist()
    ((100, 10, 5), [1, 4, 10, 9, 7])
    """
    model = NonlinearModel() if model is None else model
    n_scans = check_int(n_scans, "n_scans", minimum=1)
    states = np.full((n_scans, len(VO_TARGETS), 5), np.nan)
    birth = np.array([b for _, b, _ in VO_TARGETS])
    death = np.minimum([d for _, _, d in VO_TARGETS], n_scans)
    for t, (x0, b, _) in enumerate(VO_TARGETS):
        x = np.array([x0])
        for k in range(b, death[t] + 1):
            x = model.motion.f(x)  # his loop moves the state before recording it
            states[k - 1, t] = x[0]
    return Truth(states, birth, death)


def generate_nonlinear_measurements(truth: Truth, model: NonlinearModel, *,
                                    rng=None) -> list[Scan]:
    """Detections (``P_D``, noisy ``h``) and clutter of every scan (``gen_meas.m``).

    Parameters
    ----------
    truth : Truth
        Target states in the model's state space.
    model : NonlinearModel
        Sensor (``h``, ``R``, ``p_d``) and clutter.
    rng : None, int, Generator, ...
        Source of the draws (anything :func:`numpy.random.default_rng` accepts). Per scan:
        ``random(n)`` for the detections, ``standard_normal((n_det, d_z))`` for their noise,
        then the clutter's draws.

    Returns
    -------
    list of Scan
        ``z (M, d_z)`` in ``[bearing, range]`` order, detections first (bearings wrapped to
        ``(−π, π]``), and their origins (target index, ``-1`` for clutter).

    Examples
    --------
    >>> from rankedassign.tracking.nonlinear import (generate_nonlinear_measurements,
    ...                                             make_nonlinear_model, vo_truth)
    >>> model = make_nonlinear_model("vo-ekf")
    >>> scans = generate_nonlinear_measurements(vo_truth(model, 5), model, rng=1)
    >>> len(scans), scans[0].z.shape[1]
    (5, 2)
    """
    rng = check_rng(rng)
    sensor = model.sensor
    Rchol = np.linalg.cholesky(np.array(sensor.R))
    out = []
    for k in range(truth.n_scans):
        idx, X = truth.at(k)
        det = rng.random(idx.size) <= sensor.p_d
        Zt = sensor.h(X[det]) if det.any() else np.empty((0, sensor.ndim))
        Zt = Zt + rng.standard_normal((Zt.shape[0], sensor.ndim)) @ Rchol.T
        ang = np.asarray(sensor.angles, dtype=bool)
        Zt[:, ang] = wrap_angle(Zt[:, ang])
        C = model.clutter.sample(rng)
        out.append(Scan(np.concatenate([Zt, C]),
                        np.concatenate([idx[det], np.full(C.shape[0], -1)]).astype(np.int64)))
    return out
