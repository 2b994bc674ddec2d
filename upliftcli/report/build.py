"""A calculation report of a run (`uplift report`): the deck and its results in, a Report (data,
report/document.py) and the figure data out; report/html.py turns both into one HTML file."""

from __future__ import annotations

from collections.abc import Sequence

from ..engines.result import AnalysisResult
from ..figures.sets import analysis_figures, motion_label
from .document import Figure, Report, Section, Table, Text
from .inputs import inputs_section, model_section, modes_section, motion_section
from .method import method_section
from .results import accuracy_section, criteria_section, results_section, summary_table, warnings_section

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


def provenance_section(info: dict) -> Section:
    rows = [["tool", f"{info['tool']} {info['version']}"], ["python", info["python"]], ["platform", info["platform"]],
            ["libraries", ", ".join(f"{k} {v}" for k, v in info["libraries"].items())], ["command", info["command"]],
            ["time (UTC)", info["time_utc"]]]
    files = [[f["role"], f["path"], f["sha256"] or "-", "-" if f["bytes"] is None else str(f["bytes"])]
             for f in info["files"]]
    return Section("provenance", "Provenance", [
        Table("table-provenance", "Tool and run", ["item", "value"], rows),
        Table("table-files", "Input files", ["role", "path", "SHA-256", "bytes"], files,
              "Check a file against its SHA-256 with `sha256sum FILE`."),
    ])


def build_report(deck, results: Sequence[AnalysisResult], deck_text: str, overrides: Sequence[str],
                 info: dict, checks: Sequence = ()) -> tuple[Report, dict]:
    """(the Report, its figures: name -> FigureSpec) of a deck's results; info: provenance;
    checks: the accuracy checks (accuracy.check_accuracy)."""
    specs = analysis_figures(deck, results)
    criteria, verdict, code = criteria_section(results, deck.criteria, checks)
    motion = motion_label(deck)
    head = Section("summary", "Summary", [Text([verdict]), _copy(summary_table(results), "table-summary-head")])
    sections = [head, inputs_section(deck, deck_text, overrides), model_section(deck, results),
                motion_section(deck), modes_section(deck), results_section(results)]
    accuracy = accuracy_section(results, checks)
    if accuracy is not None:
        sections.append(accuracy)
    sections += [warnings_section(results, deck, checks), criteria, figures_section(list(specs)),
                 method_section([r.engine for r in results], getattr(deck.analysis.simplified, "procedure", "paper")),
                 provenance_section(info)]
    engines = ", ".join(dict.fromkeys(r.engine for r in results))
    supports = ", ".join(dict.fromkeys(r.support for r in results))
    subtitle = [f"Deck {deck.source}" + (f"; ground motion: {motion}" if motion else ""),
                f"Engines: {engines}; supports: {supports}",
                f"uplift {info['version']}, {info['time_utc']}"]
    return Report(f"Calculation report: {deck.title}", subtitle, sections, verdict, code), specs


def _copy(table: Table, new_id: str) -> Table:
    return Table(new_id, table.caption, table.headers, table.rows, table.note)
