"""A stand-in multi-sensor problem for the sampler tests (the attributes of the real class).

``StandIn`` carries exactly the array attributes the samplers read: ``n_rows``, ``n_sensors``,
``n_meas``, ``log_eta_dead`` (P,), ``log_eta_alive`` (P, M_1+1, ..., M_V+1), ``log_s`` (P,)
and ``log_theta`` (V arrays (P, M_v+1)). :func:`random_problem` builds the families of spec
§6.5 on any shape: ``"separable"`` (random family: ``eta = s prod_v theta``, so ``pi~ = pi``),
``"coupled"`` (random-coupled: times ``exp(eps)`` on tuples detected by two or more sensors),
``"forbidden"`` (coupled, with some entries ``-inf``) and ``"extreme"`` (coupled, log-weights
times 400, so shifted weights underflow and the samplers' exact fall-back runs).
"""

from __future__ import annotations

import numpy as np

KINDS = ("separable", "coupled", "forbidden", "extreme")


class StandIn:
    """The multi-sensor problem's array attributes, nothing else."""

    def __init__(self, log_eta_dead, log_eta_alive, log_s=None, log_theta=None):
        self.log_eta_dead = np.asarray(log_eta_dead, dtype=float)
        self.log_eta_alive = np.asarray(log_eta_alive, dtype=float)
        self.n_rows = self.log_eta_alive.shape[0]
        self.n_meas = tuple(d - 1 for d in self.log_eta_alive.shape[1:])
        self.n_sensors = len(self.n_meas)
        self.log_s = None if log_s is None else np.asarray(log_s, dtype=float)
        self.log_theta = None if log_theta is None else tuple(
            np.asarray(t, dtype=float) for t in log_theta)


def random_problem(P, M, seed, kind="separable"):
    """A random problem of spec §6.5's random family with ``P`` rows and sensors ``M``."""
    rng = np.random.default_rng(seed)
    V = len(M)
    r_ps = rng.uniform(1e-3, 1, P) * rng.uniform(1e-3, 1, P)
    log_s = np.log(r_ps)
    log_theta = []
    for m in M:
        pd = rng.uniform(1e-3, 1, (P, 1))
        q = rng.uniform(0, 50, (P, m))
        log_theta.append(np.log(np.concatenate([1 - pd, pd * q], axis=1)))
    la = log_s.reshape((P,) + (1,) * V).copy()
    for v in range(V):
        shape = [P] + [1] * V
        shape[v + 1] = M[v] + 1
        la = la + log_theta[v].reshape(shape)
    ld = np.log1p(-r_ps)
    if kind != "separable":
        ndet = sum(np.indices(la.shape[1:])[v] > 0 for v in range(V)) if V else 0
        la = la + np.where(ndet >= 2, rng.normal(size=la.shape), 0.0)
    if kind == "forbidden":
        mask = rng.uniform(size=la.shape) < 0.3
        mask[(slice(None),) + (0,) * V] = False  # (0, ..., 0) stays allowed
        la[mask] = -np.inf
        for t in log_theta:
            t[rng.uniform(size=t.shape) < 0.2] = -np.inf
        ld[rng.uniform(size=P) < 0.3] = -np.inf
    if kind == "extreme":
        la, ld = 400 * la, 400 * ld
        log_theta = [400 * t for t in log_theta]
        log_s = 400 * log_s
    return StandIn(ld, la, log_s, log_theta)
