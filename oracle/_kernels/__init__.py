"""Compiled kernels of the oracle, one module per algorithm.

* :mod:`oracle._kernels.enumeration`: depth-first enumeration and counting of ``Gamma``;
* :mod:`oracle._kernels.lsap`: shortest-augmenting-path LSAP (cold and warm-started);
* :mod:`oracle._kernels.murty`: Murty's k-best driver on top of it;
* :mod:`oracle._kernels.dp`: the subset and frontier DPs of the exact normaliser and marginals;
* :mod:`oracle._kernels.plan`: the frontier DP's planning (components, measurement orders,
  operations).

The public wrappers (:mod:`oracle.single.enumerate`, :mod:`oracle.single.murty`,
:mod:`oracle.single.dp`) validate their input once; the kernels assume clean, C-contiguous
float64 / int64 arrays and never raise. Every kernel is compiled by
:func:`rankedassign.numba_options.jit`, whose cache key is a digest of all the package's
sources, so a kernel may call helpers of another file.
"""
