"""Drawing of figure data (figures/spec.FigureSpec: sweeps, the paper's spectra over T_1, story
profiles, mode shapes, histories, energy, record spectra) with matplotlib: the Agg canvas, no
pyplot state, matplotlib imported only when a figure is drawn.

One look everywhere: the colour-blind-safe palette of figures/style.py, the legend below the
panels (outside the data), plain tick labels on log axes (0.1, 0.2, 0.5, 1, 2 ...). The
layout is computed from fixed margins [in] (figures/layout.py), each panel drawn in named steps
(figures/panels.py). Every file is written atomically (upliftcli.runtime.atomic); the format
follows the file extension.
"""

from __future__ import annotations

import io
import os
import pickle
import sys
import threading
from collections.abc import Sequence
from pathlib import Path

from ..errors import InputError
from ..runtime.atomic import TEMP_MARK, atomic_path, write_bytes, write_set
from .layout import PAD, Layout, layout
from .panels import draw_panel, legend_handles
from .spec import Bars, FigureSpec, Line, Panel, Series, Span  # noqa: F401  (the figure data types)

FIGURE_FORMATS = (".png", ".pdf", ".svg")
DPI = 150
#: zlib level of the PNG files: 3 encodes the three figures of `uplift spectra` in two thirds of the CPU
#: time of Pillow's default 6, the files 6 % larger
PNG_COMPRESSION = 3
#: whether plot_figures shares figures out to forked copies of this process: on Linux only (no
#: fork on Windows; macOS's system libraries may not survive one); elsewhere one after the other
FORK_FIGURES = hasattr(os, "fork") and sys.platform.startswith("linux")


def check_figure_path(path: str | os.PathLike, option: str = "--plot") -> Path:
    """The figure path, or InputError if its extension is not a supported format."""
    path = Path(path)
    if path.suffix.lower() not in FIGURE_FORMATS:
        raise InputError(option, str(path), f"a file name ending {', '.join(FIGURE_FORMATS)}")
    return path


#: the thread importing matplotlib for preload(background=True), until a figure is drawn
_preloading: threading.Thread | None = None


def preload(background: bool = False) -> None:
    """Import what drawing a figure needs (matplotlib's Figure, Agg canvas, tickers): about 0.3 s
    that a caller can spend while other processes work. background: in a thread, for a caller
    whose main thread then only waits on worker processes (the drawing functions wait for it)."""
    global _preloading
    if not background:
        _wait_for_preload()
        _import_matplotlib()
    elif _preloading is None:
        _preloading = threading.Thread(target=_import_matplotlib, name="uplift-preload", daemon=True)
        _preloading.start()


def _import_matplotlib() -> None:
    import matplotlib.backends.backend_agg
    import matplotlib.figure
    import matplotlib.ticker  # noqa: F401


def _wait_for_preload() -> None:
    global _preloading
    if _preloading is not None:
        _preloading.join()
        _preloading = None


def new_figure(width: float = 7.0, height: float = 4.5):
    """A matplotlib Figure with the Agg canvas (no GUI, no global pyplot state)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(width, height))
    FigureCanvasAgg(figure)
    return figure


def save_options(file_format: str) -> dict:
    """savefig's keywords for a file format beyond format and dpi: PNG_COMPRESSION for png."""
    return {"pil_kwargs": {"compress_level": PNG_COMPRESSION}} if file_format == "png" else {}


def save_figure(figure, path: str | os.PathLike, option: str = "--plot") -> Path:
    """Write the figure atomically; the format follows the extension."""
    path = check_figure_path(path, option)
    file_format = path.suffix.lower().lstrip(".")
    with atomic_path(path) as tmp:
        figure.savefig(tmp, format=file_format, dpi=DPI, **save_options(file_format))
    return path


def figure_data(spec: FigureSpec, path: str | os.PathLike, option: str = "--plot") -> bytes:
    """A FigureSpec drawn into the bytes of the file `path` names (the format follows its extension)."""
    file_format = check_figure_path(path, option).suffix.lower().lstrip(".")
    buffer = io.BytesIO()
    line_figure(spec).savefig(buffer, format=file_format, dpi=DPI, **save_options(file_format))
    return buffer.getvalue()


def plot_figure(spec: FigureSpec, path: str | os.PathLike, option: str = "--plot") -> Path:
    """Draw a FigureSpec and write it atomically."""
    data = figure_data(spec, path, option)
    write_bytes(path, data)
    return Path(path)


