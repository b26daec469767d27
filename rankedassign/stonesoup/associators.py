"""JPDA associators for Stone Soup whose marginals come from the oracle's DP or our samplers.

Stone Soup's ``JPDA`` turns the single-target hypotheses of a ``PDAHypothesiser`` (per track:
a missed-detection weight and one weight per gated detection) into the marginal probability
of every track–detection pair under the joint constraint that a detection has at most one
track. That is the ranked-assignment problem of spec §1.5 with rows = tracks and measurement
columns = detections, ``eta_i(j)`` = the hypothesis weight of track ``i`` with detection
``j``, ``eta_i(0)`` = its missed-detection weight, and no dead column (``eta_i(-1) = 0``):
the JPDA marginal ``P(track i takes detection j)`` is the association marginal of spec eq.
(5.2). Tracks that share no gated detection are independent; each cluster (connected
component of the track–detection graph) is one problem.
"""

from __future__ import annotations

import math

import numpy as np
from stonesoup.base import Property
from stonesoup.dataassociator.probability import JPDA
from stonesoup.types.hypothesis import SingleProbabilityHypothesis
from stonesoup.types.numeric import Probability

import oracle

from ..single.problem import AssignmentProblem
from ..tracking import Association, ShortChainGibbs, check_truncation, group_tracks
from .hypothesisers import _normalised_multiple_hypothesis, pda_pairs

__all__ = ["JPDAwithDP", "JPDAwithGibbs"]


def _log_weight(hypothesis) -> float:
    """``ln`` of a hypothesis' probability (a Stone Soup ``Probability`` keeps its log)."""
    p = hypothesis.probability
    if isinstance(p, Probability):
        return float(p.log_value)
    p = float(p)
    return math.log(p) if p > 0 else -math.inf


def _check_association(association, name: str) -> None:
    """Refuse what is not a single-sensor association of :mod:`rankedassign.tracking`."""
    if not callable(association):
        raise TypeError(f"{name} must be one of our associations (callable as "
                        f"association(problem, rng), e.g. ShortChainGibbs), got "
                        f"{type(association).__name__}")
    check_truncation(association, name, "single-sensor", "marginals")


class _GivenHypotheses:
    """The hypothesiser's hypotheses of every track as one log-weight matrix.

    ``log_eta[i, j]``: log-weight of track ``i`` with detection ``j`` (``-inf``: not gated),
    ``log_miss[i]``: of its missed detection; the columns are the detections in the order the
    hypotheses first name them. The same attributes as :class:`.PDAPairs`, which the
    vectorised pass makes instead.
    """

    def __init__(self, hypotheses, who: str):
        self.tracks = list(hypotheses.keys())
        self._hypotheses = hypotheses
        cols = {}
        rows = []
        for track in self.tracks:
            row = {}
            miss = None
            for hyp in hypotheses[track]:
                if not isinstance(hyp, SingleProbabilityHypothesis):
                    raise TypeError(
                        f"{who} needs probabilistic hypotheses (SingleProbabilityHypothesis, as "
                        f"PDAHypothesiser makes), got {type(hyp).__name__} from the "
                        "hypothesiser; use a PDAHypothesiser"
                    )
                if not hyp:
                    miss = _log_weight(hyp)
                else:
                    j = cols.setdefault(id(hyp.measurement), len(cols))
                    row[j] = _log_weight(hyp)
            if miss is None:
                raise ValueError(f"{who}: the hypotheses of track {track.id} have no "
                                 "missed-detection hypothesis (a PDAHypothesiser always "
                                 "makes one)")
            rows.append((miss, row))
        T, D = len(rows), len(cols)
        self.log_eta = np.full((T, D), -np.inf)
        self.log_miss = np.empty(T)
        for i, (miss, row) in enumerate(rows):
            self.log_miss[i] = miss
            for j, lw in row.items():
                self.log_eta[i, j] = lw
        self._col_of = cols

    def with_marginals(self, beta: np.ndarray) -> dict:
        """Every track's hypotheses (in the hypothesiser's order) with the JPDA marginals
        ``beta`` (``(T, D + 1)``: the detection columns, then the missed detection),
        normalised to 1 as ``JPDA`` does: ``{track: MultipleHypothesis}``."""
        out = {}
        for track, beta_row in zip(self.tracks, beta, strict=True):
            multi = self._hypotheses[track]
            p = np.array([beta_row[-1] if not hyp else beta_row[self._col_of[id(hyp.measurement)]]
                          for hyp in multi])
            with np.errstate(divide="ignore"):
                logs = np.log(p / p.sum()).tolist()
            out[track] = _normalised_multiple_hypothesis([
                SingleProbabilityHypothesis(hyp.prediction, hyp.measurement,
                                            measurement_prediction=hyp.measurement_prediction,
                                            probability=Probability(lw, log_value=True))
                for hyp, lw in zip(multi, logs, strict=True)])
        return out


