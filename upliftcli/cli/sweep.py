"""`uplift sweep` and `uplift spectra`: a deck over ranges of its fields, and the paper's
response spectra over T_1. The work is in upliftcli.sweep (plan, run, store, executors,
table, figures); this module parses options and writes the files. Running the plan (executor,
progress, interruption) is sweep_execute.py; the options' help texts and checks sweep_options.py
(those shared with `analyze`: options.py); the terminal tables sweep_render.py."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from ..errors import InputError
from ..runtime import limits
from . import plotting, stdout
from .options import (
    ENGINE_HELP,
    SET_HELP,
    UNITS_HELP,
    DisplayUnits,
    OutputFormat,
    check_out_directory,
    display_system,
    echo_warnings,
    echo_written,
    file_system,
    given_path,
    not_writable,
    refuse_unchecked,
)
from .sweep_execute import execute, stored_rows, warm_workers_early
from .sweep_exit import finish
from .sweep_options import (
    CHECK_HELP,
    DASK_HELP,
    OUT_HELP,
    OVERSUBSCRIBE_HELP,
    PER_RECORD_HELP,
    SCHEDULER_HELP,
    SUPPORT_HELP,
    VARY_HELP,
    WORKERS_HELP,
    TableFormat,
    check_name,
    default_stem,
    figure_errors,
    local_workers,
    table_paths,
)

if TYPE_CHECKING:
    from ..sweep.plan import SweepPlan, Vary

#: suite warnings printed before a sweep; the JSON document of a case has them all
MAX_WARNINGS = 5


def warn_suites(plan: SweepPlan) -> None:
    """The plan's warnings (values of the deck or of a case far outside building practice, the
    suites' too few records for the rule ...), each once, at most MAX_WARNINGS."""
    echo_warnings(plan.warnings[:MAX_WARNINGS])
    if len(plan.warnings) > MAX_WARNINGS:
        stdout.echo(f"warning: and {len(plan.warnings) - MAX_WARNINGS} more about the cases "
                   "(uplift analyze on a case's deck shows them)", err=True)


def _write(plan, rows, out, stem, table, summary, record, system: str = "si") -> list[Path]:
    """The tables of the sweep (sweep_table.write_tables, in the units of `system`); an OSError as
    one line naming --out."""
    from ..sweep import table as sweep_table

    try:
        return sweep_table.write_tables(plan, rows, out, stem, table.value, summary, record, system)
    except OSError as error:
        raise not_writable("--out", out, error) from None


def _choices(engine: list[str], support: list[str]) -> tuple[list[str], list[str]]:
    """The engines of --engine and the supports of --support (checked names)."""
    from ..deck.choices import parse_choices
    from ..engines.registry import ENGINES, SUPPORTS

    return parse_choices(engine, ENGINES, "--engine"), parse_choices(support, SUPPORTS, "--support")


