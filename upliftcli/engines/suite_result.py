"""The result of a response-history engine on a record suite: every record's AnalysisResult and
the statistics of the peak responses over the records (docs/suites.md, engines on a suite).

    result = suite_result(per_record, records, "mean", rule="asce7-22", rule_label="ASCE 7-22 16.2")
    result.base_shear, result.drift_ratio      # the design value: the statistic the code asks for
    result.statistics["p84"].base_shear        # the other statistics
    result.record_results[3]                   # one record's result

A SuiteResult *is* the AnalysisResult of the design statistic (ASCE 7-22 16.2: the mean; EN 1998-1
4.3.3.4.3: the mean from 7 records, else the maximum; "mean": the mean), so that the writers,
the terminal tables, sweep rows and the deck's [criteria] read it as any result; criteria thus
apply to the design statistic. The statistics are taken value by value over the records, for
every floor, story and element of every quantity of engines/quantities.py; the scalars (V_b,
M_b and their coefficients) are the story-1 values, so they are the statistics of the records'
scalars. Pure numpy; knows nothing of decks or files.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np

from .quantities import COMPARED, compared_values
from .result import AnalysisResult

#: statistic name -> (meaning, function of an array (records, values) along axis 0)
#: a statistic over the records: the values of every record stacked on the first axis -> the statistic
Statistic = Callable[[np.ndarray], Any]
STATISTICS: dict[str, tuple[str, Any]] = {
    "mean": ("mean over the records", lambda a: np.mean(a, axis=0)),
    "median": ("median over the records", lambda a: np.median(a, axis=0)),
    "p84": ("84th percentile over the records (linear between order statistics, numpy's default)",
            lambda a: np.percentile(a, 84.0, axis=0)),
    "max": ("maximum over the records", lambda a: np.max(a, axis=0)),
}
#: numeric details taken value by value like the peaks (the peak base shear of each mode)
STATISTIC_DETAILS = ("modal_base_shear", "cumulative_modal_base_shear")
#: scalar intermediates that are peaks or durations of one record: their statistic is kept
STATISTIC_INTERMEDIATES = ("max_rotation", "max_uplift_left", "max_uplift_right", "uplift_time")
@dataclass(frozen=True)
class SuiteRecord:
    """One record of a suite as analysed: name, source file, amplitude factor [-], provenance,
    SHA-256 of the source file (None when it cannot be read, e.g. a matched record)."""

    name: str
    source: str
    factor: float
    provenance: str = ""
    sha256: str | None = None


@dataclass(frozen=True)
class SuiteResult(AnalysisResult):
    """The design statistic of a suite (the peaks are the statistic `statistic` of the records'
    peaks), with: statistic: 'mean' or 'max' (what the code takes from this many records);
    rule, rule_label: the code rule (motion/code_rules.py); records: SuiteRecord of each record;
    record_results: each record's AnalysisResult; statistics: name -> AnalysisResult of every
    statistic of STATISTICS; simplified: the simplified engine on the target spectrum, same
    support (None if not run or failed; see simplified_ratios); suite: what the suite was
    (scaling, period range [s] and how it was found, target) for the reports; warnings: the
    suite's messages (too few records for the rule, factors ...); record_simplified: the
    simplified engine on each record's own spectrum (same support; empty if not run), which
    separates the suite's excess over the target from the procedure's error (simplified_ratios);
    acceptance: the global acceptance of ASCE 7-22 16.4.1 (analysis/acceptance.Acceptance: a
    yielding building with a [design] table under the exact engine; None otherwise)."""

    statistic: str = "mean"
    rule: str = ""
    rule_label: str = ""
    records: tuple[SuiteRecord, ...] = ()
    record_results: tuple[AnalysisResult, ...] = ()
    statistics: dict[str, AnalysisResult] = field(default_factory=dict)
    simplified: AnalysisResult | None = None
    suite: dict[str, Any] = field(default_factory=dict)
    warnings: tuple[str, ...] = ()
    record_simplified: tuple[AnalysisResult, ...] = ()
    acceptance: Any = None

    @property
    def count(self) -> int:
        """Number of records analysed."""
        return len(self.record_results)

    @property
    def uplift_count(self) -> int:
        """Number of records under which the mat lifts off."""
        return sum(bool(r.uplift) for r in self.record_results)

    @property
    def yielded(self) -> bool | None:
        """Whether the soil yielded under at least one record (None when no record's result tells:
        AnalysisResult.yielded), as `uplift` is whether the mat lifts under at least one."""
        told = [r.yielded for r in self.record_results if r.yielded is not None]
        return any(told) if told else None

    @property
    def label(self) -> str:
        """'exact (mean of 11)': the engine and the design statistic over the records."""
        return f"{self.engine} ({self.statistic} of {self.count})"


def statistic_of(results: Sequence[AnalysisResult], name: str, common: dict[str, Any] | None = None
                 ) -> AnalysisResult:
    """The AnalysisResult whose peaks are the statistic `name` (STATISTICS) of the results'
    peaks, value by value; the results are of one system and support under several records.
    uplift: whether the mat lifts off under at least one record; times (instants of the peaks of
    each record) are dropped; intermediates: those equal for every record (common_intermediates,
    if not given), and the statistic of STATISTIC_INTERMEDIATES; details: the statistic of
    STATISTIC_DETAILS."""
    if not results:
        raise ValueError("a suite statistic needs at least one result")
    function = STATISTICS[name][1]
    first = results[0]
    intermediates = dict(common_intermediates(results) if common is None else common)
    intermediates.update(_statistic_intermediates(results, function))
    return replace(first, elevations=first.elevations.copy(), peaks=_statistic_peaks(results, function),
                   uplift=any(r.uplift for r in results), times={}, intermediates=intermediates,
                   details=_statistic_details(results, function), histories={})


def _statistic_peaks(results: Sequence[AnalysisResult], function: Statistic) -> dict[str, np.ndarray]:
    """The statistic (function over the first axis) of every peak all the results have, value by value."""
    first = results[0]
    return {key: np.asarray(function(np.stack([np.asarray(r.peaks[key], dtype=float) for r in results])), dtype=float)
            for key in first.peaks if all(key in r.peaks for r in results)}


def _statistic_intermediates(results: Sequence[AnalysisResult], function: Statistic) -> dict[str, float]:
    """The statistic of each STATISTIC_INTERMEDIATES that every result gives as a number."""
    out = {}
    for key in STATISTIC_INTERMEDIATES:
        values = [r.intermediates.get(key) for r in results]
        if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
            out[key] = float(function(np.array(values, dtype=float)))
    return out


def _statistic_details(results: Sequence[AnalysisResult], function: Statistic) -> dict[str, list]:
    """The statistic of each STATISTIC_DETAILS that every result gives, with one length."""
    return {key: function(np.array([r.details[key] for r in results], dtype=float)).tolist()
            for key in STATISTIC_DETAILS
            if all(key in r.details for r in results) and len({len(r.details[key]) for r in results}) == 1}


def common_intermediates(results: Sequence[AnalysisResult]) -> dict[str, Any]:
    """The intermediates of the first result that every result has with the same value (the
    model's: n_modes, time_step, criterion ...), in their order."""
    first = results[0].intermediates
    return {key: value for key, value in first.items() if key not in STATISTIC_INTERMEDIATES
            and all(_same(value, r.intermediates.get(key)) for r in results[1:])}


def _same(a: Any, b: Any) -> bool:
    try:
        return bool(np.array_equal(np.asarray(a), np.asarray(b)))
    except (TypeError, ValueError):
        return a == b


def suite_result(results: Sequence[AnalysisResult], records: Sequence[SuiteRecord], statistic: str, *,
                 rule: str = "", rule_label: str = "", simplified: AnalysisResult | None = None,
                 suite: dict[str, Any] | None = None, warnings: Sequence[str] = (),
                 record_simplified: Sequence[AnalysisResult] = ()) -> SuiteResult:
    """The SuiteResult of the records' results (in the order of `records`) with `statistic`
    ('mean' or 'max', from the code rule) as the design value."""
    if len(results) != len(records):
        raise ValueError(f"{len(records)} records but {len(results)} results")
    common = common_intermediates(results)
    statistics = {name: statistic_of(results, name, common) for name in STATISTICS}
    design = statistics[statistic]
    values = {item.name: getattr(design, item.name) for item in fields(AnalysisResult)}
    values = {name: dict(value) if isinstance(value, dict) else value for name, value in values.items()}
    return SuiteResult(**values, statistic=statistic, rule=rule, rule_label=rule_label,
                       records=tuple(records), record_results=tuple(results), statistics=statistics,
                       simplified=simplified, suite=dict(suite or {}), warnings=tuple(warnings),
                       record_simplified=tuple(record_simplified))


def _ratio(a: float, b: float) -> float:
    return a / b if b else float("nan")


def simplified_ratios(result: SuiteResult) -> dict[str, dict[str, float]]:
    """For each value of engines/quantities.COMPARED both give: {simplified, statistic, ratio =
    simplified / statistic} (the simplified engine on the target spectrum against the suite's
    design statistic); empty when the simplified engine was not run. With the simplified engine
    on each record's own spectrum (record_simplified), the ratio is split into two factors whose
    product it is: records = the design statistic of those simplified values; spectrum_ratio =
    simplified / records, the target against the records' own spectra through the procedure
    (below 1: the records are above the target); procedure_ratio = records / statistic, the
    procedure's own error, each record's simplified value against its exact one."""
    if result.simplified is None:
        return {}
    mine, theirs = compared_values(result), compared_values(result.simplified)
    out = {name: {"simplified": theirs[name], "statistic": mine[name], "ratio": _ratio(theirs[name], mine[name])}
           for name in COMPARED if mine.get(name) is not None and theirs.get(name) is not None}
    if len(result.record_simplified) == result.count and result.count:
        _split_ratios(out, result)
    return out


def _split_ratios(out: dict[str, dict[str, float]], result: SuiteResult) -> None:
    """Add records, spectrum_ratio and procedure_ratio (simplified_ratios) to each item of out that every
    record's simplified result gives."""
    function = STATISTICS[result.statistic][1]
    each = [compared_values(r) for r in result.record_simplified]
    for name, item in out.items():
        values = [value.get(name) for value in each]
        if any(value is None for value in values):
            continue
        records = float(function(np.array(values)))
        item.update(records=records, spectrum_ratio=_ratio(item["simplified"], records),
                    procedure_ratio=_ratio(records, item["statistic"]))
