"""Sweeps: one deck analysed over ranges of its fields (cartesian product), case by case.

    plan = plan_sweep("deck.toml", ["analysis.modes=5"], ["foundation.k_f=1e7:1e10:25:log"])
    outcome = run.run_sweep(plan, executors.SerialExecutor(), store.RowStore(path))

A case is one combination of the varied values with one engine and one support. Each case
has a stable key (hash of the deck content, the --set overrides, its varied values, engine
and support) so that `--resume` can skip what a previous run finished. Cases are handed to
the executors (sweep/executors.py) in chunks; a worker builds each distinct deck of a chunk
once and keeps the loaded record and its spectrum (RecordSpectrum, which caches S_a) for all
later cases with the same ground motion (ground_motion_key). A deck with a record suite run
by a history engine gives one row per case holding the suite's design statistic, and keeps
each record's row inside it (tables: one row per record on request, SweepPlan.per_record).
Storage of the rows: sweep/store.py; the driver: sweep/run.py; the values of --vary:
sweep/values.py. The worker side (building a case's deck, running it, its row) is
sweep/worker.py. Nothing here prints or exits.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import json
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from ..analysis.run import ground_motion_for
from ..deck import schema
from ..deck.load import Deck, build_deck, read_toml
from ..deck.overrides import parse_override
from ..engines.registry import ENGINES
from ..errors import InputError
from ..motion.records import Record
from ..motion.suites import Suite
from ..provenance.files import motion_files
from ..runtime.installed import tool_version
from ..runtime.limits import cases_problem
from .cases import Case, Cases, checked_combos, expand_cases
from .unserved import unserved_error
from .values import Vary, parse_vary

__all__ = ["Case", "Cases", "expand_cases"]  # made in sweep/cases.py, asked for here too

#: status of a row: ok; failed (the analysis raised: deterministic, not retried within a run);
#: crashed (the worker process died on this case `max_attempts` times); stale (not computed: a
#: record file's content changed after the sweep had read it; run again by --resume)
STATUSES = ("ok", "failed", "crashed", "stale")


def fingerprint(raw: dict, base_overrides: Sequence[tuple[str, Any]]) -> str:
    """Hash of the parsed deck and the --set overrides (comments and layout do not count)."""
    text = json.dumps({"deck": raw, "set": [list(o) for o in base_overrides]}, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()


def ground_motion_key(deck: Deck) -> str:
    """What a case's ground motion depends on (deck loaded without it): its [ground_motion] fields
    and, for a suite whose period range comes from the structure (deck/suite.py), that range,
    since the suite is scaled for it."""
    fields = deck.values["ground_motion"]
    key: dict[str, Any] = {"fields": fields}
    if "suite" in fields and "period_range" not in fields:
        from ..deck.suite import plan_from_deck

        with contextlib.suppress(InputError):  # building the deck with its ground motion names the error
            key["period_range"] = plan_from_deck(deck).period_range
    return json.dumps(key, sort_keys=True, default=str)


def run_fingerprint(deck_fingerprint: str, records: dict[str, str], version: str) -> str:
    """What the rows of a sweep depend on beyond their case key: the record files' contents
    and the tool version (the deck and --set are in the key already), as one short hash."""
    text = json.dumps({"deck": deck_fingerprint, "records": records, "version": version}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:20]


@dataclass
class SweepPlan:
    """Everything the workers need: the parsed deck, the overrides and the cases; suite_records:
    the most records of a suite that a history engine runs in a case (0: no suite); per_record:
    the tables get each record's row after its case's row; warnings: the decks' (values far
    outside building practice) and the suites' messages (too few records for the rule ...),
    each once; check: the tables get the ratios simplified / exact
    of each simplified case (sweep/table.add_checks).

    records: every file the cases' ground motions read (records, a suite's each, a spectrum
    table), by absolute path -> its SHA-256; version: of the tool; fingerprint: run_fingerprint
    of both and the resolved deck (checked by --resume; the workers' ground-motion cache is keyed
    by it); record_steps: every record file -> (dt [s], samples); inputs: the provenance entries of every
    record (and spectrum table) file any case reads (provenance_files.motion_files). The limits of each
    case (engine memory, spectrum periods: analysis.check_resources) are checked by the worker: a
    case beyond them is a 'failed' row naming the field."""

    raw: dict
    source: str
    title: str
    base_overrides: tuple
    varies: list[Vary]
    engines: list[str]
    supports: list[str]
    cases: Sequence[Case]  # Cases: made on demand (a list in tests)
    criteria: dict = field(default_factory=dict)
    suite_records: int = 0
    per_record: bool = False
    warnings: tuple = ()
    check: bool = False
    records: dict = field(default_factory=dict)
    version: str = ""
    fingerprint: str = ""
    record_steps: dict = field(default_factory=dict)
    inputs: tuple = ()
    #: --engine and --support as overrides of analysis.engine and analysis.supports, applied after --set
    #: (not in the fingerprint: a sweep resumed with more engines keeps the rows of the others)
    chosen: tuple = ()
    motion_band: tuple = (0.5, 2.0)  # analysis.check_band_motion: simplified_error on the mat's motion (table.py)

    @property
    def input_files(self) -> list[str]:
        """The files the sweep reads: the deck and the records (never overwritten by its outputs)."""
        return [self.source, *self.records]

    @functools.cached_property
    def base_deck(self) -> Deck:
        """The deck after its --set overrides (and --engine, --support), before --vary (base_deck),
        without its ground motion (built once: the provenance and the figures' nominal values read
        it); InputError if invalid."""
        return base_deck(self.raw, self.source, [*self.base_overrides, *self.chosen], self.varies,
                         load_ground_motion=False)


def _vary_error(error: InputError, varied: set[str]) -> InputError:
    if error.source == "--set" and error.location in varied:
        return InputError("--vary", error.location, error.expected)
    return error


def base_deck(raw: dict, source: str, base: list, varies: Sequence[Vary], *, load_ground_motion: bool = True) -> Deck:
    """The deck after its --set overrides; one that a varied field completes (a bearing_pressure
    whose mat_length is varied) with the first value of each --vary (every case is checked too)."""
    try:
        return build_deck(raw, source, base, load_ground_motion=load_ground_motion)
    except InputError:
        if not varies:
            raise
    first = [(v.path, v.values[0]) for v in varies]
    try:
        return build_deck(raw, source, base + first, load_ground_motion=load_ground_motion)
    except InputError as error:
        raise _vary_error(error, {v.path for v in varies}) from None


class CaseUnsupported(InputError):
    """The ground motion cannot serve one case of a sweep (a record suite whose period range,
    which follows the structure, asks for longer records than the suite's): the sweep is
    refused before it runs (unserved.py)."""


def _with_suite(raw: dict, source: str, base: list, combo: Sequence[tuple[str, Any]], case_deck: Deck) -> Deck:
    """The case's deck with its ground motion; CaseUnsupported (naming the case's varied values)
    when a record suite that the deck of the sweep accepts does not suit this case."""
    try:
        return build_deck(raw, source, base + list(combo))
    except InputError as error:
        if not combo or "suite" not in case_deck.values["ground_motion"] or error.source == "--set":
            raise
        case = ", ".join(f"{path}={value}" for path, value in combo)
        raise CaseUnsupported(error.source, error.location,
                              f"{error.expected} (the suite of the case {case})") from None


@dataclass
class _GroundMotions:
    """The distinct ground motions of a sweep's cases (ground_motion_key -> deck with it), the
    warnings of the cases' decks and the messages of the combinations a suite cannot serve."""

    decks: dict[str, Deck] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    unsupported: list[tuple[tuple, str]] = field(default_factory=list)


