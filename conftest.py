"""Test-session setup shared by tests/, doctests and benchmarks/."""

import os

from hypothesis import HealthCheck, settings

settings.register_profile(
    "ci",
    deadline=None,
    derandomize=True,
    database=None,
    max_examples=60,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile(
    "dev", deadline=None, max_examples=20, suppress_health_check=[HealthCheck.too_slow]
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


import numpy as np  # noqa: E402
import pytest  # noqa: E402


@pytest.fixture(autouse=True)
def _isolate_numpy_print_options():
    """No test (or executed docs page) may leak numpy print settings into the next one."""
    saved = np.get_printoptions()
    yield
    np.set_printoptions(**saved)


import warnings  # noqa: E402

#: Test modules that pin the numbers of the deprecated ``MultiSensor*`` association names on
#: purpose (the digests were recorded with them and must not change), so their import may
#: construct those names without the DeprecationWarning failing the run under ``-W error``.
#: Everything else, the aliases' own tests included, sees the warning.
PINNED_DEPRECATED = {"test_digest.py"}


@pytest.hookimpl(wrapper=True)
def pytest_make_collect_report(collector):
    if isinstance(collector, pytest.Module) and collector.path.name in PINNED_DEPRECATED:
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", message=r"MultiSensor\w+ is deprecated",
                                    category=DeprecationWarning)
            return (yield)
    return (yield)
