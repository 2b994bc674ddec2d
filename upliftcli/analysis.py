"""Analysis runner: a Deck in, one AnalysisResult per (engine, support) out.

Used by `uplift analyze` and by sweeps; knows nothing of the terminal or files.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Sequence

from .deck import Deck
from .engines.result import AnalysisResult
from .errors import AnalysisError, InputError

ENGINES = ("simplified", "approximate", "exact")


def run_one(deck: Deck, engine: str, support: str) -> AnalysisResult:
    """One engine, one support condition ("rigid", "bonded" or "uplift")."""
    if engine == "simplified":
        from .engines import simplified

        if deck.spectrum is None:
            raise InputError(deck.source, "ground_motion", "a record or a design spectrum for the simplified engine")
        return simplified.analyze(deck.system, deck.spectrum, support, deck.analysis.simplified)
    if engine not in ENGINES:
        raise InputError(deck.source, "analysis.engine", f"one of {', '.join(ENGINES)}, got {engine!r}")
    from .motion.records import Record

    if not isinstance(deck.ground_motion, Record):
        raise InputError(deck.source, "ground_motion.record",
                         f"a record for the {engine} engine (a design spectrum serves only the simplified engine)")
    module = importlib.import_module(f"upliftcli.engines.{engine}")
    function = getattr(module, "analyze", None)
    if function is None:
        raise AnalysisError(f"the {engine} engine is not available in this version")
    return function(deck.system, deck.ground_motion, support, deck.analysis.exact)


def run_batch(decks: Sequence[Deck], engine: str, support: str,
              on_result: Callable[[int, AnalysisResult | Exception], None] | None = None,
              ) -> list[AnalysisResult | Exception]:
    """run_one for several decks: the result of each or the error that stopped it, also
    passed to on_result(index, result) as soon as it is known.

    The response-history engines analyse decks that share a record and options together
    (exact.iter_batch: shared work done once); results equal run_one's, bit for bit."""
    from .motion.records import Record

    out: list[AnalysisResult | Exception] = [None] * len(decks)  # type: ignore[list-item]

    def keep(k: int, result: AnalysisResult | Exception) -> None:
        out[k] = result
        if on_result:
            on_result(k, result)

    groups: dict[tuple, list[int]] = {}
    for k, deck in enumerate(decks):
        if engine in ("exact", "approximate") and isinstance(deck.ground_motion, Record):
            groups.setdefault((id(deck.ground_motion), deck.analysis.exact), []).append(k)
            continue
        try:
            result = run_one(deck, engine, support)
        except (InputError, AnalysisError) as error:
            result = error
        keep(k, result)
    if groups:
        from .engines.exact import engine as exact

        for (_, options), members in groups.items():
            systems = [decks[k].system for k in members]
            for j, result in exact.iter_batch(systems, decks[members[0]].ground_motion, support, options, engine):
                keep(members[j], result)
    return out


def run(deck: Deck, engine: str | Sequence[str] | None = None,
        supports: str | Sequence[str] | None = None) -> list[AnalysisResult]:
    """Every requested engine x support (default: those of the deck), engines outermost."""
    engines = [engine] if isinstance(engine, str) else list(engine or deck.analysis.engines)
    support_list = [supports] if isinstance(supports, str) else list(supports or deck.analysis.supports)
    return [run_one(deck, name, support) for name in engines for support in support_list]


#: criterion name -> (how to get the value from a result, unit)
_CRITERIA = {
    "drift_ratio": (lambda r: float(max(abs(r.drift_ratio))), "-"),
    "drift": (lambda r: float(max(abs(r.drift))), "m"),
    "displacement": (lambda r: float(max(abs(r.displacement))), "m"),
    "base_shear": (lambda r: abs(r.base_shear), "N"),
    "base_shear_coefficient": (lambda r: abs(r.base_shear_coefficient), "-"),
    "base_moment": (lambda r: abs(r.base_moment), "N m"),
    "base_moment_coefficient": (lambda r: abs(r.base_moment_coefficient), "-"),
}


def check_criteria(results: Sequence[AnalysisResult], criteria: dict) -> list[str]:
    """One message per violated acceptance criterion (deck [criteria]); empty when all pass."""
    messages = []
    for result in results:
        label = f"{result.engine}/{result.support}"
        for name, limit in criteria.items():
            if name == "uplift":
                if not limit and result.uplift:
                    messages.append(f"{label}: the mat lifts off (criteria.uplift = false)")
                continue
            value_of, unit = _CRITERIA[name]
            value = value_of(result)
            if value > limit:
                messages.append(f"{label}: {name} = {value:.4g} exceeds the limit {limit:.4g} [{unit}]")
    return messages
