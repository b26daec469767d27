"""The counter-based random stream shared by the reference samplers and the numba kernels.

Both sampler implementations (:mod:`rankedassign.reference` and :mod:`rankedassign.single._kernels`)
draw from SplitMix64 (Steele, Lea & Flood 2014), written once in pure Python here and once with
``np.uint64`` arithmetic in :mod:`rankedassign.single._kernels`; the two agree bit for bit (tested).

SplitMix64, with all arithmetic modulo ``2**64``::

    mix64(z):  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9
               z = (z ^ (z >> 27)) * 0x94D049BB133111EB
               return z ^ (z >> 31)
    next():    s = s + 0x9E3779B97F4A7C15;  return mix64(s)
    uniform(): (next() >> 11) * 2**-53          in [0, 1), a multiple of 2**-53

Seeding. The public samplers turn ``rng`` (anything :func:`numpy.random.default_rng`
accepts) into one 64-bit base key ``base = default_rng(rng).integers(0, 2**63,
dtype=uint64)``; a passed :class:`numpy.random.Generator` is advanced by that one draw. Chain
``c`` (0-based; the original sampler is chain 0) starts from the state
``mix64(base ^ mix64(c + 1))``. A chain's stream therefore depends only on ``rng`` and its
index, never on the backend or on how chains are spread over threads.

The tracking filters and scenario runners spawn child streams from ``rng``
(:meth:`numpy.random.Generator.spawn`); :func:`spawning_generator` turns ``rng`` into a
Generator that can spawn. A :class:`numpy.random.RandomState` (accepted by
:func:`numpy.random.default_rng`, and by the samplers, which take one draw from it) has no
seed sequence to spawn from; it is replaced by the Generator seeded with that same one draw.
Both go through :func:`check_rng`, so every public ``rng`` is refused with one message.

The Zobrist keys that hash sampler states in the kernels come from the same generator started
at the fixed state :data:`ZOBRIST_SEED`.

References
----------
.. [1] G. L. Steele Jr., D. Lea, C. H. Flood, "Fast Splittable Pseudorandom Number
   Generators", OOPSLA 2014.
"""

from __future__ import annotations

import numpy as np
from numpy.random.bit_generator import ISpawnableSeedSequence

__all__ = ["SplitMix64", "mix64", "chain_state", "base_key", "check_rng", "spawning_generator",
           "GOLDEN", "ZOBRIST_SEED"]

MASK64 = 0xFFFFFFFFFFFFFFFF
GOLDEN = 0x9E3779B97F4A7C15
MUL1 = 0xBF58476D1CE4E5B9
MUL2 = 0x94D049BB133111EB
#: 2**-53: turns the top 53 bits of a draw into a double in [0, 1) exactly.
TWO_M53 = 1.0 / 9007199254740992.0
#: Start state of the Zobrist key stream (any fixed constant; the keys only need to be distinct).
ZOBRIST_SEED = 0x2545F4914F6CDD1D


def mix64(z: int) -> int:
    """The SplitMix64 output function (a bijection on 64-bit integers).

    Parameters
    ----------
    z : int
        A value in ``[0, 2**64)``.

    Returns
    -------
    int
        The mixed value in ``[0, 2**64)``.

    Examples
    --------
    >>> mix64(0)
    0
    >>> hex(mix64(1))
    '0x5692161d100b05e5'
    """
    z &= MASK64
    z = ((z ^ (z >> 30)) * MUL1) & MASK64
    z = ((z ^ (z >> 27)) * MUL2) & MASK64
    return z ^ (z >> 31)


def chain_state(base: int, chain: int) -> int:
    """Initial SplitMix64 state of chain ``chain``: ``mix64(base ^ mix64(chain + 1))``.

    Parameters
    ----------
    base : int
        The run's 64-bit base key (:func:`base_key`); only its low 64 bits are used.
    chain : int
        0-based chain index (the original sampler's single chain is chain 0).

    Returns
    -------
    int
        The chain's initial state, in ``[0, 2**64)``.

    Examples
    --------
    >>> chain_state(0, 0) == mix64(mix64(1))
    True
    """
    return mix64((base & MASK64) ^ mix64(chain + 1))