def plot_figures(figures: Sequence[tuple[FigureSpec, str | os.PathLike]], option: str = "--plot") -> list[Path]:
    """Draw several figures (figure_data each) and write them all or none (atomic.write_set: a
    full disk at the last one leaves none behind, issue 38); their paths in the order given.

    Drawing is Python (threads would not help), so on Linux, when this process runs no other
    thread, the figures are shared out between it and forked copies of it, one per core, that
    start with matplotlib imported and the figure data in memory and send back the bytes of
    their figures (the three figures of `uplift spectra` in 0.45 s instead of 0.85 s on two
    cores; elsewhere, FORK_FIGURES, one after the other). An error in any figure is raised
    here, after every copy has ended, and nothing is written."""
    paths = [check_figure_path(path, option) for _, path in figures]
    _wait_for_preload()
    from ..runtime.process import available_cores

    groups = _shares(figures, min(available_cores(), len(figures)))
    if _can_share(groups):
        preload()
        for stream in (sys.stdout, sys.stderr):  # nothing buffered is written twice
            stream.flush()
        drawn = _draw_shared(groups, option)
    else:
        drawn = _draw_all(figures, option)
    _write_all(drawn, paths)
    return paths


def _write_all(drawn: dict[str, bytes], paths: list[Path]) -> None:
    """Write the figures' bytes (drawn: by path) all or none, in the order of paths; an OSError
    names the figure it failed on (not its temporary file)."""
    try:
        write_set({path: drawn[str(path)] for path in paths})
    except OSError as error:
        if error.filename is None:  # a write to a full disk names no file: the caller names the folder
            raise
        raise OSError(error.errno, error.strerror or str(error), _figure_of(error.filename, paths)) from None


def _figure_of(filename, paths: list[Path]) -> str:
    """The figure path an OSError's file name stands for: the figure whose temporary file or
    folder it is, else the file name itself."""
    failed = Path(filename)
    for path in paths:
        if failed == path or failed in path.parents or _temporary_of(failed, path):
            return str(path)
    return str(filename)


def _temporary_of(failed: Path, path: Path) -> bool:
    """Whether `failed` is a temporary file of `path` (atomic.TEMP_MARK beside it)."""
    return failed.parent == path.parent and failed.name.startswith(f".{path.name}{TEMP_MARK}")


def _can_share(groups: list[list]) -> bool:
    """Whether forked copies may draw the groups: more than one, on Linux (FORK_FIGURES), and
    this process runs no other thread (forking one that does is unsafe)."""
    return len(groups) >= 2 and FORK_FIGURES and threading.active_count() <= 1


def _draw_all(figures, option: str) -> dict[str, bytes]:
    """Draw figures here, one after the other: their bytes by path."""
    return {str(path): figure_data(spec, path, option) for spec, path in figures}


def _draw_shared(groups: list[list], option: str) -> dict[str, bytes]:
    """The first group drawn here, each other by a forked copy: the bytes of every figure by
    path; the first error of a copy raised once every copy has ended."""
    children: list[tuple[int, int]] = []
    try:
        for group in groups[1:]:
            children.append(_fork(group, option))
        drawn = _draw_all(groups[0], option)
    finally:
        results = [_child_result(pid, read) for pid, read in children]
    for result in results:
        if isinstance(result, BaseException):
            raise result
        drawn.update(result)
    return drawn


def _fork(group: list, option: str) -> tuple[int, int]:
    """(process id, read end of its pipe) of a forked copy that draws the group."""
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:
        os.close(read)
        _child_draws(group, option, write)
    os.close(write)
    return pid, read


def _child_draws(group: list, option: str, write: int) -> None:
    """The copy: draw its share, send the figures' bytes (or its error) through the pipe, never return."""
    code = 1
    try:
        _send(write, _drawn_message(group, option))
        code = 0
    finally:
        os._exit(code)


def _drawn_message(group: list, option: str) -> bytes:
    """The pickled figures of a copy's share (their bytes by path), or its error (_carried)."""
    try:
        return pickle.dumps(("figures", _draw_all(group, option)))
    except BaseException as error:  # every error, Ctrl-C included, goes to the parent
        return _carried(error)


def _send(write: int, data: bytes) -> None:
    """Write all of `data` to a pipe (os.write may take part of it at a time)."""
    view = memoryview(data)
    while view:
        view = view[os.write(write, view):]