def plan_sweep(deck_path: str | Path, settings: Sequence[str] = (), vary_texts: Sequence[str] = (),
               engines: Sequence[str] = (), supports: Sequence[str] = (), *, varies: Sequence[Vary] = (),
               per_record: bool = False, check: bool = False) -> SweepPlan:
    """Parse and validate a sweep: every combination's deck is built (without its record; a sweep
    of more than cases.CHECKED_COMBINATIONS: those of cases.checked_combos) and every distinct ground
    motion is read once here, so bad input stops the run before any analysis; the cases are
    made as they are asked for (cases.Cases).
    per_record: each record's row in the tables (a deck with a suite run by a history engine);
    check: the exact engine runs beside the others for the ratios simplified / exact (a deck
    with a record or a suite)."""
    base = [parse_override(text) for text in settings]
    source = str(deck_path)
    raw = read_toml(deck_path)
    varies = [replace(v, system=deck_units(raw, base)) for v in _parse_varies(varies, vary_texts)]
    chosen = _chosen(engines, supports)
    deck = base_deck(raw, source, base + list(chosen), varies)
    engines = _engines(deck, engines, check, source)
    supports = list(supports) or deck.analysis.supports
    _check_case_count(varies, engines, supports)
    deck_fingerprint = fingerprint(raw, base)
    cases = Cases(varies, engines, supports, deck_fingerprint)
    grounds = _ground_motions(raw, source, base + list(chosen), varies, engines, _follows_structure(deck))
    grounds.warnings[:0] = deck.warnings  # values far outside building practice, the base deck's and the cases'
    suites = _suites(grounds, engines)
    _check_per_record(per_record, suites, source)
    version = tool_version()
    inputs = _motion_inputs(grounds)
    records = _record_digests(inputs)
    return SweepPlan(raw, source, deck.title, tuple(base), varies, engines, supports, cases, deck.criteria,
                     max((suite.count for suite in suites), default=0), per_record,
                     _plan_warnings(grounds, suites), records=records,
                     version=version, fingerprint=run_fingerprint(deck_fingerprint, records, version),
                     record_steps=_record_steps(inputs), inputs=tuple(inputs.values()), check=check, chosen=chosen,
                     motion_band=tuple(deck.analysis.check_band_motion))


