"""The studies, one module each; each builds one :class:`~rankedassign.experiments.Study` and
registers it (:func:`~rankedassign.experiments.register_study`) when imported by
:mod:`rankedassign.experiments`."""
