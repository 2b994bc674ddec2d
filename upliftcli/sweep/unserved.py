"""The line that refuses a sweep whose record suite cannot serve some of its cases (issue 36:
`uplift spectra` on a suite deck ran 8 minutes and then exited 4 with 60 failure lines, the
records too short for the long periods). The plan (plan.py) builds the cases' suites from the
last combination of the varied values down and stops at the first it can serve, so the
refusal comes before any analysis and within seconds."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from ..errors import InputError
from .values import Vary

Combo = tuple[tuple[str, Any], ...]


def _case(combo: Combo) -> str:
    return ", ".join(f"{path}={value:g}" if isinstance(value, float) else f"{path}={value}" for path, value in combo)


def _served(served: Combo | None, varies: Sequence[Vary]) -> str:
    """What the suite serves, in words: the varied value (one field) or the case (several)."""
    if served is None:
        return "none of the values asked"
    if len(varies) == 1:
        value = served[0][1]
        unit = f" {varies[0].unit}" if varies[0].unit not in ("", "-") else ""
        return f"up to {varies[0].path} = {value:g}{unit}, the longest value asked that it serves"
    return f"the case {_case(served)} and others, not {len(varies)} fields in every combination"


def unserved_error(unsupported: Sequence[tuple[Combo, str]], served: Combo | None, varies: Sequence[Vary],
                   total: int) -> InputError:
    """The one line refusing the sweep: the varied field (--vary PATH; `uplift spectra` names
    --periods), what the suite serves, how many combinations it cannot serve and why (the first's
    reason, e.g. the records' duration against the period range's upper end)."""
    location = varies[0].path if len(varies) == 1 else ", ".join(v.path for v in varies)
    reason = unsupported[-1][1]  # the case nearest to one it serves
    return InputError("--vary", location, f"values the deck's record suite can serve: {_served(served, varies)} "
                      f"({len(unsupported)} of {total} asked it cannot, e.g. {reason}; ask for no more or give "
                      "longer records)")
