"""The Python API's own functions (the rest of `upliftcli.__all__` is re-exported from the
modules that define it): any engine on a model built in code, a sweep in a call, results as
plain dicts or pandas DataFrames. docs/api.md has a worked example.

pandas is optional (not a dependency of uplift): the DataFrame functions import it when they
are called and say how to install it when it is missing.
"""

from __future__ import annotations

import tempfile
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .engines.registry import check_support
from .engines.registry import engine as engine_named
from .engines.result import AnalysisResult


def analyze(system, ground_motion, support: str = "uplift", engine: str = "simplified", options=None
            ) -> AnalysisResult:
    """One engine, one support ("rigid", "bonded" or "uplift") on a model.system.System built in
    code. ground_motion: a motion.records.Record (any engine; the simplified engine takes its
    exact response spectrum), or for the simplified engine any spectrum with .sa(periods [s],
    damping [-]) -> S_a [m/s^2] (design_spectrum). options: engines.options.SimplifiedOptions
    for the simplified engine, ExactOptions for the exact and approximate ones (default: the
    defaults of docs/deck.md). Raises ValueError for an unknown name, InputError or
    AnalysisError as the engines do."""
    chosen = engine_named(engine)
    check_support(support)
    if options is None:
        options = _default_options(chosen)
    return chosen.analyze(system, _motion_for(chosen, engine, ground_motion), support, options)


def _default_options(chosen):
    """The default options of an engine (engines.registry): SimplifiedOptions or ExactOptions."""
    from .engines.options import ExactOptions, SimplifiedOptions

    return SimplifiedOptions() if chosen.options == "simplified" else ExactOptions()


def _motion_for(chosen, engine: str, motion):
    """The ground motion as an engine takes it: a Record for an engine that needs one (else
    ValueError), a record's exact response spectrum (RecordSpectrum) for the simplified engine."""
    from .motion.records import Record

    if chosen.needs_record and not isinstance(motion, Record):
        raise ValueError(f"the {engine} engine needs a record (motion.records.Record), got {type(motion).__name__}")
    if isinstance(motion, Record) and not chosen.needs_record:
        from .motion.spectra import RecordSpectrum

        return RecordSpectrum(motion)
    return motion


def design_spectrum(mapping: dict, source: str = "<mapping>"):
    """A design spectrum from the mapping a deck's ground_motion.design_spectrum takes
    ({type = "asce7", sds, sd1, tl}, "asce7-multiperiod", "ec8", "table": docs/deck.md);
    source: the deck file that table files are relative to."""
    from .motion.design_spectra import from_mapping

    return from_mapping(dict(mapping), source, "design_spectrum")


def to_dict(results: AnalysisResult | Sequence[AnalysisResult], deck=None) -> dict[str, Any]:
    """Plain, JSON-ready dicts (SI units): one result -> its dict (output.result_to_dict); a list
    -> the document `uplift analyze --format json` prints, with the provenance of the run when
    the deck.Deck is given (docs/provenance.md)."""
    from .output import result_to_dict, results_document
    from .provenance.record import of_deck
    from .provenance.values import to_jsonable

    if isinstance(results, AnalysisResult):
        return result_to_dict(results)
    if deck is None:
        return to_jsonable(results_document(list(results)))
    return to_jsonable(results_document(list(results), deck.source, deck.title, of_deck(deck)))


def pandas():
    """The pandas module, or ImportError saying how to install it."""
    try:
        import pandas as module
    except ImportError:
        raise ImportError("pandas is not installed (it is optional): pip install pandas; to_dict and the CSV "
                          "files need nothing") from None
    return module


def _frame(header: list[str], rows: list[list[Any]], units: dict[str, str]):
    frame = pandas().DataFrame(rows, columns=header)
    frame.attrs["units"] = units
    return frame


def to_dataframe(results: AnalysisResult | Sequence[AnalysisResult]):
    """The story table of the results as a pandas DataFrame, one row per (engine, support,
    story), columns as in <deck>.csv (units in the names, also in frame.attrs["units"]); NaN
    where an engine gives no value."""
    from .output import story_table

    header, rows = story_table(_listed(results))
    return _frame(header, rows, _units(header))


def elements_dataframe(results: AnalysisResult | Sequence[AnalysisResult]):
    """The foundation table (one row per engine, support and contact element) as a DataFrame."""
    from .output import elements_table

    header, rows = elements_table(_listed(results))
    return _frame(header, rows, _units(header))


def _listed(results: AnalysisResult | Sequence[AnalysisResult]) -> list[AnalysisResult]:
    """A result, or several, as a list."""
    return [results] if isinstance(results, AnalysisResult) else list(results)


def _units(header: list[str]) -> dict[str, str]:
    """Column -> SI unit of a story or element table (engines/quantities.column_name)."""
    from .engines.quantities import QUANTITIES, column_name

    units = {"elevation_m": "m", "position_m": "m",
             **{column_name(quantity.name, quantity.unit): quantity.unit for quantity in QUANTITIES.values()}}
    return {name: units[name] for name in header if name in units}


