"""Fixtures shared by the test modules, and the tests' numpy memory setting."""

import os

import pytest


def _no_hugepage_advice() -> None:
    """Stop numpy advising transparent huge pages for the tests' large arrays.

    numpy asks the kernel to back every array of 4 MB and more with huge pages
    (``madvise(MADV_HUGEPAGE)``). Where transparent huge pages are ``madvise`` with ``defrag``
    ``madvise`` (as on the project's 2-core machine), the first write to such an array may
    wait for the kernel to compact memory. The suite's largest test took 10.6-12.8 s with the
    advice and 7.6-9.6 s without; the default run, warm cache, back to back: 126.5, 131.8 and
    137.9 s without against 135.6 and 149.2 s with (``benchmarks/README.md``, "Thirteenth
    pass"). The results do not depend on it; the benchmarks keep numpy's default. A
    ``NUMPY_MADVISE_HUGEPAGE`` set in the environment is left as set.
    """
    if "NUMPY_MADVISE_HUGEPAGE" in os.environ:
        return
    try:
        from numpy._core.multiarray import _set_madvise_hugepage
    except ImportError:  # numpy < 2
        try:
            from numpy.core.multiarray import _set_madvise_hugepage
        except ImportError:  # pragma: no cover - a numpy without the switch
            return
    _set_madvise_hugepage(False)


_no_hugepage_advice()


@pytest.fixture(scope="session", autouse=True)
def _compiled_samplers():
    """Compile (or load from cache) every sampler kernel once, before any test is timed."""
    from rankedassign import warmup

    warmup()
