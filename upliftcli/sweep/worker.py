"""The worker side of a sweep: build each case's deck (sharing the loaded ground motion),
run the cases of a chunk (those that share a structure as one exact-engine batch) and make
each case's tidy row (columns: sweep/table.py). A suite's case row holds the design statistic
and, under "record_rows", each record's row (written to the tables with --per-record)."""

from __future__ import annotations

import functools
import json
import os
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..analysis.run import run_batch
from ..deck.criteria import check_criteria
from ..deck.load import Deck, build_deck
from ..engines.quantities import DESIGN, QUANTITIES, ROCKING, SCALARS, YIELDING, compared_values, rocking_value
from ..engines.simplified import effective_properties
from ..engines.suite_result import SuiteResult
from ..errors import AnalysisError, InputError
from .chunks import Chunk
from .plan import Case, ground_motion_key

#: per process: (deck, ground-motion fields, the plan's fingerprint) ->
#: (record or design spectrum, spectrum object with its S_a cache)
_GROUND_MOTIONS: dict[tuple, tuple[Any, Any]] = {}


#: what follows a record file's name in the message of a 'stale' row (stale_records reads it back)
STALE_TEXT = ": the record file changed after the sweep read it"


class StaleRecord(Exception):
    """A record file read by a worker is not the content the sweep planned with (its SHA-256
    differs): the case is not computed (status 'stale')."""


def check_records(motion, planned: dict[str, str]) -> None:
    """StaleRecord naming the first record of `motion` (a Record or a Suite) whose bytes, as read,
    have another SHA-256 than the plan's (`planned`: absolute path -> digest)."""
    for record in getattr(motion, "records", None) or [motion]:
        digest = getattr(record, "sha256", "")
        expected = _planned_digest(record, planned)
        if digest and expected and digest != expected:
            raise StaleRecord(f"{record.source}{STALE_TEXT} (SHA-256 "
                              f"{expected[:12]}... then, {digest[:12]}... now): this case was not computed; run the "
                              "same command with --resume --rerun-stale once the file is settled")


def stale_records(rows: Sequence[dict]) -> list[str]:
    """The record files named by the 'stale' rows, each once, in the order first met."""
    named = (row.get("message", "").partition(STALE_TEXT) for row in rows if row.get("status") == "stale")
    return list(dict.fromkeys(name for name, found, _ in named if found))


def _planned_digest(record, planned: dict[str, str]) -> str | None:
    """The plan's SHA-256 of a record's file (None for a record without a file)."""
    return planned.get(os.path.abspath(record.source)) if getattr(record, "source", "") else None


def build_case_deck(raw: dict, source: str, overrides: Sequence[tuple[str, Any]], inputs: str = "",
                    records: dict[str, str] | None = None) -> Deck:
    """build_deck, reusing the ground motion (record and spectrum cache) of earlier cases with
    the same `inputs` (SweepPlan.fingerprint, which hashes every file the ground motions read:
    a file changed between two sweeps in one process, a long-lived Dask worker, is read again).
    records: the plan's SHA-256 of every record file; a record read with other bytes (the file
    was replaced during the sweep) raises StaleRecord, and is not kept."""
    deck = build_deck(raw, source, overrides, load_ground_motion=False)
    key = (source, ground_motion_key(deck), inputs)
    if key not in _GROUND_MOTIONS:
        _make_room()
        _GROUND_MOTIONS[key] = _checked_ground_motion(raw, source, overrides, records or {})
    deck.ground_motion, deck.spectrum = _GROUND_MOTIONS[key]
    return deck


def _make_room() -> None:
    """Forget the kept ground motions once there are 16."""
    if len(_GROUND_MOTIONS) >= 16:
        _GROUND_MOTIONS.clear()


def _checked_ground_motion(raw: dict, source: str, overrides: Sequence[tuple[str, Any]],
                           records: dict[str, str]) -> tuple[Any, Any]:
    """(ground motion, spectrum) of the case's deck, its records checked against the plan's (check_records)."""
    full = build_deck(raw, source, overrides)
    check_records(full.ground_motion, records)
    return full.ground_motion, full.spectrum


def _row_head(case: Case) -> dict[str, Any]:
    return {"case": case.index, "key": case.key, "engine": case.engine, "support": case.support,
            **{path: value for path, value in case.overrides}}


