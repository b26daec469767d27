"""Synthetic families of adaptive-birth problems (spec ``multisensor.md`` §6.5).

Three families with ``V`` in ``{4, 6, 8}`` sensors (``M`` = 10, 6, 4 measurements per sensor):

* **diagonal** — 3 well-separated targets seen by every sensor (``P_D = 0.95``), the rest of
  each sensor's measurements clutter, ``r_U = 0.99`` for every measurement;
* **uniform** — ``rho = 1`` on every tuple (``psibar_B = 1``, ``r_U = 1``);
* **random** — 3 targets and the clutter uniform in the region, ``P_D^(v) ~ U[0.5, 0.99]``,
  ``r_U ~ U[tau_rU, 1]``.

References
----------
.. [1] A. Trezza, D. J. Bucci Jr., P. K. Varshney, "Multi-sensor joint adaptive birth sampler
   for labeled random finite set tracking", IEEE Trans. Signal Process. 70, 2022.
"""

from __future__ import annotations

import numpy as np

from ..validation import check_choice, check_int
from .problem import AdaptiveBirthProblem

__all__ = ["FAMILIES", "SIZES", "make_family"]

FAMILIES = ("diagonal", "uniform", "random")


#: Sensors -> measurements per sensor (spec §6.1).
SIZES = {4: 10, 6: 6, 8: 4}


# Geometry shared by the diagonal and random families (spec §7.2 values): 4-D constant-velocity
# state [x, vx, y, vy], position sensors on [-1000, 1000]^2, R = 10^2 I, clutter 5e-6 m^-2.
_REGION = 1000.0


_H = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]])


_R = 100.0 * np.eye(2)


_KAPPA = 5e-6


_MU0 = np.zeros(4)


_P0 = np.diag([1000.0**2, 50.0**2, 1000.0**2, 50.0**2])


_TARGETS = np.array([[-500.0, -500.0], [0.0, 500.0], [500.0, -200.0]])


_TAU_RU = 0.9


def make_family(family: str, V: int, M: int | None = None, *, rng=None,
                n_min: int | None = None) -> AdaptiveBirthProblem:
    """An adaptive-birth problem of one synthetic family (spec §6.5).

    Parameters
    ----------
    family : {"diagonal", "uniform", "random"}
    V : int
        Number of sensors (``>= 1``).
    M : int, optional
        Measurements per sensor (default :data:`SIZES` ``[V]``, or 4); ``>= 3`` for the
        diagonal family (three targets).
    rng : None, int, SeedSequence or Generator
        Noise, clutter and (random family) parameters.
    n_min : int, optional
        Minimum detections of a birth tuple (default ``min(2, V)``).

    Returns
    -------
    AdaptiveBirthProblem

    Raises
    ------
    ValueError
        On an unknown family or sizes out of range.

    Examples
    --------
    >>> p = make_family("diagonal", 4, rng=0)
    >>> p.n_meas, p.n_feasible()
    ((10, 10, 10, 10), 14641)
    >>> make_family("uniform", 3, 2).log_weight_of([1, 2, 0])
    0.0
    """
    check_choice(family, "family", FAMILIES)
    V = check_int(V, "V", minimum=1)
    M = SIZES.get(V, 4) if M is None else check_int(M, "M", minimum=0)
    if family == "uniform":
        return AdaptiveBirthProblem.from_log_weights(np.zeros((M + 1,) * V), n_min=n_min)
    if M < 3:
        raise ValueError(f"the {family} family needs M >= 3 (three targets), got {M}")
    g = np.random.default_rng(rng)
    if family == "diagonal":
        pd = np.full(V, 0.95)
        detected = np.ones((V, 3), dtype=bool)          # every sensor sees every target
    else:
        pd = g.uniform(0.5, 0.99, V)
        detected = g.uniform(size=(V, 3)) < pd[:, None]
    z, ru = [], []
    targets = _TARGETS if family == "diagonal" else g.uniform(-_REGION, _REGION, (3, 2))
    for v in range(V):
        own = targets[detected[v]] + g.normal(0.0, 10.0, (int(detected[v].sum()), 2))
        clutter = g.uniform(-_REGION, _REGION, (M - own.shape[0], 2))
        z.append(np.vstack([own, clutter]))
        ru.append(np.full(M, 0.99) if family == "diagonal" else g.uniform(_TAU_RU, 1.0, M))
    return AdaptiveBirthProblem.from_measurements(
        z, ru, H=_H, R=_R, P_D=pd.tolist(), clutter_intensity=_KAPPA, mu0=_MU0, P0=_P0,
        tau_rU=_TAU_RU, n_min=n_min)
