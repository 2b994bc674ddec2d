"""Every file an analysis writes: the results document (JSON), the story and foundation tables
(CSV) and the resolved deck (<stem>.deck.toml, a deck that repeats the run); the response
histories (CSV or NPZ): histories.py. Each file is written atomically (upliftcli.runtime.atomic): never half-written.
SI units in every file, or US customary units under --units us (display.file_unit); the units are
listed in it. Every result file carries the provenance of
the run (provenance/record.py): the JSON under "provenance", each CSV table in two leading '#' lines
(pandas.read_csv(path, comment="#") reads the table). Numbers are written with at most 15
significant digits (provenance/values.DIGITS), as the shortest text of that value: 15.3, not
15.299999999999999. The quantities and their units: engines/quantities.py. A record suite's
result (engines/suite_result.SuiteResult) is written as its design statistic, with a `suite`
object in the JSON (records, factors, each record's result, the statistics, the simplified
engine beside it) and, in the CSV tables, a row per record after the statistic's rows.
"""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path
from typing import Any

import numpy as np

from .analysis.level import answer_line
from .display import file_unit, in_file_units, intermediate_kind
from .engines.design import DESIGN_UNITS, design_scalars
from .engines.quantities import (
    COMPARED,
    DESIGN,
    FLOOR,
    INTERMEDIATES,
    QUANTITIES,
    ROCKING,
    SCALARS,
    STORY,
    YIELDING,
    column_name,
    element_quantities,
    file_column,
    file_kind,
    quantities,
    rocking_entries,
)
from .engines.result import AnalysisResult
from .engines.suite_result import STATISTICS, SuiteResult, simplified_ratios
from .provenance.record import csv_comments, deck_toml, of_deck
from .provenance.values import number_text, to_jsonable, to_text_numbers
from .runtime.atomic import write_set

#: units of the result fields in the written files (SI)
UNITS = {
    "elevation": "m", "position": "m", **{q.name: q.unit for q in QUANTITIES.values()},
    **{q.name: q.unit for q in ROCKING.values()},
    **{s.name: s.unit for s in SCALARS.values()}, "critical_base_shear": "N", "critical_base_moment": "N m",
    "weight": "N", "effective_height": "m", "periods": "s", "critical_coefficient": "-", "times": "s",
    "factor": "-", "period_range": "s", **{c.name: c.unit for c in COMPARED.values()},
    "intermediates": {name: unit for name, (unit, _) in INTERMEDIATES.items()},
}
_STORY_QUANTITIES = quantities(FLOOR, STORY)
#: the yielding stories' quantities (quantities.YIELDING, 15.5) in a story table that has them; story_yielded is
#: each story's `yielded` (true/false in the JSON, 1/0 in the CSV)
_YIELDING_STORY = [q for q in YIELDING.values() if q.where == STORY]
_DESIGN_STORY = [q for q in DESIGN.values() if q.where == STORY]  # with [design] (engines/design.py)
#: quantity -> its key in the story tables where it differs from its name
STORY_KEYS = {"story_yielded": "yielded"}
#: units of the yielding-story outputs, listed in a document whose results carry them (file_units)
YIELDING_UNITS = {**{STORY_KEYS.get(q.name, q.name): q.unit for q in YIELDING.values()}, "building_yielded": "-"}


def file_units(system: str = "si", yielding: bool = False, design: bool = False) -> dict:
    """UNITS (and YIELDING_UNITS for a yielding building's results, DESIGN_UNITS for results with design
    values) as the units of a file in a unit system: {name: display.Unit}, the intermediates nested."""
    listed = {**UNITS, **(YIELDING_UNITS if yielding else {}), **(DESIGN_UNITS if design else {})}
    plain = {name: unit for name, unit in listed.items() if isinstance(unit, str)}
    return {**{name: file_unit(unit, file_kind(name), system) for name, unit in plain.items()},
            "intermediates": {name: file_unit(unit, intermediate_kind(name, unit), system)
                              for name, unit in UNITS["intermediates"].items()}}


def _labels(units: dict) -> dict:
    """The unit labels of file_units (the JSON's units entry)."""
    return {name: _labels(u) if isinstance(u, dict) else u.label for name, u in units.items()}


