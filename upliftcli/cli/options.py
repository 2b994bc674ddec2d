"""Options several commands share (`analyze`, `modes`, `report`, `sweep`, `spectra`): the output
and display-unit choices, the help texts of --set, --units and --engine, and --set / --engine /
--support turned into the deck's overrides (docs/deck.md)."""

from __future__ import annotations

import json
from enum import StrEnum

from ..deck.fields import parse_choices

SET_HELP = ("Override a deck field by dotted path, e.g. --set building.period=0.5 (repeatable; TOML values in the "
            "deck's units: SI, US customary under units = \"us\", or with their unit, "
            "building.story_height='\"11.5 ft\"'; docs/deck.md).")
UNITS_HELP = ("Display units of the tables and figures: si (kN, kN m, mm, m, g) or us (kip, kip ft, in, ft, g); "
              "JSON and CSV stay SI.")
ENGINE_HELP = "Engine(s): simplified, approximate, exact or all; repeatable or comma separated (default: the deck's)."


class OutputFormat(StrEnum):
    table = "table"
    json = "json"


class DisplayUnits(StrEnum):
    """The display units of the human outputs (upliftcli/display.py); files and JSON stay SI."""

    si = "si"
    us = "us"


def overrides(settings: list[str], engines: list[str], supports: list[str]) -> list[str]:
    """The --set texts, then --engine and --support (checked here, so that a bad name is
    reported as the option's, not as a --set of analysis.engine)."""
    from ..engines.registry import ENGINES, SUPPORTS

    given = list(settings)
    engines = parse_choices(engines, tuple(ENGINES), "--engine")
    supports = parse_choices(supports, SUPPORTS, "--support")
    if engines:
        given.append("analysis.engine=" + json.dumps(engines))
    if supports:
        given.append("analysis.supports=" + json.dumps(supports))
    return given


def refuse_unchecked(criteria, check: bool, option: str = "--no-check") -> None:
    """[criteria] simplified_error is judged on the accuracy check (deck/criteria.py): a run without the
    check (--no-check; a sweep without --check) would pass the limit unchecked, so it is refused."""
    from ..errors import InputError

    if check or "simplified_error" not in criteria:
        return
    if option == "--check":
        raise InputError("--check", "criteria.simplified_error", "needed by this limit of the deck (a sweep judges it "
                         "on the ratios simplified / exact that --check adds): add --check or drop the limit")
    raise InputError(option, "criteria.simplified_error", "the accuracy check that this limit of the deck judges: "
                     "drop --no-check or the limit")
