"""The keys of a design spectrum given in a deck (`ground_motion.design_spectrum = {...}`),
declared with `Field` and checked by the one field checker (fields.check_mapping: type, unit,
the 1e-30..1e30 limits, range; every error gathered). design_spectra.py says which keys each
type of spectrum takes (its _KEYS) and builds the spectrum from the checked values.
"""

from __future__ import annotations

from ..deck.fields import Field, check_mapping, raiser, suggestion
from ..errors import InputError, gather, raise_all
from .levels import LEVELS

#: the keys of a design_spectrum table (docs/deck.md), checked by the one field checker
#: (fields.check_mapping: type, unit, the 1e-30..1e30 limits, range) wherever they are given
SPECTRUM_FIELDS: dict[str, Field] = {
    "type": Field("string", "-", "spectrum type"),
    "sds": Field("number", "g", "S_DS, design spectral acceleration at short periods", "positive",
                 plausible=(0.01, 5.0)),
    "sd1": Field("number", "g", "S_D1, design spectral acceleration at 1 s", "positive", plausible=(0.01, 5.0)),
    "tl": Field("number", "s", "T_L, long-period transition period", "positive", plausible=(1.0, 20.0)),
    "ag": Field("number", "g", "a_gR, reference peak ground acceleration on type A ground", "positive",
                plausible=(0.01, 2.0)),
    "ground_type": Field("string", "-", "EN 1998-1 ground type A to E"),
    "spectrum_type": Field("integer", "-", "EN 1998-1 spectrum type", "one-or-two", 1),
    "importance": Field("number", "-", "gamma_I, importance factor", "positive", 1.0, plausible=(0.5, 2.0)),
    "damping": Field("number", "-", "damping ratio of the table", "damping-ratio"),
    "periods": Field("numbers", "s", "periods of the ordinates", "nonnegative"),
    "sa": Field("numbers", "g (or the table's units)", "spectral ordinates", "nonnegative"),
    "units": Field("string", "-", "units of the ordinates sa", "acceleration-units", "g"),
    "file": Field("string", "-", "a file of two columns T [s], S_a (relative to the deck)"),
    "damping_correction": Field("string", "-", "damping correction of a table: asce or ec8 (any case)"),
    "name": Field("string", "-", "a label for reports and figures"),
    "level": Field("string", "-", "ASCE 7-22: the level of the ordinates given, design (S_DS, S_D1) or mce_r "
                   "(S_MS, S_M1 under the keys sds, sd1)", "", "design", LEVELS),
}


def _spectrum_kind(mapping, kinds: dict[str, tuple[set[str], set[str]]], field: str, error_for) -> str:
    """The type of a design_spectrum table (a key of `kinds`); error_for(path)(expected) for a value
    that is not a table, or an unknown type (with the nearest type)."""
    if not isinstance(mapping, dict):
        error_for(field)(f"a table with a 'type' key ({', '.join(kinds)}), got {mapping!r}")
    kind = mapping.get("type")
    if not isinstance(kind, str) or kind not in kinds:
        error_for(f"{field}.type")(f"one of {', '.join(kinds)}, got {kind!r}"
                                   f"{suggestion(str(kind), kinds) if isinstance(kind, str) else ''}")
    return kind


def check_spectrum(mapping, kinds: dict[str, tuple[set[str], set[str]]], source: str, field: str,
                   error_for=None) -> dict:
    """The keys of a design_spectrum table checked by the field checker: its type (a key of
    `kinds`: type -> (required keys, optional keys)), the keys of that type (an unknown key, a
    missing required one), each value (SPECTRUM_FIELDS); every error gathered
    (errors.InputErrors), each naming `field`.<key> and, for a spectrum read from a file, that
    file. error_for(path) gives the error function of a key (default: InputError(source, path, ...)).
    The checked values (numbers with a unit converted)."""
    error_for = error_for or raiser(source)
    kind = _spectrum_kind(mapping, kinds, field, error_for)
    required, optional = kinds[kind]
    table = mapping.get("file")
    note = f" (spectrum read from {str(table)!r})" if isinstance(table, str) else ""

    def keyed(path: str):
        def error(expected: str):
            error_for(path)(expected + note)
        return error

    allowed = {key: SPECTRUM_FIELDS[key] for key in sorted(required | optional)}
    gathered: list[InputError] = []
    checked = gather(gathered, check_mapping, allowed, mapping, field, keyed, "si",
                     f"a key of a spectrum of type {kind!r}")
    for key in sorted(required - set(mapping)):
        gather(gathered, keyed(f"{field}.{key}"), f"a value (required for a spectrum of type {kind!r})")
    raise_all(gathered)
    return checked