def _columns(result: AnalysisResult, where: list) -> list[tuple[str, Any]]:
    """(key, values per place) of each quantity of `where` the result has: its peaks, then its
    instants ('<name>_time') when known."""
    columns = []
    for q in where:
        if q.name in result.peaks:
            columns.append((STORY_KEYS.get(q.name, q.name), _story_values(q, result.peaks[q.name])))
            if q.name in result.times and q.name not in YIELDING:  # a yielding story's: the end, not a peak's
                columns.append((f"{q.name}_time", result.times[q.name]))
    return columns


def _story_values(q, values):
    return values.astype(bool) if q.name in STORY_KEYS else values  # story_yielded as booleans in the JSON


def _places(result: AnalysisResult, where: list, index: str, position: str, positions) -> list[dict[str, Any]]:
    """One dict per story or element: its number (from 1), its position [m], then each quantity's
    peak and instant (_columns)."""
    columns = _columns(result, where)
    return [{index: j + 1, position: x, **{key: values[j] for key, values in columns}} for j, x in enumerate(positions)]


def _scalars(result: AnalysisResult) -> dict[str, Any]:
    """Engine, support, the scalar results (SI units, see UNITS) and the verdicts (`yielded` only
    where the result tells)."""
    return {
        "engine": result.engine,
        "support": result.support,
        **{name: getattr(result, name) for name in SCALARS},
        "critical_base_shear": result.critical_base_shear,
        "critical_base_moment": result.critical_base_moment,
        "critical_coefficient": result.critical_coefficient,
        "weight": result.weight,
        "effective_height": result.effective_height,
        "uplift": result.uplift,
        **({"yielded": result.yielded} if result.yielded is not None else {}),
        **_building_verdict(result), **design_scalars(result),
    }


def _building_verdict(result: AnalysisResult) -> dict[str, Any]:
    """A building with story strengths (quantities.YIELDING): `building_yielded` (whether a story yielded; the
    soil's is `yielded`), `yielded_stories` and `base_shear_strength` [N]; {} for an elastic building."""
    if result.building_yielded is None:
        return {}
    return {"building_yielded": result.building_yielded,
            "yielded_stories": YIELDING["yielded_stories"].typed(result.value("yielded_stories")),
            "base_shear_strength": float(result.peaks["base_shear_strength"][0])}


def _notes(result: AnalysisResult, check) -> dict[str, Any]:
    """The result's warnings (and, given its accuracy check, the check's warnings after them and
    the check as `accuracy`), then the engine's other details."""
    warnings = list(result.details.get("warnings", []))
    details = {k: v for k, v in result.details.items() if k not in ("warnings", "level")}
    level = {"level": result.details["level"]} if "level" in result.details else {}  # analysis/level.py
    if check is None:
        return {**level, "warnings": warnings, "details": details}
    return {**level, "warnings": [*warnings, *check.warnings()], "accuracy": check.to_dict(), "details": details}


def result_to_dict(result: AnalysisResult, check=None) -> dict[str, Any]:
    """JSON-ready summary, story table and foundation table of one result (SI units, see UNITS),
    its warnings and, given its accuracy.Check (the simplified engine against the exact one), its
    `accuracy` (the check's warnings joined to the result's); a suite's result also has `suite`
    (suite_to_dict)."""
    return to_jsonable({
        **_scalars(result),
        "periods": result.periods,
        "stories": _places(result, _STORY_QUANTITIES + _YIELDING_STORY + _DESIGN_STORY, "story", "elevation",
                           result.elevations),
        "elements": _places(result, element_quantities(), "element", "position", result.element_positions),
        **({"rocking": rocking} if (rocking := rocking_to_dict(result)) else {}),
        "intermediates": result.intermediates,
        **_notes(result, check),
        **({"suite": suite_to_dict(result)} if isinstance(result, SuiteResult) else {}),
    })


