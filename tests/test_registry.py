"""engines/registry.py and the other registries the deck is built from."""

from __future__ import annotations

import pytest

from upliftcli.deck import schema as deck_schema
from upliftcli.engines import registry
from upliftcli.model.foundations import FOUNDATIONS
from upliftcli.motion.records import FORMATS, READERS


def test_names_have_one_home():
    assert deck_schema.TABLES["analysis"]["engine"].choices == tuple(registry.ENGINES)
    assert deck_schema.TABLES["analysis"]["supports"].choices == registry.SUPPORTS
    assert deck_schema.TABLES["foundation"]["type"].choices == tuple(FOUNDATIONS)
    assert deck_schema.TABLES["ground_motion"]["format"].choices == FORMATS == tuple(READERS)


def test_every_foundation_declares_its_deck_fields():
    for kind, cls in FOUNDATIONS.items():
        assert cls.kind == kind
        for name, field in cls.deck_fields.items():
            assert deck_schema.TABLES["foundation"][name] is field
        for groups in cls.deck_alternatives:
            assert all(name in cls.deck_fields for group in groups for name in group)


def test_engines_know_whether_they_need_a_record():
    assert not registry.ENGINES["simplified"].needs_record
    assert registry.ENGINES["exact"].needs_record and registry.ENGINES["approximate"].needs_record
    with pytest.raises(ValueError, match="engine must be one of simplified, approximate, exact"):
        registry.engine("fancy")
    with pytest.raises(ValueError, match="support must be one of rigid, bonded, uplift"):
        registry.check_support("pinned")


def test_the_limit_on_elements_with_a_capacity_is_one_rule():
    """registry.too_many_yielding (limits.MAX_YIELDING_ELEMENTS) decides for capacity_refusal, which the
    deck and the analysis ask, and for the stepping of a model built in code."""
    from types import SimpleNamespace

    from upliftcli.runtime.limits import MAX_YIELDING_ELEMENTS

    assert not registry.too_many_yielding(MAX_YIELDING_ELEMENTS)
    assert registry.too_many_yielding(MAX_YIELDING_ELEMENTS + 1)
    many = SimpleNamespace(foundation=SimpleNamespace(capacity=1e6, elements=MAX_YIELDING_ELEMENTS + 1))
    assert registry.capacity_refusal("exact", many, "uplift").startswith(
        f"at most {MAX_YIELDING_ELEMENTS} contact elements with a bearing capacity for the exact engine's")
    assert registry.capacity_refusal("simplified", many, "uplift") is None
    assert registry.capacity_refusal("approximate", many, "bonded") is None
    few = SimpleNamespace(foundation=SimpleNamespace(capacity=1e6, elements=MAX_YIELDING_ELEMENTS))
    assert registry.capacity_refusal("exact", few, "uplift") is None
