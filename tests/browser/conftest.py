"""The browser tier needs no compiled sampler: the session warm-up of tests/conftest.py is off."""

import pytest


@pytest.fixture(scope="session", autouse=True)
def _compiled_samplers():
    """Overrides the parent fixture of the same name: nothing to compile for the site."""
