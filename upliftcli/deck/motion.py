"""The deck's [ground_motion] table -> the analysis's ground motion: a record file read
(motion/records.py), a design spectrum, or a record suite scaled to it (deck/suite.py); and the
spectrum the simplified engine uses. Every mistake is error(dotted field, expected): the deck's
or --set's (deck.build_deck); a record option that does not suit the file is the deck's field.
"""

from __future__ import annotations

from typing import Any

from ..errors import InputError, deck_relative_path, not_found
from ..model.system import System
from ..motion.code_rules import SUITE_ONLY


def check_motion_fields(fields: dict, source: str, error):
    """The [ground_motion] fields checked as a whole, before anything is read: a record or a design
    spectrum, the suite fields with a design spectrum, the record file existing. The record's
    path, or None for a design spectrum."""
    if not fields:
        raise error("ground_motion", "a [ground_motion] table with a record (path) or a design_spectrum")
    if "design_spectrum" in fields:
        _check_spectrum_fields(fields, error)
        return None
    _check_record_fields(fields, error)
    return _record_path(fields, source, error)


def _suite_fields() -> set[str]:
    """The fields of a suite (with a design spectrum only)."""
    return {"suite", *SUITE_ONLY, "period_range", "statistics"}


def _check_spectrum_fields(fields: dict, error) -> None:
    """A design spectrum with suite fields only, scaling fields only with a suite."""
    extra = sorted(set(fields) - {"design_spectrum"} - _suite_fields())
    if extra:
        raise error(f"ground_motion.{extra[0]}", "no record fields together with a design_spectrum")
    if "suite" in fields:
        return
    for name in SUITE_ONLY:
        if name in fields:
            raise error(f"ground_motion.{name}", "a ground_motion.suite to scale (none given)")


def _check_record_fields(fields: dict, error) -> None:
    """A record without suite fields."""
    given = sorted(_suite_fields() & set(fields))
    if given:
        raise error("ground_motion.design_spectrum", f"a design spectrum, the target of ground_motion.{given[0]} "
                    "(or no suite fields with a record)")
    if "record" not in fields:
        raise error("ground_motion.record", "the path of a record file (missing; or give "
                    "ground_motion.design_spectrum)")


def _record_path(fields: dict, source: str, error):
    """The record file's path (relative to the deck), existing."""
    path = deck_relative_path(fields["record"], source)
    if not path.exists():  # the folder a relative path was resolved from: the deck's (its target's, a link)
        raise error("ground_motion.record", not_found(path, fields["record"], source,
                                                      folder=deck_relative_path(".", source)))
    return path


def read_ground_motion(fields: dict, source: str, error, system: System | None = None,
                       effective_properties: str = "formula") -> tuple[Any, Any]:
    """(record, design spectrum or suite, spectrum for the simplified engine)."""
    path = check_motion_fields(fields, source, error)
    if path is None:
        return _spectrum_motion(fields, source, error, system, effective_properties)
    return _record_motion(path, fields, error)


def _spectrum_motion(fields: dict, source: str, error, system: System | None, effective_properties: str
                     ) -> tuple[Any, Any]:
    """(the design spectrum, itself), or (the suite scaled to it, the suite's target)."""
    from .suite import load_suite, suite_plan, target_spectrum

    spectrum = target_spectrum(fields, source, error)
    if "suite" not in fields:
        return spectrum, spectrum
    plan = suite_plan(fields, spectrum, system, effective_properties, source, error)
    return load_suite(fields, plan, source, error), plan.target  # the simplified engine on the suite's target


def _record_motion(path, fields: dict, error) -> tuple[Any, Any]:
    """(the record, its response spectrum); a deck field that does not suit the file is the deck's (or
    --set's) mistake, not the file's."""
    from ..motion import records, spectra

    try:
        record = records.read_record(path, fields.get("format"), fields.get("units"), fields.get("dt"),
                                     fields.get("scale", 1.0), fields.get("window"),
                                     fields.get("override_header_units", False))
    except InputError as bad:
        if _deck_option(bad, path, fields):
            raise error(f"ground_motion.{bad.location}", bad.expected) from None
        raise
    return record, spectra.RecordSpectrum(record)


def _deck_option(bad: InputError, path, fields: dict) -> bool:
    """An error of the record file about a record option the deck gives."""
    return bad.source == str(path) and bad.location in RECORD_OPTIONS and bad.location in fields


#: record options of read_record that are deck fields of [ground_motion]
RECORD_OPTIONS = ("format", "units", "dt", "scale", "window", "override_header_units")
