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
import itertools
import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..analysis.run import ground_motion_for
from ..deck.load import Deck, build_deck, read_toml
from ..deck.overrides import parse_override
from ..engines.registry import ENGINES
from ..errors import InputError
from ..motion.records import Record
from ..motion.suites import Suite
from ..provenance.files import motion_files
from ..runtime.installed import tool_version
from ..runtime.limits import cases_problem
from .values import Vary, parse_vary

#: status of a row: ok; failed (the analysis raised: deterministic, not retried within a run);
#: crashed (the worker process died on this case `max_attempts` times); stale (not computed: a
#: record file's content changed after the sweep had read it; run again by --resume)
STATUSES = ("ok", "failed", "crashed", "stale")


@dataclass(frozen=True)
class Case:
    """One analysis of a sweep: index in the sweep, stable key, varied values, engine, support."""

    index: int
    key: str
    overrides: tuple  # ((path, value), ...) of the varied fields
    engine: str
    support: str


def fingerprint(raw: dict, base_overrides: Sequence[tuple[str, Any]]) -> str:
    """Hash of the parsed deck and the --set overrides (comments and layout do not count)."""
    text = json.dumps({"deck": raw, "set": [list(o) for o in base_overrides]}, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()


def case_key(deck_fingerprint: str, overrides: Sequence[tuple[str, Any]], engine: str, support: str) -> str:
    text = json.dumps([deck_fingerprint, [list(o) for o in overrides], engine, support], default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:20]


def expand_cases(varies: Sequence[Vary], engines: Sequence[str], supports: Sequence[str],
                 deck_fingerprint: str) -> list[Case]:
    """Cartesian product of the varied values (first --vary outermost), then engine, then support,
    so that the cases sharing one deck are adjacent."""
    combos = itertools.product(*[[(v.path, value) for value in v.values] for v in varies])
    cases = []
    for overrides, engine, support in itertools.product(combos, engines, supports):
        cases.append(Case(len(cases), case_key(deck_fingerprint, overrides, engine, support),
                          tuple(overrides), engine, support))
    return cases


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
    cases: list[Case]
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
    which follows the structure, asks for longer records than the suite's): the case fails
    alone, the others run."""


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


def plan_sweep(deck_path: str | Path, settings: Sequence[str] = (), vary_texts: Sequence[str] = (),
               engines: Sequence[str] = (), supports: Sequence[str] = (), *, varies: Sequence[Vary] = (),
               per_record: bool = False, check: bool = False) -> SweepPlan:
    """Parse and validate a sweep: every case's deck is built (without its record) and every
    distinct ground motion is read once here, so bad input stops the run before any analysis.
    per_record: each record's row in the tables (a deck with a suite run by a history engine);
    check: the exact engine runs beside the others for the ratios simplified / exact (a deck
    with a record or a suite)."""
    base = [parse_override(text) for text in settings]
    varies = list(varies) + [parse_vary(text) for text in vary_texts]
    paths = [v.path for v in varies]
    if len(set(paths)) != len(paths):
        raise InputError("--vary", next(p for p in paths if paths.count(p) > 1), "each field varied once")
    source = str(deck_path)
    raw = read_toml(deck_path)
    # --engine and --support are every case's analysis.engine and analysis.supports: the deck's checks
    # that depend on them (a rocking limit needs the exact engine) see the engines that run
    chosen = tuple((path, list(given)) for path, given in (("analysis.engine", engines),
                                                           ("analysis.supports", supports)) if given)
    deck = base_deck(raw, source, base + list(chosen), varies)
    engines = list(engines) or deck.analysis.engines
    supports = list(supports) or deck.analysis.supports
    if check:
        if not isinstance(deck.ground_motion, (Record, Suite)):
            raise InputError("--check", source, "a deck with a record or a record suite (the exact engine checks "
                             "the simplified one on it; this deck gives only a design spectrum)")
        engines = list(dict.fromkeys([*engines, "exact"]))
    problem = cases_problem([len(v.values) for v in varies], len(engines) * len(supports))
    if problem:  # before any case is expanded
        raise InputError("--vary" if varies else "--engine/--support", None, problem)
    deck_fingerprint = fingerprint(raw, base)
    cases = expand_cases(varies, engines, supports, deck_fingerprint)
    grounds: dict[str, Any] = {}
    deck_warnings = list(deck.warnings)  # values far outside building practice, the base deck's and the cases'
    unsupported: list[str] = []
    for combo in itertools.product(*[[(v.path, value) for value in v.values] for v in varies]):
        try:
            case_deck = build_deck(raw, source, base + list(chosen) + list(combo), load_ground_motion=False)
            deck_warnings += case_deck.warnings
            motion_key = ground_motion_key(case_deck)
            if motion_key not in grounds:
                grounds[motion_key] = _with_suite(raw, source, base + list(chosen), combo, case_deck)
        except CaseUnsupported as error:
            unsupported.append(str(error))  # its cases fail alone, the message in their rows (sweep/worker.py)
            continue
        except InputError as error:
            raise _vary_error(error, set(paths)) from None
        for engine in engines:
            ground_motion_for(grounds[motion_key], ENGINES[engine])
    suites = [g.ground_motion for g in grounds.values() if isinstance(g.ground_motion, Suite)]
    if not any(ENGINES[engine].needs_record for engine in engines):
        suites = []
    if per_record and not suites:
        raise InputError("--per-record", source, "a deck whose ground_motion.suite a response-history engine runs "
                         "(--engine exact or approximate)")
    warnings = tuple(dict.fromkeys([*deck_warnings, *(message for suite in suites for message in suite.warnings)]))
    if unsupported:
        total = math.prod(len(v.values) for v in varies)
        warnings += (f"{len(unsupported)} of {total} combinations of the varied fields cannot be run with the "
                     f"deck's ground motion and fail alone (exit code 4), e.g. {unsupported[0]}",)
    version = tool_version()
    inputs = {json.dumps(entry, sort_keys=True): entry
              for ground in grounds.values() for entry in motion_files(ground.ground_motion)}
    # every file the ground motions read (absolute paths: a run from another folder is the same run)
    records = {entry["path"]: entry["sha256"] for entry in inputs.values() if entry["path"] and entry["sha256"]}
    samples = {entry["path"]: (entry["dt"], entry["npts"]) for entry in inputs.values() if "dt" in entry}
    return SweepPlan(raw, source, deck.title, tuple(base), varies, engines, supports, cases, deck.criteria,
                     max((suite.count for suite in suites), default=0), per_record, warnings, records=records,
                     version=version, fingerprint=run_fingerprint(deck_fingerprint, records, version),
                     record_steps=samples, inputs=tuple(inputs.values()), check=check, chosen=chosen)


# ----------------------------------------------------------------------------- chunks

@dataclass
class Chunk:
    """A batch of cases handed to one worker at a time (picklable)."""

    raw: dict
    source: str
    base_overrides: tuple
    cases: list[Case]
    #: the plan's fingerprint (the contents of every file its ground motions read)
    inputs: str = ""
    #: the SHA-256 of every record file as the plan read it (absolute path -> digest)
    records: dict = field(default_factory=dict)


def _structure_order(case: Case) -> tuple:
    """Sort key putting together the cases that differ only in foundation fields (same
    building, record and engine options), then by engine and support: a chunk of them is
    one batch for the exact engine (analysis.run_batch)."""
    others = [(path, value) for path, value in case.overrides if not path.startswith("foundation.")]
    return json.dumps(others, default=str), case.engine, case.support


def make_chunks(plan: SweepPlan, cases: Sequence[Case], size: int) -> list[Chunk]:
    """The cases in chunks of `size`, those that share a structure together (_structure_order;
    stable, so otherwise in case order)."""
    size = max(1, int(size))
    ordered = sorted(cases, key=_structure_order)
    return [Chunk(plan.raw, plan.source, (*plan.base_overrides, *plan.chosen), ordered[i:i + size],
                  plan.fingerprint, plan.records) for i in range(0, len(ordered), size)]


def chunk_size(n_cases: int, workers: int) -> int:
    """About four chunks per worker, at most 16 cases a chunk (a chunk lost to a dead worker is small)."""
    return max(1, min(16, math.ceil(n_cases / (4 * max(1, workers)))))
