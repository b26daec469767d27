"""numba twin of the SplitMix64 stream of :mod:`rankedassign._rng`, and the Zobrist keys.

Every sampler kernel (single-sensor, multi-sensor, adaptive birth) draws its uniforms with
:func:`next_uniform` from a one-element ``uint64`` state array, one stream per chain started at
:func:`chain_state`; the pure-Python references draw the same numbers from
:class:`rankedassign._rng.SplitMix64` (tested bit for bit).

References
----------
.. [1] G. L. Steele Jr., D. Lea, C. H. Flood, "Fast Splittable Pseudorandom Number
   Generators", OOPSLA 2014.
.. [2] A. L. Zobrist, "A New Hashing Method with Application for Game Playing", Tech. Rep.
   88, Univ. of Wisconsin, 1970.
"""

from __future__ import annotations

import numpy as np

from .numba_options import jit

__all__ = ["mix64", "chain_state", "next_uniform", "uniform_stream", "zobrist_keys"]

# SplitMix64 constants (see rankedassign._rng); np.uint64 so numba stays in unsigned arithmetic.
_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MUL1 = np.uint64(0xBF58476D1CE4E5B9)
_MUL2 = np.uint64(0x94D049BB133111EB)
_S30 = np.uint64(30)
_S27 = np.uint64(27)
_S31 = np.uint64(31)
_S11 = np.uint64(11)
_TWO_M53 = 1.0 / 9007199254740992.0
_ONE = np.uint64(1)


@jit()
def mix64(z):
    """SplitMix64 output function on ``np.uint64`` (twin of :func:`rankedassign._rng.mix64`).

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign import _rng
    >>> int(mix64(np.uint64(1))) == _rng.mix64(1)
    True
    """
    # np.multiply / np.add wrap modulo 2**64 silently, also when NUMBA_DISABLE_JIT=1 runs
    # this as Python (the * and + operators warn on numpy scalar overflow there)
    z = np.multiply(z ^ (z >> _S30), _MUL1)
    z = np.multiply(z ^ (z >> _S27), _MUL2)
    return z ^ (z >> _S31)


@jit()
def chain_state(base, chain):
    """Initial stream state of chain ``chain``: ``mix64(base ^ mix64(chain + 1))``.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign import _rng
    >>> int(chain_state(np.uint64(99), 3)) == _rng.chain_state(99, 3)
    True
    """
    return mix64(base ^ mix64(np.add(np.uint64(chain), _ONE)))


@jit()
def next_uniform(rs):
    """Advance the one-element ``uint64`` state array ``rs``; return a double in ``[0, 1)``.

    Examples
    --------
    >>> import numpy as np
    >>> from rankedassign import _rng
    >>> rs = np.array([5], dtype=np.uint64)
    >>> next_uniform(rs) == _rng.SplitMix64(5).uniform()
    True
    """
    s = np.add(rs[0], _GOLDEN)
    rs[0] = s
    return np.float64(mix64(s) >> _S11) * _TWO_M53


@jit()
def uniform_stream(state, n):
    """``n`` consecutive uniforms of the stream started at ``state`` (used by the tests).

    Examples
    --------
    >>> import numpy as np
    >>> uniform_stream(np.uint64(0), 3).shape
    (3,)
    """
    rs = np.empty(1, dtype=np.uint64)
    rs[0] = state
    out = np.empty(n)
    for t in range(n):
        out[t] = next_uniform(rs)
    return out


@jit()
def zobrist_keys(L, K, seed):
    """``(L, K)`` table of 64-bit Zobrist keys, drawn row-major from SplitMix64 at ``seed``.

    Position ``l`` of a sampler state holding value ``k`` contributes ``keys[l, k]`` to the
    state's hash (XOR over positions), so a change of one position updates the hash with two
    XORs.

    Examples
    --------
    >>> import numpy as np
    >>> zobrist_keys(2, 3, np.uint64(1)).shape
    (2, 3)
    """
    keys = np.empty((L, K), dtype=np.uint64)
    s = seed
    for i in range(L):
        for k in range(K):
            s = np.add(s, _GOLDEN)
            keys[i, k] = mix64(s)
    return keys