def rocking_to_dict(result: AnalysisResult) -> dict[str, Any]:
    """The `rocking` object of a result that carries the rocking quantities (quantities.ROCKING:
    the exact engine's uplift runs): each mat quantity's value and `<name>_time` [s]; a quantity
    of the left edge, the centre and the right edge as {"left_edge", "centre", "right_edge"}
    (SI units, see UNITS). {} without them."""
    out: dict[str, Any] = {}
    for q, key, _, value, instant in rocking_entries(result):
        for name, number in ((q.name, value), (f"{q.name}_time", instant)):
            if number is None:
                continue
            if key == "mat":
                out[name] = number
            else:
                out.setdefault(name, {})[key] = number
    return out


def _suite_statistics(result: SuiteResult) -> dict[str, Any]:
    """Each statistic's uplift verdict, scalars, stories and elements (result_to_dict)."""
    picked = ("uplift", *SCALARS, "stories", "elements", "building_yielded", "base_shear_strength")
    return {name: {key: value for key, value in result_to_dict(stat).items() if key in picked}
            for name, stat in result.statistics.items()}


def _suite_simplified(result: SuiteResult) -> dict[str, Any] | None:
    """The simplified engine on the target spectrum, with the ratios simplified / design statistic
    (None without it)."""
    if result.simplified is None:
        return None
    return {"engine": result.simplified.engine, "support": result.simplified.support,
            "compared": simplified_ratios(result), "warnings": list(result.simplified.details.get("warnings", []))}


def _suite_records(result: SuiteResult) -> list[dict[str, Any]]:
    """Each record of a suite: name, source, provenance, SHA-256 of its file, amplitude factor, its result."""
    return [{"record": k + 1, "name": info.name, "source": info.source, "provenance": info.provenance,
             "sha256": info.sha256, "factor": info.factor, "result": result_to_dict(record)}
            for k, (info, record) in enumerate(zip(result.records, result.record_results, strict=True))]


def suite_to_dict(result: SuiteResult) -> dict[str, Any]:
    """The `suite` object of a suite's result: the rule and its design statistic, the count, what
    the suite was, every statistic (scalars, stories, elements), the simplified engine on the
    target spectrum with the ratios simplified / design statistic, and each record (name, source,
    provenance, SHA-256 of its file, amplitude factor, its result)."""
    return to_jsonable({
        "rule": result.rule, "rule_label": result.rule_label, "statistic": result.statistic, "count": result.count,
        "uplift_records": result.uplift_count, **result.suite, "warnings": list(result.warnings),
        "statistic_meanings": {name: meaning for name, (meaning, _) in STATISTICS.items()},
        "statistics": _suite_statistics(result), "simplified": _suite_simplified(result),
        "records": _suite_records(result),
        **({} if result.acceptance is None else {"acceptance": result.acceptance.to_dict()}),  # ASCE 7-22 16.4.1
    })


def check_of(result: AnalysisResult, checks) -> Any:
    """The accuracy.Check of a simplified result among `checks` (None if it has none)."""
    if result.engine != "simplified":
        return None
    return next((c for c in checks if c.support == result.support), None)


def results_document(results: list[AnalysisResult], source: str | None = None, title: str | None = None,
                     provenance: dict | None = None, checks=(), system: str = "si") -> dict[str, Any]:
    """The document `--format json` prints: one result -> that result's dict (plus source,
    title, units and the provenance of the run); several -> {"source", "title", "units",
    "provenance", "results": [...]}; checks: the accuracy checks (accuracy.check_accuracy);
    system: the units of its values (file_units)."""
    units = file_units(system, any(r.building_yielded is not None for r in results), any(map(design_scalars, results)))
    head = {"source": source, "title": title, "units": _labels(units), "provenance": provenance,
            "answer": answer_line(results, checks) or None}  # the design value and the check (analysis/level.py)
    head = {k: v for k, v in head.items() if v is not None}
    if len(results) == 1:
        body = result_to_dict(results[0], check_of(results[0], checks))
    else:
        body = {"results": [result_to_dict(result, check_of(result, checks)) for result in results]}
    return {**head, **(in_file_units(body, units) if system != "si" else body)}


def dumps(document: Any) -> str:  # JSON text of a document, numbers with at most 15 significant digits
    return json.dumps(to_text_numbers(to_jsonable(document)), indent=2, allow_nan=False) + "\n"


def to_json(results: list[AnalysisResult], source: str | None = None, title: str | None = None,
            provenance: dict | None = None, checks=(), system: str = "si") -> str:
    return dumps(results_document(results, source, title, provenance, checks, system))


