"""Stone Soup's ``PDAHypothesiser`` with every track–detection pair in one vectorised pass.

Stone Soup's :class:`~stonesoup.hypothesiser.probability.PDAHypothesiser` visits the
detections of a track one at a time: a (cached) prediction and measurement prediction, a
squared Mahalanobis distance against the gate, a Gaussian log-likelihood and a few
``Probability`` operations per pair. With 30 tracks and 58 detections that is 1 740 visits
and most of the time of a JPDA step. The same numbers come from one prediction and one
measurement prediction per track (the hypothesiser's own predictor and updater, whose
``predict`` and ``predict_measurement`` are cached, so that its 58 calls per track return one
object) and from numpy over all pairs at once. :func:`pda_pairs` is that pass;
:class:`VectorisedPDAHypothesiser` is a ``PDAHypothesiser`` that uses it for any associator,
and the JPDA associators of :mod:`rankedassign.stonesoup.associators` use it for all tracks at
once.
"""

from __future__ import annotations

import numpy as np
from stonesoup.hypothesiser.probability import PDAHypothesiser
from stonesoup.models.measurement.linear import LinearGaussian
from stonesoup.types.detection import MissedDetection
from stonesoup.types.hypothesis import SingleProbabilityHypothesis
from stonesoup.types.multihypothesis import MultipleHypothesis
from stonesoup.types.numeric import Probability

__all__ = ["VectorisedPDAHypothesiser", "pda_pairs"]

#: The modules whose cached Kalman-family methods the vectorised pass may call once for many
#: (every predictor of ``stonesoup.predictor.kalman`` decorates ``predict`` with an LRU cache,
#: every updater of ``stonesoup.updater.kalman`` its ``predict_measurement``).
_PREDICTORS = "stonesoup.predictor.kalman"
_UPDATERS = "stonesoup.updater.kalman"


def _cached_kalman(obj, method: str, module: str) -> bool:
    """Is ``obj.<method>`` one of Stone Soup's own (cached, deterministic) Kalman methods?"""
    fn = getattr(type(obj), method, None)
    return getattr(fn, "__module__", None) == module and hasattr(fn, "__wrapped__")


def _normalised_multiple_hypothesis(hypotheses: list) -> MultipleHypothesis:
    """``MultipleHypothesis(hypotheses, normalise=True, total_weight=1)`` of probabilities that
    already sum to one.

    Stone Soup's constructor normalises again, one ``Probability`` operation at a time (about
    0.3 ms for a track of ten hypotheses); the probabilities here were normalised with numpy,
    so the object is built without that pass and then records the flag as Stone Soup's would.
    """
    multi = MultipleHypothesis(hypotheses, normalise=False, total_weight=1)
    multi.normalise = True
    return multi