def _problems(log_eta: np.ndarray, log_miss: np.ndarray):
    """``(rows, cols, problem or None)`` of every cluster; None: no gated detection."""
    if not log_eta.shape[0]:
        return
    finite = np.isfinite(log_eta)
    for rows, cols in group_tracks(finite):
        if cols.size == 0:
            yield rows, cols, None
            continue
        lw = np.ascontiguousarray(log_eta[np.ix_(rows, cols)])
        yield rows, cols, AssignmentProblem.from_log_eta(lw, log_miss[rows],
                                                         np.full(rows.size, -np.inf))


class _ClusteredJPDA(JPDA):
    """The part both associators share: hypotheses -> clusters -> marginals -> hypotheses."""

    seed: int = Property(
        default=None,
        doc="Seed of the randomness (anything numpy.random.default_rng accepts; None: fresh).")

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._rng = np.random.default_rng(self.seed)
        self.vectorised = False

    def _cluster_marginals(self, problem, tracks, timestamp):  # pragma: no cover (abstract)
        raise NotImplementedError

    def associate(self, tracks, detections, timestamp, **kwargs):
        """Associate tracks and detections: JPDA marginals of every track's hypotheses.

        Parameters
        ----------
        tracks : set of stonesoup.types.track.Track
            Tracks which detections will be associated to.
        detections : set of stonesoup.types.detection.Detection
            Detections to be associated to tracks (may be empty).
        timestamp : datetime.datetime
            Timestamp to be used for missed detections and to predict to.
        **kwargs
            Passed to the hypothesiser (or to its predictor and updater in the vectorised
            pass).

        Returns
        -------
        dict of Track to stonesoup.types.multihypothesis.MultipleHypothesis
            Per track, its hypotheses (the hypothesiser's, in its order) with their marginal
            probabilities, normalised to 1 as Stone Soup's ``JPDA`` does.
        """
        who = type(self).__name__
        data = None
        if self.vectorise:
            data = pda_pairs(self.hypothesiser, tracks, detections, timestamp, **kwargs)
        self.vectorised = data is not None
        if data is None:
            data = _GivenHypotheses(
                self.generate_hypotheses(tracks, detections, timestamp, **kwargs), who)
        T, D = data.log_eta.shape
        if T and not np.isfinite(data.log_miss).all():
            i = int(np.flatnonzero(~np.isfinite(data.log_miss))[0])
            raise ValueError(f"{who}: track {data.tracks[i].id} has a missed-detection "
                             "probability of 0; JPDA needs it positive (prob_detect < 1)")
        # marginals per track: [detection columns | missed]
        beta = np.zeros((T, D + 1))
        self._start_call()
        for rows, cols, problem in _problems(data.log_eta, data.log_miss):
            if problem is None:
                beta[rows, D] = 1.0
                continue
            b = self._cluster_marginals(problem, [data.tracks[i] for i in rows], timestamp)
            beta[np.ix_(rows, cols)] = b[:, :-2]
            # no dead column: the missed column holds every unmatched weight
            beta[rows, D] = b[:, -2] + b[:, -1]
        return data.with_marginals(beta)

    def _start_call(self) -> None:
        """Called once per :meth:`associate`, before the clusters."""