def _csv(header: list[str], rows: list[list[Any]], provenance: dict | None = None) -> str:
    """A table as CSV text, after the provenance's '#' lines if given; floats as number_text."""
    buffer = io.StringIO()
    buffer.write(csv_comments(provenance))
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(header)
    writer.writerows([number_text(v) if isinstance(v, float) else v for v in row] for row in rows)
    return buffer.getvalue()


def _labelled(results: list[AnalysisResult]) -> tuple[list[str], list[tuple[list[str], AnalysisResult]]]:
    """(leading columns, [(their values, result)]): engine and support; with a suite's result
    also `statistic` (the design statistic on its rows, empty on a record's) and `record` (the
    record's name on the rows of each record that follow the statistic's: _suite_labelled)."""
    if not any(isinstance(r, SuiteResult) for r in results):
        return ["engine", "support"], [([r.engine, r.support], r) for r in results]
    return ["engine", "support", "statistic", "record"], [item for r in results for item in _suite_labelled(r)]


def _suite_labelled(r: AnalysisResult) -> list[tuple[list[str], AnalysisResult]]:
    """The labelled results of one result among a suite's: a suite's design statistic, then each
    of its records; another result alone, with neither."""
    if not isinstance(r, SuiteResult):
        return [([r.engine, r.support, "", ""], r)]
    return [([r.engine, r.support, r.statistic, ""], r),
            *(([r.engine, r.support, "", info.name], record)
              for info, record in zip(r.records, r.record_results, strict=True))]


def _peaks_at(r: AnalysisResult, chosen: list, k: int, factors: list[float]) -> list[float]:
    """The peaks of the quantities chosen at place k (times their factors), NaN where the result has none."""
    return [q.typed(float(r.peaks[q.name][k]) * f) if q.name in r.peaks else np.nan
            for q, f in zip(chosen, factors, strict=True)]


def _table(results: list[AnalysisResult], chosen, index: str, position: str, positions,
           system: str = "si") -> tuple[list[str], list]:
    """(header, rows): one row per (engine, support, place), the places' positions from
    `positions(result)`, a column per quantity of `chosen` that some result has (in `system`: file_column)."""
    present = [q for q in chosen if any(q.name in r.peaks for r in results)]
    lead, labelled = _labelled(results)
    (position, scale), *columns = [file_column(position, "m", "m", system),
                                   *(file_column(STORY_KEYS.get(q.name, q.name), q.unit, q.display, system)
                                     for q in present)]
    factors = [factor for _, factor in columns]
    rows = [[*labels, k + 1, float(x) * scale, *_peaks_at(r, present, k, factors)]
            for labels, r in labelled for k, x in enumerate(positions(r))]
    return [*lead, index, position, *(name for name, _ in columns)], rows


def story_table(results: list[AnalysisResult], system: str = "si") -> tuple[list[str], list[list[Any]]]:
    """(header, rows) of the story tables of all results, one row per (engine, support, story);
    units in the headers (floor quantities of floor j on story j's row); a suite's records after
    its statistic (_labelled); numbers as floats (NaN: no value)."""
    return _table(results, _STORY_QUANTITIES + _YIELDING_STORY + _DESIGN_STORY, "story", "elevation",
                  lambda r: r.elevations, system)


def elements_table(results: list[AnalysisResult], system: str = "si") -> tuple[list[str], list[list[Any]]]:
    """(header, rows) of the foundation tables: one row per (engine, support, contact element),
    left to right (a suite's records after its statistic, as story_table)."""
    return _table(results, element_quantities(), "element", "position", lambda r: r.element_positions, system)


def to_csv(results: list[AnalysisResult], provenance: dict | None = None, system: str = "si") -> str:
    """The story tables (story_table) as CSV, after the provenance's '#' lines if given."""
    return _csv(*story_table(results, system), provenance)


def elements_csv(results: list[AnalysisResult], provenance: dict | None = None, system: str = "si") -> str:
    """The foundation tables (elements_table) as CSV, after the provenance's '#' lines if given."""
    return _csv(*elements_table(results, system), provenance)