class PDAPairs:
    """A ``PDAHypothesiser``'s hypotheses of several tracks, as arrays (from :func:`pda_pairs`).

    Made by :func:`pda_pairs` only; its constructor is not part of the API.

    Attributes
    ----------
    tracks : list of Track
        The tracks (rows), in the order they were given.
    detections : list of Detection
        The detections (columns), in the order ``list(detections)`` gives, which is the
        hypothesiser's order.
    hypothesis : numpy.ndarray of bool, shape (T, D)
        Whether the hypothesiser makes a hypothesis of the pair (gated in, or ``include_all``).
    log_eta : numpy.ndarray of float64, shape (T, D)
        ``ln`` of each hypothesis' probability as the hypothesiser returns it (normalised per
        track when its ``normalise`` is set); ``-inf`` where there is no hypothesis or the
        probability is 0.
    log_miss : numpy.ndarray of float64, shape (T,)
        The same for the missed-detection hypotheses.
    """

    def __init__(self, tracks, detections, timestamp, missed, predictions,
                 measurement_predictions, group, hypothesis, log_eta, log_miss, normalised):
        self.tracks = tracks
        self.detections = detections
        self.hypothesis = hypothesis
        self.log_eta = log_eta
        self.log_miss = log_miss
        self._timestamp = timestamp
        self._missed = missed
        self._predictions = predictions
        self._measurement_predictions = measurement_predictions
        self._group = group.tolist()
        self._normalised = normalised
        # the columns of each track's hypotheses, in the hypothesiser's order
        rows, cols = np.nonzero(hypothesis)
        ends = np.cumsum(np.bincount(rows, minlength=len(tracks))).tolist()
        cols = cols.tolist()
        self._cols = [cols[a:b] for a, b in zip([0, *ends][:-1], ends, strict=True)]

    def _hypotheses(self, i: int, miss_probability, probabilities) -> list:
        """Track ``i``'s hypotheses in the hypothesiser's order with the given probabilities."""
        missed = MissedDetection(timestamp=self._timestamp)
        out = [SingleProbabilityHypothesis(self._missed[i], missed, probability=miss_probability)]
        for j, p in zip(self._cols[i], probabilities, strict=True):
            g = self._group[j]
            out.append(SingleProbabilityHypothesis(
                self._predictions[g][i], self.detections[j], probability=p,
                measurement_prediction=self._measurement_predictions[g][i]))
        return out

    def multiple_hypothesis(self, i: int) -> MultipleHypothesis:
        """Track ``i``'s hypotheses, as ``PDAHypothesiser.hypothesise`` returns them.

        Parameters
        ----------
        i : int
            Index of the track in :attr:`tracks`.

        Returns
        -------
        stonesoup.types.multihypothesis.MultipleHypothesis
            The missed detection first, then the track's detections in :attr:`detections`
            order, with the hypothesiser's probabilities (normalised if it normalises).
        """
        row = self.log_eta[i]
        logs = [self.log_miss[i], *(row[j] for j in self._cols[i])]
        if self._normalised:
            # Stone Soup's normalisation gives a plain 0.0 where a probability underflows
            probs = [0.0 if lw == -np.inf else Probability(lw, log_value=True) for lw in logs]
            return _normalised_multiple_hypothesis(self._hypotheses(i, probs[0], probs[1:]))
        probs = [Probability(lw, log_value=True) for lw in logs]
        return MultipleHypothesis(self._hypotheses(i, probs[0], probs[1:]), normalise=False)

    def with_marginals(self, beta: np.ndarray) -> dict:
        """Every track's hypotheses with the given JPDA marginals instead of its weights.

        Parameters
        ----------
        beta : numpy.ndarray of float64, shape (T, D + 1)
            ``beta[i, j]``: marginal probability of track ``i`` with detection ``j``;
            ``beta[i, D]``: of its missed detection. Zero where there is no hypothesis.

        Returns
        -------
        dict of Track to stonesoup.types.multihypothesis.MultipleHypothesis
            In the order of :attr:`tracks`, each track's hypotheses in the hypothesiser's
            order with the marginals normalised to 1, as Stone Soup's ``JPDA`` returns them.
        """
        D = self.hypothesis.shape[1]
        total = beta[:, D] + np.where(self.hypothesis, beta[:, :D], 0.0).sum(axis=1)
        with np.errstate(divide="ignore"):
            log_p = np.log(beta / total[:, None])
        out = {}
        for i, track in enumerate(self.tracks):
            row = log_p[i].tolist()
            probs = [Probability(row[j], log_value=True) for j in self._cols[i]]
            out[track] = _normalised_multiple_hypothesis(
                self._hypotheses(i, Probability(row[D], log_value=True), probs))
        return out