def failed_row(case: Case, status: str, message: str) -> dict[str, Any]:
    return {**_row_head(case), "status": status, "message": message}


def _effective_properties(deck: Deck, result) -> tuple[float | None, float | None]:
    """(T1bar [s], xi1bar [-]) of the flexibly supported system as the engine reports it;
    T_1, xi_1 for a rigid base; for an engine that does not report them, those of the
    simplified procedure's effective_properties [21-25]."""
    if "T1bar" in result.intermediates:
        return result.intermediates["T1bar"], result.intermediates["xi1bar"]
    modes = deck.system.modes
    if result.support == "rigid":
        return float(modes.periods[0]), float(modes.damping[0])
    return _simplified_properties(deck)


def _simplified_properties(deck: Deck) -> tuple[float | None, float | None]:
    """(T1bar, xi1bar) of the simplified procedure [21-25]; (None, None) where it has none."""
    try:
        props = effective_properties(deck.system, deck.analysis.simplified.effective_properties)
    except AnalysisError:
        return None, None
    return props["T1bar"], props["xi1bar"]


def case_row(case: Case, deck: Deck, result) -> dict[str, Any]:
    """The tidy row of one finished case (SI units; columns: sweep/table.output_columns); a
    suite's: its design statistic, the count, and each record's row under "record_rows"."""
    t1bar, xi1bar = _effective_properties(deck, result)
    row = {**_row_head(case), **_outputs(deck, result, t1bar, xi1bar),
           "violations": "; ".join(check_criteria([result], deck.criteria)), "status": "ok", "message": ""}
    if isinstance(result, SuiteResult):
        row.update(statistic=result.statistic, records=result.count, record_rows=[
            {"record": info.name, "factor": info.factor, **_outputs(deck, record, t1bar, xi1bar)}
            for info, record in zip(result.records, result.record_results, strict=True)])
    return row


def _mode1_base_shear(result) -> float | None:
    """The peak mode-1 contribution to the base shear [N] (None if the engine gives none)."""
    if result.engine == "simplified":
        mode1 = result.intermediates["V_n"][0]
    else:
        mode1 = (result.details.get("modal_base_shear") or [None])[0]
    return None if mode1 is None else float(mode1)


def _per_weight(value, weight: float) -> float | None:
    """A force as a coefficient of the weight (None stays None)."""
    return None if value is None else value / weight


def _peak_columns(result, quantities: dict, value: Callable[[str], Any]) -> dict[str, Any]:
    """The columns of the quantities (engines/quantities.py) with a peak in the result."""
    return {q.column: value(name) for name, q in quantities.items() if q.column and name in result.peaks}


def _yielding_value(result, name: str) -> float | int:
    """The sweep column of a yielding stories' quantity (quantities.YIELDING): its largest value (a count as an int)."""
    return YIELDING[name].typed(result.value(name))


def _outputs(deck: Deck, result, t1bar: float | None, xi1bar: float | None) -> dict[str, Any]:
    """The output columns of a result (SI units)."""
    return {
        "T1_s": float(deck.system.modes.periods[0]), "T1bar_s": t1bar, "xi1bar": xi1bar,
        **{scalar.column: result.value(name) for name, scalar in SCALARS.items()},
        "mode1_base_shear_coefficient": _per_weight(_mode1_base_shear(result), result.weight),
        "two_mode_base_shear_coefficient": _per_weight(result.intermediates.get("V_1+2"), result.weight),
        **_peak_columns(result, QUANTITIES, result.value),
        **_peak_columns(result, ROCKING, functools.partial(rocking_value, result)),
        **_peak_columns(result, YIELDING, functools.partial(_yielding_value, result)),
        **_peak_columns(result, DESIGN, result.value),
        "max_drift_story": int(np.argmax(np.abs(result.drift_ratio))) + 1,
        "uplift": bool(result.uplift), "V_c_N": result.critical_base_shear,
        "critical_coefficient": result.critical_coefficient,
        "compared": compared_values(result),  # for sweep --check (sweep/table.add_checks), not a column
    }


def _failure(error: Exception) -> str:
    if isinstance(error, (InputError, AnalysisError, StaleRecord)):
        return str(error)
    return f"{type(error).__name__}: {error}"


