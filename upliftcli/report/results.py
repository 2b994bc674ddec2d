"""Report sections on what came out: the results of every engine and support (the tables of
engines/quantities.py, in the display units of display.py). The accuracy check, the warnings and
the [criteria] verdict are report/checks.py."""

from __future__ import annotations

from collections.abc import Sequence

from ..analysis.level import answer_line, level_text, levels_legend
from ..display import (
    BUILDING_LEGEND,
    ROCKING_HEADINGS,
    SUMMARY,
    VERDICT_LEGEND,
    WEIGHT_LEGEND,
    building_verdicts,
    heading,
    intermediate_kind,
    label,
    rocking_rows,
    show,
    summary_columns,
    verdicts,
)
from ..engines.quantities import (
    FLOOR,
    INTERMEDIATES,
    STORY,
    YIELDING,
    display_kind,
    element_quantities,
    quantities,
    rocking_entries,
)
from ..engines.result import AnalysisResult
from .design import design_table
from .document import Section, Table, Text, number

STORY_QUANTITIES = quantities(FLOOR, STORY)
#: the yielding stories' quantities (quantities.YIELDING), in the story table of a result that has them
YIELDING_STORY = [q for q in YIELDING.values() if q.where == STORY]


def _slug(result: AnalysisResult) -> str:
    return f"{result.engine}-{result.support}"


def summary_table(results: Sequence[AnalysisResult], units: str = "si") -> Table:
    """One row per analysis, every column of the display record of the scalar results (display.SUMMARY;
    `yielded` where a result tells it: display.verdicts)."""
    told = "yielded" in verdicts(results)
    building = bool(building_verdicts(results))
    columns = _summary_columns(told) + summary_columns(building_verdicts(results))
    rows = [_summary_row(r, columns, units) for r in results]
    return Table("table-summary", "Summary: base shear V_b [14a] and base moment M_b [14b] of every analysis",
                 ["engine", "support", *(column.heading(units) for column in columns)], rows,
                 f"{WEIGHT_LEGEND}; the critical value of both coefficients is b/h_1* [16a, 16b]"
                 + levels_legend(results) + (f"; {VERDICT_LEGEND}" if told else "")
                 + (f"; {BUILDING_LEGEND}." if building else "."))


def _summary_columns(told: bool) -> list:
    """The columns of display.SUMMARY; `yielded` only when a result tells it."""
    return [c for name, c in SUMMARY.items() if name != "yielded" or told]


def _summary_row(result: AnalysisResult, columns: list, units: str) -> list[str]:
    """Engine (its label), support and every column of one analysis."""
    return [getattr(result, "label", result.engine), result.support,
            *(column.cell(result, units) for column in columns)]


def detail_unit(table: str, name: str) -> str:
    """SI unit of an entry of the uplift summary or the energy balance of the history engines."""
    if table == "energy":
        return "-" if name.startswith("relative") else "J"
    for part, unit in (("rotation", "rad"), ("time", "s"), ("episodes", "-"), ("uplift", "m"),
                       ("displacement", "m"), ("reaction", "N")):
        if part in name:
            return unit
    return INTERMEDIATES.get(name, ("", ""))[0]


def _peaks(result, units: str) -> list[str]:
    """The peak base shear, base moment and drift ratio of a result, in the display units."""
    return [SUMMARY["base_shear"].cell(result, units), SUMMARY["base_moment"].cell(result, units),
            show(result.value("drift_ratio"), display_kind("drift_ratio"), units)]


def _record_rows(result, told: bool, units: str) -> list[list[str]]:
    """A row per record of a suite: number, name, factor, peaks, uplift (and whether it yielded)."""
    return [[str(k + 1), record.name, number(record.factor, 4), *_peaks(r, units), number(r.uplift),
             *([SUMMARY["yielded"].cell(r)] if told else [])]
            for k, (record, r) in enumerate(zip(result.records, result.record_results, strict=True))]


