"""`uplift sweep` and `uplift spectra`: a deck over ranges of its fields, and the paper's
response spectra over T_1. The work is in upliftcli.sweep (plan, run, store, executors,
table, figures); this module parses options, shows progress and writes the files."""

from __future__ import annotations

import json
import signal
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from .. import limits
from ..atomic import refuse_existing, refuse_inputs
from ..errors import InputError
from ..sweep.signals import ignore_stop_signals
from . import plotting, stdout
from .analyze import SET_HELP, UNITS_HELP, DisplayUnits
from .sweep_options import OVERSUBSCRIBE_HELP, WORKERS_HELP, check_name, figure_errors, local_workers, table_paths

if TYPE_CHECKING:
    from ..sweep.plan import SweepPlan, Vary

EXIT_CRITERIA, EXIT_ANALYSIS, EXIT_INTERRUPTED = 3, 4, 130  # interrupted: 128 + the signal (SIGINT 130)
VARY_HELP = ("Vary a deck field (same dotted paths as --set): PATH=START:STOP:N (linear), PATH=START:STOP:N:log, "
             "PATH=a,b,c or PATH=\\[a, b], values in the deck's units (as --set); repeatable, cases are the "
             "cartesian product.")
ENGINE_HELP = "Engine(s): simplified, approximate, exact or all; repeatable or comma separated (default: the deck's)."
SUPPORT_HELP = "Support condition(s): rigid, bonded, uplift; repeatable or comma separated (default: the deck's)."
OUT_HELP = "Directory of the output files (tables in SI, the unit in each column name)."
SCHEDULER_HELP = "Run the cases on a Dask cluster at this address (tcp://host:8786), or 'local' for a local one."
DASK_HELP = "'local': run on a Dask LocalCluster of --workers processes on this machine (same as --scheduler local)."
CHECK_HELP = ("Also run the exact engine (record decks) and add to the tables the ratios simplified / exact of V_b, "
              "M_b, the largest drift ratio and the largest floor displacement of each simplified case "
              "(columns check_*).")
PER_RECORD_HELP = ("Record suite decks: after each case's row (the design statistic over the records) one row per "
                   "record in the tables (columns record and factor).")
#: suite warnings printed before a sweep; the JSON document of a case has them all
MAX_WARNINGS = 5


class OutputFormat(StrEnum):
    table = "table"
    json = "json"


class TableFormat(StrEnum):
    json = "json"
    parquet = "parquet"
    csv = "csv"


#: rough cost of one case [s], to decide whether worker processes pay for their start-up (about 1 s of one
#: core for the warm server, sweep/warm.py, and their chunks' transfer)
CASE_SECONDS = {"simplified": 0.002, "approximate": 0.04, "exact": 0.04}


def choose_executor(plan: SweepPlan, workers: int | None, scheduler: str | None, dask: str | None):
    from ..process import available_cores
    from ..sweep.dask_executor import DaskExecutor, check_reachable, import_distributed
    from ..sweep.executors import ProcessExecutor, SerialExecutor

    if dask is not None and dask != "local":
        raise InputError("--dask", dask, "'local' (or give --scheduler tcp://host:port)")
    if scheduler is not None or dask is not None:
        import_distributed()  # the extra is installed, before anything runs
        address = None if (scheduler in (None, "local")) else scheduler
        if address is not None:
            check_reachable(address)  # at once, before any file is written
        return DaskExecutor(address, workers or min(available_cores(), 4))
    if workers is not None:
        if workers < 1:
            raise InputError("--workers", str(workers), "an integer >= 1")
        return SerialExecutor() if workers == 1 else ProcessExecutor(workers)
    cores = available_cores()
    seconds = len(plan.cases) * max(CASE_SECONDS.get(engine, 0.04) for engine in plan.engines)
    seconds *= max(1, plan.suite_records)  # a suite case runs every record
    return ProcessExecutor(cores) if cores > 1 and seconds > 4.0 else SerialExecutor()


def progress_for(quiet: bool, label: str):
    from ..sweep.run import NoProgress
    from . import render
    from .sweep_render import PlainProgress, RichProgress, use_rich_progress

    if quiet:
        return NoProgress()
    console = render.console(stderr=True)
    return RichProgress(console, label) if use_rich_progress(console) else PlainProgress(label)


def _check_out(out: Path) -> None:
    if out.exists() and not out.is_dir():
        raise InputError("--out", str(out), "a directory (a file of that name exists)")


def _prepare_out(out: Path, rows_path: Path, resume: bool, overwrite: bool) -> None:
    _check_out(out)
    if rows_path.exists() and rows_path.stat().st_size > 0 and not (resume or overwrite):
        from ..sweep.store import RowStore

        rows = len(RowStore(rows_path).read())
        raise InputError("--out", str(rows_path), f"holds the rows of an earlier run of this sweep ({rows} cases): "
                         "pass --resume to continue that run, or --overwrite to discard them and start again")


