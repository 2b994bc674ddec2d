"""What an answer is (issue 36: the same building gave V_b/W 0.52 from its design deck and 1.08
from its suite deck, with no word why): the ASCE 7-22 level of the motion every number of a
result derives from, design (11.4.5: 2/3 of MCE_R) or MCE_R (11.4.6; chapter 16 scales its
suites to it, 16.2.1: motion/levels.py), and the one line that says which number is the design
value and which is the check."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

from ..engines.result import AnalysisResult
from ..engines.suite_result import SuiteResult

#: the level's name and its clause of ASCE 7-22
LEVELS = {"design": ("design", "ASCE 7-22 11.4.5"), "mce_r": ("MCE_R", "ASCE 7-22 11.4.6, 16.2")}


def motion_level(motion: Any) -> dict[str, str] | None:
    """{level, name, clause, text} of a deck's ground motion: an ASCE 7-22 spectrum's level, or
    that of a suite's target (the MCE_R spectrum under ASCE 7-22 chapter 16); None for a record or
    a spectrum without one (EN 1998-1, a table)."""
    level = getattr(getattr(motion, "target", motion), "level", None)
    if level not in LEVELS:
        return None
    name, clause = LEVELS[level]
    return {"level": level, "name": name, "clause": clause, "text": f"{name} level ({clause})"}


def with_level(result: AnalysisResult, motion: Any) -> AnalysisResult:
    """The result with the level of its motion in details["level"] (none known: as it is)."""
    level = motion_level(motion)
    if level is None:
        return result
    return replace(result, details={**result.details, "level": level})


def level_text(result: AnalysisResult) -> str:
    """'MCE_R level (ASCE 7-22 11.4.6, 16.2)' of a result, '' when it has none."""
    return result.details.get("level", {}).get("text", "")


def levels_legend(results: Sequence[AnalysisResult]) -> str:
    """'; every row: MCE_R level (ASCE 7-22 11.4.6, 16.2)' (one level), '; engine/support: level'
    each (several), '' (none)."""
    texts = {f"{r.engine}/{r.support}": level_text(r) for r in results if level_text(r)}
    if len(set(texts.values())) == 1 and len(texts) == len(results):
        return f"; level of every row: {next(iter(texts.values()))}"
    return "".join(f"; {row}: {text}" for row, text in texts.items())


def answer_line(results: Sequence[AnalysisResult], checks: Sequence = ()) -> str:
    """Which number is the design value and which the check, at which level ('' without a level)."""
    levelled = [r for r in results if level_text(r)]
    if not levelled:
        return ""
    level = level_text(levelled[0])
    suites = [r for r in levelled if isinstance(r, SuiteResult)]
    if suites:
        first = suites[0]
        return (f"design value: the {first.engine} engine's {first.statistic} of the {first.count} records "
                f"({first.rule_label}), {level}; check: the simplified engine on the target spectrum beside it "
                "(simplified / suite), not a design value")
    checked = [c for c in checks if getattr(c, "suite", None) is not None]
    check = (f"; check: the {checked[0].reference} (simplified / exact), not a design value" if checked
             else "; no check was run")
    return f"design value: the simplified engine on the design spectrum, {level}{check}"
