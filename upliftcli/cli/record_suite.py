"""`uplift record generate`, `uplift record match` and `uplift record scale`: record suites for a
deck's design spectrum (target, code rule and period range from the deck, docs/deck.md)."""

from __future__ import annotations

import hashlib
import math
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from ..errors import InputError
from ..runtime import limits
from ..runtime.atomic import refuse_existing, refuse_inputs
from ..units import STANDARD_GRAVITY
from .record import DT_HELP, INPUT_FORMAT, MOVED_FORMAT, OVERRIDE_HELP, RECORD_UNITS, read_with_options, units_of

if TYPE_CHECKING:  # imported by the commands that use them (numpy, scipy, rich, the suites: see analyze.py)
    from ..motion import records
    from ..motion.matching import MatchSettings
    from ..motion.suites import Suite

#: --units of match and scale: the display units of every command, and the record file's units as before
SUITE_UNITS = typer.Option("si", "--units", metavar="[si|us]", help=(
    "Display units, as in the other commands: si or us (this command prints accelerations in g and periods in s, "
    "the same in both). An acceleration unit here (its meaning before) is read as --record-units, with a warning."))
SET_HELP = ("Override a deck field by dotted path, e.g. --set ground_motion.period_range=[0.1,3] (repeatable; "
            "TOML values in the deck's units, as in uplift analyze; docs/deck.md).")
DEFAULT_DT = 0.01  # s, the step of generated records
OUT_HELP = "Directory for the records and manifest.json (created; existing files are kept unless --overwrite)."


def _warn(messages) -> None:
    for message in messages:
        typer.echo(f"warning: {message}", err=True)


def _records(deck_path: Path, loaded, files: list[Path] | None, file_format: str | None, units: str | None,
             dt: float | None, override: bool = False) -> tuple[list[records.Record], tuple[str, ...]]:
    """The records named on the command line, else those of the deck's ground_motion.suite, and
    how each was made (motion/origins.py: their folder's manifest)."""
    from ..motion.origins import origin_of
    from ..motion.suites import entry_origins, read_records, suite_entries

    if files:
        return ([read_with_options(f, format=file_format, units=units, dt=dt, override_header_units=override)
                 for f in files], tuple(origin_of(f) for f in files))
    suite = loaded.values.get("ground_motion", {}).get("suite")
    if suite is None:
        raise InputError(str(deck_path), "ground_motion.suite", "records: give RECORD files or a suite in the deck")
    entries = suite_entries(suite, str(deck_path))
    return read_records(entries), entry_origins(entries)


def _check_out(out: Path, names: list[str], overwrite: bool, inputs: list[Path]) -> None:
    """Nothing is written when --out is a file, a target file exists (without --overwrite) or is an input."""
    if out.exists() and not out.is_dir():
        raise InputError("--out", str(out), "a directory (a file of that name exists)")
    refuse_inputs([out / name for name in names], inputs, "--out")  # the same file by inode or path
    refuse_existing([out / name for name in names], "--out", overwrite)


def _write(out: Path, files: dict[str, str]) -> None:
    """The records and their manifest (last) all or none (atomic.write_set): a full disk or a
    stop leaves the folder as it was (it left 7 of 11 records and no manifest)."""
    from ..runtime.atomic import write_set

    try:
        write_set({out / name: text for name, text in files.items()})
    except OSError as error:
        raise InputError("--out", str(out), f"a writable directory ({error.strerror or error}); nothing was "
                         "written") from None