class JPDAwithDP(_ClusteredJPDA):
    """Joint probabilistic data association with exact marginals from a dynamic programme.

    Stone Soup's :class:`~stonesoup.dataassociator.probability.JPDA` with the marginal
    association probabilities computed by the oracle's exact DP (:func:`oracle.marginals`)
    instead of enumerating the joint hypotheses. Tracks are split into clusters that share
    gated detections, and each cluster is solved on its own.

    Parameters
    ----------
    hypothesiser : stonesoup.hypothesiser.probability.PDAHypothesiser
        Generates the probabilistic hypotheses of every track (any hypothesiser whose
        hypotheses are ``SingleProbabilityHypothesis``, such as a gater around a
        ``PDAHypothesiser``).
    fallback : rankedassign.tracking.Association, optional
        The association used for a cluster that is beyond the DP's reach, e.g.
        ``ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, marginals="rao-blackwell")``.
        None (default): such a cluster raises ``ValueError``.
    seed : int, optional
        Seed of the fallback's randomness (anything :func:`numpy.random.default_rng`
        accepts); None (default) draws fresh entropy.
    vectorise : bool, optional
        True (default): where the hypothesiser is a ``PDAHypothesiser`` the vectorised pass
        reproduces (see Notes), compute every track's hypotheses in that one pass instead of
        calling the hypothesiser track by track. False: always call the hypothesiser.

    Attributes
    ----------
    fallback_tracks : set of Track
        The tracks whose marginals came from ``fallback`` in the latest :meth:`associate`.
    fallback_log : list of (datetime.datetime, frozenset of Track)
        Every use of the fallback: the timestamp and the tracks of the cluster.
    vectorised : bool
        Whether the latest :meth:`associate` took the vectorised pass (False: it called the
        hypothesiser).

    Raises
    ------
    TypeError
        If ``fallback`` is not one of our single-sensor associations, or (from
        :meth:`associate`) the hypothesiser's hypotheses are not probabilistic.
    ValueError
        From :meth:`associate`: a cluster beyond the DP's reach without a ``fallback`` (the
        message gives the cluster's size and names :class:`JPDAwithGibbs`).

    Notes
    -----
    A cluster of ``P`` tracks and ``M`` detections is the problem of spec eq. (5.2) with
    ``eta_i(j)`` the hypothesis weights and no dead column; its marginals are exact (to
    rounding). The DP takes ``O(max(P, M) min(P, M) 2^min(P, M))`` (subset DP) or
    ``O(M F 2^F)`` (frontier DP, ``F`` the frontier width of the gated cluster) and refuses a
    cluster where both ``min(P, M)`` and ``F`` exceed 20. Tracks that gate no detection are
    missed with probability 1. An empty detection set gives every track its missed-detection
    hypothesis with probability 1, as ``JPDA`` does.

    The hypotheses. With Stone Soup's ``PDAHypothesiser`` (or our
    :class:`~rankedassign.stonesoup.VectorisedPDAHypothesiser`) around one of Stone Soup's
    Kalman predictors and updaters, and detections of ``LinearGaussian`` measurement models,
    every track's hypotheses come from one vectorised pass
    (:func:`~rankedassign.stonesoup.hypothesisers.pda_pairs`): the hypothesiser's predictor
    and updater called once per track (their cached results, the very objects the
    hypothesiser attaches), the gates and Gaussian log-likelihoods of all track–detection
    pairs in numpy, the same probabilities to rounding. The hypothesiser's own objects are not
    built: the output hypotheses are made once, with the marginals. Any other hypothesiser (a
    subclass, a gater, a non-linear model, another predictor) is called as ``JPDA`` calls it.
    At 30 tracks and 58 detections this pass, not the marginals, is most of what the
    vectorised path saves end to end (``docs/stonesoup.md``, "Speed").

    References
    ----------
    .. [1] T. E. Fortmann, Y. Bar-Shalom, M. Scheffe, "Sonar Tracking of Multiple Targets
       Using Joint Probabilistic Data Association", IEEE J. Oceanic Eng. 8(3), 1983.
    .. [2] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8), 2017.
    .. [3] S. Maskell, M. Briers, R. Wright, "Fast Mutual Exclusion", Proc. SPIE 5428, 2004
       (EHM, the exact method Stone Soup's ``JPDAwithEHM`` implements).

    Examples
    --------
    Two tracks competing for two detections, against Stone Soup's own ``JPDAwithEHM2``:

    >>> import datetime
    >>> import numpy as np
    >>> from stonesoup.dataassociator.probability import JPDAwithEHM2
    >>> from stonesoup.hypothesiser.probability import PDAHypothesiser
    >>> from stonesoup.models.measurement.linear import LinearGaussian
    >>> from stonesoup.models.transition.linear import (
    ...     CombinedLinearGaussianTransitionModel, ConstantVelocity)
    >>> from stonesoup.predictor.kalman import KalmanPredictor
    >>> from stonesoup.types.detection import Detection
    >>> from stonesoup.types.state import GaussianState
    >>> from stonesoup.types.track import Track
    >>> from stonesoup.updater.kalman import KalmanUpdater
    >>> from rankedassign.stonesoup import JPDAwithDP
    >>> t0 = datetime.datetime(2025, 1, 1)
    >>> cv = CombinedLinearGaussianTransitionModel([ConstantVelocity(0.1)] * 2)
    >>> mm = LinearGaussian(ndim_state=4, mapping=(0, 2), noise_covar=np.eye(2))
    >>> hyp = PDAHypothesiser(KalmanPredictor(cv), KalmanUpdater(mm),
    ...                       clutter_spatial_density=1e-3, prob_detect=0.9)
    >>> tracks = {Track([GaussianState([[x], [0], [0], [0]], np.eye(4), timestamp=t0)])
    ...           for x in (0.0, 1.5)}
    >>> t1 = t0 + datetime.timedelta(seconds=1)
    >>> dets = {Detection([[x], [0.0]], timestamp=t1, measurement_model=mm) for x in (0.5, 1.0)}
    >>> ours = JPDAwithDP(hyp).associate(tracks, dets, t1)
    >>> ehm2 = JPDAwithEHM2(hyp).associate(tracks, dets, t1)
    >>> def table(result):
    ...     return {(t.state_vector[0, 0], h.measurement.state_vector[0, 0] if h else -1.0):
    ...             float(h.probability) for t in result for h in result[t]}
    >>> a, b = table(ours), table(ehm2)
    >>> sorted(a) == sorted(b) and max(abs(a[k] - b[k]) for k in a) < 1e-12
    True
    >>> round(a[0.0, 0.5], 6), round(a[1.5, 1.0], 6)    # each track with its nearer detection
    (0.559506, 0.559506)
    """

    fallback: Association = Property(
        default=None,
        doc="Association used for clusters beyond the DP's reach (None: raise ValueError).")
    vectorise: bool = Property(
        default=True,
        doc="Compute a PDAHypothesiser's hypotheses for all tracks in one vectorised pass "
            "where that gives the hypothesiser's own (see Notes); False: always call the "
            "hypothesiser, track by track.")

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        if self.fallback is not None:
            _check_association(self.fallback, "fallback")
        self.fallback_tracks = set()
        self.fallback_log = []

    def _start_call(self) -> None:
        self.fallback_tracks = set()

    def _cluster_marginals(self, problem, tracks, timestamp):
        try:
            return np.asarray(oracle.marginals(problem), dtype=np.float64)
        except ValueError as err:  # the one documented ValueError: the cluster is too large
            if self.fallback is None:
                raise ValueError(
                    f"a cluster of {problem.n_rows} tracks sharing {problem.n_meas} detections "
                    f"is beyond the exact DP ({err}); use JPDAwithGibbs (sampled marginals), or "
                    "set fallback= to one of our associations (e.g. ShortChainGibbs) for such "
                    "clusters"
                ) from err
        self.fallback_tracks.update(tracks)
        self.fallback_log.append((timestamp, frozenset(tracks)))
        return np.asarray(self.fallback(problem, self._rng).beta, dtype=np.float64)


