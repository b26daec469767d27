"""What the two modules of the multi-sensor tracking study's targets share
(``tests/test_tracking_multisensor_targets.py``, narrow birth, and
``tests/test_tracking_multisensor_paper_birth.py``, the paper's wide birth)."""

from rankedassign.metrics import ospa2

__all__ = ["SHORT", "mean_ospa"]

#: The multi-sensor short chains with the exact row conditional (Alg. 1), as the numbers of
#: the targets.
SHORT = dict(n_chains=400, chain_length=25, tau_stall=5, tau_stale=10, method="exact")


def mean_ospa(run):
    """Mean OSPA(2) of a run over its scans (c = 200 m, p = 1, window 5)."""
    return float(ospa2(run.truth, run.estimates, c=200, p=1, window=5).value.mean())
