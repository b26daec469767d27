"""The test session's own settings (``tests/conftest.py``)."""

import os

import pytest


@pytest.mark.skipif("NUMPY_MADVISE_HUGEPAGE" in os.environ,
                    reason="the environment chose numpy's huge-page advice")
def test_the_tests_run_without_numpys_huge_page_advice():
    try:
        from numpy._core.multiarray import _set_madvise_hugepage
    except ImportError:  # numpy < 2
        from numpy.core.multiarray import _set_madvise_hugepage
    # the switch returns the setting it replaces; setting False again changes nothing
    assert _set_madvise_hugepage(False) is False
