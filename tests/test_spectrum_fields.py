"""spectrum_fields: the keys of a deck's design spectrum, declared once and checked by the field
checker (every type's keys declared, the type itself checked, all errors together)."""

import pytest

from upliftcli.deck.fields import Field
from upliftcli.errors import InputError, InputErrors
from upliftcli.motion.design_spectra import _KEYS, KEY_UNITS
from upliftcli.motion.spectrum_fields import SPECTRUM_FIELDS, check_spectrum


def test_every_key_of_every_type_is_declared():
    for kind, (required, optional) in _KEYS.items():
        assert required | optional <= set(SPECTRUM_FIELDS), kind
        assert "type" in required
    assert all(isinstance(field, Field) for field in SPECTRUM_FIELDS.values())
    assert KEY_UNITS["sds"] == "g" and KEY_UNITS["tl"] == "s"


@pytest.mark.parametrize(("mapping", "location", "expected"), [
    ([1, 2], "spectrum", "a table with a 'type' key (asce7, asce7-multiperiod, ec8, table), got [1, 2]"),
    ({"sds": 1.0}, "spectrum.type", "one of asce7, asce7-multiperiod, ec8, table, got None"),
    ({"type": ["asce7"]}, "spectrum.type", "one of asce7, asce7-multiperiod, ec8, table, got ['asce7']"),
    ({"type": "asce8"}, "spectrum.type", "one of asce7, asce7-multiperiod, ec8, table, got 'asce8' "
                                          "(did you mean 'asce7'?)"),
])
def test_the_type_is_checked_first(mapping, location, expected):
    with pytest.raises(InputError) as info:
        check_spectrum(mapping, _KEYS, "deck.toml", "spectrum")
    assert (info.value.location, info.value.expected) == (location, expected)


def test_unknown_missing_and_bad_keys_are_reported_together():
    with pytest.raises(InputErrors) as info:
        check_spectrum({"type": "ec8", "ag": "0.3", "ground_typ": "B"}, _KEYS, "deck.toml", "spectrum")
    assert [(e.location, e.expected.split(",")[0]) for e in info.value.errors] == [
        ("spectrum.ag", "a number > 0 [g] or a text 'number unit' with a unit of spectral acceleration (docs/deck.md"),
        ("spectrum.ground_typ", "a key of a spectrum of type 'ec8': ag"),
        ("spectrum.ground_type", "a value (required for a spectrum of type 'ec8')")]
    assert "did you mean 'ground_type'" in info.value.errors[1].expected


def test_the_values_come_back_checked_and_converted():
    checked = check_spectrum({"type": "asce7", "sds": "0.5 g", "sd1": 0.6, "tl": 8}, _KEYS, "deck.toml", "s")
    assert checked == {"type": "asce7", "sds": 0.5, "sd1": 0.6, "tl": 8.0}