def output_paths(out: Path, stem: str, extra=()) -> list[Path]:
    """The files a sweep writes under --out (rows, tables and any figures)."""
    return [out / f"{stem}{suffix}" for suffix in (".rows.jsonl", ".csv", ".json", ".parquet")] + list(extra)


def warm_workers_early(workers: int | None, scheduler: str | None, dask: str | None) -> None:
    """Start the warm server of local worker processes now, before the deck is read and the cases
    planned, when they are likely (more than one core, neither --workers 1 nor Dask; `uplift
    sweep` asks only with --workers N): it imports the engines on another core meanwhile. A sweep
    that then runs in this process leaves it unused (it ends with this process)."""
    if scheduler is not None or dask is not None or (workers is not None and workers <= 1):
        return
    from ..process import available_cores
    from ..sweep.executors import ProcessExecutor

    if workers is None and available_cores() < 2:
        return
    ProcessExecutor(workers or 2).prestart()


def head_start(executor, figures: bool) -> None:
    """Local worker processes: start their warm server (it imports and loads the engines, about
    0.25 s of one core) if warm_workers_early did not, and import matplotlib in a thread of this
    process when figures follow the run (this process only waits on the workers meanwhile).
    Measured on the Fig. 3 spectrum with warm_workers_early, 10 runs of each on 2 cores: 2.07 ->
    1.94 s end to end (median)."""
    prestart = getattr(executor, "prestart", None)
    if prestart is None:
        return
    prestart()
    if figures:
        from .. import plots

        plots.preload(background=True)


def execute(plan: SweepPlan, out: Path, stem: str, *, workers, scheduler, dask, resume, retry_failed,
            overwrite, quiet, label, rerun_stale=False, figures_written=(), tables=()):
    """Run the plan with progress (the caller holds stem_lock); exit 128 + the signal (130 for
    Ctrl-C, 143 for SIGTERM, 129 for SIGHUP) keeping the rows when interrupted. figures_written:
    the figures that follow the run (their paths); tables: the tables it writes (both refused if
    they exist, unless overwrite or resume)."""
    from ..sweep.run import run_sweep
    from ..sweep.store import RowStore

    rows_path = out / f"{stem}.rows.jsonl"
    refuse_inputs(output_paths(out, stem, figures_written), plan.input_files, "--out")
    _prepare_out(out, rows_path, resume, overwrite)
    if not resume:  # --resume finishes an earlier run: its tables and figures are written again
        refuse_existing([*tables, *figures_written], "--out", overwrite, ": written by an earlier run; --resume "
                        "continues that run")
    executor = choose_executor(plan, workers, scheduler, dask)
    head_start(executor, bool(figures_written))
    try:
        outcome = run_sweep(plan, executor, RowStore(rows_path), resume=resume, retry_failed=retry_failed,
                            rerun_stale=rerun_stale, progress=progress_for(quiet, label), exit_on_stop=True)
    except OSError as error:  # a full disk: the rows written so far are kept
        kept = len(RowStore(rows_path).read())
        raise InputError("--out", str(out), f"a writable directory ({error.strerror or error}); {kept} finished "
                         f"rows are kept in {rows_path}: run the same command with --resume once there is room"
                         ) from None
    if outcome.interrupted:
        ignore_stop_signals()  # a second Ctrl-C while exiting changes nothing
        name = signal.Signals(outcome.signal).name if outcome.signal else "SIGINT"
        typer.echo(f"interrupted ({name}): {len(outcome.rows)} of {outcome.total} cases are kept in {rows_path}; "
                   "run the same command with --resume to finish", err=True)
        raise typer.Exit(128 + (outcome.signal or signal.SIGINT))
    return outcome


def warn_suites(plan: SweepPlan) -> None:
    """The plan's warnings (values of the deck or of a case far outside building practice, the
    suites' too few records for the rule ...), each once, at most MAX_WARNINGS."""
    for message in plan.warnings[:MAX_WARNINGS]:
        typer.echo(f"warning: {message}", err=True)
    if len(plan.warnings) > MAX_WARNINGS:
        typer.echo(f"warning: and {len(plan.warnings) - MAX_WARNINGS} more about the cases "
                   "(uplift analyze on a case's deck shows them)", err=True)


def _write(plan, rows, out, stem, table, summary, record) -> list[Path]:
    from ..sweep import table as sweep_table

    try:
        return sweep_table.write_tables(plan, rows, out, stem, table.value, summary, record)
    except OSError as error:
        raise InputError("--out", str(out), f"a writable directory ({error.strerror or error})") from None


