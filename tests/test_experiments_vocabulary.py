"""The studies' one vocabulary: truncations by their classes' names, old spellings deprecated."""

from __future__ import annotations

import warnings

import pytest

from rankedassign import tracking
from rankedassign.experiments.vocabulary import (
    DEPRECATED_TRUNCATIONS,
    TRUNCATIONS,
    canonical_truncation,
)


def test_the_truncations_are_the_association_classes_names():
    assert TRUNCATIONS == ("original", "short-chain", "herded", "tempered", "murty", "exact",
                           "lbp")
    assert tracking.OriginalGibbs.name in TRUNCATIONS and tracking.LBP.name in TRUNCATIONS


@pytest.mark.parametrize(("old", "new", "cls"), [("long", "original", "OriginalGibbs"),
                                                 ("gibbs", "original", "OriginalGibbs"),
                                                 ("short", "short-chain", "ShortChainGibbs")])
def test_an_old_spelling_reads_as_the_new_name_with_a_warning_naming_it(old, new, cls):
    assert DEPRECATED_TRUNCATIONS[old] == new
    with pytest.warns(DeprecationWarning, match=rf"^truncations: '{old}' is deprecated; write "
                                                rf"'{new}' \(the {cls} class's name\)$"):
        assert canonical_truncation(old, "truncations") == new


@pytest.mark.parametrize("value", [*TRUNCATIONS, "no-such", 3])
def test_a_current_name_or_another_value_passes_unchanged_and_silently(value):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert canonical_truncation(value, "truncations") == value
