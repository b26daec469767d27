"""``rankedassign.rows.unique_rows``: the same array as ``np.unique(a, axis=0)``, faster.

The exact truncation error (single-sensor, multi-sensor, adaptive birth) and the association's
duplicate check drop repeated assignments with it; numpy's row-wise ``unique`` sorted the rows as
structured records and took most of a Table I run's time."""

import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from rankedassign.rows import unique_rows

_DTYPES = st.sampled_from([np.int8, np.int16, np.int32, np.int64, np.uint8, np.uint32])


@settings(max_examples=300, deadline=None)
@given(data=st.data(), dtype=_DTYPES, n=st.integers(0, 40), p=st.integers(0, 6))
def test_unique_rows_is_numpys_unique_along_axis_0(data, dtype, n, p):
    info = np.iinfo(dtype)
    # narrow ranges (repeated rows, the table of keys), wide ones (sorted keys) and the
    # dtype's whole range (keys over 63 bits: the lexsort path)
    width = data.draw(st.sampled_from([3, 40, 2**20, None]))
    lo = info.min if width is None else max(info.min, -width // 2)
    hi = info.max if width is None else min(info.max, lo + width)
    a = data.draw(arrays(dtype, (n, p), elements=st.integers(int(lo), int(hi))))
    if n > 2:
        a[n // 2] = a[0]  # at least one repeated row
    expected = np.unique(a, axis=0)
    got = unique_rows(a)
    assert got.dtype == expected.dtype and got.shape == expected.shape
    np.testing.assert_array_equal(got, expected)


def test_unique_rows_on_a_samplers_output():
    rng = np.random.default_rng(0)
    a = rng.integers(-1, 30, size=(100_000, 5))
    np.testing.assert_array_equal(unique_rows(a), np.unique(a, axis=0))
    wide = rng.integers(-(2**40), 2**40, size=(1_000, 3))  # 3 x 41 bits: over 63, lexsort
    wide[::7] = wide[0]
    np.testing.assert_array_equal(unique_rows(wide), np.unique(wide, axis=0))


@pytest.mark.parametrize("bad", [np.zeros(3, dtype=np.int64), np.zeros((2, 2)),
                                 np.zeros((1, 2, 2), dtype=np.int64)])
def test_unique_rows_names_a_bad_input(bad):
    message = (f"unique_rows needs a 2-D integer array, got shape {bad.shape} and dtype "
               f"{bad.dtype}")
    with pytest.raises(ValueError, match=re.escape(message)):
        unique_rows(bad)
