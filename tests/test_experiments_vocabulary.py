"""The studies' one vocabulary: truncations by their classes' names, old spellings deprecated."""

from __future__ import annotations

import warnings

import pytest

from rankedassign import tracking
from rankedassign.experiments.vocabulary import (
    DEPRECATED_ASSOCIATIONS,
    DEPRECATED_FILTER_TRUNCATIONS,
    DEPRECATED_GLMB_TRUNCATIONS,
    DEPRECATED_TRACKING_SAMPLERS,
    DEPRECATED_TRUNCATIONS,
    DEPRECATED_VARIANTS,
    PLAIN_TRUNCATIONS,
    ROW_METHODS,
    TRUNCATIONS,
    canonical_pair,
    canonical_truncation,
    canonical_value,
    canonical_variant,
    variant,
)
from rankedassign.multisensor.prepare import METHODS


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


def test_method_is_the_row_conditional_alone():
    assert ROW_METHODS is METHODS == ("exact", "mm", "mm-fixed", "componentwise")


def test_every_replacement_is_made_of_the_vocabulary():
    # the truncations by the classes' names, the row conditionals by the samplers' methods
    for truncation, method in DEPRECATED_ASSOCIATIONS.values():
        assert truncation in TRUNCATIONS and method in ROW_METHODS
    for filt, truncation in DEPRECATED_FILTER_TRUNCATIONS.values():
        assert filt in ("lmb", "glmb")
        assert truncation in TRUNCATIONS or truncation == "murty-matched"  # the study's rule
    assert set(DEPRECATED_GLMB_TRUNCATIONS.values()) <= {*TRUNCATIONS, "murty-matched"}
    assert DEPRECATED_TRACKING_SAMPLERS == {"proposed": "short-chain"}
    assert DEPRECATED_ASSOCIATIONS["short-mm"] == ("short-chain", "mm")
    assert DEPRECATED_FILTER_TRUNCATIONS["glmb-long"] == ("glmb", "original")


def test_a_pair_reads_as_a_tuple_and_its_old_truncation_spelling_is_deprecated():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert canonical_pair(["short-chain", "mm"], "methods", DEPRECATED_ASSOCIATIONS) == (
            "short-chain", "mm")
        assert canonical_pair(("glmb", "murty"), "methods", DEPRECATED_FILTER_TRUNCATIONS,
                              truncation_at=1) == ("glmb", "murty")
        for other in ("no-such", 3, ("a", "b", "c")):  # left for the study's check
            assert canonical_pair(other, "methods", DEPRECATED_ASSOCIATIONS) == other
    with pytest.warns(DeprecationWarning, match=r"^methods: 'short' is deprecated; write "
                                                r"'short-chain' \(the ShortChainGibbs "):
        assert canonical_pair(["short", "mm"], "methods", DEPRECATED_ASSOCIATIONS) == (
            "short-chain", "mm")
    with pytest.warns(DeprecationWarning, match=r"^methods: 'long' is deprecated; write "
                                                r"'original' \(the OriginalGibbs "):
        assert canonical_pair(["lmb", "long"], "methods", DEPRECATED_FILTER_TRUNCATIONS,
                              truncation_at=1) == ("lmb", "original")


def test_a_deprecated_value_warns_with_the_replacement_as_a_config_file_writes_it():
    with pytest.warns(DeprecationWarning, match=r'^methods: \'exact\' is deprecated; write '
                                                r'\["exact", "exact"\]$'):
        assert canonical_pair("exact", "methods", DEPRECATED_ASSOCIATIONS) == ("exact", "exact")
    with pytest.warns(DeprecationWarning, match=r"^truncation: 'proposed' is deprecated; write "
                                                r"'short-chain'$"):
        assert canonical_value("proposed", "truncation", DEPRECATED_TRACKING_SAMPLERS) == \
            "short-chain"


def test_a_variant_is_its_class_settings_written_out():
    assert variant() == ""
    assert variant(keys="full") == "keys=full"
    assert variant(chains="short", keys="shared") == "chains=short,keys=shared"
    assert variant(beta=0.5) == "beta=0.5" and variant(scheme="zanella-roberts") == \
        "scheme=zanella-roberts"


def test_every_old_method_string_of_tempering_herding_is_a_class_name_and_a_variant():
    for truncation, v in DEPRECATED_VARIANTS.values():
        assert truncation in ("herded", "tempered") and truncation in TRUNCATIONS and v
    assert set(PLAIN_TRUNCATIONS) <= set(TRUNCATIONS)
    # the one herded chain of the tracking part ran with the class's default keys
    assert DEPRECATED_VARIANTS["herded"] == DEPRECATED_VARIANTS["herded-shared"]


@pytest.mark.parametrize(("old", "new"), sorted(DEPRECATED_VARIANTS.items()))
def test_an_old_method_string_reads_as_its_pair_with_a_warning_naming_it(old, new):
    shown = f'\\["{new[0]}", "{new[1]}"\\]'
    with pytest.warns(DeprecationWarning, match=rf"^methods: '{old}' is deprecated; write "
                                                rf"{shown}$"):
        assert canonical_variant(old, "methods") == new


@pytest.mark.parametrize(("value", "want"), [
    ("lbp", ("lbp", "")), ("exact", ("exact", "")), ("original", ("original", "")),
    (["herded", "keys=full"], ("herded", "keys=full")), (("lbp", ""), ("lbp", "")),
    ("tempered", "tempered"), (3, 3)])
def test_a_pair_or_a_plain_truncation_reads_silently(value, want):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert canonical_variant(value, "methods") == want


def test_the_old_truncation_spellings_read_in_a_variant_too():
    with pytest.warns(DeprecationWarning, match=r"^methods: 'gibbs' is deprecated; write "
                                                r"'original' \(the OriginalGibbs class's name\)$"):
        assert canonical_variant("gibbs", "methods") == ("original", "")
    with pytest.warns(DeprecationWarning, match=r"^methods: 'short' is deprecated"):
        assert canonical_variant(["short", ""], "methods") == ("short-chain", "")