def _finish(rows: list[dict], criteria: bool) -> None:
    """Failures: exit 4; else criteria violations: exit 3 (each case named on stderr)."""
    failed = [row for row in rows if row.get("status") != "ok"]
    for row in failed:
        typer.echo(f"case {row['case']} ({row['engine']}/{row['support']}) {row['status']}: {row['message']}", err=True)
    violating = [row for row in rows if row.get("violations")] if criteria else []
    for row in violating:
        inputs = ", ".join(f"{k}={v}" for k, v in row.items() if "." in k)
        typer.echo(f"criterion violated: case {row['case']}{f' ({inputs})' if inputs else ''}: {row['violations']}",
                   err=True)
    if failed:
        raise typer.Exit(EXIT_ANALYSIS)
    if violating:
        raise typer.Exit(EXIT_CRITERIA)


def sweep(
    deck: Path = typer.Argument(..., help="Deck file (TOML), see docs/deck.md."),
    vary: list[str] = typer.Option([], "--vary", "-v", help=VARY_HELP),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    engine: list[str] = typer.Option([], "--engine", "-e", help=ENGINE_HELP),
    support: list[str] = typer.Option([], "--support", help=SUPPORT_HELP),
    out: Path = typer.Option(Path("."), "--out", "-o", help=OUT_HELP),
    name: str | None = typer.Option(None, "--name", help="Stem of the output files (default: <deck>.sweep)."),
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
    units: DisplayUnits = typer.Option(DisplayUnits.si, "--units", help=UNITS_HELP),
) -> None:
    """Analyse a deck over ranges of its fields: one tidy row per case, summary and envelope.

    Rows are appended to <out>/<stem>.rows.jsonl as cases finish; <stem>.csv and .json (or .parquet) at the end.

    Exit codes: 0 ok, 2 bad input, 3 a case exceeds a limit of the deck's criteria, 4 a case failed, 130 interrupted
    (Ctrl-C; 143 SIGTERM, 129 SIGHUP).
    """
    workers = local_workers(workers, oversubscribe, scheduler)
    if workers is not None:  # by default the plan's size decides whether local workers run
        warm_workers_early(workers, scheduler, dask)
    from .. import plots
    from ..engines.registry import ENGINES, SUPPORTS
    from ..sweep import figures
    from ..sweep import table as sweep_table
    from ..sweep.plan import parse_choices, plan_sweep
    from ..sweep.store import stem_lock
    from . import render
    from .sweep_render import print_summary

    check_name(name)
    plot_path = plots.check_figure_path(out / f"{name or deck.stem + '.sweep'}.{plot_format}", "--plot-format") \
        if plot else None
    sweep_table.check_table_format(table.value)
    engines = parse_choices(engine, ENGINES, "--engine")
    plan = plan_sweep(deck, settings, vary, engines, parse_choices(support, SUPPORTS, "--support"),
                      per_record=per_record, check=check)  # --check: the exact engine's cases batched as usual
    warn_suites(plan)
    if plot_path is not None:
        figures.sweep_figure(plan, [])  # a numeric varied field to plot against, checked before running
    stem = name or f"{deck.stem}.sweep"
    _check_out(out)
    with stem_lock(out, stem):
        outcome = execute(plan, out, stem, workers=workers, scheduler=scheduler, dask=dask, resume=resume,
                          retry_failed=retry_failed, overwrite=overwrite, quiet=quiet, label="sweep",
                          rerun_stale=rerun_stale, figures_written=[plot_path] if plot_path else [],
                          tables=table_paths(out, stem, table.value))
        rows = sweep_table.add_checks(plan, outcome.rows) if plan.check else outcome.rows
        summary = sweep_table.summarize(plan, rows)
        record = sweep_table.sweep_provenance(plan)
        written = _write(plan, rows, out, stem, table, summary, record)
        if plot_path is not None:
            with figure_errors(out, written):
                written.append(plots.plot_figure(figures.sweep_figure(plan, rows, figures.plan_motion_label(plan),
                                                                      units.value),
                                                 plot_path, "--plot-format"))
    if output_format is OutputFormat.json:
        stdout.echo(json.dumps(sweep_table.document(plan, rows, summary, record), indent=1))
    elif not quiet:
        print_summary(render.console(), plan, summary, units.value)
    for path in written:
        typer.echo(f"wrote {path}", err=True)
    _finish(rows, criteria=True)