def _print_suite(suite: Suite, labels: list[str], title: str, tolerance: MatchSettings | None = None) -> None:
    from rich.markup import escape
    from rich.table import Table

    from . import render

    out = render.console()
    out.print(escape(f"target: {suite.target.name}; {suite.rule.label}, design value: {suite.statistic} "
                     f"of {suite.count}"))
    out.print(escape(f"period range {suite.period_range[0]:.4g}-{suite.period_range[1]:.4g} s: {suite.period_note}"))
    target = suite.target.sa(suite.periods, suite.damping)
    table = Table(title=escape(title))
    for header in ("record", "factor [-]", "PGA [g]", "S_a/target min", "S_a/target max"):
        table.add_column(escape(header), justify="right" if header != "record" else "left")
    for label, motion, factor, spectrum in zip(labels, suite.motions(), suite.factors, suite.spectra(), strict=True):
        ratios = spectrum / target
        table.add_row(escape(label), f"{factor:.4f}", f"{motion.pga / STANDARD_GRAVITY:.4f}",
                      f"{ratios.min():.3f}", f"{ratios.max():.3f}")
    out.print(table)
    mean = suite.mean_ratio()
    out.print(escape(f"mean S_a/target over the range: min {mean.min():.3f}, max {mean.max():.3f} "
                     f"(the code asks >= {suite.mean_minimum:g})"))
    if tolerance is not None:
        low, high = tolerance.low * tolerance.reference, tolerance.high * tolerance.reference
        out.print(escape(f"tolerance of each record: {tolerance.low:g}-{tolerance.high:g} x {tolerance.reference:g} "
                         f"x target = {low:.3g}-{high:.3g} x target, at {suite.periods.size} periods"))


def generate(
    deck: Path = typer.Argument(..., help="Deck (TOML) whose ground_motion.design_spectrum is the target."),
    count: int = typer.Option(11, "--count", "-n", help="Number of records (ASCE 7-22 asks >= 11, EN 1998-1 >= 3)."),
    seed: int = typer.Option(..., "--seed", help="Seed: record k is reproducible from (seed, k)."),
    out: Path = typer.Option(..., "--out", "-o", help=OUT_HELP),
    dt: float | None = typer.Option(None, "--dt", help=f"Time step of the records [s] (default {DEFAULT_DT:g})."),
    stationary: float = typer.Option(10.0, "--stationary", help="Stationary part of the envelope [s] (EC8: >= 10)."),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace existing files in --out."),
) -> None:
    """Artificial records for the deck's design spectrum (Rezaeian & Der Kiureghian stochastic model, matched by
    wavelets), with a manifest."""
    from ..analysis.run import BUILDING_PATHS
    from ..deck.load import load_deck
    from ..deck.suite import plan_from_deck
    from ..motion.generate import GENERATOR_VERSION, Envelope, generate_suite, suite_envelope
    from ..motion.matching import settings_for
    from ..motion.record_files import manifest_text, measure_row, model_row, record_checks, record_text, sha256
    from ..motion.suites import SAMPLES_PER_PERIOD

    if not 1 <= count <= limits.MAX_SUITE_RECORDS:
        raise InputError("--count", str(count), f"from 1 to {limits.MAX_SUITE_RECORDS:,} records")
    if not 0 <= seed <= limits.MAX_SEED:
        raise InputError("--seed", str(seed), f"an integer from 0 to {limits.MAX_SEED:,}")
    if not (math.isfinite(stationary) and stationary > 0.0):
        raise InputError("--stationary", f"{stationary:g}", "a stationary duration > 0 s")
    loaded = load_deck(deck, settings, load_ground_motion=False)
    plan = plan_from_deck(loaded)
    largest = plan.period_range[0] / SAMPLES_PER_PERIOD
    if dt is None and largest < DEFAULT_DT:  # the period range asks for a finer step than the default
        raise InputError(*loaded.blame("ground_motion.period_range", *BUILDING_PATHS),
                         f"a lower period of at least {SAMPLES_PER_PERIOD * DEFAULT_DT:g} s for records at the "
                         f"default step of {DEFAULT_DT:g} s (or give --dt <= {largest:.4g} s), got "
                         f"{plan.period_range[0]:.4g} s")
    dt = DEFAULT_DT if dt is None else dt
    if not 0.0 < dt <= largest:
        raise InputError("--dt", f"{dt:g}", f"a time step > 0 and <= {largest:.4g} s "
                         f"(the lower period {plan.period_range[0]:.4g} s / {SAMPLES_PER_PERIOD})")
    envelope = suite_envelope(plan.period_range, plan.rule, Envelope(strong=stationary))
    samples = envelope.samples(dt)
    problem = limits.suite_samples_problem([samples] * count, f"{count:,} records of {samples:,} samples: "
                                           f"{envelope.duration:.4g} s at dt = {dt:g} s")
    if problem:
        raise InputError(*_generate_blame(envelope, dt, count, plan.period_range[0] / SAMPLES_PER_PERIOD,
                                          stationary), problem)
    names = [f"artificial_{seed}_{k + 1:02d}.txt" for k in range(count)]
    _check_out(out, [*names, "manifest.json"], overwrite, [deck])
    match_settings = settings_for(plan.rule)
    suite, items = generate_suite(plan.target, plan.period_range, plan.rule, count, seed, dt, envelope, match_settings,
                                  plan.period_note)
    files, rows = {}, []
    for name, motion, factor, item, check in zip(names, suite.motions(), suite.factors, items,
                                                 record_checks(suite, match_settings), strict=True):
        envelope, model = item.envelope, item.parameters
        provenance = [
            f"synthetic: generated by `uplift record generate` (seed {seed}, index {item.index}, draw {item.attempt})",
            "model: Rezaeian & Der Kiureghian (2010) filtered white noise, time-varying filter "
            f"(f_mid {model.mid_frequency:.3g} Hz, f' {model.rate:.3g} Hz/s, damping {model.damping:.3g}), "
            f"high-pass corner {model.corner:.3g} Hz",
            f"envelope: rise {envelope.rise:g} s, stationary {envelope.strong:g} s, decay {envelope.decay:g} s",
            f"matched by wavelets (Al Atik & Abrahamson 2010) over {item.match_range[0]:.3g}-"
            f"{item.match_range[1]:.3g} s to {plan.target.name}, {plan.rule.label}",
            f"period range {plan.period_range[0]:.4g}-{plan.period_range[1]:.4g} s; amplitude factor {factor:.6g}",
        ]
        text = record_text(name.removesuffix(".txt"), motion.dt, motion.acceleration, provenance)
        files[name] = text
        rows.append({"file": name, "index": item.index, "draw": item.attempt, "factor": round(factor, 6),
                     "iterations": item.result.iterations, "filter": model_row(model), **check,
                     **measure_row(motion), "sha256": sha256(text)})
    files["manifest.json"] = manifest_text(suite, match_settings, "record generate", str(deck), rows,
                                           {"seed": seed, "count": count, "generator": GENERATOR_VERSION,
                                            "match_range_s": list(items[0].match_range)})
    _write(out, files)
    _print_suite(suite, names, f"Artificial records, seed {seed}", match_settings)
    _warn(suite.warnings)
    typer.echo(f"wrote {count} records and manifest.json to {out}", err=True)


