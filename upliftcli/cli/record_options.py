"""The options the `uplift record` commands share (record.py: info, spectrum; record_suite.py:
generate, match, scale; record_select.py: select): how a record file is read (--input-format,
--record-units, --dt, --scale, --window), the display units, and the deck a suite is made for."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import typer

from ..errors import InputError
from ..runtime import limits
from . import stdout

if TYPE_CHECKING:
    from ..motion import records

FORMAT_HELP = "The record file's format: at2, text, csv or shared (default: detected from the extension and header)."
RECORD_UNITS_HELP = ("Acceleration units of the record file: g, m/s2, cm/s2, in/s2 or an alias (docs/deck.md; "
                     "default: from the header; units that contradict the header's are refused unless "
                     "--override-header-units).")
DISPLAY_HELP = ("Display units of the printed values and the figure, as in the other commands: si (mm, mm/s, "
                "m/s^2, g) or us (in, in/s, in/s^2, g; the spectrum CSV too: sd_in ...; SI by default). "
                "(--units named the record file's units before: an acceleration unit given here is still read as "
                "--record-units, with a warning.)")
OVERRIDE_HELP = "Read the file in --record-units even where its header declares other units."
DT_HELP = "Time step [s] of a plain-text file without a 'dt = ...' header line."
SCALE_HELP = "Scale factor applied to the acceleration [-], > 0."
WINDOW_HELP = "Keep only this time window, START:END [s] (time restarts at 0)."
#: --set of the suite commands (generate, match, scale, select)
SUITE_SET_HELP = ("Override a deck field by dotted path, e.g. --set ground_motion.period_range=[0.1,3] (repeatable; "
                  "TOML values in the deck's units, as in uplift analyze; docs/deck.md).")
#: --out of the commands that write a suite (generate, match, select)
SUITE_OUT_HELP = "Directory for the records and manifest.json (created; existing files are kept unless --overwrite)."


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
#: --units of match and scale: the display units of every command, and the record file's units as before
SUITE_UNITS = typer.Option("si", "--units", metavar="[si|us]", help=(
    "Display units, as in the other commands: si or us (this command prints accelerations in g and periods in s, "
    "the same in both). An acceleration unit here (its meaning before) is read as --record-units, with a warning."))


def units_of(units: str, record_units: str | None) -> tuple[str, str | None]:
    """(display units, the record file's units) from --units and --record-units. --units named
    the file's units before it named the display units (si, us) of every command; the two sets of
    values do not overlap, so an acceleration unit given to --units is still read as the file's,
    with a warning that names --record-units (docs/deck.md, "Acceleration units")."""
    from ..units import SYSTEMS

    _check_record_units(record_units)
    if units in SYSTEMS:
        return units, record_units
    return "si", _moved_units(units, record_units)


def _check_record_units(record_units: str | None) -> None:
    """--record-units, if given, is an acceleration unit."""
    from ..units import acceleration_unit

    if record_units is not None and acceleration_unit(record_units) is None:
        raise InputError("--record-units", record_units, "acceleration units g, m/s2, cm/s2 or in/s2 (or an alias, "
                         "docs/deck.md)")


def _moved_units(units: str, record_units: str | None) -> str:
    """An acceleration unit given to --units (its meaning before): the record file's units, with a
    warning; refused if it is none or --record-units is given too."""
    from ..units import acceleration_unit

    if acceleration_unit(units) is None:
        raise InputError("--units", units, "si or us (display units; the record file's acceleration units are "
                         "--record-units)")
    if record_units is not None:
        raise InputError("--units", units, f"si or us with --record-units {record_units} (--units is the display "
                         "units)")
    stdout.echo(f"warning: --units {units}: the record file's units are --record-units now (--units is the display "
               f"units, si or us, as in the other commands); read as --record-units {units}", err=True)
    return units


def parse_window(text: str | None) -> tuple[float, float] | None:
    """'START:END' [s] -> (start, end)."""
    if text is None:
        return None
    try:
        start, end = map(float, text.split(":"))
    except ValueError:
        raise InputError("--window", text, "START:END in seconds, e.g. 0:20") from None
    return start, end


def check_count(count: int) -> None:
    """--count of a suite: from 1 to the tool's limit of records."""
    if not 1 <= count <= limits.MAX_SUITE_RECORDS:
        raise InputError("--count", str(count), f"from 1 to {limits.MAX_SUITE_RECORDS:,} records")


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
        option = _option_at_fault(file, bad, options)
        if option is None:
            raise
        raise InputError(option, str(file), bad.expected) from None


def _option_at_fault(file: Path, bad: InputError, options: dict) -> str | None:
    """The command-line option whose value read_record refused for this file, or None (the file's
    own mistake, or the value the option was not given: --scale 1 is the default)."""
    given = options.get(bad.location or "")
    if bad.source != str(file) or bad.location not in RECORD_OPTIONS or given is None:
        return None
    if bad.location == "scale" and given == 1.0:
        return None
    return RECORD_OPTIONS[bad.location]


def _refuse_scale(expected: str):
    """The error function of --scale for deck.fields.check_value."""
    raise InputError("--scale", None, expected)


def read_record_options(file: Path, file_format: str | None, units: str | None, dt: float | None, scale: float,
                        window: str | None, override: bool = False) -> records.Record:
    """The record as the options read it; --scale is checked first by the rule of the deck's
    ground_motion.scale (records.RECORD_FIELDS: > 0; read_record alone also takes a negative one)."""
    from ..deck.fields import check_value
    from ..motion.records import RECORD_FIELDS

    check_value(RECORD_FIELDS["scale"], scale, _refuse_scale)
    return read_with_options(file, format=file_format, units=units, dt=dt, scale=scale, window=parse_window(window),
                             override_header_units=override)


def load_plan(deck: Path, settings: list[str]) -> tuple:
    """(the deck without its ground motion, its suite plan: target spectrum, code rule, period range)."""
    from ..deck.load import load_deck
    from ..deck.suite import plan_from_deck

    loaded = load_deck(deck, settings, load_ground_motion=False)
    return loaded, plan_from_deck(loaded)