def deck_units(raw: dict, base: Sequence[tuple[str, Any]]) -> str:
    """The deck's unit system (`units`, or a --set of it): that of its bare numbers and its display units."""
    return schema.unit_system({"units": dict(base).get("units", raw.get("units", "si"))})


def _parse_varies(varies: Sequence[Vary], vary_texts: Sequence[str]) -> list[Vary]:
    """The given Vary objects, then the parsed --vary texts; InputError if a field is varied twice."""
    varies = list(varies) + [parse_vary(text) for text in vary_texts]
    paths = [v.path for v in varies]
    if len(set(paths)) != len(paths):
        raise InputError("--vary", next(p for p in paths if paths.count(p) > 1), "each field varied once")
    return varies


def _chosen(engines: Sequence[str], supports: Sequence[str]) -> tuple:
    """--engine and --support as every case's analysis.engine and analysis.supports: the deck's checks
    that depend on them (a rocking limit needs the exact engine) see the engines that run."""
    return tuple((path, list(given)) for path, given in (("analysis.engine", engines),
                                                         ("analysis.supports", supports)) if given)


def _engines(deck: Deck, engines: Sequence[str], check: bool, source: str) -> list[str]:
    """The engines that run (given, else the deck's), with the exact one for --check (a deck
    with a record or a suite)."""
    engines = list(engines) or deck.analysis.engines
    if not check:
        return engines
    if not isinstance(deck.ground_motion, (Record, Suite)):
        raise InputError("--check", source, "a deck with a record or a record suite (the exact engine checks "
                         "the simplified one on it; this deck gives only a design spectrum)")
    return list(dict.fromkeys([*engines, "exact"]))


def _check_case_count(varies: Sequence[Vary], engines: Sequence[str], supports: Sequence[str]) -> None:
    """The number of cases within the tool's limits, before any case is expanded."""
    problem = cases_problem([len(v.values) for v in varies], len(engines) * len(supports))
    if problem:
        raise InputError("--vary" if varies else "--engine/--support", None, problem)


