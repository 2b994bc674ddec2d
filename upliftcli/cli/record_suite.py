"""`uplift record generate`, `uplift record match` and `uplift record scale`: record suites for a
deck's design spectrum (target, code rule and period range from the deck, docs/deck.md)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from ..errors import InputError
from ..runtime import limits
from . import stdout
from .options import echo_warnings, given_path
from .record_options import (
    DT_HELP,
    INPUT_FORMAT,
    MOVED_FORMAT,
    OVERRIDE_HELP,
    RECORD_UNITS,
    SUITE_OUT_HELP,
    SUITE_SET_HELP,
    SUITE_UNITS,
    check_count,
    load_plan,
    read_with_options,
    units_of,
)
from .record_output import check_out, print_suite, write_suite

if TYPE_CHECKING:  # imported by the commands that use them (numpy, scipy, rich, the suites: see analyze.py)
    from ..deck.suite import SuitePlan
    from ..motion import records
    from ..motion.matching import MatchSettings
    from ..motion.suites import Suite

DEFAULT_DT = 0.01  # s, the step of generated records


def _records(deck_path: Path, loaded, files: list[Path] | None, file_format: str | None, units: str | None,
             dt: float | None, override: bool = False) -> tuple[list[records.Record], tuple[str, ...]]:
    """The records named on the command line, else those of the deck's ground_motion.suite, and
    how each was made (motion/origins.py: their folder's manifest)."""
    if files:
        return _given_records(files, file_format, units, dt, override)
    return _deck_records(deck_path, loaded)


def _given_records(files: list[Path], file_format: str | None, units: str | None, dt: float | None,
                   override: bool) -> tuple[list[records.Record], tuple[str, ...]]:
    """The records of the command line as its options read them, and how each was made."""
    from ..motion.origins import origin_of

    return ([read_with_options(f, format=file_format, units=units, dt=dt, override_header_units=override)
             for f in files], tuple(origin_of(f) for f in files))


def _deck_records(deck_path: Path, loaded) -> tuple[list[records.Record], tuple[str, ...]]:
    """The records of the deck's ground_motion.suite, and how each was made."""
    from ..motion.suites import entry_origins, read_records, suite_entries

    suite = loaded.values.get("ground_motion", {}).get("suite")
    if suite is None:
        raise InputError(str(deck_path), "ground_motion.suite", "records: give RECORD files or a suite in the deck")
    entries = suite_entries(suite, str(deck_path))
    return read_records(entries), entry_origins(entries)


def generate(
    deck: Path = typer.Argument(..., parser=given_path,
                                help="Deck (TOML) whose ground_motion.design_spectrum is the target."),
    count: int = typer.Option(11, "--count", "-n", help="Number of records (ASCE 7-22 asks >= 11, EN 1998-1 >= 3)."),
    seed: int = typer.Option(..., "--seed", help="Seed: record k is reproducible from (seed, k)."),
    out: Path = typer.Option(..., "--out", "-o", parser=given_path, help=SUITE_OUT_HELP),
    dt: float | None = typer.Option(None, "--dt", help=f"Time step of the records [s] (default {DEFAULT_DT:g})."),
    stationary: float | None = typer.Option(None, "--stationary", help="Shortest strong-motion duration D5-95 of a "
                                            "record [s] (default: the code's, 10 s for EN 1998-1)."),
    scenario: str | None = typer.Option(None, "--scenario", help="Earthquake scenario of the durations: 'M,R_rup "
                                        "km,Vs30 m/s[,SS|NS|RS]' (default: by the spectrum's level and site)."),
    settings: list[str] = typer.Option([], "--set", "-s", help=SUITE_SET_HELP),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace existing files in --out."),
) -> None:
    """Artificial records for the deck's design spectrum (Rezaeian & Der Kiureghian stochastic model, matched by
    wavelets), with a manifest."""
    from ..motion.generate import generate_suite
    from ..motion.matching import settings_for

    _check_generate_options(count, seed, stationary)
    given = _scenario(scenario)
    loaded, plan = load_plan(deck, settings)
    dt = _generate_step(loaded, plan, dt)
    envelopes = _generate_envelopes(plan, dt, count, seed, stationary, given)
    names = [f"artificial_{seed}_{k + 1:02d}.txt" for k in range(count)]
    check_out(out, [*names, "manifest.json"], overwrite, [deck])
    match_settings = settings_for(plan.rule)
    suite, items = generate_suite(plan.target, plan.period_range, plan.rule, count, seed, dt, envelopes,
                                  match_settings, plan.period_note, given)
    files = _generated_files(deck, plan, suite, items, names, match_settings, seed, given)
    write_suite(out, files, suite, names, f"Artificial records, seed {seed}", match_settings, suite.warnings)


def _check_generate_options(count: int, seed: int, stationary: float | None) -> None:
    """--count, --seed and --stationary within their ranges, before the deck is read."""
    check_count(count)
    if not 0 <= seed <= limits.MAX_SEED:
        raise InputError("--seed", str(seed), f"an integer from 0 to {limits.MAX_SEED:,}")
    if stationary is not None and not (math.isfinite(stationary) and stationary > 0.0):
        raise InputError("--stationary", f"{stationary:g}", "a stationary duration > 0 s")


def _generate_step(loaded, plan: SuitePlan, dt: float | None) -> float:
    """The time step of the records: --dt, at most the lower period / SAMPLES_PER_PERIOD, or DEFAULT_DT."""
    from ..motion.suites import SAMPLES_PER_PERIOD

    largest = plan.period_range[0] / SAMPLES_PER_PERIOD
    if dt is None:
        return _default_step(loaded, plan, largest)
    if not 0.0 < dt <= largest:
        raise InputError("--dt", f"{dt:g}", f"a time step > 0 and <= {largest:.4g} s "
                         f"(the lower period {plan.period_range[0]:.4g} s / {SAMPLES_PER_PERIOD})")
    return dt


def _default_step(loaded, plan: SuitePlan, largest: float) -> float:
    """DEFAULT_DT, unless the period range asks for a finer step (then the deck's period range is blamed)."""
    from ..analysis.run import BUILDING_PATHS
    from ..motion.suites import SAMPLES_PER_PERIOD

    if largest < DEFAULT_DT:
        raise InputError(*loaded.blame("ground_motion.period_range", *BUILDING_PATHS),
                         f"a lower period of at least {SAMPLES_PER_PERIOD * DEFAULT_DT:g} s for records at the "
                         f"default step of {DEFAULT_DT:g} s (or give --dt <= {largest:.4g} s), got "
                         f"{plan.period_range[0]:.4g} s")
    return DEFAULT_DT


SCENARIO_HELP = ("'M,R_rup,Vs30' or 'M,R_rup,Vs30,SS|NS|RS' with M 3-7.9, R_rup 0-300 km, Vs30 150-1500 m/s "
                 "(Afshari & Stewart 2016)")


def _scenario(text: str | None):
    """The --scenario 'M,R,Vs30[,mechanism]' as a durations.Scenario (None: the default); one line if malformed."""
    if text is None:
        return None
    from ..motion.durations import Scenario

    parts = [p.strip() for p in text.split(",")]
    values = _scenario_numbers(parts[:3])
    mechanism = parts[3].upper() if len(parts) == 4 else ""
    if values is None or len(parts) > 4 or mechanism not in ("", "SS", "NS", "RS"):
        raise InputError("--scenario", text, SCENARIO_HELP)
    return Scenario(*values, mechanism)


def _scenario_numbers(parts: list[str]) -> list[float] | None:
    """M, R_rup, Vs30 within the model's ranges, or None."""
    from ..motion.durations import RANGES

    bounds = (RANGES["magnitude"], (0.0, 300.0), RANGES["vs30"])
    try:
        values = [float(p) for p in parts]
    except ValueError:
        return None
    inside = len(values) == 3 and all(lo <= v <= hi for v, (lo, hi) in zip(values, bounds, strict=True))
    return values if inside else None


def _generate_envelopes(plan: SuitePlan, dt: float, count: int, seed: int, stationary: float | None,
                        scenario=None) -> list:
    """The envelopes of the records (generate.suite_envelopes), the suite within the tool's limits of samples."""
    from ..motion.generate import suite_envelopes
    from ..motion.suites import SAMPLES_PER_PERIOD

    envelopes = suite_envelopes(plan.target, plan.period_range, plan.rule, count, seed, scenario,
                                stationary or 0.0)
    longest = max(envelopes, key=lambda e: e.duration)
    samples = [e.samples(dt) for e in envelopes]
    problem = limits.suite_samples_problem(samples, f"{count:,} records of up to {max(samples):,} samples: "
                                           f"{longest.duration:.4g} s at dt = {dt:g} s")
    if problem:
        raise InputError(*_generate_blame(longest, dt, count, plan.period_range[0] / SAMPLES_PER_PERIOD,
                                          stationary), problem)
    return envelopes


def _generate_blame(envelope, dt: float, count: int, largest_dt: float, stationary: float | None
                    ) -> tuple[str, str]:
    """(option, value) of `record generate` that exceeds the suite limits: --count when one record
    is within them, else --dt when a record at the default step would be, else --stationary."""
    if _fits(envelope.samples(dt)) and count > 1:
        return "--count", str(count)
    if _fits(envelope.samples(min(0.01, largest_dt))):
        return "--dt", f"{dt:g}"
    return "--stationary", f"{stationary or 0.0:g}"


def _fits(samples: int) -> bool:
    """One record of this many samples is within the limits of a record and of a suite."""
    return samples <= min(limits.MAX_RECORD_SAMPLES, limits.MAX_SUITE_SAMPLES)


def _generated_files(deck: Path, plan: SuitePlan, suite: Suite, items: list, names: list[str],
                     match_settings: MatchSettings, seed: int, given=None) -> dict[str, str]:
    """The generated records as text files with their provenance, then manifest.json."""
    from dataclasses import asdict

    from ..motion.generate import GENERATOR_VERSION, suite_scenario
    from ..motion.record_files import manifest_text, measure_row, model_row, record_checks, record_text, sha256

    files, rows = {}, []
    for name, motion, factor, item, check in zip(names, suite.motions(), suite.factors, items,
                                                 record_checks(suite, match_settings), strict=True):
        text = record_text(name.removesuffix(".txt"), motion.dt, motion.acceleration,
                           _generated_provenance(plan, item, seed, factor))
        files[name] = text
        rows.append({"file": name, "index": item.index, "draw": item.attempt, "factor": round(factor, 6),
                     "iterations": item.result.iterations, "filter": model_row(item.parameters), **check,
                     **measure_row(motion), "sha256": sha256(text)})
    files["manifest.json"] = manifest_text(suite, match_settings, "record generate", str(deck), rows,
                                           {"seed": seed, "count": len(names), "generator": GENERATOR_VERSION,
                                            "match_range_s": list(items[0].match_range),
                                            "scenario": {**asdict(suite_scenario(plan.target, given)),
                                                         "given": given is not None}})
    return files


def _generated_provenance(plan: SuitePlan, item, seed: int, factor: float) -> list[str]:
    """The provenance lines of one generated record: its draw, model, envelope and matching."""
    envelope, model = item.envelope, item.parameters
    start, middle = envelope.arias_time(0.05), envelope.arias_time(0.45)
    return [
        f"synthetic: generated by `uplift record generate` (seed {seed}, index {item.index}, draw {item.attempt})",
        "model: Rezaeian & Der Kiureghian (2010) filtered white noise, time-varying filter "
        f"(f_mid {model.mid_frequency:.3g} Hz, f' {model.rate:.3g} Hz/s, damping {model.damping:.3g}), "
        f"high-pass corner {model.corner:.3g} Hz",
        f"envelope: gamma (Rezaeian & Der Kiureghian 2008), shape {envelope.shape:.4g}, D5-95 {envelope.d5_95:.4g} s "
        f"(Afshari & Stewart 2016), t_45 {middle:.4g} s, t_5 {start:.4g} s, length {envelope.duration:.4g} s",
        f"matched by wavelets (Al Atik & Abrahamson 2010) over {item.match_range[0]:.3g}-"
        f"{item.match_range[1]:.3g} s to {plan.target.name}, {plan.rule.label}",
        f"period range {plan.period_range[0]:.4g}-{plan.period_range[1]:.4g} s; amplitude factor {factor:.6g}",
    ]


def match(
    deck: Path = typer.Argument(..., parser=given_path,
                                help="Deck (TOML) whose ground_motion.design_spectrum is the target."),
    files: list[Path] = typer.Argument(None, parser=given_path,
                                       help="Records to match (default: the deck's ground_motion.suite)."),
    out: Path = typer.Option(..., "--out", "-o", parser=given_path, help=SUITE_OUT_HELP),
    file_format: str | None = INPUT_FORMAT,
    moved_format: str | None = MOVED_FORMAT,
    record_units: str | None = RECORD_UNITS,
    override: bool = typer.Option(False, "--override-header-units", help=OVERRIDE_HELP),
    dt: float | None = typer.Option(None, "--dt", help=DT_HELP),
    settings: list[str] = typer.Option([], "--set", "-s", help=SUITE_SET_HELP),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace existing files in --out."),
    units: str = SUITE_UNITS,
) -> None:
    """Spectrally match records to the deck's design spectrum; writes them with their provenance."""
    from ..motion.matching import settings_for
    from ..motion.suites import build_suite

    _, record_units = units_of(units, record_units)
    loaded, plan = load_plan(deck, settings)
    seeds, _ = _records(deck, loaded, files, file_format, record_units, dt, override)
    _check_match_size(deck, files, seeds)
    names = _matched_names(seeds)
    check_out(out, [*names, "manifest.json"], overwrite, [deck, *(Path(r.source) for r in seeds)])
    match_settings = settings_for(plan.rule)
    suite = build_suite(seeds, plan.target, plan.period_range, plan.rule, "match", period_note=plan.period_note,
                        settings=match_settings, source=str(deck))
    files_out, changes = _matched_files(deck, plan, suite, seeds, names, match_settings)
    write_suite(out, files_out, suite, names, "Matched records", match_settings, suite.warnings)
    _print_changes(names, changes)


def _print_changes(names: list[str], changes: list[dict[str, float]]) -> None:
    """One line per matched record: what matching changed (record_files.character_row)."""
    stdout.echo("what matching changed (D5-95 and PGV, PGD: matched / original at the same Arias intensity; "
               "net Arias share added before the original's t_5):")
    for name, change in zip(names, changes, strict=True):
        stdout.echo(f"  {name}: D5-95 x{change['d5_95_ratio']:.3f}, PGV x{change['pgv_ratio']:.3f}, "
                   f"PGD x{change['pgd_ratio']:.3f}, early Arias {100 * change['early_arias_gain']:+.2f} %")


def _check_match_size(deck: Path, files: list[Path] | None, seeds: list[records.Record]) -> None:
    """The records to match within the tool's limit of samples (blamed on RECORD or on the deck's suite)."""
    problem = limits.suite_samples_problem([r.npts for r in seeds], f"{len(seeds):,} records of "
                                           f"{sum(r.npts for r in seeds):,} samples")
    if problem:
        raise InputError(*_records_source(deck, files), problem)


def _records_source(deck: Path, files: list[Path] | None) -> tuple[str, str | None]:
    """(source, location) of the records in a message: RECORD arguments, or the deck's ground_motion.suite."""
    return ("RECORD", None) if files else (str(deck), "ground_motion.suite")


def _matched_names(seeds: list[records.Record]) -> list[str]:
    """<record>_matched.txt of each record; their file names must differ."""
    names = [f"{Path(r.source).stem}_matched.txt" for r in seeds]
    if len(set(names)) != len(names):
        raise InputError("RECORD", ", ".join(names), "records with different file names")
    return names


def _matched_files(deck: Path, plan: SuitePlan, suite: Suite, seeds: list[records.Record], names: list[str],
                   match_settings: MatchSettings) -> tuple[dict[str, str], list[dict[str, float]]]:
    """The matched records as text files with their provenance, then manifest.json; and what
    matching changed in each record (record_files.character_row)."""
    from ..motion.record_files import character_row, manifest_text, measure_row, record_checks, record_text, sha256

    files, rows, changes = {}, [], []
    for name, seed, motion, factor, check in zip(names, seeds, suite.motions(), suite.factors,
                                                 record_checks(suite, match_settings), strict=True):
        text = record_text(f"{seed.name} (matched)", motion.dt, motion.acceleration,
                           _matched_provenance(plan, seed, factor))
        files[name] = text
        changes.append(character_row(seed, motion))
        rows.append({"file": name, "from": seed.source, "factor": round(factor, 6), **check, **measure_row(motion),
                     **changes[-1], "sha256": sha256(text)})
    files["manifest.json"] = manifest_text(suite, match_settings, "record match", str(deck), rows)
    return files, changes


def _matched_provenance(plan: SuitePlan, seed: records.Record, factor: float) -> list[str]:
    """The provenance lines of one matched record: its seed record (and its SHA-256), target and range."""
    import hashlib

    digest = hashlib.sha256(Path(seed.source).read_bytes()).hexdigest()
    return [
        f"matched by `uplift record match` (wavelets, Al Atik & Abrahamson 2010) from {seed.source}",
        f"seed record SHA-256 {digest}, read as {seed.units}, scale {seed.scale:g}",
        f"target: {plan.target.name}, {plan.rule.label}",
        f"period range {plan.period_range[0]:.4g}-{plan.period_range[1]:.4g} s; amplitude factor {factor:.6g}",
    ]


def scale(
    deck: Path = typer.Argument(..., parser=given_path,
                                help="Deck (TOML) whose ground_motion.design_spectrum is the target."),
    files: list[Path] = typer.Argument(None, parser=given_path,
                                       help="Records to scale (default: the deck's ground_motion.suite)."),
    suite_factor: bool = typer.Option(False, "--suite-factor", help="One factor for the whole suite."),
    file_format: str | None = INPUT_FORMAT,
    moved_format: str | None = MOVED_FORMAT,
    record_units: str | None = RECORD_UNITS,
    override: bool = typer.Option(False, "--override-header-units", help=OVERRIDE_HELP),
    dt: float | None = typer.Option(None, "--dt", help=DT_HELP),
    settings: list[str] = typer.Option([], "--set", "-s", help=SUITE_SET_HELP),
    units: str = SUITE_UNITS,
) -> None:
    """Amplitude factors that bring the suite's mean spectrum to the code's criterion (printed)."""
    from ..motion.suites import build_suite

    _, record_units = units_of(units, record_units)
    loaded, plan = load_plan(deck, settings)
    seeds, made = _records(deck, loaded, files, file_format, record_units, dt, override)
    suite = build_suite(seeds, plan.target, plan.period_range, plan.rule, "amplitude", suite_factor,
                        plan.period_note, source=str(deck), made=made)
    print_suite(suite, [Path(r.source).name for r in seeds], "Amplitude factors")
    echo_warnings(suite.warnings)


def register(record_app: typer.Typer) -> None:
    """Add generate, match and scale to the `record` command group."""
    record_app.command("generate")(generate)
    record_app.command("match")(match)
    record_app.command("scale")(scale)
