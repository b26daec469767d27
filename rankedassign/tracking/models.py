"""Models of the linear-Gaussian tracking study: motion, sensor, clutter, birth, survival.

Spec §6.1 (the paper's model, with Vo's public linear-Gaussian example for what the paper
leaves open). State ``x = [p_x, v_x, p_y, v_y]``; measurements are positions ``[p_x, p_y]``.
Every model is a small frozen dataclass; :func:`make_model` builds the two presets.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from ..validation import check_choice, check_real, check_type

__all__ = [
    "ConstantVelocity",
    "LinearMotion",
    "PositionSensor",
    "PoissonClutter",
    "BirthComponent",
    "LMBBirth",
    "ConstantSurvival",
    "EXTRACTIONS",
    "Model",
    "PRESETS",
    "PRESET_EXTRACTION",
    "make_model",
]


def _readonly(a) -> np.ndarray:
    a = np.array(a, dtype=np.float64, copy=True)
    a.setflags(write=False)
    return a


def _real_array(a, what: str) -> np.ndarray:
    """``a`` as a float64 array if it holds real numbers (not strings, booleans or complex).

    ``np.asarray(a, dtype=float)`` would parse ``"1.5"`` and turn ``True`` into 1.
    """
    try:
        given = np.asarray(a)
    except ValueError:  # numpy: "inhomogeneous shape"
        raise ValueError(f"{what} must be a rectangular array of real numbers, got the ragged "
                         f"sequence {a!r}") from None
    if given.dtype.kind not in "iuf":
        raise TypeError(f"{what} must hold real numbers, got {a!r} (dtype {given.dtype})")
    return given.astype(np.float64)


def _finite(compute):
    """``compute()`` if it runs without overflow and gives finite values, else None."""
    try:
        with np.errstate(all="ignore"):
            out = compute()
    except OverflowError:  # Python's float ** raises instead of returning inf
        return None
    return out if np.isfinite(out).all() else None


def _eigenvalues(P) -> np.ndarray:
    """Eigenvalues of the symmetric ``P``; non-finite ones (refused) if not representable."""
    with np.errstate(all="ignore"):
        return np.linalg.eigvalsh(P)


def _spd(P, n: int, what: str) -> np.ndarray:
    """``P`` (or the diagonal matrix of a vector ``P``) as a read-only n x n SPD matrix.

    Its determinant must be finite too: the filter divides by ``|H P Hᵀ + R|``.
    """
    given = _real_array(P, what)
    P = np.diag(given) if given.ndim == 1 else given
    with np.errstate(all="ignore"):  # entries near the float64 range: the tests say no
        bad = (P.shape != (n, n) or not np.isfinite(P).all() or not np.allclose(P, P.T)
               or not _eigenvalues(P).min() > 0)
    if bad:
        raise ValueError(
            f"{what} must be a symmetric positive definite {n}x{n} matrix, got shape "
            f"{given.shape}" + ("" if P.shape != (n, n) else f" with values {P.tolist()}")
        )
    if _finite(lambda: np.prod(_eigenvalues(P))) is None:
        raise ValueError(f"{what} is too large: its determinant overflows (values {P.tolist()})")
    return _readonly(P)


@dataclass(frozen=True)
class ConstantVelocity:
    """Nearly constant velocity motion in 2-D (spec §6.1, A14).

    Parameters
    ----------
    dt : float
        Sampling period ``Δ`` in seconds (default 1).
    sigma_w : float
        Standard deviation of the white acceleration noise per axis in m/s² (default 5).

    Attributes
    ----------
    dt : float
        Sampling period ``Δ`` in s, positive and finite (stored as a Python float).
    sigma_w : float
        Acceleration noise standard deviation ``σ_w`` in m/s², finite and ``>= 0``.
        :attr:`F`, :attr:`G` and :attr:`Q` are derived from the two.

    Raises
    ------
    TypeError
        If ``dt`` or ``sigma_w`` is not a real number (booleans included).
    ValueError
        If ``dt`` is not positive and finite, ``sigma_w`` not finite and ``>= 0``, or if they
        are so large that ``G`` or ``Q`` overflows.

    Notes
    -----
    ``F = I_2 ⊗ [[1, Δ], [0, 1]]``, ``G = I_2 ⊗ [Δ²/2, Δ]ᵀ``, ``Q = σ_w² G Gᵀ``; per axis
    ``Q = σ_w² [[Δ⁴/4, Δ³/2], [Δ³/2, Δ²]]`` (``[[6.25, 12.5], [12.5, 25]]`` for the defaults).

    Examples
    --------
    >>> from rankedassign.tracking.models import ConstantVelocity
    >>> cv = ConstantVelocity()
    >>> cv.F[:2, :2].tolist(), cv.Q[:2, :2].tolist()
    ([[1.0, 1.0], [0.0, 1.0]], [[6.25, 12.5], [12.5, 25.0]])
    """

    dt: float = 1.0
    sigma_w: float = 5.0

    def __post_init__(self):
        dt = check_real(self.dt, "dt", finite=False)
        sigma_w = check_real(self.sigma_w, "sigma_w", finite=False)
        if not (np.isfinite(dt) and dt > 0):
            raise ValueError(f"dt must be a positive finite number, got {dt}")
        if not (np.isfinite(sigma_w) and sigma_w >= 0):
            raise ValueError(f"sigma_w must be a finite number >= 0, got {sigma_w}")
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "sigma_w", sigma_w)
        # the derived matrices must be finite: an inf in Q would reach the filter's covariances
        if _finite(lambda: self.G) is None:
            raise ValueError(f"dt = {dt!r} is too large: the noise gain G = I_2 ⊗ [dt**2 / 2, "
                             "dt]' overflows")
        if _finite(lambda: sigma_w**2) is None:
            raise ValueError(f"sigma_w = {sigma_w!r} is too large: sigma_w**2 overflows")
        if _finite(lambda: self.Q) is None:
            raise ValueError(
                f"dt = {dt!r} with sigma_w = {sigma_w!r} makes the process noise covariance "
                "Q = sigma_w**2 G G' overflow (its largest entry is sigma_w**2 dt**4 / 4); use "
                "a smaller dt or sigma_w"
            )

    @property
    def F(self) -> np.ndarray:
        """State transition matrix, shape (4, 4)."""
        return _readonly(np.kron(np.eye(2), [[1.0, self.dt], [0.0, 1.0]]))

    @property
    def G(self) -> np.ndarray:
        """Noise gain, shape (4, 2)."""
        return _readonly(np.kron(np.eye(2), [[self.dt**2 / 2], [self.dt]]))

    @property
    def Q(self) -> np.ndarray:
        """Process noise covariance ``σ_w² G Gᵀ``, shape (4, 4)."""
        G = self.G
        return _readonly(self.sigma_w**2 * G @ G.T)



@dataclass(frozen=True, eq=False)
class LinearMotion:
    """Linear-Gaussian motion given by its matrices: ``x' = F x + w``, ``w ~ N(0, Q)``.

    For motion models that :class:`ConstantVelocity` does not describe, such as the
    continuous white-noise acceleration model of Stone Soup's ``ConstantVelocity`` (used by
    :mod:`rankedassign.stonesoup`). The state is ``[p_x, v_x, p_y, v_y]``, as everywhere in
    the filters.

    Parameters
    ----------
    F : array_like, shape (4, 4)
        State transition matrix (finite).
    Q : array_like, shape (4, 4)
        Process noise covariance, symmetric positive semi-definite (``0`` is allowed: no time
        has passed).

    Attributes
    ----------
    F : ndarray of float64, shape (4, 4)
        Read-only transition matrix.
    Q : ndarray of float64, shape (4, 4)
        Read-only process noise covariance.

    Raises
    ------
    TypeError
        If ``F`` or ``Q`` does not hold real numbers.
    ValueError
        If ``F`` is not a finite 4 x 4 matrix, or ``Q`` is not a finite symmetric positive
        semi-definite 4 x 4 matrix.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign.tracking.models import ConstantVelocity, LinearMotion
    >>> cv = ConstantVelocity()
    >>> LinearMotion(cv.F, cv.Q).Q[:2, :2].tolist()
    [[6.25, 12.5], [12.5, 25.0]]
    >>> LinearMotion(np.eye(4), np.zeros((4, 4))).F.shape
    (4, 4)
    """

    F: np.ndarray
    Q: np.ndarray

    def __post_init__(self):
        F = _real_array(self.F, "F")
        if F.shape != (4, 4) or not np.isfinite(F).all():
            raise ValueError(f"F must be a finite 4x4 matrix, got shape {F.shape}"
                             + ("" if F.shape != (4, 4) else f" with values {F.tolist()}"))
        Q = _real_array(self.Q, "Q")
        with np.errstate(all="ignore"):
            bad = (Q.shape != (4, 4) or not np.isfinite(Q).all() or not np.allclose(Q, Q.T)
                   or not _eigenvalues(Q).min() >= -1e-12 * max(1.0, np.abs(Q).max()))
        if bad:
            raise ValueError(
                "Q must be a symmetric positive semi-definite 4x4 matrix, got shape "
                f"{Q.shape}" + ("" if Q.shape != (4, 4) else f" with values {Q.tolist()}")
            )
        object.__setattr__(self, "F", _readonly(F))
        object.__setattr__(self, "Q", _readonly(Q))

@dataclass(frozen=True)
class PositionSensor:
    """Linear position sensor with constant detection probability (spec §6.1, A15).

    Parameters
    ----------
    p_d : float
        Detection probability ``P_D`` in ``(0, 1]`` (default 0.98).
    sigma_v : float, optional
        Standard deviation of the position noise per axis in m: ``R = σ_v² I_2`` (default
        10 m, the paper's). Leave it out when giving ``noise_cov``.
    noise_cov : array_like, shape (2, 2) or (2,), optional
        A general noise covariance ``R`` (symmetric positive definite; a vector is its
        diagonal), e.g. ``[25.0, 400.0]`` for 5 m in x and 20 m in y. Stored as a tuple of
        rows, so that sensors compare by value; :attr:`R` gives the array.

    Attributes
    ----------
    p_d : float
        Detection probability ``P_D`` in ``(0, 1]``.
    sigma_v : float or None
        Position noise standard deviation in m (10 when neither it nor ``noise_cov`` is
        given); None when the sensor has a general ``noise_cov``.
    noise_cov : tuple of tuple of float or None
        The general ``R`` as 2 rows of 2 floats (a diagonal given as a vector is expanded);
        None when ``R = σ_v² I_2``. Use :attr:`R` for the covariance either way.

    Raises
    ------
    TypeError
        If ``p_d`` or ``sigma_v`` is not a real number (booleans included) or ``noise_cov``
        does not hold real numbers.
    ValueError
        If ``p_d`` is outside ``(0, 1]``, ``sigma_v`` is not positive and finite or so large
        (small) that ``σ_v⁴ = |R|`` overflows (``σ_v²`` underflows to 0), ``noise_cov`` is
        not a symmetric positive definite 2 x 2 matrix with a finite determinant, or both
        ``sigma_v`` and ``noise_cov`` are given.

    Notes
    -----
    ``H = I_2 ⊗ [1, 0]`` (measures ``p_x, p_y``), ``R = σ_v² I_2`` or ``noise_cov``.

    Examples
    --------
    >>> from rankedassign.tracking.models import PositionSensor
    >>> s = PositionSensor()
    >>> s.H.tolist(), s.R.tolist()
    ([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]], [[100.0, 0.0], [0.0, 100.0]])
    >>> PositionSensor(noise_cov=[25.0, 400.0]).R.tolist()
    [[25.0, 0.0], [0.0, 400.0]]
    """

    p_d: float = 0.98
    sigma_v: float | None = None
    noise_cov: tuple | None = None

    def __post_init__(self):
        p_d = check_real(self.p_d, "p_d", finite=False)
        if not (0 < p_d <= 1):
            raise ValueError(f"p_d must be in (0, 1], got {p_d}")
        object.__setattr__(self, "p_d", p_d)
        if self.noise_cov is not None:
            if self.sigma_v is not None:
                raise ValueError("give either sigma_v or noise_cov, not both")
            # kept as nested tuples, so that sensors stay hashable and compare by value
            R = _spd(self.noise_cov, 2, "noise_cov")
            object.__setattr__(self, "noise_cov", tuple(map(tuple, R.tolist())))
            return
        sigma_v = 10.0 if self.sigma_v is None else check_real(self.sigma_v, "sigma_v",
                                                                finite=False)
        if not (np.isfinite(sigma_v) and sigma_v > 0):
            raise ValueError(f"sigma_v must be a positive finite number, got {sigma_v}")
        object.__setattr__(self, "sigma_v", sigma_v)
        variance = _finite(lambda: sigma_v**2)
        # the filter divides by |S| >= |R| = sigma_v**4
        if variance is None or _finite(lambda: variance * variance) is None:
            raise ValueError(f"sigma_v = {sigma_v!r} is too large: the noise covariance "
                             "R = sigma_v**2 I or its determinant sigma_v**4 overflows")
        if variance == 0:
            raise ValueError(f"sigma_v = {sigma_v!r} is too small: the noise covariance "
                             "R = sigma_v**2 I underflows to 0 (not positive definite)")

    @property
    def H(self) -> np.ndarray:
        """Measurement matrix, shape (2, 4)."""
        return _readonly(np.kron(np.eye(2), [[1.0, 0.0]]))

    @property
    def R(self) -> np.ndarray:
        """Measurement noise covariance, shape (2, 2)."""
        if self.noise_cov is not None:
            return _readonly(self.noise_cov)
        return _readonly(self.sigma_v**2 * np.eye(2))


@dataclass(frozen=True)
class PoissonClutter:
    """Poisson clutter, uniform over a rectangle (spec §6.1, A16).

    Parameters
    ----------
    rate : float
        Mean number ``λ_c`` of clutter points per scan (paper: 50; Vo's example: 30).
    region : tuple of tuple of float
        ``((x_min, x_max), (y_min, y_max))`` in m (default ``[−1000, 1000]²``).

    Attributes
    ----------
    rate : float
        Mean clutter points per scan ``λ_c``, positive and finite.
    region : tuple of tuple of float
        ``((x_min, x_max), (y_min, y_max))`` in m as Python floats, finite, ``max > min``;
        :attr:`area` and :attr:`intensity` are derived from it.

    Raises
    ------
    TypeError
        If ``rate`` is not a real number (booleans included) or ``region`` does not hold real
        numbers.
    ValueError
        If ``rate`` is not positive and finite, ``region`` is not two finite intervals with
        ``max > min``, or its area or the intensity ``κ = λ_c / area`` is not a positive
        finite number (a region too large or too small for float64).

    Examples
    --------
    >>> from rankedassign.tracking.models import PoissonClutter
    >>> cl = PoissonClutter(50.0)
    >>> cl.area, cl.intensity
    (4000000.0, 1.25e-05)
    """

    rate: float = 50.0
    region: tuple = ((-1000.0, 1000.0), (-1000.0, 1000.0))

    def __post_init__(self):
        rate = check_real(self.rate, "rate", finite=False)
        if not (np.isfinite(rate) and rate > 0):
            raise ValueError(f"clutter rate must be a positive finite number, got {rate}")
        object.__setattr__(self, "rate", rate)
        reg = _real_array(self.region, "region")
        if reg.shape != (2, 2) or not np.all(reg[:, 1] > reg[:, 0]):
            raise ValueError(
                f"region must be ((x_min, x_max), (y_min, y_max)) with max > min, got {self.region}"
            )
        if not np.isfinite(reg).all():
            raise ValueError(f"region must have finite bounds, got {self.region}")
        object.__setattr__(self, "region", tuple(tuple(float(v) for v in r) for r in reg))
        # the filter takes ln κ: the area and κ = λ_c / area must be positive and finite
        area = self.area
        if not (0 < area < math.inf):
            raise ValueError(
                f"region {self.region} has area (x_max - x_min) * (y_max - y_min) = {area}, "
                "which is not a positive finite number"
            )
        if not (0 < self.intensity < math.inf):
            raise ValueError(
                f"clutter intensity rate / area = {rate!r} / {area!r} = {self.intensity} is not "
                "a positive finite number; choose rate and region on a common scale"
            )

    @property
    def area(self) -> float:
        """Area of the region in m²."""
        (x0, x1), (y0, y1) = self.region
        return (x1 - x0) * (y1 - y0)

    @property
    def intensity(self) -> float:
        """Clutter intensity ``κ = λ_c / area`` in m⁻² (constant over the region)."""
        return self.rate / self.area

    def sample(self, rng: np.random.Generator) -> np.ndarray:
        """Draw one scan of clutter: ``Poisson(λ_c)`` points uniform on the region, (n, 2).

        Parameters
        ----------
        rng : numpy.random.Generator
            Source of the draws: one ``poisson`` draw for the count ``n``, then
            ``random((n, 2))`` for the positions (a RandomState also works, it has both
            methods).

        Returns
        -------
        ndarray of float64, shape (n, 2)
            Clutter positions ``(x, y)`` in m, uniform on :attr:`region`;
            ``n ~ Poisson(rate)``, possibly 0 (shape ``(0, 2)``).

        Examples
        --------
        >>> import numpy as np
        >>> from rankedassign.tracking.models import PoissonClutter
        >>> pts = PoissonClutter(5.0, ((0.0, 1.0), (0.0, 2.0))).sample(np.random.default_rng(0))
        >>> bool(((pts >= 0) & (pts <= [1.0, 2.0])).all())
        True
        """
        n = rng.poisson(self.rate)
        (x0, x1), (y0, y1) = self.region
        u = rng.random((n, 2))
        return np.column_stack([x0 + (x1 - x0) * u[:, 0], y0 + (y1 - y0) * u[:, 1]])


@dataclass(frozen=True, eq=False)
class BirthComponent:
    """One Bernoulli component of the LMB birth: existence ``r`` and a Gaussian ``N(mean, cov)``.

    Parameters
    ----------
    r : float
        Existence probability ``r_B`` of the birth track, in ``(0, 1)``.
    mean : array_like, shape (4,)
        Mean ``m_B`` of the birth state ``[p_x, v_x, p_y, v_y]`` (finite; any shape with 4
        entries is flattened).
    cov : array_like, shape (4, 4) or (4,)
        Covariance ``P_B``, symmetric positive definite; a vector is its diagonal.

    Attributes
    ----------
    r : float
        Existence probability in ``(0, 1)``.
    mean : ndarray of float64, shape (4,)
        Read-only mean.
    cov : ndarray of float64, shape (4, 4)
        Read-only covariance (symmetric positive definite, with a finite determinant).

    Raises
    ------
    TypeError
        If ``r`` is not a real number (booleans included) or ``mean`` or ``cov`` does not hold
        real numbers.
    ValueError
        If ``r`` is outside ``(0, 1)``, ``mean`` is not 4 finite numbers, or ``cov`` is not a
        symmetric positive definite 4 x 4 matrix with a finite determinant.

    Examples
    --------
    >>> from rankedassign.tracking.models import BirthComponent
    >>> b = BirthComponent(0.03, [0.0, 0.0, 0.0, 0.0], [100.0, 100.0, 100.0, 100.0])
    >>> b.cov.shape
    (4, 4)
    """

    r: float
    mean: np.ndarray
    cov: np.ndarray

    def __post_init__(self):
        r = check_real(self.r, "r", finite=False)
        if not (0 < r < 1):
            raise ValueError(f"birth existence probability r must be in (0, 1), got {r}")
        object.__setattr__(self, "r", r)
        m = _real_array(self.mean, "birth mean").reshape(-1)
        if m.shape != (4,) or not np.isfinite(m).all():
            raise ValueError(f"birth mean must be 4 finite numbers, got {self.mean}")
        object.__setattr__(self, "mean", _readonly(m))
        object.__setattr__(self, "cov", _spd(self.cov, 4, "birth covariance"))


@dataclass(frozen=True)
class LMBBirth:
    """LMB birth model: the same Bernoulli components at every scan (spec §6.1).

    Labels of the tracks born at scan ``k`` are ``(k, b)``, ``b = 1..len(components)``.

    Parameters
    ----------
    components : iterable of BirthComponent
        The Bernoulli components, in label order (may be empty: no static birth).

    Attributes
    ----------
    components : tuple of BirthComponent
        The components; component ``b - 1`` gives the tracks of label ``(k, b)``.
        :attr:`r`, :attr:`means` and :attr:`covs` stack them as arrays.

    Raises
    ------
    TypeError
        If a component is not a :class:`BirthComponent`.

    Examples
    --------
    >>> from rankedassign.tracking.models import LMBBirth
    >>> birth = LMBBirth.paper()
    >>> len(birth.components), birth.components[1].mean.tolist()
    (4, [400.0, 0.0, -600.0, 0.0])
    """

    components: tuple

    def __post_init__(self):
        comps = tuple(self.components)
        for c in comps:
            if not isinstance(c, BirthComponent):
                raise TypeError(f"components must be BirthComponent, got {type(c).__name__}")
        object.__setattr__(self, "components", comps)

    MEANS = ((0.0, 0.0, 0.0, 0.0), (400.0, 0.0, -600.0, 0.0), (-800.0, 0.0, -200.0, 0.0),
             (-200.0, 0.0, 800.0, 0.0))

    @classmethod
    def paper(cls, r: float = 0.03, std=(300.0, 10.0, 300.0, 10.0)) -> LMBBirth:
        """The four birth locations of spec §6.1 with ``P_B = diag(std)²``.

        Parameters
        ----------
        r : float, optional
            Existence probability ``r_B`` of each of the four components, in ``(0, 1)``
            (default 0.03, spec §6.1).
        std : array_like, shape (4,), optional
            Standard deviations of ``[p_x, v_x, p_y, v_y]`` in m and m/s (default
            ``(300, 10, 300, 10)``); ``P_B = diag(std²)``, the same for every component.

        Returns
        -------
        LMBBirth
            Four components with the means of :attr:`MEANS` (in that order), each with
            existence ``r`` and covariance ``P_B``.
        """
        cov = np.diag(np.asarray(std, dtype=np.float64) ** 2)
        return cls(tuple(BirthComponent(r, m, cov) for m in cls.MEANS))

    @property
    def r(self) -> np.ndarray:
        """Existence probabilities, shape (B,)."""
        return np.array([c.r for c in self.components])

    @property
    def means(self) -> np.ndarray:
        """Means, shape (B, 4)."""
        return np.array([c.mean for c in self.components]).reshape(-1, 4)

    @property
    def covs(self) -> np.ndarray:
        """Covariances, shape (B, 4, 4)."""
        return np.array([c.cov for c in self.components]).reshape(-1, 4, 4)


@dataclass(frozen=True)
class ConstantSurvival:
    """Constant survival probability ``P_S`` (spec §6.1: 0.99).

    Parameters
    ----------
    p_s : float
        Survival probability ``P_S`` of every track from one scan to the next, in ``(0, 1]``
        (default 0.99).

    Attributes
    ----------
    p_s : float
        Survival probability in ``(0, 1]`` (stored as a Python float).

    Raises
    ------
    TypeError
        If ``p_s`` is not a real number (booleans included).
    ValueError
        If ``p_s`` is outside ``(0, 1]``.

    Examples
    --------
    >>> from rankedassign.tracking.models import ConstantSurvival
    >>> ConstantSurvival().p_s
    0.99
    """

    p_s: float = 0.99

    def __post_init__(self):
        p_s = check_real(self.p_s, "p_s", finite=False)
        if not (0 < p_s <= 1):
            raise ValueError(f"p_s must be in (0, 1], got {p_s}")
        object.__setattr__(self, "p_s", p_s)


#: State extraction rules (spec §6.5): the paper's hysteresis on the existence probabilities, or
#: the MAP cardinality of Vo's public LMB code (the ``n̂`` most likely tracks).
EXTRACTIONS = ("hysteresis", "map")


@dataclass(frozen=True)
class Model:
    """Everything the filter and the measurement generator need.

    Parameters
    ----------
    motion, sensor, clutter, birth, survival
        The parts of the model (defaults: the paper's, spec §6.1).
    extraction : {"hysteresis", "map"}, optional
        The state extraction a filter on this model uses unless told otherwise (its
        ``extraction=None``): the paper's hysteresis (default) or Vo's MAP cardinality
        (:data:`EXTRACTIONS`). :func:`make_model` sets the preset's own
        (:data:`PRESET_EXTRACTION`), so that a filter built on a preset's model extracts as
        :func:`~rankedassign.tracking.run.run_scenario` does on that preset.

    Attributes
    ----------
    motion : ConstantVelocity or LinearMotion
        Motion model (``F``, ``Q``).
    sensor : PositionSensor
        Sensor model (``H``, ``R``, ``P_D``).
    clutter : PoissonClutter
        Clutter model (``λ_c``, region, intensity ``κ``).
    birth : LMBBirth
        Static LMB birth appended at every scan.
    survival : ConstantSurvival
        Survival probability ``P_S``.
    extraction : {"hysteresis", "map"}
        Default state extraction of a filter on this model.

    Raises
    ------
    TypeError
        If a part is not of its type (``motion`` a :class:`ConstantVelocity` or
        :class:`LinearMotion`, ...).
    ValueError
        On an unknown ``extraction`` (one not in :data:`EXTRACTIONS`).

    Examples
    --------
    >>> from rankedassign.tracking.models import Model, make_model
    >>> m = make_model("paper")
    >>> m.clutter.rate, m.sensor.p_d, m.survival.p_s
    (50.0, 0.98, 0.99)
    >>> make_model("vo").extraction, Model().extraction
    ('map', 'hysteresis')
    """

    motion: ConstantVelocity = field(default_factory=ConstantVelocity)
    sensor: PositionSensor = field(default_factory=PositionSensor)
    clutter: PoissonClutter = field(default_factory=PoissonClutter)
    birth: LMBBirth = field(default_factory=LMBBirth.paper)
    survival: ConstantSurvival = field(default_factory=ConstantSurvival)
    extraction: str = "hysteresis"

    def __post_init__(self):
        check_type(self.motion, "motion", (ConstantVelocity, LinearMotion))
        check_type(self.sensor, "sensor", PositionSensor)
        check_type(self.clutter, "clutter", PoissonClutter)
        check_type(self.birth, "birth", LMBBirth)
        check_type(self.survival, "survival", ConstantSurvival)
        check_choice(self.extraction, "extraction", EXTRACTIONS)


def _paper() -> Model:
    return Model(
        ConstantVelocity(1.0, 5.0),
        PositionSensor(0.98, 10.0),
        PoissonClutter(50.0),
        LMBBirth.paper(0.03, (300.0, 10.0, 300.0, 10.0)),
        ConstantSurvival(0.99),
    )


def _paper_var() -> Model:
    # The paper's birth covariance numbers read as variances, diag(300, 10, 300, 10), not as
    # standard deviations (spec §6.1 reads them as standard deviations).
    return Model(
        ConstantVelocity(1.0, 5.0),
        PositionSensor(0.98, 10.0),
        PoissonClutter(50.0),
        LMBBirth.paper(0.03, tuple(math.sqrt(v) for v in (300.0, 10.0, 300.0, 10.0))),
        ConstantSurvival(0.99),
    )


def _vo() -> Model:
    # Vo's public jointlmb example: B_birth = diag([10; 10; 10; 10]), P_birth = B B' = 100 I,
    # lambda_c = 30; everything else as the paper.
    return Model(
        ConstantVelocity(1.0, 5.0),
        PositionSensor(0.98, 10.0),
        PoissonClutter(30.0),
        LMBBirth.paper(0.03, (10.0, 10.0, 10.0, 10.0)),
        ConstantSurvival(0.99),
    )


PRESETS = {"paper": _paper, "paper-var": _paper_var, "vo": _vo}

#: State extraction of each preset (spec §6.5), carried by its model (:attr:`Model.extraction`)
#: and so the default of every filter built on it: the paper's hysteresis (``ϑ_u = 0.9``,
#: ``ϑ_l = 10⁻³``) for ``"paper"`` and ``"paper-var"``; the MAP cardinality of Vo's public LMB
#: code (the ``n̂`` most likely tracks) for ``"vo"``, the preset that reproduces that code's
#: example.
PRESET_EXTRACTION = {"paper": "hysteresis", "paper-var": "hysteresis", "vo": "map"}


def make_model(preset: str = "paper") -> Model:
    """Build the model of a preset.

    Parameters
    ----------
    preset : {"paper", "paper-var", "vo"}
        ``"paper"``: λ_c = 50, ``P_B = diag(300², 10², 300², 10²)``, ``r_B = 0.03``,
        ``P_D = 0.98``, ``P_S = 0.99``, ``R = 10² I`` (spec §6.1). ``"paper-var"``: the same
        with the paper's birth numbers read as variances, ``P_B = diag(300, 10, 300, 10)``
        (σ ≈ 17.3 m and 3.16 m/s); the paper's observation totals fit this reading (see the
        Tracking page of the documentation). ``"vo"``: Vo's public example, λ_c = 30 and
        ``P_B = 100 I``, otherwise as ``"paper"``.

    Returns
    -------
    Model
        With the preset's state extraction (:data:`PRESET_EXTRACTION`: MAP cardinality for
        ``"vo"``, hysteresis otherwise), which filters built on it use by default.

    Raises
    ------
    ValueError
        On an unknown preset.

    Examples
    --------
    >>> from rankedassign.tracking.models import make_model
    >>> make_model("vo").birth.covs[0].diagonal().tolist()
    [100.0, 100.0, 100.0, 100.0]
    >>> make_model("paper-var").birth.covs[0].diagonal().round(6).tolist()
    [300.0, 10.0, 300.0, 10.0]
    >>> make_model("vo").extraction
    'map'
    """
    preset = check_choice(preset, "preset", tuple(PRESETS))
    return dataclasses.replace(PRESETS[preset](), extraction=PRESET_EXTRACTION[preset])