def sweep(
    deck: Path = typer.Argument(..., parser=given_path, help="Deck file (TOML), see docs/deck.md."),
    vary: list[str] = typer.Option([], "--vary", "-v", help=VARY_HELP),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    engine: list[str] = typer.Option([], "--engine", "-e", help=ENGINE_HELP),
    support: list[str] = typer.Option([], "--support", help=SUPPORT_HELP),
    out: Path = typer.Option(Path("."), "--out", "-o", parser=given_path, help=OUT_HELP),
    name: str | None = typer.Option(None, "--name", help="Stem of the output files (default: <deck>.<fields>.sweep, "
                                    "the varied fields' last names: ten_story.period-k_f.sweep)."),
    table: TableFormat = typer.Option(TableFormat.json, "--table",
                                      help="Besides <stem>.csv: <stem>.json (rows, summary), .parquet or none (csv)."),
    output_format: OutputFormat = typer.Option(OutputFormat.table, "--format", "-f",
                                               help="table (summary on the terminal) or json (document on stdout)."),
    plot: bool = typer.Option(False, "--plot", help="Plot the responses against the first varied field."),
    plot_format: str = typer.Option("png", "--plot-format", help="png, svg or pdf."),
    workers: int | None = typer.Option(None, "--workers", "-w", help=WORKERS_HELP),
    oversubscribe: bool = typer.Option(False, "--oversubscribe", help=OVERSUBSCRIBE_HELP),
    scheduler: str | None = typer.Option(None, "--scheduler", help=SCHEDULER_HELP),
    dask: str | None = typer.Option(None, "--dask", help=DASK_HELP),
    resume: bool = typer.Option(False, "--resume", help="Skip the cases a previous run of this sweep finished "
                                "(refused if their record files or the tool version changed since)."),
    retry_failed: bool = typer.Option(False, "--retry-failed", help="With --resume: run failed cases again."),
    rerun_stale: bool = typer.Option(False, "--rerun-stale", help="With --resume: run again the cases computed "
                                     "from another record file or tool version (instead of refusing)."),
    overwrite: bool = typer.Option(False, "--overwrite", help="Discard the rows of a previous run and replace its "
                                   "tables and figures."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress and no summary tables."),
    per_record: bool = typer.Option(False, "--per-record", help=PER_RECORD_HELP),
    check: bool = typer.Option(False, "--check", help=CHECK_HELP),
    units: DisplayUnits | None = typer.Option(None, "--units", help=UNITS_HELP),
) -> None:
    """Analyse a deck over ranges of its fields: one tidy row per case, summary and envelope.

    Rows are appended to <out>/<stem>.rows.jsonl as cases finish; <stem>.csv and .json (or .parquet) at the end.

    Exit codes: 0 ok, 2 bad input, 3 a case exceeds a limit of the deck's criteria, 4 a case failed, 130 interrupted
    (Ctrl-C; 143 SIGTERM, 129 SIGHUP).
    """
    workers = local_workers(workers, oversubscribe, scheduler)
    if workers is not None:  # by default the plan's size decides whether local workers run
        warm_workers_early(workers, scheduler, dask)
    from ..sweep import table as sweep_table
    from ..sweep.plan import plan_sweep
    from ..sweep.store import stem_lock

    check_name(name)
    stem = name or default_stem(deck, vary)
    plot_path = _plot_path(out, stem, plot_format) if plot else None
    sweep_table.check_table_format(table.value)
    engines, supports = _choices(engine, support)
    plan = plan_sweep(deck, settings, vary, engines, supports, per_record=per_record,
                      check=check)  # --check: the exact engine's cases batched as usual
    _check_plan(plan, check, plot_path)
    check_out_directory(out)
    with stem_lock(out, stem):
        outcome = execute(plan, out, stem, workers=workers, scheduler=scheduler, dask=dask, resume=resume,
                          retry_failed=retry_failed, overwrite=overwrite, quiet=quiet, label="sweep",
                          rerun_stale=rerun_stale, figures_written=[plot_path] if plot_path else [],
                          tables=table_paths(out, stem, table.value))
        rows, summary, record, written = _sweep_tables(plan, stored_rows(plan, out, stem, outcome), out, stem, table,
                                                       file_system(units))
        _sweep_figure(plan, rows, plot_path, out, written, _display(units, plan))
        _print_sweep(plan, rows, summary, record, output_format, quiet, units)
        echo_written(written)
        finish(rows, criteria=True)


def _plot_path(out: Path, stem: str, plot_format: str) -> Path:
    """The figure of --plot, <out>/<stem>.<plot format> (a format the figures know)."""
    from ..figures import draw as plots

    return plots.check_figure_path(out / f"{stem}.{plot_format}", "--plot-format")


def _check_plan(plan: SweepPlan, check: bool, plot_path: Path | None) -> None:
    """Before running: [criteria] simplified_error needs --check, the plan's warnings, and a numeric
    varied field to plot against (--plot)."""
    from ..sweep import figures

    refuse_unchecked([*plan.criteria, *(v.path.removeprefix("criteria.") for v in plan.varies)], check, "--check")
    warn_suites(plan)
    if plot_path is not None:
        figures.sweep_figure(plan, [])


def _sweep_tables(plan: SweepPlan, rows: Iterable[dict], out: Path, stem: str, table: TableFormat,
                  system: str = "si") -> tuple:
    """(rows with the accuracy ratios under --check, summary, provenance, the tables written); `rows`
    (read back from the rows file) read a few times, one row at a time."""
    from ..sweep import table as sweep_table

    rows = sweep_table.checked_rows(plan, rows) if plan.check else rows
    summary = sweep_table.summarize(plan, rows)
    record = sweep_table.sweep_provenance(plan)
    return rows, summary, record, _write(plan, rows, out, stem, table, summary, record, system)


def _sweep_figure(plan: SweepPlan, rows: Iterable[dict], plot_path: Path | None, out: Path, written: list[Path],
                  units: str) -> None:
    """The --plot figure (added to `written`, the tables before it), of what it reads of the rows (figure_rows)."""
    from ..figures import draw as plots
    from ..sweep import figures

    if plot_path is None:
        return
    rows = figures.figure_rows(plan, rows)
    if not _any_finished(rows):
        return
    with figure_errors(out, written):
        written.append(plots.plot_figure(figures.sweep_figure(plan, rows, figures.plan_motion_label(plan), units),
                                         plot_path, "--plot-format"))


def _print_sweep(plan: SweepPlan, rows: Iterable[dict], summary, record: dict, output_format: OutputFormat,
                 quiet: bool, units: DisplayUnits | None) -> None:
    """The sweep's JSON document on stdout (in the files' units, written a row at a time), or its
    summary tables in the display units (none under --quiet)."""
    from ..sweep import table as sweep_table
    from . import render
    from .sweep_render import EchoBuffer, print_summary

    if output_format is OutputFormat.json:
        echoed = EchoBuffer()
        sweep_table.write_document(echoed.write, plan, rows, summary, record, file_system(units))
        echoed.flush()
        return
    if not quiet:
        print_summary(render.console(), plan, summary, _display(units, plan))


def _display(units: DisplayUnits | None, plan: SweepPlan) -> str:
    """The display units of a sweep: --units, else its deck's (after a --set of `units`)."""
    from ..sweep.plan import deck_units

    return display_system(units, {"units": deck_units(plan.raw, plan.base_overrides)})


def spectra(
    deck: Path = typer.Argument(..., parser=given_path, help="Deck file (TOML), see docs/deck.md."),
    periods: str = typer.Option("0.05:5:100", "--periods", "-p",
                                help="Fixed-base periods T_1 [s]: START:STOP:N (log-spaced; add :lin for linear) "
                                     "or a comma list."),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    engine: list[str] = typer.Option([], "--engine", "-e", help=ENGINE_HELP),
    support: list[str] = typer.Option([], "--support", help=SUPPORT_HELP),
    out: Path = typer.Option(Path("."), "--out", "-o", parser=given_path, help=OUT_HELP),
    name: str | None = typer.Option(None, "--name", help="Stem of the output files (default: <deck>.spectra)."),
    table: TableFormat = typer.Option(TableFormat.json, "--table", help="Besides <stem>.csv: json, parquet or csv."),
    plot_format: list[str] = typer.Option(["png"], "--plot-format",
                                          help="png, svg, pdf or all; repeatable or comma list."),
    workers: int | None = typer.Option(None, "--workers", "-w", help=WORKERS_HELP),
    oversubscribe: bool = typer.Option(False, "--oversubscribe", help=OVERSUBSCRIBE_HELP),
    scheduler: str | None = typer.Option(None, "--scheduler", help=SCHEDULER_HELP),
    dask: str | None = typer.Option(None, "--dask", help=DASK_HELP),
    resume: bool = typer.Option(False, "--resume", help="Skip the periods a previous run finished."),
    overwrite: bool = typer.Option(False, "--overwrite", help="Discard the rows of a previous run and replace its "
                                   "tables and figures."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress."),
    per_record: bool = typer.Option(False, "--per-record", help=PER_RECORD_HELP),
    units: DisplayUnits | None = typer.Option(None, "--units", help=UNITS_HELP),
) -> None:
    """The paper's response spectra over T_1 (Yim & Chopra Figs. 3-4, 6-10), with the critical value b/h_1*.

    V_b/(m_t g) and M_b/(m_t g h_1*) for rigid, bonded and uplift, modal contributions, engines compared.

    Writes <stem>.csv, <stem>.json and one plot per figure.

    Exit codes: 0 ok, 2 bad input, 4 a case failed, 130 interrupted (Ctrl-C; 143 SIGTERM, 129 SIGHUP).
    """
    workers = local_workers(workers, oversubscribe, scheduler)
    warm_workers_early(workers, scheduler, dask)
    from ..deck.choices import parse_choices
    from ..sweep import figures
    from ..sweep import table as sweep_table
    from ..sweep.store import stem_lock
    from . import render
    from .sweep_render import print_spectra_summary

    check_name(name)
    formats = parse_choices(plot_format, plotting.FORMATS, "--plot-format")
    sweep_table.check_table_format(table.value)
    period_vary: Vary = figures.period_vary(periods)
    plan = _plan_spectra(deck, settings, _choices(engine, support), period_vary, per_record, periods)
    warn_suites(plan)
    stem = name or f"{deck.stem}.spectra"
    figure_paths = _figure_paths(plan, out, stem, formats)
    check_out_directory(out)
    with stem_lock(out, stem):
        outcome = execute(plan, out, stem, workers=workers, scheduler=scheduler, dask=dask, resume=resume,
                          retry_failed=False, overwrite=overwrite, quiet=quiet, label="spectra",
                          figures_written=figure_paths,
                          tables=table_paths(out, stem, table.value))
        rows = stored_rows(plan, out, stem, outcome)
        summary = sweep_table.summarize(plan, rows)
        written = _write(plan, rows, out, stem, table, summary, sweep_table.sweep_provenance(plan), file_system(units))
        finished = figures.figure_rows(plan, rows)
        written += _spectra_figures(plan, finished, out, stem, formats, written)
        if not quiet:
            print_spectra_summary(render.console(), plan, finished)
        echo_written(written)
        finish(rows, criteria=False)


def _plan_spectra(deck: Path, settings: list[str], choices: tuple[list[str], list[str]], period_vary: Vary,
                  per_record: bool, periods: str) -> SweepPlan:
    """The plan over the periods of --periods (its mistakes named as --periods, not as a --vary), each
    period within the records' spectrum range, before running."""
    from ..sweep import figures
    from ..sweep.plan import plan_sweep

    try:
        plan = plan_sweep(deck, settings, (), *choices, varies=[period_vary], per_record=per_record)
    except InputError as error:  # the periods come from --periods, not from a --vary
        if error.source == "--vary" and error.location == figures.PERIOD_PATH:
            raise InputError("--periods", periods, error.expected) from None
        raise
    _check_periods(plan, period_vary, periods)
    return plan


def _check_periods(plan: SweepPlan, period_vary: Vary, periods: str) -> None:
    """T_1 within the spectrum range of each record step of the plan."""
    for dt, samples in plan.record_steps.values():
        problem = limits.period_problem(period_vary.values, dt, samples)
        if problem:
            raise InputError("--periods", periods, problem)


def _figure_paths(plan: SweepPlan, out: Path, stem: str, formats: list[str]) -> list[Path]:
    """The files of the paper's figures the run will draw, <stem>.<figure>.<format> each."""
    from ..sweep import figures

    specs = figures.paper_figures([], plan.engines, plan.supports, "")
    return [out / f"{stem}.{figure}.{extension}" for figure in specs for extension in formats]


def _any_finished(rows: list[dict]) -> bool:
    """Whether some case finished; the figures of failed cases alone have nothing to draw (a log axis
    of no positive value cannot be drawn at all): they are left out, said in one line."""
    if any(row.get("status") == "ok" for row in rows):
        return True
    stdout.echo("warning: no figure drawn: no case finished", err=True)
    return False


def _spectra_figures(plan: SweepPlan, rows: list[dict], out: Path, stem: str, formats: list[str],
                     tables: list[Path]) -> list[Path]:
    """The paper's figures of the rows, in each format (an OSError names the tables written before)."""
    from ..figures import draw as plots
    from ..sweep import figures

    if not _any_finished(rows):
        return []

    specs = figures.paper_figures(rows, plan.engines, plan.supports, figures.plan_motion_label(plan),
                                  figures.nominal_value(plan, figures.PERIOD_PATH))
    with figure_errors(out, tables):
        return plots.plot_figures([(spec, out / f"{stem}.{figure_name}.{extension}")
                                   for figure_name, spec in specs.items() for extension in formats], "--plot-format")


def register(app: typer.Typer) -> None:
    app.command("sweep")(sweep)
    app.command("spectra")(spectra)