def _design_row(result, told: bool, units: str) -> list[str]:
    """The suite's design statistic: its peaks and how many records lifted (and yielded)."""
    yielded = sum(bool(r.yielded) for r in result.record_results)
    return ["", f"{result.statistic} (design value)", "", *_peaks(result, units),
            f"{result.uplift_count} of {result.count}", *([f"{yielded} of {result.count}"] if told else [])]


def records_table(result, units: str = "si") -> Table:
    """A suite's records (engines/suite_result.SuiteResult): factor and peak response of each."""
    told = "yielded" in verdicts(result.record_results)
    rows = [*_record_rows(result, told, units), _design_row(result, told, units)]
    return Table(f"table-{_slug(result)}-records", f"Each record of the suite, {result.engine} engine, "
                 f"{result.support} support ({result.rule_label or result.rule}: the {result.statistic})",
                 _records_headers(told, units), rows)


def _records_headers(told: bool, units: str) -> list[str]:
    drift = heading("largest drift ratio", display_kind("drift_ratio"), units)
    return ["record", "name", "factor [-]", SUMMARY["base_shear"].heading(units), SUMMARY["base_moment"].heading(units),
            drift, "uplift", *(["yielded"] if told else [])]


#: the detail tables of the history engines: key of result.details -> caption
DETAILS = {"uplift_summary": "Uplift summary", "energy": "Energy balance"}


def result_tables(result: AnalysisResult, units: str = "si") -> list[Table]:
    """Story table, foundation elements, intermediates and the history engines' extras (for a
    suite: of its design statistic, and each record's peaks), in the display units."""
    what = f"{getattr(result, 'label', result.engine)} engine, {result.support} support"
    what += f", {level_text(result)}" if level_text(result) else ""
    tables = [story_table(result, what, units), design_table(result, units),  # with [design]: report/design.py
              elements_table(result, what, units), rocking_table(result, units),
              intermediates_table(result, what, units),
              *(detail_table(result, key, f"{caption}, {what}", units) for key, caption in DETAILS.items()),
              _suite_records(result, units)]
    return [table for table in tables if table is not None]


def story_table(result: AnalysisResult, what: str, units: str = "si") -> Table:
    """Peak response per story, top story first; what: the analysis in words."""
    shown = [q for q in STORY_QUANTITIES + YIELDING_STORY if q.name in result.peaks]
    rows = [_story_row(result, j, shown, units) for j in range(result.elevations.size - 1, -1, -1)]
    return Table(f"table-{_slug(result)}-stories", f"Peak response per story, {what} (top story first)",
                 ["story", heading("elevation", "m", units)] + [q.heading(units) for q in shown], rows,
                 "Floor quantities are those of the floor at the top of the story." + _yielding_note(result))


#: the story table's note on the yielding stories' columns (a result with story strengths)
YIELDING_NOTE = (" Ductility: peak |drift| over the yield drift V_y/k; residual drift ratio: at the end of the "
                 "analysis; hysteretic energy: dissipated by the story's yielding (docs/theory.md 15.5).")


def _yielding_note(result: AnalysisResult) -> str:
    """YIELDING_NOTE for a result with story strengths, else ''."""
    return YIELDING_NOTE if result.building_yielded is not None else ""


def _story_row(result: AnalysisResult, j: int, shown: list, units: str) -> list[str]:
    """Story j + 1: its elevation and the peak of each quantity shown."""
    peaks = [_story_cell(q, result.peaks[q.name][j], units) for q in shown]
    return [str(j + 1), show(result.elevations[j], "m", units), *peaks]


def _story_cell(quantity, value, units: str) -> str:
    """A story's value in its display unit; its yielded flag (story_yielded) as yes/no."""
    return show(bool(value) if quantity.name == "story_yielded" else value, quantity.display, units)


