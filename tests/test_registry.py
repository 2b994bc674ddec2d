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
