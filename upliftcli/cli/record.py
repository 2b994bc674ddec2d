"""`uplift record info` and `uplift record spectrum` (generate, match, scale: record_suite.py; select:
record_select.py; the options they share: record_options.py)."""

from __future__ import annotations

import io
import math
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from ..errors import InputError
from ..runtime import limits
from ..runtime.atomic import refuse_existing, refuse_inputs, write_text
from . import record_select, record_suite, stdout
from .options import given_path, not_writable, refuse_directory
from .record_options import (
    DISPLAY_UNITS,
    DT_HELP,
    INPUT_FORMAT,
    MOVED_FORMAT,
    OVERRIDE_HELP,
    RECORD_UNITS,
    SCALE_HELP,
    WINDOW_HELP,
    parse_window,
    read_record_options,
    units_of,
)

if TYPE_CHECKING:
    import numpy as np

    from ..motion import records, spectra

INFO_PERIODS = (0.1, 0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0)  # s


def parse_periods(text: str) -> np.ndarray:
    """'START:STOP:N' (N log-spaced periods, START > 0) or a comma list, in s."""
    try:
        return _period_range(text) if ":" in text else _period_list(text)
    except ValueError:
        raise InputError("--periods", text, "START:STOP:N with 0 < START < STOP and N >= 2 "
                         "(log-spaced, s) or a comma list of periods >= 0 s without an empty item") from None


def _period_range(text: str) -> np.ndarray:
    """'START:STOP:N': N log-spaced periods (ValueError if it is not one)."""
    import numpy as np

    first, last, number = text.split(":")
    start, stop, count = float(first), float(last), int(number)
    if not (0.0 < start < stop and math.isfinite(stop) and count >= 2):
        raise ValueError
    if count > limits.MAX_SPECTRUM_PERIODS:  # before anything is allocated
        raise _too_many_periods(text, count)
    return np.geomspace(start, stop, count)


def _period_list(text: str) -> np.ndarray:
    """A comma list of periods >= 0 s (ValueError if it is not one; an empty item is refused by float(""))."""
    import numpy as np

    if text.count(",") >= limits.MAX_SPECTRUM_PERIODS:
        raise _too_many_periods(text[:40] + "...", text.count(",") + 1)
    values = np.array([float(part) for part in text.split(",")])
    if not np.all(np.isfinite(values) & (values >= 0.0)):
        raise ValueError
    return values


def _too_many_periods(shown: str, count: int) -> InputError:
    return InputError("--periods", shown, f"at most {limits.MAX_SPECTRUM_PERIODS:,} periods (limit of the tool), "
                      f"got {count:,}")


def parse_dampings(text: str) -> np.ndarray:
    """Comma list of damping ratios (0.05) or percentages (5%)."""
    import numpy as np

    if not text.strip():
        raise InputError("--damping", text, "at least one damping ratio, e.g. 0.05")
    return np.array([_damping(part.strip(), text) for part in text.split(",")])


def _damping(part: str, text: str) -> float:
    """One item of --damping `text` as a ratio in [0, 1)."""
    if not part:
        raise InputError("--damping", text, "damping ratios separated by single commas, e.g. 0.02,0.05 (or "
                         "2%,5%), without an empty item")
    value = _ratio(part)
    if not (0.0 <= value < 1.0):
        raise InputError("--damping", part, "damping ratios in [0, 1), e.g. 0.02,0.05 (or 2%,5%)")
    return value


def _ratio(part: str) -> float:
    """'0.05' or '5%' as a ratio; nan if it is no number."""
    try:
        return float(part[:-1]) / 100.0 if part.endswith("%") else float(part)
    except ValueError:
        return math.nan


def info(
    file: Path = typer.Argument(..., parser=given_path, help="Record file."),
    file_format: str | None = INPUT_FORMAT,
    moved_format: str | None = MOVED_FORMAT,
    record_units: str | None = RECORD_UNITS,
    override: bool = typer.Option(False, "--override-header-units", help=OVERRIDE_HELP),
    dt: float | None = typer.Option(None, "--dt", help=DT_HELP),
    scale: float = typer.Option(1.0, "--scale", help=SCALE_HELP),
    window: str | None = typer.Option(None, "--window", help=WINDOW_HELP),
    damping: str = typer.Option("0.05", "--damping", help="Damping ratio(s) [-] of the spectrum table, comma "
                                "separated: 0.02,0.05 (or 2%,5%)."),
    units: str = DISPLAY_UNITS,
) -> None:
    """dt, duration, points, PGA, PGV, PGD, Arias intensity and a small response-spectrum table."""
    from ..motion import spectra
    from . import render

    system, record_units = units_of(units, record_units)
    dampings = parse_dampings(damping)
    record = read_record_options(file, file_format, record_units, dt, scale, window, override)
    periods = _info_periods(record, dampings, damping)
    spectrum = spectra.response_spectrum(record.acceleration, record.dt, periods, dampings)
    out = render.console()
    _print_measures(out, record, system)
    out.print(_spectrum_table(periods, dampings, spectrum, system))