def elements_table(result: AnalysisResult, what: str, units: str = "si") -> Table | None:
    """The peaks of each foundation element (largest compression, plastic settlement), or None."""
    elements = _element_quantities(result)
    if not elements:
        return None
    rows = [_element_row(result, i, x, elements, units) for i, x in enumerate(result.element_positions)]
    plastic = ", plastic settlement" if "plastic_settlement" in result.peaks else ""
    return Table(f"table-{_slug(result)}-elements", f"Foundation elements, {what}: largest compression{plastic}",
                 ["element", heading("position x", "m", units), *(q.heading(units) for q in elements)], rows)


def _element_quantities(result: AnalysisResult) -> list:
    """The quantities of the foundation elements the result gives a value for."""
    return [q for q in element_quantities() if q.name in result.peaks and result.peaks[q.name].size]


def _element_row(result: AnalysisResult, i: int, x: float, elements: list, units: str) -> list[str]:
    """Element i at position x: its peak of each quantity."""
    return [str(i + 1), show(x, "m", units)] + [show(result.peaks[q.name][i], q.display, units) for q in elements]


def _intermediate_row(name: str, value, units: str) -> list[str]:
    unit, meaning = INTERMEDIATES.get(name, ("", ""))
    kind = intermediate_kind(name, unit)
    return [name, show(value, kind, units), label(kind, units), meaning]


def intermediates_table(result: AnalysisResult, what: str, units: str = "si") -> Table | None:
    """The intermediate values of an engine (quantities.INTERMEDIATES), or None."""
    if not result.intermediates:
        return None
    rows = [_intermediate_row(name, value, units) for name, value in result.intermediates.items()]
    return Table(f"table-{_slug(result)}-intermediates", f"Intermediate values, {what}",
                 ["quantity", "value", "unit", "meaning"], rows)


def _detail_kind(key: str, name: str) -> str:
    """The display kind of a detail entry: its SI unit, lengths in mm (display.py)."""
    unit = detail_unit(key, name)
    return "mm" if unit == "m" else unit


def detail_table(result: AnalysisResult, key: str, caption: str, units: str = "si") -> Table | None:
    """A detail of the history engines (DETAILS: the uplift summary, the energy balance), or None."""
    values = result.details.get(key)
    if not values:
        return None
    rows = [[name, show(value, _detail_kind(key, name), units), label(_detail_kind(key, name), units)]
            for name, value in values.items()]
    return Table(f"table-{_slug(result)}-{key.replace('_', '-')}", caption, ["quantity", "value", "unit"], rows)


def _suite_records(result: AnalysisResult, units: str) -> Table | None:
    """The records table of a suite result, None for a single analysis."""
    return records_table(result, units) if getattr(result, "record_results", ()) else None


def rocking_table(result: AnalysisResult, units: str = "si") -> Table | None:
    """The mat's peak and residual rotation and settlement and, on yielding soil, the yielded
    elements and the plastic work (quantities.ROCKING: the exact engine's uplift runs), or None."""
    entries = rocking_entries(result)
    if not entries:
        return None
    return Table(f"table-{_slug(result)}-rocking", f"Rocking of the mat, {result.engine} engine, {result.support} "
                 "support: rotation and settlement (ASCE 41-17 section 8.4)", list(ROCKING_HEADINGS),
                 rocking_rows(entries, units),
                 "Rotation |theta|; settlement: downward displacement from the rest position under gravity (< 0: "
                 "above it); residual: at the end of the analysis (docs/theory.md 14.7). With a bearing capacity, "
                 "the plastic work is the energy the yielding soil dissipated (14.5).")


def results_section(results: Sequence[AnalysisResult], units: str = "si", checks: Sequence = ()) -> Section:
    blocks: list = [summary_table(results, units)]
    if answer_line(results, checks):  # which number is the design value, which the check (analysis/level.py)
        blocks.append(Text([answer_line(results, checks)]))
    for result in results:
        blocks += result_tables(result, units)
    return Section("results", "Results", blocks)
