"""A record suite through a response-history engine: every record of the suite (its factor
applied) is one engine batch over the decks' systems, each record's result is kept, and each
deck gets its SuiteResult (engines/suite_result.py): the statistics over the records, the design
statistic of its code rule, the simplified engine on the target spectrum beside it and, for a
yielding building with a [design] table, the global acceptance of ASCE 7-22 16.4.1 (acceptance.py).

Used by analysis.run_batch; knows nothing of the terminal. Nothing here writes files (the
SHA-256 of each record's source file is read, when the file is there).
"""

from __future__ import annotations

import hashlib
from collections.abc import Generator, Iterator, Sequence
from dataclasses import dataclass, replace
from typing import Any

from ..deck.load import Deck
from ..engines.registry import ENGINES, Engine
from ..engines.result import AnalysisResult
from ..engines.suite_result import SuiteRecord, SuiteResult, suite_result
from ..errors import AnalysisError, InputError
from ..motion.suites import Suite
from ..provenance.files import record_sha256
from .acceptance import suite_acceptance
from .comparison import compare, deck_bands


def motion_key(suite: Suite) -> tuple:
    """What the analyses of a suite depend on: the scaled records (step and content). Decks whose
    suites differ only in what does not change the motions (warnings, statistics rule, period
    range of an unscaled suite) share one batch per record."""
    return ("suite", *((m.dt, hashlib.sha1(m.acceleration.tobytes()).hexdigest()) for m in suite.motions()))


def suite_records(suite: Suite) -> tuple[SuiteRecord, ...]:
    """Name, source, factor, provenance and the source file's SHA-256 of every record (a matched
    record's source is the record it was matched from: its SHA-256 is that file's)."""
    provenance = tuple(suite.provenance) + ("",) * (suite.count - len(suite.provenance))
    return tuple(SuiteRecord(record.name, record.source, float(factor), note,
                             record_sha256(record))
                 for record, factor, note in zip(suite.records, suite.factors, provenance, strict=True))


def suite_summary(suite: Suite) -> dict[str, Any]:
    """What the suite was, for the reports: target, scaling, period range [s] and its note, damping."""
    return {"target": getattr(suite.target, "name", ""), "scaling": suite.scaling,
            "period_range": list(suite.period_range), "period_note": suite.period_note, "damping": suite.damping}


def _simplified(deck: Deck, support: str, spectrum=None) -> AnalysisResult | None:
    """The simplified engine on `spectrum` (default: the deck's target spectrum); None if it cannot run."""
    spectrum = deck.spectrum if spectrum is None else spectrum
    if spectrum is None:
        return None
    try:
        return ENGINES["simplified"].analyze(deck.system, spectrum, support, deck.analysis.simplified)
    except (AnalysisError, InputError):
        return None


def record_simplified(deck: Deck, suite: Suite, support: str) -> tuple[AnalysisResult, ...]:
    """The simplified engine on each scaled record's own spectrum (empty if it cannot run on one)."""
    results = [_simplified(deck, support, spectrum) for spectrum in suite.record_spectra]
    return tuple(results) if all(r is not None for r in results) else ()


def iter_suite_batch(engine: Engine, decks: Sequence[Deck], suite: Suite, support: str, options: Any,
                     operators: Any = None) -> Iterator[tuple[int, SuiteResult | AnalysisError | InputError]]:
    """The suite's records (motions with their factors) through `engine` for every deck's system
    (decks sharing the suite's motions and the engine options), one batch per record; yields
    (index, SuiteResult or the error that stopped it) as each deck's last record ends. A deck
    whose analysis fails on a record is not run on the later ones; the error names the record.
    operators: passed to engine.iter_batch (a check of the residuals: engines/exact/reuse.py)."""
    motions = suite.motions()
    alive = list(range(len(decks)))
    per_deck: dict[int, list[AnalysisResult]] = {k: [] for k in alive}
    for r, motion in enumerate(motions):
        record = f"record {r + 1} of {len(motions)} ({motion.name})"
        failed = yield from _record_batch(engine, decks, alive, per_deck, motion, record, support, options,
                                          operators)
        alive = [k for k in alive if k not in failed]
        if not alive:
            return
    for k in alive:
        yield k, _suite_outcome(decks[k], per_deck[k], support, operators)


