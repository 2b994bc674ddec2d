"""What the suite commands of `uplift record` (generate, match, select: record_suite.py and
record_select.py) do with a suite: --out checked before anything is made, the records and their
manifest written all or none, the suite's table on the terminal and its warnings on stderr."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ..runtime.atomic import refuse_existing, refuse_inputs
from . import stdout
from .options import check_out_directory, echo_warnings, not_writable

if TYPE_CHECKING:  # imported by the commands that use them (numpy, scipy, rich, the suites: see analyze.py)
    from ..motion.matching import MatchSettings
    from ..motion.suites import Suite


def check_out(out: Path, names: list[str], overwrite: bool, inputs: list[Path]) -> None:
    """Nothing is written when --out is a file, a target file exists (without --overwrite) or is an input."""
    check_out_directory(out)
    refuse_inputs([out / name for name in names], inputs, "--out")  # the same file by inode or path
    refuse_existing([out / name for name in names], "--out", overwrite)


def write_files(out: Path, files: dict[str, str]) -> None:
    """The records and their manifest (last) all or none (atomic.write_set): a full disk or a
    stop leaves the folder as it was (it left 7 of 11 records and no manifest)."""
    from ..runtime.atomic import write_set

    try:
        write_set({out / name: text for name, text in files.items()})
    except OSError as error:
        raise not_writable("--out", out, error, more="; nothing was written") from None


def write_suite(out: Path, files: dict[str, str], suite: Suite, labels: list[str], title: str,
                tolerance: MatchSettings | None, warnings) -> None:
    """The suite's files written, its table printed, its warnings and the files written on stderr."""
    write_files(out, files)
    print_suite(suite, labels, title, tolerance)
    echo_warnings(warnings)
    stdout.echo(f"wrote {len(labels)} records and manifest.json to {out}", err=True)


def print_suite(suite: Suite, labels: list[str], title: str, tolerance: MatchSettings | None = None) -> None:
    """The suite on the terminal: its target and period range, a row per record, the mean's ratio
    to the target (and each record's tolerance when matched)."""
    from rich.markup import escape

    from . import render

    out = render.console()
    out.print(escape(f"target: {suite.target.name}; {suite.rule.label}, design value: {suite.statistic} "
                     f"of {suite.count}"))
    out.print(escape(f"period range {suite.period_range[0]:.4g}-{suite.period_range[1]:.4g} s: {suite.period_note}"))
    out.print(_suite_table(suite, labels, title))
    mean = suite.mean_ratio()
    out.print(escape(f"mean S_a/target over the range: min {mean.min():.3f}, max {mean.max():.3f} "
                     f"(the code asks >= {suite.mean_minimum:g})"))
    if tolerance is not None:
        out.print(escape(_tolerance_line(suite, tolerance)))


def _suite_table(suite: Suite, labels: list[str], title: str):
    """A row per record: its factor, PGA and the range of its spectrum's ratio to the target."""
    from rich.markup import escape
    from rich.table import Table

    from ..units import STANDARD_GRAVITY

    target = suite.target.sa(suite.periods, suite.damping)
    table = Table(title=escape(title))
    table.add_column(escape("record"), justify="left")
    for header in ("factor [-]", "PGA [g]", "S_a/target min", "S_a/target max"):
        table.add_column(escape(header), justify="right")
    for label, motion, factor, spectrum in zip(labels, suite.motions(), suite.factors, suite.spectra(), strict=True):
        ratios = spectrum / target
        table.add_row(escape(label), f"{factor:.4f}", f"{motion.pga / STANDARD_GRAVITY:.4f}",
                      f"{ratios.min():.3f}", f"{ratios.max():.3f}")
    return table


def _tolerance_line(suite: Suite, tolerance: MatchSettings) -> str:
    """The band each matched record is held within, as a multiple of the target."""
    low, high = tolerance.low * tolerance.reference, tolerance.high * tolerance.reference
    return (f"tolerance of each record: {tolerance.low:g}-{tolerance.high:g} x {tolerance.reference:g} "
            f"x target = {low:.3g}-{high:.3g} x target, at {suite.periods.size} periods")