def _follows_structure(deck: Deck) -> bool:
    """Whether the deck's ground motion follows the structure (a suite scaled over a period range
    that the structure gives: ground_motion_key): every combination is checked then."""
    fields = deck.values["ground_motion"]
    return "suite" in fields and "period_range" not in fields


def _ground_motions(raw: dict, source: str, base: list, varies: Sequence[Vary],
                    engines: Sequence[str], every: bool = True) -> _GroundMotions:
    """Build the checked combinations' decks (cases.checked_combos; without their record) and read
    each distinct ground motion once, prepared for every engine, from the last combination down (the
    longest periods first); a combination a record suite cannot serve refuses the sweep (unserved.py)
    as soon as one it serves is met, before any analysis."""
    grounds = _GroundMotions()
    combos = list(checked_combos(varies, every))
    for combo in reversed(combos):
        key = _add_combo(grounds, raw, source, base, combo, {v.path for v in varies})
        if key and grounds.unsupported:
            raise unserved_error(grounds.unsupported, combo, varies, len(combos))
        for engine in engines if key else ():
            ground_motion_for(grounds.decks[key], ENGINES[engine])
    if grounds.unsupported:
        raise unserved_error(grounds.unsupported, None, varies, len(combos))
    grounds.decks = dict(reversed(grounds.decks.items()))
    return grounds


def _add_combo(grounds: _GroundMotions, raw: dict, source: str, base: list, combo: tuple, varied: set[str]) -> str:
    """_add_ground_motion of one combination: its ground_motion_key, or "" (noted in
    grounds.unsupported) if its record suite cannot serve it."""
    try:
        return _add_ground_motion(grounds, raw, source, base, combo)
    except CaseUnsupported as error:
        grounds.unsupported.append((combo, f"{error.location}: {error.expected}" if error.location else error.expected))
        return ""
    except InputError as error:
        raise _vary_error(error, varied) from None


def _add_ground_motion(grounds: _GroundMotions, raw: dict, source: str, base: list, combo: tuple) -> str:
    """Build one combination's deck, keep its warnings and, if new, its ground motion; its ground_motion_key."""
    case_deck = build_deck(raw, source, base + list(combo), load_ground_motion=False)
    grounds.warnings += case_deck.warnings
    motion_key = ground_motion_key(case_deck)
    if motion_key not in grounds.decks:
        grounds.decks[motion_key] = _with_suite(raw, source, base, combo, case_deck)
    return motion_key


def _suites(grounds: _GroundMotions, engines: Sequence[str]) -> list[Suite]:
    """The record suites the cases read, if a response-history engine runs them (else none)."""
    if not any(ENGINES[engine].needs_record for engine in engines):
        return []
    return [g.ground_motion for g in grounds.decks.values() if isinstance(g.ground_motion, Suite)]


def _check_per_record(per_record: bool, suites: Sequence[Suite], source: str) -> None:
    if per_record and not suites:
        raise InputError("--per-record", source, "a deck whose ground_motion.suite a response-history engine runs "
                         "(--engine exact or approximate)")


def _plan_warnings(grounds: _GroundMotions, suites: Sequence[Suite]) -> tuple:
    """The decks' and the suites' warnings, each once."""
    return tuple(dict.fromkeys([*grounds.warnings, *(message for suite in suites for message in suite.warnings)]))


def _motion_inputs(grounds: _GroundMotions) -> dict[str, dict]:
    """The provenance entry of every file the ground motions read, each once (by its JSON text)."""
    return {json.dumps(entry, sort_keys=True): entry
            for ground in grounds.decks.values() for entry in motion_files(ground.ground_motion)}


def _record_digests(inputs: dict[str, dict]) -> dict[str, str]:
    """Every file the ground motions read -> its SHA-256 (absolute paths: a run from another folder
    is the same run)."""
    return {entry["path"]: entry["sha256"] for entry in inputs.values() if entry["path"] and entry["sha256"]}


def _record_steps(inputs: dict[str, dict]) -> dict[str, tuple]:
    """Every record file -> (dt [s], samples)."""
    return {entry["path"]: (entry["dt"], entry["npts"]) for entry in inputs.values() if "dt" in entry}