@dataclass(frozen=True)
class RecordTwins:
    """The twins of a suite's records (a check of the residuals, analysis/residuals.py): each record's
    result, its residuals only (engines/exact/reuse.Twins); no statistics, no simplified engine and no
    acceptance, which the check does not read."""

    record_results: tuple[AnalysisResult, ...]


def _suite_outcome(deck: Deck, results: list[AnalysisResult], support: str, operators: Any
                   ) -> SuiteResult | RecordTwins:
    """A deck's SuiteResult, or for the twins of a check of the residuals (operators.residuals_only)
    their records' results."""
    if getattr(operators, "residuals_only", False):
        return RecordTwins(tuple(results))
    return deck_suite_result(deck, results, support)


def _record_batch(engine: Engine, decks: Sequence[Deck], alive: list[int], per_deck: dict[int, list[AnalysisResult]],
                  motion: Any, record: str, support: str, options: Any, operators: Any = None
                  ) -> Generator[tuple[int, AnalysisError | InputError], None, list[int]]:
    """One record (motion) through `engine` for the decks still alive (indices into decks): each
    result added to per_deck, each error yielded (index, the error naming the record); returns
    the decks that failed."""
    failed = []
    for j, outcome in engine.iter_batch([decks[k].system for k in alive], motion, support, options, operators):
        k = alive[j]
        if isinstance(outcome, AnalysisResult):
            per_deck[k].append(outcome)
        else:
            failed.append(k)
            yield k, _named_error(outcome, record)
    return failed


def _named_error(error: Exception, record: str) -> Exception:
    """An AnalysisError with the record it stopped on before its words; any other error as it is."""
    if isinstance(error, AnalysisError):
        return AnalysisError(f"{record}: {error}")
    return error


def deck_suite_result(deck: Deck, results: Sequence[AnalysisResult], support: str) -> SuiteResult:
    """The SuiteResult of a deck (its suite, rule and target) from the results of its records."""
    suite: Suite = deck.ground_motion
    warnings = [*suite.warnings, *refinement_warning(results, deck.analysis.exact.steps_per_period)]
    result = suite_result(results, suite_records(suite), suite.statistic, rule=suite.rule.name,
                          rule_label=suite.rule.label, simplified=_simplified(deck, support),
                          suite=suite_summary(suite), warnings=warnings,
                          record_simplified=record_simplified(deck, suite, support))
    result = flagged(deck, result)
    return replace(result, acceptance=suite_acceptance(deck, result))


def flagged(deck: Deck, result: SuiteResult) -> SuiteResult:
    """The suite's result with the bands of the deck's accuracy check (accuracy.deck_bands) in its
    `suite` summary (the terminal flags a ratio outside them with '!') and one warning per ratio
    simplified / suite outside them, as the design-spectrum path's check gives (issue 36: 0.44 and
    0.46 went unflagged)."""
    if result.simplified is None:
        return result
    band, motion_band = deck_bands(deck)
    check = compare(result.simplified, result, band, "the suite", motion_band)
    head = f"simplified/{result.support} on the target spectrum against the suite: "
    lines = [line.replace("accuracy check: ", head, 1)
             .replace("simplified / exact", "simplified / suite") for line in check.band_warnings()]
    summary = {**result.suite, "check_band": list(band), "check_band_motion": list(motion_band)}
    return replace(result, suite=summary, warnings=(*result.warnings, *lines))


def refinement_warning(results: Sequence[AnalysisResult], given: int) -> list[str]:
    """One line for the records whose step the exact engine refined to close the energy balance
    (engines/exact/engine._refined: intermediates["steps_per_period"]), none if it refined none."""
    refined = [r.intermediates["steps_per_period"] for r in results if "steps_per_period" in r.intermediates]
    if not refined:
        return []
    steps = f"{min(refined)}" if min(refined) == max(refined) else f"{min(refined)}-{max(refined)}"
    return [f"the energy balance closed to its tolerance only after refining the step on {len(refined)} of "
            f"{len(results)} records, to {steps} steps per governing period (analysis.exact.steps_per_period = "
            f"{given})"]