def _rocking_values(r: AnalysisResult, system: str = "si") -> dict[str, float]:
    """A result's rocking columns (column name with unit -> value): each value and the instant of a
    peak (a residual's instant is the end: none); {} when it carries no rocking quantity."""
    values: dict[str, float] = {}
    for q, key, _, value, instant in rocking_entries(r):
        name = q.name if key == "mat" else f"{q.name}_{key}"
        column, factor = file_column(name, q.unit, q.display, system)
        values[column] = value * factor if factor != 1.0 else value  # a count stays an integer
        if instant is not None and not q.name.startswith("residual"):
            values[column_name(f"{name}_time", "s")] = instant
    return values


def rocking_table(results: list[AnalysisResult], system: str = "si") -> tuple[list[str], list[list[Any]]]:
    """(header, rows) of the rocking tables: one row per result that carries the rocking
    quantities (quantities.ROCKING: the exact engine's uplift runs), a column per value and its
    instant, units in the headers (rotation_rad, settlement_left_edge_m, settlement_left_edge_time_s,
    plastic_work_J); ([], []) when no result carries them."""
    lead, labelled = _labelled(results)
    rows = [(labels, values) for labels, r in labelled if (values := _rocking_values(r, system))]
    if not rows:
        return [], []
    columns = dict.fromkeys(name for _, values in rows for name in values)
    return [*lead, *columns], [[*labels, *(values.get(c, np.nan) for c in columns)] for labels, values in rows]


def rocking_csv(results: list[AnalysisResult], provenance: dict | None = None, system: str = "si") -> str:
    """The rocking tables (rocking_table) as CSV, after the provenance's '#' lines if given."""
    return _csv(*rocking_table(results, system), provenance)


def result_paths(directory, stem: str, elements: bool = True, deck: bool = True, rocking: bool = False) -> list[Path]:
    """The files write_results writes into directory for `stem`."""
    names = [".json", ".csv"] + [".elements.csv"] * elements + [".rocking.csv"] * rocking + [".deck.toml"] * deck
    return [Path(directory) / f"{stem}{suffix}" for suffix in names]


def _given_or_deck(deck, source: str | None, title: str | None, provenance: dict | None) -> tuple:
    """(source, title, provenance) of write_results: those of the deck where not given."""
    if deck is None:
        return source, title, provenance
    return (deck.source if source is None else source, deck.title if title is None else title,
            of_deck(deck) if provenance is None else provenance)


def _tables(results: list[AnalysisResult], provenance: dict | None, elements: bool, rocking: bool,
            system: str) -> list[str]:
    """The CSV texts of write_results: the story tables, then the foundation and the rocking tables when asked."""
    return [to_csv(results, provenance, system), *[elements_csv(results, provenance, system)] * elements,
            *[rocking_csv(results, provenance, system)] * rocking]


def write_results(results: list[AnalysisResult], directory, stem: str, source: str | None = None,
                  title: str | None = None, *, deck=None, provenance: dict | None = None, checks=(),
                  system: str = "si") -> list:
    """Write <stem>.json, <stem>.csv (stories), <stem>.elements.csv (foundation elements, when
    a flexible support was analysed), <stem>.rocking.csv (the mat's rotation and settlement, when
    a result carries them: rocking_table) and, given the deck.Deck, <stem>.deck.toml (the resolved
    deck: `uplift analyze` on it repeats the run) into directory, each atomically; return the
    paths. The provenance (default: provenance.of_deck of the deck) goes into every file. All
    texts are built before the first file is written, and the files are written all or none
    (atomic.write_set), so a failure (a full disk) leaves no file of the set. system: the units
    of the JSON and CSV files (file_units; the resolved deck is SI)."""
    source, title, provenance = _given_or_deck(deck, source, title, provenance)
    elements = any(r.element_positions.size for r in results)
    rocking = any(rocking_entries(r) for r in results)
    paths = result_paths(directory, stem, elements, deck is not None, rocking)
    texts = [to_json(results, source, title, provenance, checks, system),
             *_tables(results, provenance, elements, rocking, system)]
    if deck is not None:
        texts.append(deck_toml(deck, provenance, directory))
    write_set(dict(zip(paths, texts, strict=True)))  # all or none: a full disk leaves no file of the set
    return paths
