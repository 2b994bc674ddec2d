"""`uplift record info` and `uplift record spectrum` (generate, match, scale: record_suite.py; select:
record_select.py)."""

from __future__ import annotations

import io
import math
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from ..errors import InputError
from ..runtime import limits
from ..runtime.atomic import refuse_existing, refuse_inputs, write_text
from ..units import STANDARD_GRAVITY
from . import stdout

if TYPE_CHECKING:
    import numpy as np

    from ..motion import records, spectra

INFO_PERIODS = (0.1, 0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0)  # s

FORMAT_HELP = "The record file's format: at2, text, csv or shared (default: detected from the extension and header)."
RECORD_UNITS_HELP = ("Acceleration units of the record file: g, m/s2, cm/s2, in/s2 or an alias (docs/deck.md; "
                     "default: from the header; units that contradict the header's are refused unless "
                     "--override-header-units).")
DISPLAY_HELP = ("Display units of the printed values and the figure, as in the other commands: si (mm, mm/s, "
                "m/s^2, g) or us (in, in/s, in/s^2, g); CSV stays SI. (--units named the record file's units "
                "before: an acceleration unit given here is still read as --record-units, with a warning.)")
OVERRIDE_HELP = "Read the file in --record-units even where its header declares other units."
DT_HELP = "Time step [s] of a plain-text file without a 'dt = ...' header line."
SCALE_HELP = "Scale factor applied to the acceleration [-], > 0."
WINDOW_HELP = "Keep only this time window, START:END [s] (time restarts at 0)."


def _moved_format(value: str | None) -> None:
    """--format under `uplift record` named the record's file format; it is --input-format now
    (--format is the output format everywhere else): the old spelling is refused, never misread."""
    if value is not None:
        raise InputError("--format", None, f"under `uplift record` the record file's format is --input-format "
                         f"(--input-format {value}); --format is the output format of the other commands")


#: the record's file format, and the old spelling refused with the new one named
INPUT_FORMAT = typer.Option(None, "--input-format", help=FORMAT_HELP)
MOVED_FORMAT = typer.Option(None, "--format", hidden=True, expose_value=False, callback=_moved_format)
#: the record file's acceleration units, and the display units (--units, as every command)
RECORD_UNITS = typer.Option(None, "--record-units", help=RECORD_UNITS_HELP)
DISPLAY_UNITS = typer.Option("si", "--units", metavar="[si|us]", help=DISPLAY_HELP)


def units_of(units: str, record_units: str | None) -> tuple[str, str | None]:
    """(display units, the record file's units) from --units and --record-units. --units named
    the file's units before it named the display units (si, us) of every command; the two sets of
    values do not overlap, so an acceleration unit given to --units is still read as the file's,
    with a warning that names --record-units (docs/deck.md, "Acceleration units")."""
    from ..units import SYSTEMS, acceleration_unit

    if record_units is not None and acceleration_unit(record_units) is None:
        raise InputError("--record-units", record_units, "acceleration units g, m/s2, cm/s2 or in/s2 (or an alias, "
                         "docs/deck.md)")
    if units in SYSTEMS:
        return units, record_units
    if acceleration_unit(units) is None:
        raise InputError("--units", units, "si or us (display units; the record file's acceleration units are "
                         "--record-units)")
    if record_units is not None:
        raise InputError("--units", units, f"si or us with --record-units {record_units} (--units is the display "
                         "units)")
    typer.echo(f"warning: --units {units}: the record file's units are --record-units now (--units is the display "
               f"units, si or us, as in the other commands); read as --record-units {units}", err=True)
    return "si", units


def parse_window(text: str | None) -> tuple[float, float] | None:
    """'START:END' [s] -> (start, end)."""
    if text is None:
        return None
    parts = text.split(":")
    try:
        if len(parts) != 2:
            raise ValueError
        start, end = float(parts[0]), float(parts[1])
    except ValueError:
        raise InputError("--window", text, "START:END in seconds, e.g. 0:20") from None
    return start, end


