"""Analysis runner: a Deck in, one AnalysisResult per (engine, support) out, through the
engine registry (engines/registry.py).

Used by `uplift analyze` and by sweeps; knows nothing of the terminal or files.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from .deck import Deck
from .engines.quantities import QUANTITIES, SCALARS
from .engines.registry import ENGINES, Engine
from .engines.result import AnalysisResult
from .errors import InputError
from .motion.records import Record
from .motion.suites import Suite


def ground_motion_for(deck: Deck, engine: Engine) -> Any:
    """The deck's record for a response-history engine, its spectrum (.sa) for the simplified
    engine; InputError naming the deck field when the deck has not what the engine needs."""
    if not engine.needs_record:
        if deck.spectrum is None:
            raise InputError(deck.source, "ground_motion", f"a record or a design spectrum for the {engine.name} engine")
        return deck.spectrum
    if isinstance(deck.ground_motion, Suite):
        raise InputError(deck.source, "ground_motion.suite",
                         f"a single record for the {engine.name} engine: record suites are not yet analysed by the "
                         "response-history engines (the simplified engine runs on the suite's target spectrum; "
                         "`uplift record scale/match` prepares the records)")
    if not isinstance(deck.ground_motion, Record):
        raise InputError(deck.source, "ground_motion.record",
                         f"a record for the {engine.name} engine (a design spectrum serves only the simplified engine)")
    return deck.ground_motion


def run_batch(decks: Sequence[Deck], engine: str, support: str,
              on_result: Callable[[int, AnalysisResult | Exception], None] | None = None,
              ) -> list[AnalysisResult | Exception]:
    """One engine, one support ("rigid", "bonded" or "uplift") for several decks: the result
    of each or the error that stopped it, also passed to on_result(index, result) as soon as
    it is known.

    Decks that share the ground motion and the engine options are analysed together (the
    exact engine shares work across them); results equal one-at-a-time analysis, bit for bit."""
    if engine not in ENGINES:
        raise InputError(decks[0].source if decks else "engine", "analysis.engine",
                         f"one of {', '.join(ENGINES)}, got {engine!r}")
    chosen = ENGINES[engine]
    out: list[AnalysisResult | Exception] = [None] * len(decks)  # type: ignore[list-item]

    def keep(k: int, result: AnalysisResult | Exception) -> None:
        out[k] = result
        if on_result:
            on_result(k, result)

    groups: dict[tuple, list[int]] = {}
    motions: dict[int, Any] = {}
    for k, deck in enumerate(decks):
        try:
            motions[k] = ground_motion_for(deck, chosen)
        except InputError as error:
            keep(k, error)
            continue
        groups.setdefault((id(motions[k]), getattr(deck.analysis, chosen.options)), []).append(k)
    for (_, options), members in groups.items():
        systems = [decks[k].system for k in members]
        for j, result in chosen.iter_batch(systems, motions[members[0]], support, options):
            keep(members[j], result)
    return out


def run_one(deck: Deck, engine: str, support: str) -> AnalysisResult:
    """One engine, one support condition; raises the error that stopped it."""
    (result,) = run_batch([deck], engine, support)
    if not isinstance(result, AnalysisResult):
        raise result
    return result


def run(deck: Deck, engine: str | Sequence[str] | None = None,
        supports: str | Sequence[str] | None = None) -> list[AnalysisResult]:
    """Every requested engine x support (default: those of the deck), engines outermost."""
    engines = [engine] if isinstance(engine, str) else list(engine or deck.analysis.engines)
    support_list = [supports] if isinstance(supports, str) else list(supports or deck.analysis.supports)
    return [run_one(deck, name, support) for name in engines for support in support_list]


def check_criteria(results: Sequence[AnalysisResult], criteria: dict) -> list[str]:
    """One message per violated acceptance criterion (deck [criteria]: a limit on the largest
    |value| of a response quantity, on a scalar, or uplift = false); empty when all pass."""
    messages = []
    for result in results:
        label = f"{result.engine}/{result.support}"
        for name, limit in criteria.items():
            if name == "uplift":
                if not limit and result.uplift:
                    messages.append(f"{label}: the mat lifts off (criteria.uplift = false)")
                continue
            unit = (QUANTITIES.get(name) or SCALARS[name]).unit
            value = abs(result.value(name))
            if value > limit:
                messages.append(f"{label}: {name} = {value:.4g} exceeds the limit {limit:.4g} [{unit}]")
    return messages
