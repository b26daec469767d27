"""Adaptive-birth preparation: the chain inputs of a sampler call on an adaptive-birth problem.

The state is one measurement tuple (``V`` entries, ``0`` missed); see
:class:`~rankedassign.adaptive_birth.problem.AdaptiveBirthProblem`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..engine.herding import INIT_CODES, KEY_CODES
from ..engine.kind import DrawInputs
from ..engine.records import HerdedDraw, record
from ..engine.result import Prepared
from ..engine.rng import base_key
from ..validation import check_choice, check_type
from .problem import SENSOR_ORDERS, AdaptiveBirthProblem
from .reference import HerdData, reference_data


# ---------------------------------------------------------------------------- kernel records
class AdaptiveBirthData(NamedTuple):
    """The kernels' inputs of an adaptive-birth sampler call (:func:`chain_inputs`).

    Read by :func:`rankedassign.adaptive_birth._kernels.sweep`; the reference reads the same
    values as lists (:class:`~rankedassign.adaptive_birth.reference.RefData`, whose fields
    these are). The arrays the other mode does not read are placeholders (one numba type for
    both modes); integers are int64, reals float64, arrays C-contiguous.

    Attributes
    ----------
    mode : int
        0: ``ln rho`` read from the tensor ``logw``; 1: the linear-Gaussian closed form.
    V : int
        Sensors, the length of a tuple ``J``.
    n : int
        State dimension of the Gaussian model (1 in tensor mode).
    random_order : int
        1: a fresh random sensor order every sweep (``sensor_order="random"``), 0: ``0..V-1``.
    shape : ndarray, shape (V,), int64
        ``M_s + 1``, the candidates of each sensor.
    off : ndarray, shape (V + 1,), int64
        Offsets of each sensor's measurements in ``a``, ``cz``, ``const`` (zeros in tensor
        mode).
    strides : ndarray, shape (V,), int64
        C-order strides of the tensor, in entries.
    logw : ndarray, shape (prod(shape),), float64
        Tensor mode: ``ln rho(J)`` of every tuple, flat in C order (length 1 in Gaussian mode).
    M0 : ndarray, shape (n, n), float64
        Prior information matrix.
    b0 : ndarray, shape (n,), float64
        Prior information vector.
    c0 : float
        Prior scalar term.
    A : ndarray, shape (V, n, n), float64
        ``H_s' R_s^-1 H_s`` per sensor.
    a : ndarray, shape (T, n), float64
        ``H_s' R_s^-1 z_sj`` per kept measurement, stacked over the sensors.
    cz, const : ndarray, shape (T,), float64
        ``z_sj' R_s^-1 z_sj`` and the measurement's constant term.
    log_miss : ndarray, shape (V,), float64
        ``ln(1 - P_D^(s))``.
    """

    mode: np.int64
    V: np.int64
    n: np.int64
    random_order: np.int64
    shape: np.ndarray
    off: np.ndarray
    strides: np.ndarray
    logw: np.ndarray
    M0: np.ndarray
    b0: np.ndarray
    c0: float
    A: np.ndarray
    a: np.ndarray
    cz: np.ndarray
    const: np.ndarray
    log_miss: np.ndarray


class AdaptiveBirthHerdedData(record(AdaptiveBirthData, HerdedDraw)):
    """The herded kernel's inputs (:func:`herd_inputs`): the fields of
    :class:`AdaptiveBirthData`, then those of the herded draw.

    Read by :func:`rankedassign.adaptive_birth._kernels.sweep_herded`; the reference's twin is
    :class:`~rankedassign.adaptive_birth.reference.HerdData`. One flat record, so that the
    Gibbs kernel's functions read it as they read :class:`AdaptiveBirthData`.

    Attributes
    ----------
    mode, V, n, random_order, shape, off, strides, logw, M0, b0, c0, A, a, cz, const, log_miss
        As in :class:`AdaptiveBirthData`.
    key_mode, init_mode, capacity, chain_length, tally
        As in :class:`~rankedassign.engine.records.HerdedDraw` (both keys are the other
        sensors' entries here).
    """


# ---------------------------------------------------------------------------- sampler inputs
def chain_inputs(problem: AdaptiveBirthProblem, sensor_order: str = "random"):
    """The arrays shared by the reference row update and the numba kernel.

    Parameters
    ----------
    problem : AdaptiveBirthProblem
    sensor_order : {"random", "fixed"}
        Sensor order of every sweep (spec §4.3, Q8).

    Returns
    -------
    AdaptiveBirthData
        Mode 0 = tensor (``logw`` flat, C order, ``strides`` in entries), 1 = Gaussian (``M0,
        b0, c0`` prior information, ``A`` (V, n, n), ``a`` (T, n), ``cz`` and ``const`` (T,)
        stacked over sensors at offsets ``off``, ``log_miss`` (V,)). Integers are int64
        scalars or arrays, reals float64, arrays C-contiguous (one numba type for both modes;
        unused arrays have length 1).

    Examples
    --------
    >>> import numpy as np
    >>> data = chain_inputs(AdaptiveBirthProblem.from_log_weights(np.zeros((2, 3))))
    >>> int(data.mode), data.shape.tolist(), data.strides.tolist()
    (0, [2, 3], [3, 1])
    """
    check_type(problem, "problem", AdaptiveBirthProblem)
    random_order = check_choice(sensor_order, "sensor_order", SENSOR_ORDERS) == "random"
    V = problem.n_sensors
    shape = np.asarray(problem.shape, dtype=np.int64)
    strides = np.ones(V, dtype=np.int64)
    for v in range(V - 2, -1, -1):
        strides[v] = strides[v + 1] * shape[v + 1]
    z1 = np.zeros(1)
    if problem._tensor is not None:
        return AdaptiveBirthData(
            mode=np.int64(0), V=np.int64(V), n=np.int64(1), random_order=np.int64(random_order),
            shape=shape, off=np.zeros(V + 1, dtype=np.int64), strides=strides,
            logw=_writable(problem._tensor.reshape(-1)),
            M0=np.zeros((1, 1)), b0=z1, c0=0.0, A=np.zeros((V, 1, 1)), a=np.zeros((1, 1)),
            cz=z1, const=z1, log_miss=np.zeros(V))
    m = problem._model
    T = int(m["off"][-1])
    a = m["a"] if T else np.zeros((1, m["n"]))
    cz = m["cz"] if T else z1
    const = m["const"] if T else z1
    c = _writable
    return AdaptiveBirthData(
        mode=np.int64(1), V=np.int64(V), n=np.int64(m["n"]), random_order=np.int64(random_order),
        shape=shape, off=m["off"].copy(), strides=strides, logw=z1, M0=c(m["M0"]),
        b0=c(m["b0"]), c0=float(m["c0"]), A=c(m["A"]), a=c(a), cz=c(cz), const=c(const),
        log_miss=c(m["log_miss"]))


def _writable(a) -> np.ndarray:
    """``a`` as a C-contiguous, writable float64 array (a copy only where it is not one).

    numba compiles a read-only array as a type of its own: a problem whose weights are
    read-only (a frozen tensor) would compile every sampler a second time.
    """
    return np.require(a, dtype=np.float64, requirements=["C", "W"])


def prepare(problem, start, scan, rng, options) -> Prepared:
    """Validate a sampler call on an :class:`AdaptiveBirthProblem`; the fields of its
    ``Prepared`` record (:mod:`rankedassign.engine.result`).

    Parameters
    ----------
    problem : AdaptiveBirthProblem
    start : "all_missed" or array_like of int, shape (V,)
        Start tuple of every chain (spec §5: the all-missed tuple); an explicit tuple must be
        in range and of positive weight.
    scan : str
        Must be ``"systematic"`` (the default): the sweep order of this sampler is the
        ``sensor_order`` option.
    rng
        As for the samplers.
    options : dict
        ``sensor_order`` (``"random"``, default, or ``"fixed"``; spec §4.3, Q8); nothing else.

    Returns
    -------
    Prepared
        Kind ``"adaptive_birth"``, driver ``"chains"`` (the reference's lists are built only
        when the Python backend asks).

    Raises
    ------
    TypeError
        On an unknown option or a non-integer start tuple.
    ValueError
        On ``scan != "systematic"``, an unknown ``sensor_order`` or start, or a start tuple out
        of range or of zero weight.

    Examples
    --------
    >>> import numpy as np
    >>> p = AdaptiveBirthProblem.from_log_weights(np.zeros((2, 3)))
    >>> f = prepare(p, "all_missed", "systematic", 0, {"sensor_order": "fixed"})
    >>> f.kind, f.x0.tolist(), f.n_values, f.rows
    ('adaptive_birth', [0, 0], 3, 2)
    """
    options = dict(options)
    sensor_order = options.pop("sensor_order", "random")
    if options:
        raise TypeError(f"unexpected option(s) {sorted(options)} for an AdaptiveBirthProblem "
                        "(its only option is sensor_order)")
    sensor_order = check_choice(sensor_order, "sensor_order", SENSOR_ORDERS)
    if scan != "systematic":
        raise ValueError(f"scan={scan!r} does not apply to an AdaptiveBirthProblem: its sweep "
                         "order is the option sensor_order='random' (default) or 'fixed'")
    V = problem.n_sensors
    if isinstance(start, str):
        check_choice(start, "start", ("all_missed",))
        x0 = np.zeros(V, dtype=np.int32)
    else:
        J, single = problem._as_tuples(start, "start")
        if not single:
            raise ValueError(f"start must be a single tuple of shape ({V},), got "
                             f"{np.shape(start)}")
        if not np.isfinite(problem.log_weight_of(J[0])):
            raise ValueError(f"start tuple {J[0].tolist()} has zero weight")
        x0 = J[0].astype(np.int32)
    data = chain_inputs(problem, sensor_order)
    n = int(data.n)

    def to_result(states):
        states = np.asarray(states, dtype=np.int64).reshape(-1, V)
        return states, np.asarray(problem.cost_of(states), dtype=np.float64).reshape(-1)

    return Prepared(kind="adaptive_birth", driver="chains", problem=problem, data=data,
                make_ref_data=lambda: reference_data(data),
                x0=x0, n_values=max(problem.shape), base=base_key(rng), rows=V,
                sweep_cost=sum(problem.shape) * (n * n + 1), to_result=to_result)


def temper(problem: AdaptiveBirthProblem, beta: float, options) -> AdaptiveBirthProblem:
    """The problem of weights ``ρ^β`` (its dense log-weight tensor times ``beta``).

    Every per-sensor conditional (spec §4.2) becomes the one of ``problem`` raised to
    ``beta``. A linear-Gaussian problem is evaluated once on its whole tuple space
    (:meth:`~rankedassign.adaptive_birth.AdaptiveBirthProblem.log_weights`), so tempering it
    is refused beyond that method's ``2**26`` tuples.

    Parameters
    ----------
    problem : AdaptiveBirthProblem
    beta : float
        Inverse temperature in ``(0, 1]``.
    options : dict
        The sampler's options (``sensor_order`` applies unchanged).

    Returns
    -------
    AdaptiveBirthProblem
        With the same ``n_min``.

    Raises
    ------
    ValueError
        If the tuple space is too large for the dense tensor.

    Examples
    --------
    >>> p = AdaptiveBirthProblem.from_log_weights(np.log([[4.0, 1.0]]), n_min=0)
    >>> np.exp(temper(p, 0.5, {}).log_weights()).tolist()
    [[2.0, 1.0]]
    """
    return AdaptiveBirthProblem.from_log_weights(problem.log_weights() * beta,
                                                 n_min=problem.n_min)



def herd_inputs(prep: Prepared, herding, chain_length: int):
    """The herded driver's inputs from an adaptive-birth call's Gibbs inputs.

    Parameters
    ----------
    prep : Prepared
        The call's :func:`prepare` result.
    herding : rankedassign.engine.herding.Herding
        Keys (``"shared"`` and ``"full"`` are the same key here:
        :func:`rankedassign.adaptive_birth.reference.herd_key`), initial weights and the
        table bound.
    chain_length : int
        Observations per chain (a sweep makes ``V`` draws).

    Returns
    -------
    DrawInputs
        As :attr:`rankedassign.engine.kind.DrawRule.inputs` documents: ``data`` is an
        :class:`AdaptiveBirthHerdedData` (the Gibbs inputs of :func:`chain_inputs`, the key
        and init codes, the table capacity, ``chain_length`` and the tallies ``[keys created,
        fall-back draws]``).

    Examples
    --------
    >>> from rankedassign.engine.herding import Herding
    >>> p = AdaptiveBirthProblem.from_log_weights(np.zeros((2, 3)))
    >>> prep = prepare(p, "all_missed", "systematic", 0, {})
    >>> data, tally, make_ref = herd_inputs(prep, Herding(), 10)[:3]
    >>> data.capacity, make_ref()[0].capacity       # 2 sensors x 10 sweeps
    (20, 20)
    """
    data = prep.data
    V = int(data.V)
    K = int(max(data.shape)) if V else 1
    cap = herding.capacity(V, chain_length)
    tally = np.zeros(2, dtype=np.int64)
    hdata = AdaptiveBirthHerdedData(
        **data._asdict(), key_mode=KEY_CODES[herding.keys], init_mode=INIT_CODES[herding.init],
        capacity=cap, chain_length=chain_length, tally=tally)

    def make_ref():
        ref_tally = [0, 0]
        return HerdData(prep.ref_data, herding.keys, herding.init, cap, ref_tally), ref_tally

    T = 4
    while T < 2 * cap:
        T *= 2
    chain_bytes = cap * (8 * K + 4 * V + 4) + 16 * T + 16 * (chain_length + 1) + 8 * K
    return DrawInputs(data=hdata, tally=tally, make_ref=make_ref, chain_bytes=chain_bytes)
