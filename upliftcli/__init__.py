"""uplift: earthquake response of multistory buildings whose foundation mat may lift off
(Yim & Chopra). The command line is upliftcli.cli; the Python API is this package's
`__all__` (docs/api.md has a worked example):

    import upliftcli
    deck = upliftcli.load_deck("inputs/ten_story_elcentro.toml", ["building.period=1.0"])
    results = upliftcli.run(deck)                      # every engine x support of the deck
    upliftcli.to_dict(results, deck)                   # plain dicts, as `--format json`
    upliftcli.to_dataframe(results)                    # pandas, when installed

Decks: load_deck, build_deck (a mapping; numpy arrays accepted), Deck.
Model in code: Building, shear_building, uniform_building, modal_analysis, System, TwoElement,
two_element_from_ratios, Winkler, HalfSpace.
Ground motions: read_record, Record, design_spectrum, response_spectrum.
Engines: run (a deck), analyze (a System), ENGINES, SUPPORTS, SimplifiedOptions, ExactOptions,
AnalysisResult, SuiteResult; run_sweep, SweepTable.
Results: to_dict, to_dataframe, elements_dataframe, write_results, provenance_of.
Figures (matplotlib Figure objects): profile_figure, mode_shape_figure, history_figure,
moment_rotation_figure, spectrum_figure, sweep_figure, and draw (any figures.spec.FigureSpec).
Errors: InputError (bad input, one line naming the field), AnalysisError.

Every name is imported on first use (PEP 562), so that `import upliftcli` and `uplift --help`
load neither numpy nor scipy.
"""

from __future__ import annotations

import importlib
from typing import Any

#: public name -> (module, attribute) it is re-exported from
_EXPORTS: dict[str, tuple[str, str]] = {
    "load_deck": ("deck.load", "load_deck"), "build_deck": ("deck.load", "build_deck"), "Deck": ("deck.load", "Deck"),
    "Building": ("model.building", "Building"), "shear_building": ("model.building", "shear_building"),
    "uniform_building": ("model.building", "uniform_building"), "modal_analysis": ("model.building", "modal_analysis"),
    "System": ("model.system", "System"), "TwoElement": ("model.foundations", "TwoElement"),
    "two_element_from_ratios": ("model.foundations", "two_element_from_ratios"),
    "Winkler": ("model.foundations", "Winkler"), "HalfSpace": ("model.foundations", "HalfSpace"),
    "read_record": ("motion.records", "read_record"), "Record": ("motion.records", "Record"),
    "design_spectrum": ("api", "design_spectrum"), "response_spectrum": ("motion.spectra", "response_spectrum"),
    "run": ("analysis.run", "run"), "analyze": ("api", "analyze"), "ENGINES": ("engines.registry", "ENGINES"),
    "SUPPORTS": ("engines.registry", "SUPPORTS"), "SimplifiedOptions": ("engines.options", "SimplifiedOptions"),
    "ExactOptions": ("engines.options", "ExactOptions"), "AnalysisResult": ("engines.result", "AnalysisResult"),
    "SuiteResult": ("engines.suite_result", "SuiteResult"), "run_sweep": ("api", "run_sweep"),
    "SweepTable": ("api", "SweepTable"), "to_dict": ("api", "to_dict"), "to_dataframe": ("api", "to_dataframe"),
    "elements_dataframe": ("api", "elements_dataframe"), "write_results": ("output", "write_results"),
    "provenance_of": ("provenance.record", "of_deck"), "InputError": ("errors", "InputError"),
    "AnalysisError": ("errors", "AnalysisError"),
    "draw": ("api", "draw"), "profile_figure": ("api", "profile_figure"),
    "mode_shape_figure": ("api", "mode_shape_figure"), "history_figure": ("api", "history_figure"),
    "moment_rotation_figure": ("api", "moment_rotation_figure"), "spectrum_figure": ("api", "spectrum_figure"),
    "sweep_figure": ("api", "sweep_figure"),
}

__all__ = ["__version__", *_EXPORTS]


def __getattr__(name: str) -> Any:
    """The public names, imported when first used; __version__ from the package metadata."""
    if name == "__version__":
        from .runtime.installed import tool_version

        value = tool_version()
    elif name in _EXPORTS:
        module, attribute = _EXPORTS[name]
        value = getattr(importlib.import_module(f".{module}", __name__), attribute)
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})
