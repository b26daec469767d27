"""Fixtures shared by the test modules, and the tests' numpy memory setting."""

import os

import pytest


def _no_hugepage_advice() -> bool | None:
    """Stop numpy advising transparent huge pages for the tests' large arrays.

    numpy asks the kernel to back every array of 4 MB and more with huge pages
    (``madvise(MADV_HUGEPAGE)``). Where transparent huge pages are ``madvise`` with ``defrag``
    ``madvise`` (as on the 2-core CI machine), the first write to such an array may wait for
    the kernel to compact memory: one gather into a new 88 MB array took 1.0-1.2 s inside a
    test instead of 0.06 s. Over the default run, warm cache, back to back: 126.5, 131.8 and
    137.9 s without the advice against 135.6 and 149.2 s with it (``benchmarks/README.md``,
    "Thirteenth pass"). The results do not depend on it; the benchmarks keep numpy's default.
    A ``NUMPY_MADVISE_HUGEPAGE`` set in the environment is left as set. Returns numpy's
    previous setting, or None where it was left alone.
    """
    if "NUMPY_MADVISE_HUGEPAGE" in os.environ:
        return None
    try:
        from numpy._core.multiarray import _set_madvise_hugepage
    except ImportError:  # numpy < 2
        try:
            from numpy.core.multiarray import _set_madvise_hugepage
        except ImportError:  # pragma: no cover - a numpy without the switch
            return None
    return bool(_set_madvise_hugepage(False))


_no_hugepage_advice()


@pytest.fixture(scope="session", autouse=True)
def _compiled_samplers():
    """Compile (or load from cache) every sampler kernel once, before any test is timed."""
    from rankedassign import warmup

    warmup()