def _shares(figures: Sequence[tuple[FigureSpec, object]], count: int) -> list[list]:
    """The figures in `count` groups of about equal work (by number of panels, largest first)."""
    groups: list[list] = [[] for _ in range(max(count, 1))]
    loads = [0] * len(groups)
    for item in sorted(figures, key=lambda item: -max(len(item[0].panels), 1)):
        lightest = loads.index(min(loads))
        groups[lightest].append(item)
        loads[lightest] += max(len(item[0].panels), 1)
    return [group for group in groups if group]


def _carried(error: BaseException) -> bytes:
    """An error of a forked copy as bytes for the parent (an InputError by its fields)."""
    if isinstance(error, InputError):
        return pickle.dumps(("input", error.source, error.location, error.expected))
    try:
        return pickle.dumps(("error", error))
    except Exception:  # an error that does not pickle goes as its text
        return pickle.dumps(("text", f"{type(error).__name__}: {error}"))


def _child_result(pid: int, read: int) -> dict[str, bytes] | BaseException:
    """Wait for a forked copy: the bytes of its figures by path, or the error it reported (or its death)."""
    message = _read_all(read)
    _, status = os.waitpid(pid, 0)
    if status != 0 or not message:
        return RuntimeError(f"a process drawing figures ended with status {status}")
    return _uncarried(message)


def _read_all(read: int) -> bytes:
    """Everything written to a pipe until its writer closed it (the pipe then closed)."""
    chunks = []
    while chunk := os.read(read, 65536):
        chunks.append(chunk)
    os.close(read)
    return b"".join(chunks)


def _uncarried(message: bytes) -> dict[str, bytes] | BaseException:
    """What a forked copy sent: its figures (_drawn_message), or its error (_carried)."""
    kind, *fields = pickle.loads(message)
    if kind == "input":
        return InputError(*fields)
    return fields[0] if kind in ("figures", "error") else RuntimeError(fields[0])


def figure_bytes(spec: FigureSpec, file_format: str = "png", dpi: int = 110) -> bytes:
    """A FigureSpec drawn into memory (png or svg), e.g. to embed in a report."""
    buffer = io.BytesIO()
    line_figure(spec).savefig(buffer, format=file_format, dpi=dpi, **save_options(file_format))
    return buffer.getvalue()


def plot_spectrum(spectrum, path: str | os.PathLike, title: str = "", option: str = "--plot",
                  units: str = "si") -> Path:
    """Plot a spectra.Spectrum: S_d, S_v and S_a panels, one line per damping, log period axis,
    in the display units (display.py)."""
    from .spectra import record_spectrum_figure

    return plot_figure(record_spectrum_figure(spectrum, title, units=units), path, option)


def line_figure(spec: FigureSpec):
    """The matplotlib Figure of a FigureSpec: panels in rows of at most spec.columns, the
    figure title on top, one legend of every labelled item below the panels (figures/layout.py)."""
    shape = layout(spec)
    figure = new_figure(shape.width, shape.height)
    drawn: list = []
    for index, panel in enumerate(spec.panels):
        axes = figure.add_axes(shape.panel_box(spec, index), **_shared_with(spec, drawn))
        draw_panel(axes, spec, panel, shape.titles[index])
        _hide_inner_labels(axes, spec, shape, index)
        drawn.append(axes)
    _draw_title(figure, shape)
    _draw_legend(figure, spec, shape)
    return figure


def _shared_with(spec: FigureSpec, drawn: list) -> dict:
    """The axes a new panel shares x and y with: the first panel's, where the figure shares them."""
    first = drawn[0] if drawn else None
    return {"sharex": first if spec.sharex else None, "sharey": first if spec.sharey else None}


def _hide_inner_labels(axes, spec: FigureSpec, shape: Layout, index: int) -> None:
    """No y tick labels right of the first column of panels sharing y, no x tick labels above
    the bottom row of panels sharing x (nor their axis labels)."""
    if spec.sharey and index % shape.columns > 0:
        axes.tick_params(which="both", labelleft=False)
        axes.set_ylabel("")
    if spec.sharex and not shape.bottom_row(index):
        axes.tick_params(which="both", labelbottom=False)
        axes.set_xlabel("")


def _draw_title(figure, shape: Layout) -> None:
    if shape.suptitle:
        figure.suptitle(shape.suptitle, fontsize="medium", y=1.0 - PAD / shape.height, va="top")


def _draw_legend(figure, spec: FigureSpec, shape: Layout) -> None:
    """One legend of every labelled item, below the panels."""
    if shape.labels:
        figure.legend(legend_handles(spec, shape.labels), shape.labels, loc="lower center",
                      ncol=shape.legend_columns, fontsize="small", bbox_to_anchor=(0.5, PAD / 2 / shape.height),
                      frameon=False)
