"""The deck's record suite: `[ground_motion] suite = ...` with its design_spectrum as target.

    plan = suite_plan(fields, target, system, settings, source, error)   # rule, period range
    suite = load_suite(fields, plan, source, error)                      # records read and scaled

The code rule is `ground_motion.statistics`, or that of the design spectrum (ASCE 7-22 spectra:
"asce7-22", EC8: "ec8", a table: "mean"). Under ASCE 7-22 the target is the MCE_R spectrum
(16.2.1): the deck's spectrum if its level is "mce_r", 1.5 x it if "design" (motion/levels.py).
The period range is `ground_motion.period_range`, or
the code's rule (motion/code_rules.py) applied to the structure: the upper bound from the
flexible-base first-mode period T1bar of the bonded system (Eq. 21; T_1 fixed-base if longer),
the lower bound from the fixed-base T_1 and the mode that completes 90 % of the building mass.
Every InputError names the deck (or "--set") and the ground_motion field.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ..errors import InputError, not_found
from ..model.building import modes_for_mass_target
from ..motion.code_rules import RULES, CodeRule
from ..motion.design_spectra import ASCE7MultiPeriodSpectrum, ASCE7Spectrum, EC8Spectrum
from ..motion.levels import suite_target
from ..motion.suites import Suite, build_suite, check_target, entry_origins, read_records, suite_entries
from .schema import FieldErrors

#: ground_motion.statistics -> damping correction of a table spectrum that names none
TABLE_CORRECTION = {"asce7-22": "asce", "ec8": "ec8", "mean": "ec8"}


@dataclass(frozen=True)
class SuitePlan:
    """What a deck asks of a suite before any record is read: target spectrum, code rule,
    period range [s] and how it was found."""

    target: Any
    rule: CodeRule
    period_range: tuple[float, float]
    period_note: str


def default_statistics(spectrum) -> str:
    """The code rule of a design spectrum: 'asce7-22', 'ec8' or 'mean' (a table)."""
    if isinstance(spectrum, (ASCE7Spectrum, ASCE7MultiPeriodSpectrum)):
        return "asce7-22"
    return "ec8" if isinstance(spectrum, EC8Spectrum) else "mean"


def structure_period_range(rule: CodeRule, system, effective_properties: str = "formula"
                           ) -> tuple[tuple[float, float], str]:
    """The code's period range [s] for the structure (module docstring) and how it was found."""
    from ..engines.simplified import effective_properties as properties

    modes = system.modes
    first = float(modes.periods[0])
    flexible = float(properties(system, effective_properties)["T1bar"])
    # the last mode needed for 90 % of the building's mass (the shortest mode if never)
    period_90 = float(modes.periods[modes_for_mass_target(modes, float(system.building.masses.sum()), 0.9) - 1])
    period_range, note = rule.period_range(max(first, flexible), first, period_90)
    return period_range, f"{note}; T_1 fixed-base {first:.4g} s, flexible-base T1bar {flexible:.4g} s"


def suite_plan(fields: dict, target, system, effective_properties: str, source: str,
               error: Callable[[str, str], InputError]) -> SuitePlan:
    """The SuitePlan of validated [ground_motion] fields with `target`, the deck's design spectrum
    (under ASCE 7-22 the plan's target is the MCE_R spectrum: 1.5 x a design-level one, levels.py)."""
    rule = RULES[fields.get("statistics") or default_statistics(target)]
    target = suite_target(target, rule.name)
    if "period_range" in fields:
        period_range, note = _deck_period_range(fields, error)
    else:
        period_range, note = structure_period_range(rule, system, effective_properties)
    _check_target(target, period_range, source, error)
    return SuitePlan(target, rule, period_range, note)


def _deck_period_range(fields: dict, error) -> tuple[tuple[float, float], str]:
    """ground_motion.period_range [s] (0 < lower) and how it was found."""
    period_range = tuple(float(v) for v in fields["period_range"])
    if period_range[0] <= 0.0:
        raise error("ground_motion.period_range", f"[lower, upper] with 0 < lower < upper [s], got "
                    f"{list(period_range)}")
    return period_range, f"ground_motion.period_range = {period_range[0]:.4g}-{period_range[1]:.4g} s"