def check_rng(rng) -> np.random.Generator:
    """``np.random.default_rng(rng)``, with numpy's errors turned into messages naming ``rng``.

    Parameters
    ----------
    rng : None, int, array_like of int, SeedSequence, BitGenerator, Generator or RandomState
        Anything :func:`numpy.random.default_rng` accepts. A Generator is returned as it is;
        a RandomState or a BitGenerator is wrapped, so draws from the result advance it.

    Returns
    -------
    numpy.random.Generator

    Raises
    ------
    TypeError
        If ``rng`` is of a kind numpy cannot seed from (a float, a string, ...).
    ValueError
        If it is of the right kind but not a valid seed (a negative int).

    Examples
    --------
    >>> int(check_rng(3).integers(10)) == int(check_rng(3).integers(10))
    True
    >>> check_rng(1.5)
    Traceback (most recent call last):
    ...
    TypeError: rng must be None, a non-negative int or sequence of them, a SeedSequence, a
    BitGenerator or a Generator; got 1.5 (SeedSequence expects int or sequence of ints for
    entropy not 1.5)
    """
    try:
        return np.random.default_rng(rng)
    except (TypeError, ValueError) as exc:  # numpy's message does not name the argument
        raise type(exc)(
            "rng must be None, a non-negative int or sequence of them, a SeedSequence, a "
            f"BitGenerator or a Generator; got {rng!r} ({exc})"
        ) from None


def base_key(rng) -> int:
    """Draw the 64-bit base key of a sampler run from ``rng``.

    Parameters
    ----------
    rng : None, int, array_like of int, SeedSequence, BitGenerator or Generator
        Anything :func:`numpy.random.default_rng` accepts (:func:`check_rng`). A Generator (or
        a RandomState) is advanced by one draw; ``None`` gives a fresh, unpredictable key.

    Returns
    -------
    int
        A value in ``[0, 2**63)``.

    Examples
    --------
    >>> base_key(7) == base_key(7)
    True
    >>> base_key(-1)
    Traceback (most recent call last):
    ...
    ValueError: rng must be None, a non-negative int or sequence of them, a SeedSequence, a
    BitGenerator or a Generator; got -1 (expected non-negative integer)
    """
    return int(check_rng(rng).integers(0, 2**63, dtype=np.uint64))


def spawning_generator(rng) -> np.random.Generator:
    """``rng`` as a Generator that can spawn child streams (:meth:`~numpy.random.Generator.spawn`).

    Parameters
    ----------
    rng : None, int, array_like of int, SeedSequence, BitGenerator, Generator or RandomState
        As :func:`check_rng`. A Generator whose bit generator has a seed sequence is returned
        as it is (spawning advances it). A RandomState, or a BitGenerator or Generator without
        a seed sequence, cannot spawn: it is advanced by the one draw :func:`base_key` takes
        from it (the draw the samplers take) and the Generator seeded with that draw is
        returned, so the result is a deterministic function of its state.

    Returns
    -------
    numpy.random.Generator

    Raises
    ------
    TypeError, ValueError
        As :func:`check_rng`.

    Examples
    --------
    >>> import numpy as np
    >>> g = spawning_generator(np.random.RandomState(5))
    >>> h = np.random.default_rng(base_key(np.random.RandomState(5)))
    >>> bool(g.spawn(1)[0].random() == h.spawn(1)[0].random())
    True
    """
    gen = check_rng(rng)
    if isinstance(gen.bit_generator.seed_seq, ISpawnableSeedSequence):
        return gen
    return np.random.default_rng(int(gen.integers(0, 2**63, dtype=np.uint64)))


class SplitMix64:
    """Pure-Python SplitMix64 stream (the reference twin of the kernels' generator).

    Parameters
    ----------
    state : int
        Initial 64-bit state (see :func:`chain_state`).

    Examples
    --------
    >>> g = SplitMix64(chain_state(12345, 0))
    >>> u = g.uniform()
    >>> 0.0 <= u < 1.0
    True
    >>> SplitMix64(0).next_u64() == mix64(GOLDEN)
    True
    """

    __slots__ = ("state",)

    def __init__(self, state: int):
        self.state = state & MASK64

    def next_u64(self) -> int:
        """Advance the state by the golden-ratio increment and return the mixed state.

        Returns
        -------
        int
            ``mix64(state)`` of the advanced state, in ``[0, 2**64)``.
        """
        self.state = (self.state + GOLDEN) & MASK64
        return mix64(self.state)

    def uniform(self) -> float:
        """A double in ``[0, 1)``: the top 53 bits of :meth:`next_u64` times ``2**-53``.

        Returns
        -------
        float
            A multiple of ``2**-53`` in ``[0, 1)``; the state advances by one step.
        """
        return (self.next_u64() >> 11) * TWO_M53
