"""The bearing capacity of the two-element and Winkler foundations from the deck: the fields they
share, the capacity of a strip of the mat from whichever field is given, and the static check
(docs/theory.md section 14; ASCE 41-17 section 8.4: q_c, q/q_c, FS_v). The capacity itself is
an attribute of the foundation (model/foundations.py), each element's Q_y [N] in its contact
elements.
"""

from __future__ import annotations

from typing import Any

from ..deck.fields import Field
from .deck_context import DeckContext

#: the bearing-capacity fields the two-element and Winkler foundations share (docs/deck.md);
#: each also has its own capacity field (element_capacity, line_capacity): exactly one of the three
CAPACITY_FIELDS: dict[str, Field] = {
    "bearing_pressure": Field("number", "Pa", "two-element, winkler: expected bearing capacity pressure q_c "
                              "(ASCE 41-17 section 8.4), with mat_length", "positive"),
    "mat_length": Field("number", "m", "two-element, winkler: length L of the mat normal to the plane of motion "
                        "(used with bearing_pressure)", "positive"),
    "safety_factor": Field("number", "-", "two-element, winkler: FS_v = q_c/q, factor of safety against vertical "
                           "bearing failure under the static load (ASCE 41-17 section 8.4)", "greater-than-one",
                           plausible=(1.2, 100.0)),
}
#: each foundation's own capacity field (declared with it, model/foundations.py)
OWN_CAPACITY_FIELDS = ("element_capacity", "line_capacity")
#: the fields that go with another (mat_length scales bearing_pressure): a --set that replaces the
#: latter by another way to the capacity (deck_overrides.ALTERNATIVES) removes them too
COMPANIONS = {"bearing_pressure": ("mat_length",)}
#: every deck field that gives a foundation its bearing capacity or scales it (mat_length)
CAPACITY_NAMES = (*OWN_CAPACITY_FIELDS, *CAPACITY_FIELDS)


def bearing_capacity(fields: dict[str, Any], context: DeckContext, own: str, tributary: float) -> float | None:
    """The capacity of a strip of width `tributary` [m] of the mat (None: no capacity given): the
    foundation's own field `own` as given, q_c L tributary from bearing_pressure [Pa] and
    mat_length [m], or FS_v W tributary / (2 b) from safety_factor (W = m_t g: the static
    pressure q = W / (2 b L) times FS_v). mat_length without bearing_pressure, which it scales, is
    refused: nothing would read it."""
    if "mat_length" in fields and "bearing_pressure" not in fields:
        context.missing("mat_length", "only with foundation.bearing_pressure, which it scales (q_c L); without it "
                        "the mat length is not used (a capacity from safety_factor or the foundation's own field "
                        "needs no length)")
    if own in fields:
        return float(fields[own])
    if "bearing_pressure" in fields:
        if "mat_length" not in fields:
            context.missing("mat_length", "the mat length L > 0 [m] normal to the plane of motion, with "
                            "foundation.bearing_pressure (missing)")
        return float(fields["bearing_pressure"] * fields["mat_length"] * tributary)
    if "safety_factor" in fields:
        weight = context.total_mass * context.gravity
        return float(fields["safety_factor"] * weight * tributary / (2.0 * context.half_width))
    return None


def check_static_capacity(total: float, context: DeckContext, fields: dict[str, Any], own: str) -> None:
    """The static weight must be carried below the capacity (FS_v > 1; uniform elements)."""
    weight = context.total_mass * context.gravity
    if total <= weight:
        name = next(n for n in (own, "bearing_pressure", "safety_factor") if n in fields)
        context.missing(name, f"a bearing capacity above the static load: the elements carry {total:.6g} N in "
                        f"all, the weight m_t g is {weight:.6g} N (FS_v = {total / weight:.4g} <= 1)")
