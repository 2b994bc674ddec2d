"""The exact answer for a design spectrum: the simplified engine checked against the exact engine
on a spectrum-compatible suite (issue 24; docs/suites.md, "The exact answer by default").

`uplift analyze` on a deck with a design spectrum runs the simplified engine, and, as its
accuracy check, the exact engine on every record of a suite for that spectrum: the deck's own
suite when it has one, else CHECK_COUNT artificial records generated for the spectrum from the
fixed seed CHECK_SEED (motion/generate.py, matched to 100 % of it over CHECK_RANGE) and cached
in the user's cache directory (cache_dir: $XDG_CACHE_HOME/uplift, or the platform's), keyed by
the target's ordinates and the generator's version, written atomically. Each simplified result
gets an accuracy.Check (accuracy.compare: simplified / the exact suite statistic of every value
of engines/quantities.COMPARED, with the deck's bands), carried beside the results as the record
check is, whose reference names the suite; the Check also has the suite described and the
ratio split into its two factors (engines/suite_result.simplified_ratios):

    spectrum_ratio   the simplified engine on the target / on each record's own spectrum (mean):
                     how the records stand against the target, seen through the procedure;
    procedure_ratio  the simplified engine on each record's own spectrum / the exact engine on
                     that record (mean): the procedure's own error;

ratio = spectrum_ratio x procedure_ratio. `--no-check` skips it. check_deck gives a deck's checks,
on its record (accuracy.check_accuracy) or on a suite (check_suite_accuracy).
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import re
import sys
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..deck.load import Deck
from ..engines.result import AnalysisResult
from ..engines.suite_result import SuiteResult, simplified_ratios
from ..errors import AnalysisError, InputError
from ..motion.records import Record, is_suite
from .accuracy import Check, check_accuracy, compare, deck_bands

if TYPE_CHECKING:
    from ..motion.suites import Suite

CHECK_COUNT = 11
CHECK_SEED = 2024
#: periods [s] over which the check suite follows the target (within the target's own range)
CHECK_RANGE = (0.05, 5.0)
CHECK_DT = 0.01


def cache_dir() -> Path:
    """The user's cache folder for uplift: $XDG_CACHE_HOME/uplift, else ~/Library/Caches/uplift
    (macOS), %LOCALAPPDATA%/uplift/Cache (Windows) or ~/.cache/uplift."""
    if os.environ.get("XDG_CACHE_HOME"):
        return Path(os.environ["XDG_CACHE_HOME"]) / "uplift"
    if sys.platform == "darwin":
        return Path.home() / "Library" / "Caches" / "uplift"
    if os.name == "nt" and os.environ.get("LOCALAPPDATA"):
        return Path(os.environ["LOCALAPPDATA"]) / "uplift" / "Cache"
    return Path.home() / ".cache" / "uplift"


def check_range(spectrum) -> tuple[float, float]:
    """CHECK_RANGE within the spectrum's defined periods [s]."""
    low, high = spectrum.period_range
    return max(CHECK_RANGE[0], low), min(CHECK_RANGE[1], high)


def suite_key(spectrum, period_range: tuple[float, float]) -> str:
    """What a check suite depends on: the generator, seed, count, step, range and the target's
    5 % ordinates at 200 periods over the range."""
    from ..motion.generate import GENERATOR_VERSION

    periods = np.geomspace(*period_range, 200)
    digest = hashlib.sha256(json.dumps([GENERATOR_VERSION, CHECK_SEED, CHECK_COUNT, CHECK_DT,
                                        list(period_range)]).encode())
    digest.update(np.ascontiguousarray(spectrum.sa(periods, 0.05), dtype=float).tobytes())
    return digest.hexdigest()[:24]


def check_suite(spectrum, note=None) -> tuple[Suite, dict[str, Any]]:
    """The check suite of a design spectrum (module docstring), from the cache or generated and
    cached; note(text) is told when it is generated. Returns the suite and what it is."""
    from ..motion.code_rules import RULES
    from ..motion.generate import GENERATOR_VERSION
    from ..motion.suites import Suite

    period_range = check_range(spectrum)
    rule = RULES["mean"]
    path = cache_dir() / "check-suites" / f"{suite_key(spectrum, period_range)}.npz"
    info = {"source": "generated", "count": CHECK_COUNT, "seed": CHECK_SEED, "generator": GENERATOR_VERSION,
            "period_range": list(period_range), "target": spectrum.name, "cache": str(path)}
    try:
        with np.load(path) as stored:
            accelerations = np.split(stored["acceleration"], np.cumsum(stored["lengths"])[:-1])
            factors = stored["factors"]
    except (OSError, KeyError, ValueError):
        if note is not None:
            note(f"generating the check suite ({CHECK_COUNT} records for {spectrum.name}, seed {CHECK_SEED}); "
                 f"cached in {path}")
        accelerations, factors = _generated(spectrum, period_range, rule, path)
    records = tuple(Record(f"check {CHECK_SEED}-{k + 1:02d}", CHECK_DT, np.array(a), source="", units="g")
                    for k, a in enumerate(accelerations))
    suite = Suite(records, tuple(float(f) for f in factors), spectrum, period_range, rule, "match",
                  f"the check suite's range {period_range[0]:g}-{period_range[1]:g} s",
                  made=("artificial",) * len(records))
    return suite, info


def _generated(spectrum, period_range: tuple[float, float], rule, path: Path) -> tuple[list[np.ndarray], np.ndarray]:
    """The accelerations [g] (records of their own lengths, issue 36) and factors of a newly
    generated check suite (generate.generate_suite), stored at path (_store)."""
    from ..motion.generate import generate_suite

    suite, _ = generate_suite(spectrum, period_range, rule, CHECK_COUNT, CHECK_SEED, CHECK_DT)
    accelerations = [record.acceleration for record in suite.records]
    factors = np.array(suite.factors)
    _store(path, accelerations, factors)
    return accelerations, factors