def _check_target(target, period_range: tuple[float, float], source: str, error) -> None:
    """The target spectrum defined over the period range (suites.check_target), else the range's error."""
    try:
        check_target(target, period_range, source, "ground_motion.period_range")
    except InputError as bad:
        raise error("ground_motion.period_range", bad.expected) from None


def load_suite(fields: dict, plan: SuitePlan, source: str, error: Callable[[str, str], InputError]) -> Suite:
    """Read the deck's suite and scale or match it as `ground_motion.scaling` says; a listed
    record that does not exist names its entry, ground_motion.suite[k], and the folder."""
    entries = _entries(fields, source, error)
    if isinstance(fields["suite"], list):
        _check_listed_files(entries, fields["suite"], source, error)
    records = []
    for k, entry in enumerate(entries):
        records += _read_entry(k, entry, error)
    return _scaled(records, entries, fields, plan, source, error)


def _in_deck(bad: InputError, source: str) -> bool:
    """An error located at a field of the deck file itself (to report through the deck's error)."""
    return bad.source == source and bool(bad.location)


def _entries(fields: dict, source: str, error) -> list:
    """The suite's entries (suites.suite_entries): (path, options) of each record."""
    try:
        return suite_entries(fields["suite"], source)
    except InputError as bad:
        if _in_deck(bad, source):
            raise error(bad.location, bad.expected) from None
        raise


def _check_listed_files(entries: list, listed: list, source: str, error) -> None:
    """Every record file the deck lists exists (the error names its entry)."""
    for k, ((path, _), item) in enumerate(zip(entries, listed, strict=True)):
        if not path.exists():
            where, given = _listed_file(k, item)
            raise error(where, not_found(path, given, source))


def _listed_file(k: int, item: str | dict) -> tuple[str, str]:
    """(deck field, path as written) of the suite's entry k: a path, or a table's file."""
    if isinstance(item, str):
        return f"ground_motion.suite[{k}]", item
    return f"ground_motion.suite[{k}].file", item["file"]


def _read_entry(k: int, entry, error) -> list:
    """The records of entry k; an option the entry gives that does not suit its file is the deck's mistake."""
    try:
        return read_records([entry])
    except InputError as bad:
        if bad.source == str(entry[0]) and bad.location in entry[1]:
            raise error(f"ground_motion.suite[{k}].{bad.location}", bad.expected) from None
        raise


def _scaled(records: list, entries: list, fields: dict, plan: SuitePlan, source: str, error) -> Suite:
    """The suite scaled or matched to the plan's target (suites.build_suite)."""
    try:
        return build_suite(records, plan.target, plan.period_range, plan.rule, fields.get("scaling", "none"),
                           bool(fields.get("suite_factor", False)), plan.period_note, source=source,
                           made=entry_origins(entries))
    except InputError as bad:
        if _in_deck(bad, source) and not bad.location.startswith("ground_motion."):
            raise error(f"ground_motion.{bad.location}", bad.expected) from None
        raise


def target_spectrum(fields: dict, source: str, error: Callable[[str, str], InputError]):
    """The design spectrum of a [ground_motion] table (design_spectra.from_mapping, the table's
    damping correction by the suite's code rule); its errors through `error` (naming "--set"
    for a value that came from an override)."""
    from ..motion.design_spectra import from_mapping

    try:
        return from_mapping(fields["design_spectrum"], source, "ground_motion.design_spectrum",
                            default_correction=TABLE_CORRECTION[fields.get("statistics", "mean")])
    except InputError as bad:
        if _in_deck(bad, source):
            raise error(bad.location, bad.expected) from None
        raise


def plan_from_deck(deck) -> SuitePlan:
    """The SuitePlan of a deck loaded without its ground motion (load_deck(load_ground_motion=False)):
    its design spectrum, code rule and period range, whether or not its suite exists yet."""
    fields = deck.values.get("ground_motion", {})
    error = FieldErrors(deck.source, deck.overridden)
    if "design_spectrum" not in fields:
        raise error("ground_motion.design_spectrum", "a design spectrum (the target of the records)")
    target = target_spectrum(fields, deck.source, error)
    return suite_plan(fields, target, deck.system, deck.analysis.simplified.effective_properties, deck.source, error)