def pda_pairs(hypothesiser, tracks, detections, timestamp, **kwargs) -> PDAPairs | None:
    """The hypotheses of ``hypothesiser`` for every track and detection in one vectorised pass.

    Parameters
    ----------
    hypothesiser : stonesoup.hypothesiser.base.Hypothesiser
        The hypothesiser; the pass applies only under the conditions of the Notes.
    tracks : iterable of stonesoup.types.track.Track
        The tracks.
    detections : iterable of stonesoup.types.detection.Detection
        The detections (a set, as for ``PDAHypothesiser.hypothesise``).
    timestamp : datetime.datetime
        The time of the missed-detection hypotheses (and the prediction for them).
    **kwargs
        Passed to the predictor's ``predict`` and the updater's ``predict_measurement``, as
        ``PDAHypothesiser`` passes them.

    Returns
    -------
    PDAPairs or None
        Every track's hypotheses as arrays, equal to what ``hypothesiser.hypothesise`` returns
        track by track (to rounding: the log-likelihoods and distances are the same formulas
        over all pairs at once); None when the conditions do not hold, and the caller should
        call the hypothesiser.

    Notes
    -----
    The pass applies when

    * the hypothesiser is exactly Stone Soup's ``PDAHypothesiser`` or our
      :class:`VectorisedPDAHypothesiser` (not a subclass, which may change ``hypothesise``);
    * its predictor's ``predict`` is one of ``stonesoup.predictor.kalman``'s and its updater's
      ``predict_measurement`` one of ``stonesoup.updater.kalman``'s: Stone Soup caches those
      (an LRU cache on the arguments), so the hypothesiser's one call per detection returns
      the same prediction and measurement prediction as the pass's one call per track (per
      detection timestamp and measurement model);
    * every detection's measurement model (or the updater's, for a detection without one) is
      a ``LinearGaussian`` and its state vector real-valued: then a detection minus a
      measurement prediction is a plain difference (an angle would wrap), and the
      measurement prediction is Gaussian;
    * ``prob_detect``, ``prob_gate`` and ``clutter_spatial_density`` are in their ranges
      (``> 0``), every innovation covariance has a Cholesky factor (Stone Soup would fall
      back to the nearest positive-definite matrix), and no track's hypotheses all have
      probability 0.

    Per pair it forms what ``PDAHypothesiser.hypothesise`` forms: the Gaussian log-likelihood
    of the detection under the measurement prediction ``N(z; z_hat, S)`` through the Cholesky
    factor of ``S`` (as ``stonesoup.functions.batch_multivariate_normal_logpdf``), the squared
    Mahalanobis distance through ``pinv(S)`` (as ``SquaredMahalanobis``) against the gate
    ``chi2.ppf(prob_gate, dim)``, the weight ``ln N + ln P_D - ln lambda`` (or, without a
    clutter density, ``ln N + ln P_D + ln(V / m)`` with ``V`` the validation region's volume
    and ``m`` the number of gated detections), the missed-detection weight ``1 - P_D P_G``, and
    the normalisation of each track's weights in log space. A pair whose distance is within
    rounding of the gate threshold may be gated differently from the hypothesiser (the sums
    run in another order); a pair exactly on it is gated in, as there.
    """
    h = hypothesiser
    if type(h) not in (PDAHypothesiser, VectorisedPDAHypothesiser):
        return None
    if not (_cached_kalman(h.predictor, "predict", _PREDICTORS)
            and _cached_kalman(h.updater, "predict_measurement", _UPDATERS)):
        return None
    if not (float(h.prob_detect) > 0 and float(h.prob_gate) > 0):
        return None
    csd = h.clutter_spatial_density
    if csd is not None and not float(csd) > 0:
        return None
    tracks = list(tracks)
    detections = list(detections)
    T, D = len(tracks), len(detections)

    # one group per detection timestamp and measurement model: one prediction and one
    # measurement prediction per track and group, as the hypothesiser's cached calls give
    keys: dict = {}
    groups = []
    group = np.empty(D, dtype=np.intp)
    for j, det in enumerate(detections):
        model = det.measurement_model
        if not isinstance(model if model is not None else h.updater.measurement_model,
                          LinearGaussian):
            return None
        g = keys.setdefault((det.timestamp, id(model)), len(groups))
        if g == len(groups):
            groups.append((det.timestamp, model, []))
        groups[g][2].append(j)
        group[j] = g

    missed = [h.predictor.predict(track, timestamp=timestamp, **kwargs) for track in tracks]
    log_pd = Probability._log(h.prob_detect)
    log_eta = np.full((T, D), -np.inf)
    valid = np.zeros((T, D), dtype=bool)
    predictions, measurement_predictions, volumes = [], [], []
    for when, model, cols in (groups if T else []):
        pred = [h.predictor.predict(track, timestamp=when, **kwargs) for track in tracks]
        mpred = [h.updater.predict_measurement(p, model, **kwargs) for p in pred]
        predictions.append(pred)
        measurement_predictions.append(mpred)
        z = np.array([detections[j].state_vector for j in cols])          # (Dg, n, 1)
        mean = np.array([m.state_vector for m in mpred])                  # (T, n, 1)
        if z.dtype != np.float64 or mean.dtype != np.float64 or z.shape[1:] != mean.shape[1:] \
                or z.shape[2] != 1:
            return None
        covar = np.array([m.covar for m in mpred], dtype=np.float64)       # (T, n, n)
        n = z.shape[1]
        try:
            chol = np.linalg.cholesky(covar)
        except np.linalg.LinAlgError:
            return None
        # ln N(z; z_hat, S) = -(ln|S| + |L^-1 (z - z_hat)|^2 + n ln 2 pi) / 2, S = L L'
        log_det = 2 * np.sum(np.log(np.diagonal(chol, axis1=-2, axis2=-1)), axis=-1)
        dev = z[None, :, :, 0] - mean[:, None, :, 0]                       # (T, Dg, n)
        white = np.linalg.solve(chol[:, None], dev[..., None])            # one solve per pair
        maha = np.sum(white ** 2, axis=(-2, -1))
        logpdf = -0.5 * (log_det[:, None] + maha + n * np.log(2 * np.pi))
        # the gate: (z - z_hat)' pinv(S) (z - z_hat) <= chi2.ppf(P_G, n)
        delta = -dev
        d2 = np.sum(np.matmul(delta, np.linalg.pinv(covar)) * delta, axis=-1)
        valid[:, cols] = d2 <= h._gate_threshold(h.prob_gate, n)
        # Probability(ln N) *= P_D, then /= lambda
        lw = logpdf + log_pd
        if csd is not None:
            lw = lw - Probability._log(csd)
        log_eta[:, cols] = lw
        if csd is None:
            volumes.append([h._validation_region_volume(h.prob_gate, m) for m in mpred])

    hypothesis = valid | bool(h.include_all)
    log_eta[~hypothesis] = -np.inf
    if csd is None and T:
        # no clutter density (include_all is off): each weight times V / m, with V the
        # validation region's volume and m the number of gated detections of the track
        n_valid = valid.sum(axis=1)
        rows = np.flatnonzero(n_valid)
        for g, (_, _, cols) in enumerate(groups):
            volume = np.array([volumes[g][i] for i in rows.tolist()], dtype=np.float64)
            block = log_eta[np.ix_(rows, cols)]
            log_eta[np.ix_(rows, cols)] = block + np.log(volume / n_valid[rows])[:, None]
    log_miss = np.full(T, Probability(1 - h.prob_detect * h.prob_gate).log_value,
                       dtype=np.float64)

    if h.normalise and T:
        # MultipleHypothesis normalises in log space: the log-sum-exp of the track's weights,
        # then each probability p * 1 / sum, where p * 1 is exp(ln p) (0.0 if it underflows)
        full = np.concatenate((log_miss[:, None], log_eta), axis=1)
        top = full.max(axis=1)
        if not np.isfinite(top).all():
            return None
        log_sum = np.log(np.sum(np.exp(full - top[:, None]), axis=1)) + top
        with np.errstate(divide="ignore"):
            full = np.log(np.exp(full)) - log_sum[:, None]
        log_miss, log_eta = full[:, 0].copy(), np.ascontiguousarray(full[:, 1:])
        log_eta[~hypothesis] = -np.inf
    return PDAPairs(tracks, detections, timestamp, missed, predictions,
                    measurement_predictions, group, hypothesis, log_eta, log_miss,
                    bool(h.normalise))