def parse_periods(text: str) -> np.ndarray:
    """'START:STOP:N' (N log-spaced periods, START > 0) or a comma list, in s."""
    import numpy as np

    try:
        if ":" in text:
            parts = text.split(":")
            if len(parts) != 3:
                raise ValueError
            start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
            if not (0.0 < start < stop and math.isfinite(stop) and count >= 2):
                raise ValueError
            if count > limits.MAX_SPECTRUM_PERIODS:  # before anything is allocated
                raise InputError("--periods", text, f"at most {limits.MAX_SPECTRUM_PERIODS:,} periods (limit of the "
                                 f"tool), got {count:,}")
            return np.geomspace(start, stop, count)
        if text.count(",") >= limits.MAX_SPECTRUM_PERIODS:
            raise InputError("--periods", text[:40] + "...", f"at most {limits.MAX_SPECTRUM_PERIODS:,} periods (limit "
                             f"of the tool), got {text.count(',') + 1:,}")
        values = np.array([float(part) for part in text.split(",")])  # an empty item is refused (float(""))
        if values.size == 0 or not np.all(np.isfinite(values)) or np.any(values < 0.0):
            raise ValueError
        return values
    except ValueError:
        raise InputError("--periods", text, "START:STOP:N with 0 < START < STOP and N >= 2 "
                         "(log-spaced, s) or a comma list of periods >= 0 s without an empty item") from None


def parse_dampings(text: str) -> np.ndarray:
    """Comma list of damping ratios (0.05) or percentages (5%)."""
    import numpy as np

    if not text.strip():
        raise InputError("--damping", text, "at least one damping ratio, e.g. 0.05")
    values = []
    for part in text.split(","):
        part = part.strip()
        if not part:
            raise InputError("--damping", text, "damping ratios separated by single commas, e.g. 0.02,0.05 (or "
                             "2%,5%), without an empty item")
        try:
            value = float(part[:-1]) / 100.0 if part.endswith("%") else float(part)
        except ValueError:
            value = math.nan
        if not (0.0 <= value < 1.0):
            raise InputError("--damping", part, "damping ratios in [0, 1), e.g. 0.02,0.05 (or 2%,5%)")
        values.append(value)
    return np.array(values)


#: read_record's options -> the command-line options that give them
RECORD_OPTIONS = {"format": "--input-format", "units": "--record-units", "dt": "--dt", "scale": "--scale",
                  "window": "--window"}


def read_with_options(file: Path, **options) -> records.Record:
    """records.read_record with the options of the command line; a value that does not suit the
    file (--dt 0, --scale nan, a --window past its end, --record-units that contradict its header)
    is the option's mistake, named with the file, not the file's (deck/motion.py does the same for
    the deck's fields)."""
    from ..motion import records

    try:
        return records.read_record(file, **options)
    except InputError as bad:
        given = options.get(bad.location or "")
        if bad.source == str(file) and bad.location in RECORD_OPTIONS and given is not None \
                and not (bad.location == "scale" and given == 1.0):
            raise InputError(RECORD_OPTIONS[bad.location], str(file), bad.expected) from None
        raise


def _read(file: Path, file_format: str | None, units: str | None, dt: float | None, scale: float,
          window: str | None, override: bool = False) -> records.Record:
    """The record as the options read it; --scale is checked first by the rule of the deck's
    ground_motion.scale (records.RECORD_FIELDS: > 0; read_record alone also takes a negative one)."""
    from ..deck.fields import check_value
    from ..motion.records import RECORD_FIELDS

    def error(expected: str):
        raise InputError("--scale", None, expected)

    check_value(RECORD_FIELDS["scale"], scale, error)
    return read_with_options(file, format=file_format, units=units, dt=dt, scale=scale, window=parse_window(window),
                             override_header_units=override)