def _generate_blame(envelope, dt: float, count: int, largest_dt: float, stationary: float) -> tuple[str, str]:
    """(option, value) of `record generate` that exceeds the suite limits: --count when one record
    is within them, else --dt when a record at the default step would be, else --stationary."""
    def fits(samples: int) -> bool:
        return samples <= min(limits.MAX_RECORD_SAMPLES, limits.MAX_SUITE_SAMPLES)

    if fits(envelope.samples(dt)) and count > 1:
        return "--count", str(count)
    if fits(envelope.samples(min(0.01, largest_dt))):
        return "--dt", f"{dt:g}"
    return "--stationary", f"{stationary:g}"


def match(
    deck: Path = typer.Argument(..., help="Deck (TOML) whose ground_motion.design_spectrum is the target."),
    files: list[Path] = typer.Argument(None, help="Records to match (default: the deck's ground_motion.suite)."),
    out: Path = typer.Option(..., "--out", "-o", help=OUT_HELP),
    file_format: str | None = INPUT_FORMAT,
    moved_format: str | None = MOVED_FORMAT,
    record_units: str | None = RECORD_UNITS,
    override: bool = typer.Option(False, "--override-header-units", help=OVERRIDE_HELP),
    dt: float | None = typer.Option(None, "--dt", help=DT_HELP),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace existing files in --out."),
    units: str = SUITE_UNITS,
) -> None:
    """Spectrally match records to the deck's design spectrum; writes them with their provenance."""
    from ..deck.load import load_deck
    from ..deck.suite import plan_from_deck
    from ..motion.matching import settings_for
    from ..motion.record_files import manifest_text, measure_row, record_checks, record_text, sha256
    from ..motion.suites import build_suite

    _, record_units = units_of(units, record_units)
    loaded = load_deck(deck, settings, load_ground_motion=False)
    plan = plan_from_deck(loaded)
    seeds, _ = _records(deck, loaded, files, file_format, record_units, dt, override)
    problem = limits.suite_samples_problem([r.npts for r in seeds], f"{len(seeds):,} records of "
                                           f"{sum(r.npts for r in seeds):,} samples")
    if problem:
        raise InputError("RECORD" if files else str(deck), None if files else "ground_motion.suite", problem)
    names = [f"{Path(r.source).stem}_matched.txt" for r in seeds]
    if len(set(names)) != len(names):
        raise InputError("RECORD", ", ".join(names), "records with different file names")
    _check_out(out, [*names, "manifest.json"], overwrite, [deck, *(Path(r.source) for r in seeds)])
    match_settings = settings_for(plan.rule)
    suite = build_suite(seeds, plan.target, plan.period_range, plan.rule, "match", period_note=plan.period_note,
                        settings=match_settings, source=str(deck))
    files_out, rows = {}, []
    for name, seed, motion, factor, check in zip(names, seeds, suite.motions(), suite.factors,
                                                 record_checks(suite, match_settings), strict=True):
        digest = hashlib.sha256(Path(seed.source).read_bytes()).hexdigest()
        provenance = [
            f"matched by `uplift record match` (wavelets, Al Atik & Abrahamson 2010) from {seed.source}",
            f"seed record SHA-256 {digest}, read as {seed.units}, scale {seed.scale:g}",
            f"target: {plan.target.name}, {plan.rule.label}",
            f"period range {plan.period_range[0]:.4g}-{plan.period_range[1]:.4g} s; amplitude factor {factor:.6g}",
        ]
        text = record_text(f"{seed.name} (matched)", motion.dt, motion.acceleration, provenance)
        files_out[name] = text
        rows.append({"file": name, "from": seed.source, "factor": round(factor, 6), **check, **measure_row(motion),
                     "sha256": sha256(text)})
    files_out["manifest.json"] = manifest_text(suite, match_settings, "record match", str(deck), rows)
    _write(out, files_out)
    _print_suite(suite, names, "Matched records", match_settings)
    _warn(suite.warnings)
    typer.echo(f"wrote {len(names)} records and manifest.json to {out}", err=True)