def spectra(
    deck: Path = typer.Argument(..., help="Deck file (TOML), see docs/deck.md."),
    periods: str = typer.Option("0.05:5:100", "--periods", "-p",
                                help="Fixed-base periods T_1 [s]: START:STOP:N (log-spaced; add :lin for linear) "
                                     "or a comma list."),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    engine: list[str] = typer.Option([], "--engine", "-e", help=ENGINE_HELP),
    support: list[str] = typer.Option([], "--support", help=SUPPORT_HELP),
    out: Path = typer.Option(Path("."), "--out", "-o", help=OUT_HELP),
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
    units: DisplayUnits = typer.Option(DisplayUnits.si, "--units", help=UNITS_HELP),
) -> None:
    """The paper's response spectra over T_1 (Yim & Chopra Figs. 3-4, 6-10), with the critical value b/h_1*.

    V_b/(m_t g) and M_b/(m_t g h_1*) for rigid, bonded and uplift, modal contributions, engines compared.

    Writes <stem>.csv, <stem>.json and one plot per figure.

    Exit codes: 0 ok, 2 bad input, 4 a case failed, 130 interrupted (Ctrl-C; 143 SIGTERM, 129 SIGHUP).
    """
    workers = local_workers(workers, oversubscribe, scheduler)
    warm_workers_early(workers, scheduler, dask)
    from .. import plots
    from ..engines.registry import ENGINES, SUPPORTS
    from ..sweep import figures
    from ..sweep import table as sweep_table
    from ..sweep.plan import parse_choices, plan_sweep
    from ..sweep.store import stem_lock

    check_name(name)
    formats = parse_choices(plot_format, plotting.FORMATS, "--plot-format")
    sweep_table.check_table_format(table.value)
    period_vary: Vary = figures.period_vary(periods)
    engines = parse_choices(engine, ENGINES, "--engine")
    try:
        plan = plan_sweep(deck, settings, (), engines, parse_choices(support, SUPPORTS, "--support"),
                          varies=[period_vary], per_record=per_record)
    except InputError as error:  # the periods come from --periods, not from a --vary
        if error.source == "--vary" and error.location == figures.PERIOD_PATH:
            raise InputError("--periods", periods, error.expected) from None
        raise
    for dt, samples in plan.record_steps.values():  # T_1 within the records' spectrum range, before running
        problem = limits.period_problem(period_vary.values, dt, samples)
        if problem:
            raise InputError("--periods", periods, problem)
    warn_suites(plan)
    stem = name or f"{deck.stem}.spectra"
    figure_specs = figures.paper_figures([], plan.engines, plan.supports, "")
    figure_paths = [out / f"{stem}.{figure}.{extension}" for figure in figure_specs for extension in formats]
    _check_out(out)
    with stem_lock(out, stem):
        outcome = execute(plan, out, stem, workers=workers, scheduler=scheduler, dask=dask, resume=resume,
                          retry_failed=False, overwrite=overwrite, quiet=quiet, label="spectra",
                          figures_written=figure_paths, tables=table_paths(out, stem, table.value))
        summary = sweep_table.summarize(plan, outcome.rows)
        written = _write(plan, outcome.rows, out, stem, table, summary, sweep_table.sweep_provenance(plan))
        specs = figures.paper_figures(outcome.rows, plan.engines, plan.supports, figures.plan_motion_label(plan),
                                      figures.nominal_value(plan, figures.PERIOD_PATH))
        with figure_errors(out, written):
            written += plots.plot_figures([(spec, out / f"{stem}.{figure_name}.{extension}")
                                           for figure_name, spec in specs.items() for extension in formats],
                                          "--plot-format")
    if not quiet:
        _print_spectra_summary(plan, outcome.rows)
    for path in written:
        typer.echo(f"wrote {path}", err=True)
    _finish(outcome.rows, criteria=False)


def _print_spectra_summary(plan: SweepPlan, rows: list[dict]) -> None:
    from rich.markup import escape
    from rich.table import Table

    from ..sweep import figures
    from . import render

    table = Table(title=escape(f"{plan.title}: spectra over T_1 = {plan.varies[0].values[0]:g} .. "
                               f"{plan.varies[0].values[-1]:g} s ({len(plan.varies[0].values)} periods)"))
    for header in ("engine", "support", "max V_b/(m_t g)", "at T_1 [s]", "max M_b/(m_t g h_1*)", "b/h_1*",
                   "uplift for T_1 [s]"):
        table.add_column(escape(header), justify="right")
    for engine in plan.engines:
        for support in plan.supports:
            mine = [r for r in rows if r["engine"] == engine and r["support"] == support and r["status"] == "ok"]
            if not mine:
                continue
            top = max(mine, key=lambda r: r["base_shear_coefficient"])
            lifted = [r[figures.PERIOD_PATH] for r in mine if r["uplift"]]
            table.add_row(engine, support, f"{top['base_shear_coefficient']:.4g}", f"{top[figures.PERIOD_PATH]:.4g}",
                          f"{max(r['base_moment_coefficient'] for r in mine):.4g}",
                          f"{top['critical_coefficient']:.4g}",
                          f"{min(lifted):.3g} .. {max(lifted):.3g}" if lifted else "none")
    render.console().print(table)


def register(app: typer.Typer) -> None:
    app.command("sweep")(sweep)
    app.command("spectra")(spectra)

