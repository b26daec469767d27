"""The chain engine: what every sampler runs on, whatever the problem kind.

It imports no problem kind; each kind (:mod:`rankedassign.single`,
:mod:`rankedassign.multisensor`, :mod:`rankedassign.adaptive_birth`) builds on it.

* :mod:`~rankedassign.engine.kind` — the :class:`~rankedassign.engine.kind.Kind` record a
  kind hands to the samplers and the oracle;
* :mod:`~rankedassign.engine.result` — a run's prepared inputs, the stall/stale rule checks
  and the :class:`~rankedassign.engine.result.SamplerResult`;
* :mod:`~rankedassign.engine.records` — kernel records declared from the records they
  extend (:func:`~rankedassign.engine.records.record`, the herded draw's fields);
* :mod:`~rankedassign.engine.rng` — the counter-based random streams (SplitMix64) and the
  handling of ``rng``;
* :mod:`~rankedassign.engine.reference` — the chains, stall and stale in pure Python (the
  specification of record);
* :mod:`~rankedassign.engine._kernels` — the same compiled once per kind: speculation, replay,
  slices, the unique set, and the numba twin of the random streams;
* :mod:`~rankedassign.engine.tempered` — the tempered Gibbs loop of Zanella & Roberts shared
  by the multi-sensor and adaptive-birth kinds (pure Python) and its result record;
  :mod:`~rankedassign.engine._tempered_kernels` compiles it once per kind.
"""