def _info_periods(record: records.Record, dampings: np.ndarray, damping: str) -> np.ndarray:
    """The periods of INFO_PERIODS the record resolves (a record with a long dt: fewer rows), within
    the tool's limit of work for the dampings of --damping."""
    import numpy as np

    shortest = limits.shortest_period(record.dt, record.npts)
    periods = np.array([t for t in INFO_PERIODS if t >= shortest])
    problem = limits.spectrum_work_problem(periods, dampings.size, record.dt, record.npts)
    if problem:
        raise InputError("--damping", _shortened(damping), problem)
    return periods


def _shortened(text: str) -> str:
    """An option's value, cut to 40 characters in a message."""
    return text if len(text) <= 40 else text[:37] + "..."


def _print_measures(out, record: records.Record, system: str) -> None:
    """The record's summary measures, one 'name  value' line each."""
    from rich.markup import escape

    for key, value in _measures(record, system):
        out.print(f"{key:<16} {escape(value)}")


def _measures(record: records.Record, system: str) -> list[tuple[str, str]]:
    """(name, value in the display units) of the record's summary measures."""
    import numpy as np

    from ..display import show, stated
    from ..motion import records

    a = record.acceleration
    velocity = records.ground_velocity(a, record.dt)
    displacement = records.ground_displacement(a, record.dt)
    i_a, i_v, i_d = (int(np.argmax(np.abs(x))) for x in (a, velocity, displacement))
    return [
        ("record", record.name),
        ("file", f"{record.source} (units {record.units}, scale {record.scale:g})"),
        ("dt", f"{record.dt:g} s"),
        ("points", f"{record.npts}"),
        ("duration", f"{record.duration:.4g} s"),
        ("PGA", f"{show(record.pga, 'g', system)} g = {stated(record.pga, 'm/s^2', system)} at t = "
                f"{record.time[i_a]:.4g} s"),
        ("PGV", f"{stated(abs(velocity[i_v]), 'mm/s', system)} at t = {record.time[i_v]:.4g} s"),
        ("PGD", f"{stated(abs(displacement[i_d]), 'mm', system)} at t = {record.time[i_d]:.4g} s"),
        ("", "(PGV, PGD: exact integration of the piecewise-linear record, no baseline correction)"),
        ("Arias intensity", stated(records.arias_intensity(a, record.dt), "m/s", system, ".4g")),
    ]


def _spectrum_table(periods: np.ndarray, dampings: np.ndarray, spectrum: spectra.Spectrum, system: str):
    """The response-spectrum table of `info`: S_a and S_d of each damping, a row per period."""
    from rich.markup import escape
    from rich.table import Table

    from ..display import heading

    table = Table(title="Response spectrum",
                  caption="exact; peaks between samples and in the free vibration after the record")
    table.add_column(escape("T [s]"), justify="right")
    for xi in dampings:
        pct = f"{100 * xi:g} %"
        table.add_column(escape(f"{heading('S_a', 'g', system)} {pct}"), justify="right")
        table.add_column(escape(f"{heading('S_d', 'mm', system)} {pct}"), justify="right")
    for j, period in enumerate(periods):
        table.add_row(f"{period:g}", *_spectrum_cells(spectrum, j, dampings.size, system))
    return table


def _spectrum_cells(spectrum: spectra.Spectrum, j: int, dampings: int, system: str) -> list[str]:
    """S_a and S_d of each of the `dampings` damping ratios at the j-th period."""
    from ..display import show

    cells = []
    for k in range(dampings):
        cells += [show(spectrum.pseudo_acceleration[k, j], "g", system), show(spectrum.displacement[k, j], "mm",
                                                                              system)]
    return cells


#: the columns of a spectrum's CSV: (name, SI unit, display kind), in order
SPECTRUM_COLUMNS = (("damping_ratio", "-", ""), ("period", "s", ""), ("sd", "m", "mm"), ("psv", "m/s", "mm/s"),
                    ("psa", "m/s^2", ""), ("psa", "g", ""), ("abs_acc", "m/s^2", ""))


def spectrum_csv(spectrum: spectra.Spectrum, record: dict | None = None, system: str = "si") -> str:
    """Long-format CSV of a spectrum, one row per (damping, period), SI units (or US under --units
    us: sd_in, psv_in_s, psa_in_s2) and S_a in g, after the provenance's two '#' lines if given
    (docs/provenance.md)."""
    from ..engines.quantities import file_column
    from ..provenance.record import csv_comments

    columns = [file_column(name, unit, kind, system) for name, unit, kind in SPECTRUM_COLUMNS]
    buffer = io.StringIO()
    if record is not None:
        buffer.write(csv_comments(record))
    buffer.write(",".join(name for name, _ in columns) + "\n")  # quantity_unit, as every CSV
    buffer.writelines(_csv_rows(spectrum, [factor for _, factor in columns]))
    return buffer.getvalue()


