"""A calculation report of a run (`uplift report`): the deck and its results in, a Report (data,
report/document.py) and the figure data out; report/html.py turns both into one HTML file."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence

from ..engines.result import AnalysisResult
from ..figures.sets import analysis_figures, motion_label
from .acceptance import acceptance_section, with_acceptance
from .checks import accuracy_section, criteria_section, warnings_section
from .document import PROJECT_FIELDS, Figure, Report, Section, SignOff, Table, Text
from .inputs import inputs_section, model_section, modes_section, motion_section
from .method import method_section
from .provenance import relative_path
from .results import results_section, summary_table

#: --units -> the words of the report's subtitle
UNIT_NAMES = {"si": "SI (kN, kN m, mm, m, g)", "us": "US (kip, kip ft, in, ft, g)"}
#: figure name (or its prefix before "_<engine>") -> caption
CAPTIONS = {
    "profiles": "Peak response over the height: floor displacement, story drift ratio (with the [criteria] limit), "
                "story shear, overturning moment and floor acceleration; supports by colour, engines by line style.",
    "modes": "Fixed-base mode shapes with their periods T_n and effective mass ratios m_n*/m_t [9].",
    "spectrum": "Response spectra of the ground motion at the building's damping, with T_1 (and T1bar) marked.",
    "histories": "Response histories in the style of the paper's Fig. 5: base shear [14a], base moment [14b] with "
                 "+-M_c [16b], mat rotation and edge displacements; shaded: an edge of the mat lifted.",
    "moment_rotation": "Base moment against mat rotation, with +-M_c = m_t g b [16b].",
    "energy": "Energy balance: input work = dissipated energy + change of stored energy + residual.",
    "hysteresis": "Story shear against story drift of each story that yields (bilinear story springs, docs/theory.md "
                  "15.5).",
}


def caption(name: str) -> str:
    """The caption of a figure of figures/sets.analysis_figures ('histories_exact' ...)."""
    if name in CAPTIONS:
        return CAPTIONS[name]
    base, _, engine = name.rpartition("_")
    return f"{CAPTIONS.get(base, name)} ({engine} engine)"


def figures_section(names: Sequence[str]) -> Section:
    blocks = [Figure(f"figure-{name.replace('_', '-')}", f"Figure {k + 1}. {caption(name)}", name)
              for k, name in enumerate(names)]
    return Section("figures", "Figures", blocks)


def provenance_section(info: dict, folder: str | None = None) -> Section:
    """Tool and run, and every input file with its SHA-256 (paths relative to `folder`, the
    deck's, when given: no absolute path in the report)."""
    rows = [["tool", f"{info['tool']} {info['version']}"], ["python", info["python"]], ["platform", info["platform"]],
            ["libraries", ", ".join(f"{k} {v}" for k, v in info["libraries"].items())], ["command", info["command"]],
            ["time (UTC)", info["time_utc"]]]
    files = [_file_row(f, folder) for f in info["files"]]
    return Section("provenance", "Provenance", [
        Table("table-provenance", "Tool and run", ["item", "value"], rows),
        Table("table-files", "Input files" + (" (paths relative to the deck's folder)" if folder else ""),
              ["role", "path", "SHA-256", "bytes"], files, "Check a file against its SHA-256 with `sha256sum FILE`."),
    ])


def _file_row(entry: dict, folder: str | None) -> list[str]:
    """Role, path, SHA-256 and size of an input file ("-" where unknown)."""
    return [entry["role"], relative_path(entry["path"], folder), entry["sha256"] or "-",
            "-" if entry["bytes"] is None else str(entry["bytes"])]


def project_fields(deck, given: Mapping[str, str] | None = None) -> dict[str, str]:
    """The deck's [project] fields, replaced by those given (uplift report --project ...), in
    the order of document.PROJECT_FIELDS; empty ones left out."""
    found = {**getattr(deck, "values", {}).get("project", {}), **_given_fields(given)}
    return {name: str(found[name]) for name in PROJECT_FIELDS if found.get(name)}


def _given_fields(given: Mapping[str, str] | None) -> dict[str, str]:
    """The fields given with a value."""
    return {k: v for k, v in (given or {}).items() if v}


def build_report(deck, results: Sequence[AnalysisResult], deck_text: str, overrides: Sequence[str],
                 info: dict, units: str = "si", project: Mapping[str, str] | None = None, checks: Sequence = ()
                 ) -> tuple[Report, dict]:
    """(the Report, its figures: name -> FigureSpec) of a deck's results in the display units
    (display.py); info: provenance; project: [project] fields that replace the deck's; checks: the
    accuracy checks (accuracy.check_accuracy)."""
    specs = analysis_figures(deck, results, units)
    criteria, verdict, code = criteria_section(results, deck.criteria, units, checks)
    verdict, code = with_acceptance(results, verdict, code)
    fields = project_fields(deck, project)
    sections = [summary_section(results, verdict, fields, units), inputs_section(deck, deck_text, overrides, units),
                model_section(deck, results, units), motion_section(deck), modes_section(deck, units),
                results_section(results, units, checks), accuracy_section(results, units, checks),
                warnings_section(results, deck, checks), criteria, acceptance_section(results),
                figures_section(list(specs)),
                method_section([r.engine for r in results], getattr(deck.analysis.simplified, "procedure", "paper")),
                provenance_section(info, os.path.dirname(os.path.abspath(deck.source)))]
    return Report(f"Calculation report: {deck.title}", subtitle(deck, results, info, units),
                  [section for section in sections if section is not None], verdict, code, fields, deck.title,
                  info["time_utc"][:10], f"uplift {info['version']}"), specs


def summary_section(results: Sequence[AnalysisResult], verdict: str, fields: Mapping[str, str],
                    units: str = "si") -> Section:
    """The verdict, the summary table and the sign-off block (prepared and checked by)."""
    signoff = SignOff([("Prepared by", fields.get("engineer", "")), ("Checked by", fields.get("checker", ""))])
    return Section("summary", "Summary", [Text([verdict]), _copy(summary_table(results, units), "table-summary-head"),
                                          signoff])


def subtitle(deck, results: Sequence[AnalysisResult], info: dict, units: str = "si") -> list[str]:
    """The lines under the title: the deck and its ground motion; engines, supports and units; the tool and time."""
    motion = motion_label(deck)
    engines = ", ".join(dict.fromkeys(r.engine for r in results))
    supports = ", ".join(dict.fromkeys(r.support for r in results))
    return [f"Deck {os.path.basename(deck.source)}" + (f"; ground motion: {motion}" if motion else ""),
            f"Engines: {engines}; supports: {supports}; units: {UNIT_NAMES[units]}",
            f"uplift {info['version']}, {info['time_utc']}"]


def _copy(table: Table, new_id: str) -> Table:
    return Table(new_id, table.caption, table.headers, table.rows, table.note)