def _safe_row(case: Case, deck: Deck, result) -> dict[str, Any]:
    if isinstance(result, Exception):
        return failed_row(case, "failed", _failure(result))
    try:
        return case_row(case, deck, result)
    except Exception as error:
        return failed_row(case, "failed", _failure(error))


def _run_batch(members: list[tuple[Case, Deck]], deliver: Callable[[int, Any], None]) -> None:
    """run_batch, each result to deliver(j, result) as soon as it is known; if the batch
    raises, the cases still without a result run alone, so the failure is charged to its case."""
    engine, support = members[0][0].engine, members[0][0].support
    delivered: set[int] = set()
    try:
        run_batch([deck for _, deck in members], engine, support, functools.partial(_noted, delivered, deliver))
    except Exception as error:
        _run_alone(members, deliver, delivered, error)


def _noted(delivered: set[int], deliver: Callable[[int, Any], None], j: int, result) -> None:
    """Note that case j has its result, and deliver it."""
    delivered.add(j)
    deliver(j, result)


def _run_alone(members: list[tuple[Case, Deck]], deliver: Callable[[int, Any], None], delivered: set[int],
               error: Exception) -> None:
    """After a batch raised: each case without a result alone (a batch of one: the error is its result)."""
    for j in [j for j in range(len(members)) if j not in delivered]:
        if len(members) == 1:
            deliver(j, error)
        else:
            _run_batch([members[j]], functools.partial(_deliver_as, deliver, j))


def _deliver_as(deliver: Callable[[int, Any], None], j: int, _: int, result) -> None:
    """The result of a batch of one, delivered as case j's."""
    deliver(j, result)


def _ignore(message: tuple) -> None:
    """An emit that drops the messages."""


def run_chunk(chunk: Chunk, emit: Callable[[tuple], None] | None = None) -> list[dict[str, Any]]:
    """Run a chunk of cases; `emit(("start", [key, ...]))` before the cases that run together
    and `emit(("row", row))` after each.

    Cases with the same engine and support whose decks share the record and the engine
    options run as one batch (analysis.run_batch: the exact engine shares work across
    them); an exception becomes a 'failed' row with its message (never retried). Rows come
    back in case order."""
    if emit is None:
        emit = _ignore
    rows: dict[int, dict[str, Any]] = {}
    for members in _batches(chunk, rows, emit).values():
        emit(("start", [case.key for case, _ in members]))
        _run_batch(members, functools.partial(_deliver_row, members, rows, emit))
    return [rows[case.index] for case in chunk.cases]


def _batches(chunk: Chunk, rows: dict[int, dict[str, Any]], emit: Callable[[tuple], None]) -> dict[tuple, list]:
    """The chunk's cases with their decks (each distinct deck built once), by batch (_batch_key);
    a case whose deck cannot be built gets its row at once ('failed', or 'stale': StaleRecord)."""
    decks: dict[str, Deck] = {}
    batches: dict[tuple, list[tuple[Case, Deck]]] = {}
    for case in chunk.cases:
        try:
            deck = _case_deck(chunk, case, decks)
        except Exception as error:
            rows[case.index] = failed_row(case, "stale" if isinstance(error, StaleRecord) else "failed",
                                          _failure(error))
            emit(("start", [case.key]))
            emit(("row", rows[case.index]))
            continue
        batches.setdefault(_batch_key(case), []).append((case, deck))
    return batches


def _case_deck(chunk: Chunk, case: Case, decks: dict[str, Deck]) -> Deck:
    """The case's deck, built once for all the chunk's cases with the same varied values."""
    deck_key = json.dumps([list(o) for o in case.overrides], default=str)
    if deck_key not in decks:
        overrides = list(chunk.base_overrides) + list(case.overrides)
        decks[deck_key] = build_case_deck(chunk.raw, chunk.source, overrides, chunk.inputs, chunk.records)
    return decks[deck_key]


def _batch_key(case: Case) -> tuple:
    """Cases with one engine and support run as one batch; a simplified case alone."""
    return (case.engine, case.support) if case.engine != "simplified" else (case.index,)


def _deliver_row(members: list[tuple[Case, Deck]], rows: dict[int, dict[str, Any]], emit: Callable[[tuple], None],
                 j: int, result) -> None:
    """Make case j's row from its result (or error) and emit it."""
    case, deck = members[j]
    rows[case.index] = _safe_row(case, deck, result)
    emit(("row", rows[case.index]))