class VectorisedPDAHypothesiser(PDAHypothesiser):
    """Stone Soup's ``PDAHypothesiser`` with a track's detections in one vectorised pass.

    The same properties, the same hypotheses in the same order with the same probabilities
    (to rounding), the same ``MultipleHypothesis``; the prediction and measurement prediction
    of each hypothesis are the very objects ``PDAHypothesiser`` would attach (its predictor's
    and updater's cached results). Where the vectorised pass does not apply (see
    :func:`pda_pairs`: e.g. a non-linear measurement model, or an updater of another family),
    :meth:`hypothesise` is ``PDAHypothesiser.hypothesise``. Hand it to any associator
    (``PDA``, ``JPDAwithEHM2``, :class:`~rankedassign.stonesoup.JPDAwithDP`, ...) in place of
    a ``PDAHypothesiser``.

    Parameters
    ----------
    predictor : stonesoup.predictor.Predictor
        Predicts the tracks to the detections' times.
    updater : stonesoup.updater.Updater
        Gives the measurement predictions.
    clutter_spatial_density : float, optional
        Spatial density of clutter ``lambda``; None (default) estimates it per track as
        ``PDAHypothesiser`` does (all but one gated detection are clutter).
    prob_detect : Probability, optional
        Detection probability ``P_D`` (default 0.85).
    prob_gate : Probability, optional
        Gate probability ``P_G`` (default 0.95).
    include_all : bool, optional
        Also return hypotheses outside the gate (needs ``clutter_spatial_density``).
    normalise : bool, optional
        Normalise each track's probabilities to sum to 1 (default True).

    Notes
    -----
    The weights are those of ``PDAHypothesiser`` (Bar-Shalom et al. 2009): for a gated
    detection ``z``, ``N(z; z_hat, S) P_D / lambda``; for the missed detection
    ``1 - P_D P_G``. Per track the pass costs one prediction, one measurement prediction and
    a few numpy operations over its detections instead of a Python loop with a distance, a
    log-likelihood and several ``Probability`` operations per detection. An associator that
    asks for all tracks at once (:class:`~rankedassign.stonesoup.JPDAwithDP` does, through
    :func:`pda_pairs`) saves the per-track overhead as well.

    References
    ----------
    .. [1] Y. Bar-Shalom, F. Daum, J. Huang, "The Probabilistic Data Association Filter:
       Estimation in the Presence of Measurement Origin Uncertainty", IEEE Control Systems
       Magazine 29(6), 2009.

    Examples
    --------
    >>> import datetime
    >>> import numpy as np
    >>> from stonesoup.hypothesiser.probability import PDAHypothesiser
    >>> from stonesoup.models.measurement.linear import LinearGaussian
    >>> from stonesoup.models.transition.linear import (
    ...     CombinedLinearGaussianTransitionModel, ConstantVelocity)
    >>> from stonesoup.predictor.kalman import KalmanPredictor
    >>> from stonesoup.types.detection import Detection
    >>> from stonesoup.types.state import GaussianState
    >>> from stonesoup.types.track import Track
    >>> from stonesoup.updater.kalman import KalmanUpdater
    >>> from rankedassign.stonesoup import VectorisedPDAHypothesiser
    >>> t0 = datetime.datetime(2025, 1, 1)
    >>> t1 = t0 + datetime.timedelta(seconds=1)
    >>> cv = CombinedLinearGaussianTransitionModel([ConstantVelocity(0.1)] * 2)
    >>> mm = LinearGaussian(ndim_state=4, mapping=(0, 2), noise_covar=np.eye(2))
    >>> parts = dict(predictor=KalmanPredictor(cv), updater=KalmanUpdater(mm),
    ...              clutter_spatial_density=1e-3, prob_detect=0.9)
    >>> track = Track([GaussianState([[0], [0], [0], [0]], np.eye(4), timestamp=t0)])
    >>> dets = {Detection([[x], [0.0]], timestamp=t1, measurement_model=mm)
    ...         for x in (0.5, 1.0, 9.0)}
    >>> ours = VectorisedPDAHypothesiser(**parts).hypothesise(track, dets, t1)
    >>> theirs = PDAHypothesiser(**parts).hypothesise(track, dets, t1)
    >>> len(ours), [bool(h) for h in ours]       # the detection at 9 m is outside the gate
    (3, [False, True, True])
    >>> [a.prediction is b.prediction for a, b in zip(ours, theirs)]  # the predictor's own
    [True, True, True]
    >>> [a.measurement is b.measurement for a, b in zip(list(ours)[1:], list(theirs)[1:])]
    [True, True]
    >>> bool(max(abs(a.probability.log_value - b.probability.log_value)
    ...          for a, b in zip(ours, theirs)) < 1e-12)
    True
    """

    def hypothesise(self, track, detections, timestamp, **kwargs):
        """All hypotheses of one track: its missed detection, then each gated detection.

        Parameters
        ----------
        track : stonesoup.types.track.Track
            The track.
        detections : set of stonesoup.types.detection.Detection
            The available detections.
        timestamp : datetime.datetime
            The time of the missed-detection hypothesis (detections are predicted to their
            own timestamps).
        **kwargs
            Passed to the predictor and the updater.

        Returns
        -------
        stonesoup.types.multihypothesis.MultipleHypothesis
            ``SingleProbabilityHypothesis`` objects, the missed detection first, as
            ``PDAHypothesiser.hypothesise`` returns them.
        """
        pairs = pda_pairs(self, [track], detections, timestamp, **kwargs)
        if pairs is None:
            return super().hypothesise(track, detections, timestamp, **kwargs)
        return pairs.multiple_hypothesis(0)