def _default_sampler():
    return ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, marginals="rao-blackwell")


class JPDAwithGibbs(_ClusteredJPDA):
    """Joint probabilistic data association with marginals from one of our samplers.

    As :class:`JPDAwithDP`, cluster by cluster, with each cluster's marginals from
    ``association`` (by default the short-chain sampler of Trezza et al. 2023 with the
    paper's settings and the Rao-Blackwellised estimator,
    :func:`rankedassign.tracking.marginals_from_hypotheses`). For clusters of any size.

    Parameters
    ----------
    hypothesiser : stonesoup.hypothesiser.probability.PDAHypothesiser
        Generates the probabilistic hypotheses of every track (as :class:`JPDAwithDP`).
    association : rankedassign.tracking.Association, optional
        The sampler (or any of our single-sensor associations): default
        ``ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, marginals="rao-blackwell")``.
    seed : int, optional
        Seed of the samplers' randomness (anything :func:`numpy.random.default_rng` accepts);
        one generator made from it at construction draws for every cluster in turn. None
        (default) draws fresh entropy.
    vectorise : bool, optional
        True (default): hypotheses from the vectorised pass where it applies, as
        :class:`JPDAwithDP`; False: always call the hypothesiser.

    Attributes
    ----------
    vectorised : bool
        Whether the latest :meth:`associate` took the vectorised pass.

    Raises
    ------
    TypeError
        If ``association`` is not one of our single-sensor associations, or (from
        :meth:`associate`) the hypothesiser's hypotheses are not probabilistic.

    Notes
    -----
    The Rao-Blackwellised marginals (spec §6.3 with each hypothesis contributing its rows'
    conditional distributions) are exact when the chains visit every hypothesis and close to
    the exact ones after a few sweeps otherwise; ``marginals="truncated"`` gives the
    marginals of the visited hypotheses alone.

    References
    ----------
    .. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "On Gibbs Sampling Architecture for
       Labeled Random Finite Sets Multi-Object Tracking", arXiv:2306.15135, 2023.
    .. [2] B.-N. Vo, B.-T. Vo, H. G. Hoang, "An Efficient Implementation of the Generalized
       Labeled Multi-Bernoulli Filter", IEEE Trans. Signal Process. 65(8), 2017.

    Examples
    --------
    >>> from rankedassign.stonesoup import JPDAwithGibbs
    >>> from rankedassign.tracking import Murty
    >>> JPDAwithGibbs(hypothesiser=None).association
    ShortChainGibbs(400, 25, tau_stall=5, tau_stale=10, marginals='rao-blackwell')
    >>> JPDAwithGibbs(hypothesiser=None, association=Murty(100), seed=1).association
    Murty(100)
    """

    association: Association = Property(
        default_factory=_default_sampler,
        doc="The sampler whose hypotheses give each cluster's marginals.")
    vectorise: bool = Property(
        default=True,
        doc="Compute a PDAHypothesiser's hypotheses for all tracks in one vectorised pass "
            "where that gives the hypothesiser's own (as JPDAwithDP); False: always call the "
            "hypothesiser, track by track.")

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        _check_association(self.association, "association")

    def _cluster_marginals(self, problem, tracks, timestamp):
        return np.asarray(self.association(problem, self._rng).beta, dtype=np.float64)