def _store(path: Path, accelerations: list[np.ndarray], factors: np.ndarray) -> None:
    """Write the suite's arrays atomically (the records end to end, and their lengths); a cache
    that cannot be written (a full disk, or a symbolic link at path: never written through,
    runtime/atomic.refuse_symlink) is only not kept."""
    from ..errors import InputError
    from ..runtime.atomic import write_bytes

    buffer = io.BytesIO()
    np.savez(buffer, acceleration=np.concatenate(accelerations), lengths=np.array([a.size for a in accelerations]),
             factors=factors)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        write_bytes(path, buffer.getvalue())
    except (OSError, InputError):
        pass


def split_ratios(result: SuiteResult) -> dict[str, dict[str, float | None]]:
    """spectrum_ratio and procedure_ratio of each compared value (module docstring;
    engines/suite_result.simplified_ratios), None where a factor is not finite."""
    items = simplified_ratios(result)
    return {key: {name: float(item[key]) if np.isfinite(item.get(key, np.nan)) else None
                  for name, item in items.items()} for key in ("spectrum_ratio", "procedure_ratio")}


def suite_label(info: dict[str, Any], statistic: str) -> str:
    """The check's reference: 'exact engine on a spectrum-compatible suite (11 artificial records,
    seed 2024, mean)'."""
    made = (f"{info['count']} artificial records, seed {info['seed']}" if info["source"] == "generated"
            else f"the deck's {info['count']} records")
    return f"exact engine on a spectrum-compatible suite ({made}, {statistic})"


def check_suite_accuracy(deck: Deck, results: list[AnalysisResult], note=None) -> list[Check]:
    """One accuracy.Check (module docstring) per simplified result of a deck whose ground motion
    is a design spectrum or a suite, running the exact engine on the suite (its results reused
    when the deck ran it); none for a deck with a record. The results are not changed."""
    if isinstance(deck.ground_motion, Record) or deck.spectrum is None:
        return []
    simplified = [r for r in results if r.engine == "simplified"]
    if not simplified:
        return []
    try:
        checked, info = _checked_deck(deck, note)
    except AnalysisError as error:  # no check suite could be made for the user's spectrum
        return [_unmatched(result, deck, error) for result in simplified]
    statistic = checked.ground_motion.statistic
    info = {**info, "statistic": statistic}
    label = suite_label(info, statistic)
    exact = _exact_suite_results(results)
    return [_suite_check(result, exact.get(result.support), checked, label, info) for result in simplified]


def _unmatched(result: AnalysisResult, deck: Deck, error: AnalysisError) -> Check:
    """A Check that could not run because no check suite could be matched to the deck's spectrum:
    its error names what the user gave (ground_motion.design_spectrum), not the internal record
    and seed that failed (issue 36: "artificial record 1 (seed 2024) ... try another seed")."""
    band, motion_band = deck_bands(deck)
    reason = re.sub(r"^artificial record \d+ \(seed \d+\): ", "", str(error)).replace("; try another seed", "")
    words = (f"{deck.source}: ground_motion.design_spectrum ({deck.spectrum.name}): no suite of {CHECK_COUNT} "
             f"spectrum-compatible records could be made for it ({reason}); give the deck a record suite "
             "(ground_motion.suite) to check against, or --no-check")
    return Check(result.support, "exact engine on a spectrum-compatible suite", band, error=words,
                 motion_band=motion_band)


def _exact_suite_results(results: list[AnalysisResult]) -> dict[str, SuiteResult]:
    """The exact engine's suite results the deck ran, by support (reused as the check's reference)."""
    return {r.support: r for r in results if isinstance(r, SuiteResult) and r.engine == "exact"}


def _checked_deck(deck: Deck, note=None) -> tuple[Deck, dict[str, Any]]:
    """The deck the exact engine runs for the check, and what its suite is: the deck itself on its
    own suite, else the deck on the check suite of its design spectrum (check_suite)."""
    if is_suite(deck.ground_motion):
        return deck, {"source": "deck", "count": deck.ground_motion.count, "target": deck.spectrum.name}
    suite, info = check_suite(deck.spectrum, note)
    return replace(deck, ground_motion=suite), info


def _suite_check(result: AnalysisResult, reference: SuiteResult | None, checked: Deck, label: str,
                 info: dict[str, Any]) -> Check:
    """accuracy.compare on the suite (reference: the deck's own exact result, else the exact engine
    is run here on the checked deck), with what the suite is and, when the reference knows them,
    each ratio's two factors (split_ratios); a Check with the error that stopped the exact engine."""
    from .run import run_one

    band, motion_band = deck_bands(checked)
    try:
        reference = reference or run_one(checked, "exact", result.support, single=False)
    except (AnalysisError, InputError) as error:
        given = ("" if info["source"] != "generated" else
                 f"on the suite generated for ground_motion.design_spectrum ({info['target']}): ")
        return Check(result.support, label, band, error=given + str(error), motion_band=motion_band, suite=info)
    check = compare(result, reference, band, label, motion_band)
    split = split_ratios(reference) if reference.record_simplified else {}
    return replace(check, suite=info, **split)


def check_deck(deck: Deck, results: list[AnalysisResult], note=None) -> list[Check]:
    """The accuracy checks of a deck's simplified results: on its record (accuracy.check_accuracy)
    or, with a design spectrum, on a spectrum-compatible suite (check_suite_accuracy); note(text)
    is told when a check suite is generated."""
    return check_accuracy(deck, results) + check_suite_accuracy(deck, results, note)
