"""rankedassign as a Stone Soup plug-in: exact and sampled JPDA, OSPA(2), LMB and δ-GLMB trackers.

Installed with the extra ``rankedassign[stonesoup]`` and registered under Stone Soup's
``stonesoup.plugins`` entry-point group as ``rankedassign``, so that Stone Soup's plug-in
loader makes this module available as ``stonesoup.plugins.rankedassign``::

    from stonesoup.plugins.rankedassign import JPDAwithDP, OSPA2Metric, LMBTracker

* :class:`JPDAwithDP` — Stone Soup's ``JPDA`` with the exact marginals of the oracle's DP
  (:func:`oracle.marginals`), cluster by cluster;
* :class:`JPDAwithGibbs` — the same with marginals from one of our samplers;
* :class:`VectorisedPDAHypothesiser` — Stone Soup's ``PDAHypothesiser`` with a track's
  detections in one vectorised pass (the same hypotheses), for any associator;
* :class:`OSPA2Metric` — OSPA(2) (:func:`rankedassign.metrics.ospa2`) as a Stone Soup
  ``MetricGenerator``;
* :class:`GOSPAMetric` — GOSPA (:func:`rankedassign.metrics.gospa`) as one, a float per
  timestamp for the distance and each of its parts;
* :class:`LMBTracker`, :class:`GLMBTracker` — Stone Soup trackers around
  :class:`rankedassign.tracking.LMBFilter` and :class:`rankedassign.tracking.GLMBFilter`, built
  from Stone Soup's models (linear-Gaussian, bearing–range, elevation–bearing–range, bearing)
  or a Kalman, extended or unscented Kalman predictor and updater, with births placed by hand
  or made from the measurements;
* :class:`MultiSensorLMBTracker`, :class:`MultiSensorGLMBTracker` — the same around the
  multi-sensor filters, one measurement model per sensor;
* :mod:`rankedassign.stonesoup.models` — Stone Soup's measurement and transition models and
  Kalman-family predictors/updaters as the array models and filters of
  :mod:`rankedassign.tracking.nonlinear` (the same predictions and updates).

The classes follow Stone Soup's conventions: declarative ``Property`` attributes, a ``seed``
property where there is randomness (mapped onto our ``rng`` by
:func:`numpy.random.default_rng`), Stone Soup types in and out. This module imports Stone
Soup; :mod:`rankedassign` itself does not import this module.
"""

from .associators import JPDAwithDP, JPDAwithGibbs
from .hypothesisers import VectorisedPDAHypothesiser
from .metrics import GOSPAMetric, OSPA2Metric
from .trackers import GLMBTracker, LMBTracker, MultiSensorGLMBTracker, MultiSensorLMBTracker

__all__ = ["GLMBTracker", "GOSPAMetric", "JPDAwithDP", "JPDAwithGibbs", "LMBTracker",
           "MultiSensorGLMBTracker", "MultiSensorLMBTracker", "OSPA2Metric",
           "VectorisedPDAHypothesiser"]
