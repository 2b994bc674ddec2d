"""`--plot DIR` of `uplift analyze` and `uplift modes`: check the options before anything runs,
draw the run's figures (upliftcli.figures.sets) and write them atomically as
DIR/<deck stem>.<figure>.<format>."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from ..deck.choices import parse_choices
from ..errors import InputError
from . import stdout

PLOT_HELP = ("Also draw the figures into this directory, as <deck>.<figure>.png: story profiles, mode shapes, "
             "the ground motion's spectra and, for the exact/approximate engines, response histories (paper "
             "Fig. 5 style), base moment against mat rotation and the energy balance.")
#: figure formats (file extensions)
FORMATS = ("png", "svg", "pdf")
FORMAT_HELP = "Figure formats with --plot: png, svg, pdf or all; repeatable or comma list."
HISTORY_ENGINES = ("exact", "approximate")
#: the figures of each history engine's run (figures/sets.analysis_figures)
HISTORY_FIGURES = ("histories", "moment_rotation", "energy")


def history_engines(loaded) -> list[str]:
    """The deck's engines that keep response histories (HISTORY_ENGINES), in its order."""
    return [engine for engine in loaded.analysis.engines if engine in HISTORY_ENGINES]


def not_a_directory(path: Path | None) -> bool:
    """A path that exists and is not a directory (a file in the way)."""
    return path is not None and path.exists() and not path.is_dir()


def error_reason(error: OSError) -> str:
    """Why an OSError happened: its strerror, else the error itself."""
    return error.strerror or str(error)


def check_plot(directory: Path | None, formats: list[str]) -> list[str]:
    """The figure formats, or InputError: --plot must name a directory (it is created)."""
    chosen = parse_choices(formats, FORMATS, "--plot-format")  # as sweep and spectra read it
    if not_a_directory(directory):
        raise InputError("--plot", str(directory), "a directory (a file of that name exists)")
    return chosen or ["png"]


def figure_paths(loaded, directory: Path, stem: str, formats: list[str], modes_only: bool = False) -> list[Path]:
    """Every file the figures of a run may be written to (figures.sets.analysis_figures names
    them from the results: this is the most it may hold), checked before the run."""
    names = ["modes"] if modes_only else _analysis_figures(loaded)
    return [directory / f"{stem}.{name}.{extension}" for name in names for extension in formats]


def _analysis_figures(loaded) -> list[str]:
    """The names of every figure `uplift analyze` may draw for the deck."""
    return ["profiles", "modes", "spectrum", *(f"{kind}_{engine}" for engine in history_engines(loaded)
                                               for kind in HISTORY_FIGURES)]


def check_outputs(paths: list[Path], inputs: list[str], overwrite: bool) -> None:
    """--plot never replaces an input of the run, nor an existing file unless --overwrite."""
    from ..runtime.atomic import refuse_existing, refuse_inputs

    refuse_inputs(paths, inputs, "--plot")
    refuse_existing(paths, "--plot", overwrite)


def keep_histories(loaded):
    """The deck with the history engines keeping their histories (ExactOptions.histories)."""
    if not history_engines(loaded):
        return loaded
    exact = replace(loaded.analysis.exact, histories=True)
    return replace(loaded, analysis=replace(loaded.analysis, exact=exact))


def write_figures(specs: dict, directory: Path, stem: str, formats: list[str]) -> list[Path]:
    """Draw every figure and write it as directory/<stem>.<name>.<format>; report each file."""
    figures = [(spec, directory / f"{stem}.{name}.{extension}") for name, spec in specs.items()
               for extension in formats]
    written = _plot(figures, directory)
    for path in written:
        stdout.echo(f"wrote {path}", err=True)
    return written


def _plot(figures: list, directory: Path) -> list[Path]:
    """Draw and write the figures (figures/draw.plot_figures); a file not written: InputError."""
    from ..figures import draw as plots

    try:
        return plots.plot_figures(figures, "--plot")
    except OSError as error:
        where = error.filename or str(directory)
        raise InputError("--plot", str(where), f"a writable directory ({error_reason(error)})") from None


def analysis_plots(results, loaded, directory: Path, stem: str, formats: list[str], units: str = "si") -> list[Path]:
    """The figures of `uplift analyze` (figures.sets.analysis_figures) in the display units."""
    from ..figures.sets import analysis_figures

    return write_figures(analysis_figures(loaded, results, units), directory, stem, formats)


def modes_plots(loaded, directory: Path, stem: str, formats: list[str], units: str = "si") -> list[Path]:
    """The mode-shape figure of `uplift modes`."""
    from ..figures.sets import modes_figures

    return write_figures(modes_figures(loaded, units), directory, stem, formats)