def info(
    file: Path = typer.Argument(..., help="Record file."),
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
    import numpy as np
    from rich.markup import escape
    from rich.table import Table

    from ..display import heading, show, stated
    from ..motion import records, spectra
    from . import render

    system, record_units = units_of(units, record_units)
    dampings = parse_dampings(damping)
    record = _read(file, file_format, record_units, dt, scale, window, override)
    a = record.acceleration
    velocity = records.ground_velocity(a, record.dt)
    displacement = records.ground_displacement(a, record.dt)
    i_a, i_v, i_d = (int(np.argmax(np.abs(x))) for x in (a, velocity, displacement))
    shortest = limits.shortest_period(record.dt, record.npts)
    periods = np.array([t for t in INFO_PERIODS if t >= shortest])  # a record with a long dt: fewer rows
    problem = limits.spectrum_work_problem(periods, dampings.size, record.dt, record.npts)
    if problem:
        raise InputError("--damping", damping if len(damping) <= 40 else damping[:37] + "...", problem)
    spectrum = spectra.response_spectrum(a, record.dt, periods, dampings)
    out = render.console()
    lines = [
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
    for key, value in lines:
        out.print(f"{key:<16} {escape(value)}" if key else f"{'':<16} {escape(value)}")
    table = Table(title="Response spectrum",
                  caption="exact; peaks between samples and in the free vibration after the record")
    table.add_column(escape("T [s]"), justify="right")
    for xi in dampings:
        pct = f"{100 * xi:g} %"
        table.add_column(escape(f"{heading('S_a', 'g', system)} {pct}"), justify="right")
        table.add_column(escape(f"{heading('S_d', 'mm', system)} {pct}"), justify="right")
    for j, period in enumerate(periods):
        row = [f"{period:g}"]
        for k in range(dampings.size):
            row += [show(spectrum.pseudo_acceleration[k, j], "g", system), show(spectrum.displacement[k, j], "mm",
                                                                                system)]
        table.add_row(*row)
    out.print(table)


def spectrum_csv(spectrum: spectra.Spectrum, record: dict | None = None) -> str:
    """Long-format CSV of a spectrum, one row per (damping, period), SI units and S_a in g,
    after the provenance's two '#' lines if given (docs/provenance.md)."""
    from ..provenance.record import csv_comments, number_text

    buffer = io.StringIO()
    if record is not None:
        buffer.write(csv_comments(record))
    buffer.write("damping_ratio,period_s,sd_m,psv_m_s,psa_m_s2,psa_g,abs_acc_m_s2\n")  # quantity_unit, as every CSV
    g = STANDARD_GRAVITY
    for k, xi in enumerate(spectrum.dampings):
        for j, period in enumerate(spectrum.periods):
            values = (xi, period, spectrum.displacement[k, j], spectrum.pseudo_velocity[k, j],
                      spectrum.pseudo_acceleration[k, j], spectrum.pseudo_acceleration[k, j] / g,
                      spectrum.absolute_acceleration[k, j])
            buffer.write(",".join(number_text(value) for value in values) + "\n")
    return buffer.getvalue()


def spectrum(
    file: Path = typer.Argument(..., help="Record file."),
    damping: str = typer.Option("0.05", "--damping", help="Damping ratios [-], comma separated: 0.02,0.05 (or 2%,5%)."),
    periods: str = typer.Option("0.05:5:100", "--periods",
                                help="START:STOP:N log-spaced periods [s], or a comma list of periods [s]."),
    out: Path | None = typer.Option(None, "--out", "-o", help="Write the spectrum as CSV here (default: stdout)."),
    plot: Path | None = typer.Option(None, "--plot",
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
    from ..figures import draw as plots
    from ..motion import spectra

    system, record_units = units_of(units, record_units)
    dampings = parse_dampings(damping)
    period_values = parse_periods(periods)
    if plot is not None:
        plots.check_figure_path(plot)
    if out is not None and out.is_dir():
        raise InputError("--out", str(out), "a file name (a directory of that name exists)")
    record = _read(file, file_format, record_units, dt, scale, window, override)
    problem = limits.period_problem(period_values, record.dt, record.npts)
    if problem:
        raise InputError("--periods", periods, problem)
    problem = limits.spectrum_work_problem(period_values, dampings.size, record.dt, record.npts)
    if problem:
        raise InputError("--periods", periods, problem)
    refuse_inputs([path for path in (out, plot) if path is not None], [record.source], "--out/--plot")
    for option, path in (("--out", out), ("--plot", plot)):
        refuse_existing([path] if path is not None else [], option, overwrite)
    result = spectra.response_spectrum(record.acceleration, record.dt, period_values, dampings)
    from ..provenance.record import of_record

    text = spectrum_csv(result, of_record(record, window=parse_window(window), periods=period_values,
                                          dampings=dampings))
    try:
        if out is None:
            stdout.echo(text, nl=False)
        else:
            write_text(out, text)
            typer.echo(f"wrote {out}", err=True)
        if plot is not None:
            plots.plot_spectrum(result, plot, title=f"{record.name}", units=system)
            typer.echo(f"wrote {plot}", err=True)
    except OSError as error:
        raise InputError("--out/--plot", str(out or plot), f"a writable path ({error.strerror or error})") from None


def register(app: typer.Typer) -> None:
    """Add the `record` command group (info, spectrum; generate, match, scale from record_suite.py;
    select from record_select.py)."""
    from . import record_select, record_suite

    record_app = typer.Typer(help="Ground-motion records: summary measures, response spectra and suites.",
                             no_args_is_help=True, rich_markup_mode=None)
    record_app.command("info")(info)
    record_app.command("spectrum")(spectrum)
    record_suite.register(record_app)
    record_select.register(record_app)
    app.add_typer(record_app, name="record")