def _csv_rows(spectrum: spectra.Spectrum, factors: list[float]):
    """The CSV lines of spectrum_csv, damping by damping, period by period (each value times its factor)."""
    from ..provenance.record import number_text
    from ..units import STANDARD_GRAVITY

    g = STANDARD_GRAVITY
    for k, xi in enumerate(spectrum.dampings):
        for j, period in enumerate(spectrum.periods):
            values = (xi, period, spectrum.displacement[k, j], spectrum.pseudo_velocity[k, j],
                      spectrum.pseudo_acceleration[k, j], spectrum.pseudo_acceleration[k, j] / g,
                      spectrum.absolute_acceleration[k, j])
            yield ",".join(number_text(value * f) for value, f in zip(values, factors, strict=True)) + "\n"


def spectrum(
    file: Path = typer.Argument(..., parser=given_path, help="Record file."),
    damping: str = typer.Option("0.05", "--damping", help="Damping ratios [-], comma separated: 0.02,0.05 (or 2%,5%)."),
    periods: str = typer.Option("0.05:5:100", "--periods",
                                help="START:STOP:N log-spaced periods [s], or a comma list of periods [s]."),
    out: Path | None = typer.Option(None, "--out", "-o", parser=given_path,
                                    help="Write the spectrum as CSV here (default: stdout)."),
    plot: Path | None = typer.Option(None, "--plot", parser=given_path,
                                     help="Plot S_d, S_v and S_a against log T into this .png/.pdf/.svg file."),
    file_format: str | None = INPUT_FORMAT,
    moved_format: str | None = MOVED_FORMAT,
    record_units: str | None = RECORD_UNITS,
    override: bool = typer.Option(False, "--override-header-units", help=OVERRIDE_HELP),
    dt: float | None = typer.Option(None, "--dt", help=DT_HELP),
    scale: float = typer.Option(1.0, "--scale", help=SCALE_HELP),
    window: str | None = typer.Option(None, "--window", help=WINDOW_HELP),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace existing --out and --plot files."),
    units: str = DISPLAY_UNITS,
) -> None:
    """Exact linear response spectra (S_d, pseudo S_v and S_a, absolute acceleration) of a record."""
    from ..motion import spectra
    from ..provenance.record import of_record

    system, record_units = units_of(units, record_units)
    dampings = parse_dampings(damping)
    period_values = parse_periods(periods)
    _check_paths(out, plot)
    record = read_record_options(file, file_format, record_units, dt, scale, window, override)
    _check_work(record, period_values, dampings.size, periods)
    _refuse_outputs(record, out, plot, overwrite)
    result = spectra.response_spectrum(record.acceleration, record.dt, period_values, dampings)
    text = spectrum_csv(result, of_record(record, window=parse_window(window), periods=period_values,
                                          dampings=dampings), system)
    _write_spectrum(text, result, record, out, plot, system)


def _check_paths(out: Path | None, plot: Path | None) -> None:
    """--plot a figure file name, --out a file name, before the record is read."""
    from ..figures import draw as plots

    if plot is not None:
        plots.check_figure_path(plot)
    refuse_directory(out)


def _check_work(record: records.Record, periods: np.ndarray, dampings: int, text: str) -> None:
    """The periods of --periods (given as `text`) within the record's spectrum range and the tool's limit of work."""
    problem = limits.period_problem(periods, record.dt, record.npts) or \
        limits.spectrum_work_problem(periods, dampings, record.dt, record.npts)
    if problem:
        raise InputError("--periods", text, problem)


def _refuse_outputs(record: records.Record, out: Path | None, plot: Path | None, overwrite: bool) -> None:
    """--out and --plot: neither the record file, neither an existing file unless --overwrite."""
    refuse_inputs([path for path in (out, plot) if path is not None], [record.source], "--out/--plot")
    for option, path in (("--out", out), ("--plot", plot)):
        refuse_existing([path] if path is not None else [], option, overwrite)


def _write_spectrum(text: str, result: spectra.Spectrum, record: records.Record, out: Path | None,
                    plot: Path | None, system: str) -> None:
    """The CSV to --out (or stdout), then the --plot figure, each file named on stderr."""
    from ..figures import draw as plots

    try:
        _write_csv(text, out)
        if plot is not None:
            plots.plot_spectrum(result, plot, title=f"{record.name}", units=system)
            stdout.echo(f"wrote {plot}", err=True)
    except OSError as error:
        raise not_writable("--out/--plot", out or plot, error, "a writable path") from None


def _write_csv(text: str, out: Path | None) -> None:
    """The CSV on stdout, or into --out (named on stderr)."""
    if out is None:
        stdout.echo(text, nl=False)
        return
    write_text(out, text)
    stdout.echo(f"wrote {out}", err=True)


def register(app: typer.Typer) -> None:
    """Add the `record` command group (info, spectrum; generate, match, scale from record_suite.py;
    select from record_select.py)."""
    record_app = typer.Typer(help="Ground-motion records: summary measures, response spectra and suites.",
                             no_args_is_help=True, rich_markup_mode=None)
    record_app.command("info")(info)
    record_app.command("spectrum")(spectrum)
    record_suite.register(record_app)
    record_select.register(record_app)
    app.add_typer(record_app, name="record")