def scale(
    deck: Path = typer.Argument(..., help="Deck (TOML) whose ground_motion.design_spectrum is the target."),
    files: list[Path] = typer.Argument(None, help="Records to scale (default: the deck's ground_motion.suite)."),
    suite_factor: bool = typer.Option(False, "--suite-factor", help="One factor for the whole suite."),
    file_format: str | None = INPUT_FORMAT,
    moved_format: str | None = MOVED_FORMAT,
    record_units: str | None = RECORD_UNITS,
    override: bool = typer.Option(False, "--override-header-units", help=OVERRIDE_HELP),
    dt: float | None = typer.Option(None, "--dt", help=DT_HELP),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    units: str = SUITE_UNITS,
) -> None:
    """Amplitude factors that bring the suite's mean spectrum to the code's criterion (printed)."""
    from ..deck.load import load_deck
    from ..deck.suite import plan_from_deck
    from ..motion.suites import build_suite

    _, record_units = units_of(units, record_units)
    loaded = load_deck(deck, settings, load_ground_motion=False)
    plan = plan_from_deck(loaded)
    seeds, made = _records(deck, loaded, files, file_format, record_units, dt, override)
    suite = build_suite(seeds, plan.target, plan.period_range, plan.rule, "amplitude", suite_factor,
                        plan.period_note, source=str(deck), made=made)
    _print_suite(suite, [Path(r.source).name for r in seeds], "Amplitude factors")
    _warn(suite.warnings)


def register(record_app: typer.Typer) -> None:
    """Add generate, match and scale to the `record` command group."""
    record_app.command("generate")(generate)
    record_app.command("match")(match)
    record_app.command("scale")(scale)
