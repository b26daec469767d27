"""Fixtures shared by the test modules."""

import pytest


@pytest.fixture(scope="session", autouse=True)
def _compiled_samplers():
    """Compile (or load from cache) every sampler kernel once, before any test is timed."""
    from rankedassign import warmup

    warmup()