@dataclass
class SweepTable:
    """The outcome of run_sweep: the plan (sweep.plan.SweepPlan), one row per case (case_rows;
    `rows` adds each record's row after its case with per_record, as <stem>.csv), the column
    names and their units, the summary (ranges, governing cases, envelope) and the provenance
    (docs/provenance.md)."""

    plan: Any
    case_rows: list[dict]
    columns: list[str]
    units: dict[str, str]
    summary: dict
    provenance: dict = field(default_factory=dict)

    @property
    def rows(self) -> list[dict]:
        """The rows of the tables: each case and, with per_record, its records after it."""
        from .sweep.table import table_rows

        return table_rows(self.plan, self.case_rows)

    def to_dataframe(self):
        """The rows as a pandas DataFrame (columns as in <stem>.csv, units in frame.attrs["units"])."""
        frame = pandas().DataFrame([[row.get(name) for name in self.columns] for row in self.rows],
                                   columns=self.columns)
        frame.attrs["units"] = dict(self.units)
        return frame

    def document(self) -> dict:
        """The JSON document of <stem>.json (rows, units, summary, provenance)."""
        from .sweep.table import document

        return document(self.plan, self.case_rows, self.summary, self.provenance)


def run_sweep(deck: str | Path, vary: Sequence[str] = (), overrides: Sequence[str] = (),
              engines: Sequence[str] = (), supports: Sequence[str] = (), *, workers: int = 1,
              per_record: bool = False, rows_file: str | Path | None = None, resume: bool = False) -> SweepTable:
    """`uplift sweep` in a call: the deck file over the --vary ranges ("foundation.k_f=1e7:1e10:25:log",
    "building.period=0.5,1,2" ...), with the overrides of --set ("analysis.modes=3" ...), engines
    and supports (default: the deck's). workers: 1 runs in this process, more in worker processes.
    rows_file: keep the rows (JSON lines) there, and with resume=True skip the cases it holds;
    default: a temporary file."""
    from .sweep import table
    from .sweep.executors import ProcessExecutor, SerialExecutor
    from .sweep.plan import plan_sweep
    from .sweep.run import run_sweep as drive
    from .sweep.store import RowStore

    plan = plan_sweep(deck, list(overrides), list(vary), list(engines), list(supports), per_record=per_record)
    executor = SerialExecutor() if workers <= 1 else ProcessExecutor(int(workers))
    with tempfile.TemporaryDirectory(prefix="uplift-sweep-") as folder:
        store = RowStore(Path(rows_file) if rows_file is not None else Path(folder) / "rows.jsonl")
        outcome = drive(plan, executor, store, resume=resume and rows_file is not None)
    rows = outcome.rows
    summary = table.summarize(plan, rows)
    return SweepTable(plan, rows, table.columns(plan), table.units(plan), summary, table.sweep_provenance(plan))


# ----------------------------------------------------------------------------- figures

def draw(spec):
    """The matplotlib Figure (Agg canvas, no pyplot state) of a figure description
    (figures/spec.FigureSpec); show it in a notebook as it is, save it with figure.savefig."""
    from .figures.draw import line_figure

    return line_figure(spec)


def profile_figure(results: AnalysisResult | Sequence[AnalysisResult], criteria: dict | None = None):
    """Story profiles of the peak response (displacement, drift ratio, shear, moment, floor
    acceleration against the elevation), every engine and support overlaid; criteria: the
    deck's [criteria] limits drawn as lines."""
    from .figures.analysis import profile_figure as spec

    return draw(spec(_listed(results), criteria))


def mode_shape_figure(system, n_modes: int | None = None):
    """The fixed-base mode shapes of a System with T_n and m_n*/m_t."""
    from .figures.modes import mode_shape_figure as spec

    return draw(spec(system, n_modes))


def history_figure(results: AnalysisResult | Sequence[AnalysisResult]):
    """Response histories (paper Fig. 5 style, the lifted intervals shaded) of results of a
    response-history engine run with ExactOptions(histories=True)."""
    from .figures.histories import history_figure as spec

    return draw(spec(_listed(results)))


def moment_rotation_figure(results: AnalysisResult | Sequence[AnalysisResult]):
    """Base moment M_b against the mat rotation, with +-M_c, of results with histories."""
    from .figures.histories import moment_rotation_figure as spec

    return draw(spec(_listed(results)))


def spectrum_figure(record, periods=None, dampings: Sequence[float] = (0.05,)):
    """S_d, S_v and S_a of a Record (its exact spectra at periods [s], default 100 log-spaced
    from 0.05 to 5 s, and the damping ratios) or of a spectra.Spectrum already computed."""
    import numpy as np

    from .figures.spectra import record_spectrum_figure
    from .motion.spectra import response_spectrum

    if hasattr(record, "acceleration"):
        grid = np.geomspace(0.05, 5.0, 100) if periods is None else np.asarray(periods, dtype=float)
        spectrum, title = response_spectrum(record.acceleration, record.dt, grid, list(dampings)), record.name
    else:
        spectrum, title = record, ""
    return draw(record_spectrum_figure(spectrum, title))


def sweep_figure(sweep: SweepTable):
    """The responses of a sweep (run_sweep) against its first numeric varied field."""
    from .sweep.figures import plan_motion_label
    from .sweep.figures import sweep_figure as spec

    return draw(spec(sweep.plan, sweep.case_rows, plan_motion_label(sweep.plan)))
