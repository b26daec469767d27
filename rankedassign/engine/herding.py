"""Settings of the herded draw (Chen et al. 2016), shared by every kind that herds.

Herded Gibbs replaces each row's random draw by a deterministic one: for row ``i`` and the
*key* of the other rows' state, a weight vector ``w`` over the row's candidates is kept, and
one update is

1. ``w += π_i(· | γ_{-i})``,
2. ``γ_i = argmax w`` among the candidates of positive conditional probability, ties to the
   first candidate in the row's order,
3. ``w[γ_i] -= 1``.

A key's conditional is fixed (it is a function of the key), so over its visits the
frequencies of its choices track the conditional with an error that falls as ``1/n``. The
key table holds at most ``max_keys`` keys per chain; a row update whose key is new while the
table is full draws by an ordinary Gibbs draw instead, and the result counts it
(:attr:`~rankedassign.SamplerResult.n_fallbacks`).

References
----------
.. [1] Y. Chen, L. Bornn, N. de Freitas, M. Eskelin, J. Fang, M. Welling, "Herded Gibbs
   Sampling", J. Mach. Learn. Res. 17(10):1-29, 2016.
.. [2] H. Yamashita, H. Suzuki, "Convergence analysis of herded-Gibbs-type sampling
   algorithms: effects of weight sharing", Stat. Comput. 29:1035-1053, 2019.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..validation import check_choice, check_int

__all__ = ["Herding", "check_herding", "HERDING_KEYS", "HERDING_INITS", "DEFAULT_MAX_KEYS",
           "KEY_CODES", "INIT_CODES"]

#: What a key is: the other rows' whole state, or the statistic the conditional depends on.
HERDING_KEYS = ("full", "shared")
#: Initial weights of a new key: its conditional, zeros, or uniforms from the chain's stream.
HERDING_INITS = ("conditional", "zero", "uniform")
KEY_CODES = {"full": 0, "shared": 1}
INIT_CODES = {"conditional": 0, "zero": 1, "uniform": 2}
#: Default bound on the keys of one chain's table.
DEFAULT_MAX_KEYS = 1 << 16
# Bytes of key tables of the chains simulated at once beyond which speculation is not used.
MAX_TABLE_BYTES = 1 << 30


@dataclass(frozen=True)
class Herding:
    """The herded draw's settings (validated on construction).

    Parameters
    ----------
    keys : {"shared", "full"}
        ``"full"``: the key of row ``i`` is the other rows' state ``γ_{-i}`` (Chen et al.);
        ``"shared"`` (default): the key is what row ``i``'s conditional depends on, i.e. the
        kind's statistic of the other rows (for the single-sensor problem: which of row
        ``i``'s gated measurements the other rows hold). Shared keys are revisited far more
        often, so the herding takes hold sooner, at the price of a bias in the long run
        (Yamashita & Suzuki 2019).
    init : {"uniform", "conditional", "zero"}
        A new key's initial weights: uniforms in ``[0, 1)`` drawn from the chain's stream
        (default; chains with different streams then differ), the key's conditional, or zero.
    max_keys : int
        Keys a chain's table may hold (default ``65 536``, at least 1); a chain's table is
        never larger than its row updates. A row update with a new key when the table is full
        draws as the Gibbs sampler does and is counted in ``n_fallbacks``.

    Attributes
    ----------
    keys, init, max_keys
        The parameters, validated.

    Examples
    --------
    >>> Herding()
    Herding(keys='shared', init='uniform', max_keys=65536)
    >>> Herding(keys="leaf")
    Traceback (most recent call last):
    ...
    ValueError: unknown keys 'leaf'; expected one of ('full', 'shared')
    """

    keys: str = "shared"
    init: str = "uniform"
    max_keys: int = DEFAULT_MAX_KEYS

    def __post_init__(self):
        check_choice(self.keys, "keys", HERDING_KEYS)
        check_choice(self.init, "init", HERDING_INITS)
        object.__setattr__(self, "max_keys", check_int(self.max_keys, "max_keys", minimum=1))

    def capacity(self, rows: int, chain_length: int) -> int:
        """Keys one chain's table needs room for: ``min(max_keys, rows * chain_length)``, >= 1.

        Parameters
        ----------
        rows : int
            Row updates per sweep.
        chain_length : int
            Sweeps of the chain.

        Returns
        -------
        int

        Examples
        --------
        >>> Herding().capacity(4, 25)
        100
        """
        return max(1, min(self.max_keys, rows * chain_length))


def check_herding(herding):
    """Return ``herding`` if it is None or a :class:`Herding`, else raise ``TypeError``.

    Parameters
    ----------
    herding : object
        The ``herding`` argument of a sampler.

    Returns
    -------
    Herding or None

    Examples
    --------
    >>> check_herding(None) is None
    True
    >>> check_herding("herded")
    Traceback (most recent call last):
    ...
    TypeError: herding must be None or a Herding(keys=..., init=..., max_keys=...), got str
    """
    if herding is None or isinstance(herding, Herding):
        return herding
    raise TypeError("herding must be None or a Herding(keys=..., init=..., max_keys=...), got "
                    f"{type(herding).__name__}")
